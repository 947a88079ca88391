//! The floating base from the legs and the IMU (leg odometry), or read directly, with the
//! feet's wrenches and the ZMP from the F/T sensors.
//!
//! Leg odometry, each tick (seed 000 §3.16 names the inputs; the equations are this module's):
//! 1. joints from the encoders and joint velocity sensors;
//! 2. base orientation from the IMU: `R_b = R_imu · (ᵇR_imu(q))ᵀ`, and base rate
//!    `ω_b = ᵇR_imu (ω_gyro − ω_rel)`, with `ω_rel` the IMU body's rate relative to the base
//!    from the joint velocities;
//! 3. with `calibrate_foot_weight` (a sensor that carries the foot below it), each foot's
//!    F/T reading loses that foot's weight (the subtree's mass and centre of mass from the
//!    model at the last estimate, gravity in the sole's last estimated orientation); the
//!    foot's inertial forces stay in it, as on the robot;
//!    the wrench then goes through a second-order Butterworth low-pass filter when
//!    `ft_lowpass` is set (seed 002 §4.12: Wn = 0.4); a foot is in contact above `contact_on`
//!    of normal force (until it drops below
//!    `contact_off`); once it carries `settle_share` of the feet's load it settles and is
//!    anchored where the estimate puts it; a landing foot that carries less (it may still
//!    slide or bounce) follows the estimate of the settled feet;
//! 4. base position `p = Σ w_i (a_i − r_i) / Σ w_i` and velocity `ṗ_odo = −Σ w_i ṙ_i / Σ w_i`
//!    over the settled feet, weighted by their normal force `w_i`, where `r_i`, `ṙ_i` are
//!    the sole's position and velocity relative to the base point (world axes) and `a_i` its
//!    anchor; with no foot carrying the robot, the IMU's acceleration is integrated alone;
//! 5. the velocity is a complementary filter of the IMU's acceleration and the odometry:
//!    `ṗ⁻ = ṗ + (R_imu f_imu + g) dt`, `ṗ ← ṗ⁻ + (dt / (T + dt)) (ṗ_odo − ṗ⁻)`, with the IMU's
//!    specific force `f_imu` and time constant T (`velocity_fusion_time`): the feet vibrate on
//!    a stiff contact, and that motion, which odometry cannot see, reaches the velocity
//!    above 1/T only through the IMU.

use crate::lowpass::Butterworth2;
use crate::soles::{sensor_to_sole, zmp_of_feet};
use crate::{EstimatedState, EstimationError, Estimator, FootEstimate, Readings};
use corps_model::spatial::{rotation, Force, Se3};
use corps_model::{
    center_of_mass, forward_kinematics, frame_placement, frame_velocity, Data, JointKind, Model,
    ReferenceFrame,
};
use nalgebra::{DVector, Matrix3, Vector3, Vector6};
use serde::{Deserialize, Serialize};
use std::sync::Arc;

/// Where the base pose and twist come from.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum BaseSource {
    /// Leg odometry from the feet in contact, fused with the IMU's orientation and rate.
    #[default]
    LegOdometry,
    /// The base pose and twist channels of the readings (motion capture; the simulator's
    /// exact state when the readings are its ground truth).
    Direct,
}

/// Settings of a [`KinematicEstimator`].
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct EstimatorSettings {
    pub base: BaseSource,
    /// Normal force (N) above which a foot enters contact.
    pub contact_on: f64,
    /// Normal force (N) below which a foot leaves contact (≤ `contact_on`).
    pub contact_off: f64,
    /// Gravity (world, m/s²) for the flight phases and the IMU's specific force.
    pub gravity: [f64; 3],
    /// Share of the feet's total normal force a foot in contact must carry before it anchors
    /// the odometry; until then (a landing foot that may still slide) it follows the estimate.
    pub settle_share: f64,
    /// Time constant (s) of the complementary filter on the base velocity: the IMU's
    /// acceleration below it, leg odometry above it (0: odometry alone).
    pub velocity_fusion_time: f64,
    /// The foot sensors read the weight of the foot below them (real sensors; a simulated
    /// contact sensor does not): remove it from each reading.
    pub calibrate_foot_weight: bool,
    /// Cutoff of the second-order Butterworth low-pass filter on each foot's wrench, as a
    /// fraction of the Nyquist frequency of the update rate; 0 (the default): none. Seed 002
    /// §4.12 filters at 0.4; on corps' IK stairs walk that delay in the contact detection
    /// makes TALOS fall (RESULTS.md), so it is an option, not the default.
    pub ft_lowpass: f64,
}

impl Default for EstimatorSettings {
    /// Contact thresholds 30 N on, 15 N off: above the F/T noise of a loaded foot and below
    /// the load of a foot that starts to carry the robot (this module's choice).
    fn default() -> Self {
        Self {
            base: BaseSource::LegOdometry,
            contact_on: 30.0,
            contact_off: 15.0,
            gravity: [0.0, 0.0, -corps_model::STANDARD_GRAVITY],
            velocity_fusion_time: 0.02,
            settle_share: 0.25,
            calibrate_foot_weight: false,
            ft_lowpass: 0.0,
        }
    }
}

impl EstimatorSettings {
    /// An error naming the setting that cannot work.
    pub fn check(&self) -> Result<(), EstimationError> {
        let ordered = self.contact_off >= 0.0 && self.contact_on >= self.contact_off;
        if !(ordered && self.contact_on.is_finite()) {
            return Err(EstimationError::Setup(format!(
                "contact_on ({}) and contact_off ({}) must be finite with 0 ≤ contact_off ≤ contact_on",
                self.contact_on, self.contact_off
            )));
        }
        if !(0.0..=1.0).contains(&self.settle_share) {
            return Err(EstimationError::Setup(format!(
                "settle_share must be in [0, 1], got {}",
                self.settle_share
            )));
        }
        if !(self.velocity_fusion_time >= 0.0 && self.velocity_fusion_time.is_finite()) {
            return Err(EstimationError::Setup(format!(
                "velocity_fusion_time must be finite and ≥ 0, got {}",
                self.velocity_fusion_time
            )));
        }
        if self.gravity.iter().any(|g| !g.is_finite()) {
            return Err(EstimationError::Setup("gravity must be finite".into()));
        }
        if !(0.0..1.0).contains(&self.ft_lowpass) {
            return Err(EstimationError::Setup(format!(
                "ft_lowpass must be in [0, 1) of the Nyquist frequency (0: no filter), got {}",
                self.ft_lowpass
            )));
        }
        Ok(())
    }
}

/// A foot the estimator watches: the F/T sensor above it and its sole frame.
#[derive(Clone, Debug, PartialEq)]
pub struct FootSensor {
    /// Index of the sensor in [`Readings::force_torque`].
    pub sensor: usize,
    /// Frame of the sensor in the model.
    pub sensor_frame: usize,
    /// Sole frame (z along the sole's normal, origin on the sole).
    pub sole_frame: usize,
}

/// A foot with its sensor's placement in the sole frame and its anchor.
#[derive(Clone, Debug)]
struct Foot {
    sensor: usize,
    /// Joint of the body carrying the sensor: its subtree hangs below the sensor.
    sensor_joint: usize,
    /// Low-pass filter of the sole-frame wrench (None: unfiltered).
    lowpass: Option<Butterworth2<6>>,
    sole_frame: usize,
    sole_m_sensor: Se3,
    /// Where the sole stays while the foot is settled (world).
    anchor: Option<Vector3<f64>>,
    /// Whether the foot carries enough of the load to anchor the odometry.
    settled: bool,
    /// This tick's sole position and velocity relative to the base point (world axes) and
    /// normal force.
    relative: Vector3<f64>,
    rate: Vector3<f64>,
    load: f64,
}

impl Foot {
    /// The foot of `f`: its sensor and its sole frame on one body.
    fn new(
        model: &Model,
        f: &FootSensor,
        settings: &EstimatorSettings,
    ) -> Result<Self, EstimationError> {
        let frame = |id: usize, what: &str| {
            model
                .frames
                .get(id)
                .ok_or_else(|| EstimationError::Setup(format!("{what}: no frame #{id}")))
        };
        let (sensor, sole) = (
            frame(f.sensor_frame, "F/T sensor")?,
            frame(f.sole_frame, "contact frame")?,
        );
        if sensor.parent_joint != sole.parent_joint || sole.parent_joint.is_none() {
            return Err(EstimationError::Setup(format!(
                "the F/T sensor frame '{}' and the contact frame '{}' are not on one body",
                sensor.name, sole.name
            )));
        }
        Ok(Foot {
            sensor: f.sensor,
            sensor_joint: sensor.parent_joint.unwrap_or(0),
            lowpass: (settings.ft_lowpass > 0.0).then(|| Butterworth2::new(settings.ft_lowpass)),
            sole_frame: f.sole_frame,
            sole_m_sensor: sole.placement.inverse() * sensor.placement,
            anchor: None,
            settled: false,
            relative: Vector3::zeros(),
            rate: Vector3::zeros(),
            load: 0.0,
        })
    }
}

/// Base from leg odometry and the IMU (or direct), feet and ZMP from the F/T sensors.
pub struct KinematicEstimator {
    model: Arc<Model>,
    data: Data,
    settings: EstimatorSettings,
    feet: Vec<Foot>,
    /// Hands whose wrench is read as the feet's (no anchor, no odometry).
    hands: Vec<Foot>,
    /// The IMU's joint and its placement in that joint's frame.
    imu: (usize, Se3),
    state: EstimatedState,
    /// Base velocity in world axes (for flight).
    base_velocity_world: Vector3<f64>,
    /// Time of the last update (None before the first).
    last_time: Option<f64>,
    zeros: DVector<f64>,
}

impl KinematicEstimator {
    /// An estimator of `model`'s state with `feet` and the IMU at frame `imu_frame`.
    pub fn new(
        model: Arc<Model>,
        feet: Vec<FootSensor>,
        imu_frame: usize,
        settings: EstimatorSettings,
    ) -> Result<Self, EstimationError> {
        settings.check()?;
        if !model.has_free_flyer() {
            return Err(EstimationError::Setup(
                "the robot has no floating base to estimate".into(),
            ));
        }
        let frame = |id: usize, what: &str| {
            model
                .frames
                .get(id)
                .ok_or_else(|| EstimationError::Setup(format!("{what}: no frame #{id}")))
        };
        let feet = feet
            .iter()
            .map(|f| Foot::new(&model, f, &settings))
            .collect::<Result<Vec<_>, _>>()?;
        let imu = frame(imu_frame, "IMU")?;
        let imu = (imu.parent_joint.unwrap_or(0), imu.placement);
        let state = EstimatedState {
            time: 0.0,
            q: corps_model::neutral(&model),
            v: DVector::zeros(model.nv),
            com: Vector3::zeros(),
            com_velocity: Vector3::zeros(),
            feet: feet
                .iter()
                .map(|_| FootEstimate {
                    placement: Se3::identity(),
                    wrench: Vector6::zeros(),
                    in_contact: false,
                })
                .collect(),
            zmp: None,
            hands: Vec::new(),
        };
        Ok(Self {
            data: Data::new(&model),
            zeros: DVector::zeros(model.nv),
            model,
            settings,
            feet,
            hands: Vec::new(),
            imu,
            state,
            base_velocity_world: Vector3::zeros(),
            last_time: None,
        })
    }

    /// Also reads `hands`: F/T sensors above a hand or a tool, each expressed in its contact
    /// frame (given as the [`FootSensor`]'s sole frame) with the same compensation of the
    /// weight below the sensor and the same filter as the feet; see [`EstimatedState::hands`].
    pub fn with_hands(mut self, hands: &[FootSensor]) -> Result<Self, EstimationError> {
        self.hands = hands
            .iter()
            .map(|h| Foot::new(&self.model, h, &self.settings))
            .collect::<Result<Vec<_>, _>>()?;
        self.state.hands = self
            .hands
            .iter()
            .map(|_| FootEstimate {
                placement: Se3::identity(),
                wrench: Vector6::zeros(),
                in_contact: false,
            })
            .collect();
        Ok(self)
    }

    /// Joint positions and velocities of the readings into the estimate's q and v.
    fn read_joints(&mut self, r: &Readings) -> Result<(), EstimationError> {
        let na = self.model.na();
        for (channel, got) in [
            ("joint_positions", r.joint_positions.len()),
            ("joint_velocities", r.joint_velocities.len()),
        ] {
            if got != na {
                return Err(EstimationError::Dimension {
                    channel,
                    got,
                    expected: na,
                });
            }
        }
        let (q, v) = (&mut self.state.q, &mut self.state.v);
        for j in self.model.joints.iter().filter(|j| j.idx_v >= 6) {
            let k = j.idx_v - 6;
            match j.kind {
                JointKind::RevoluteUnbounded { .. } => {
                    q[j.idx_q] = r.joint_positions[k].cos();
                    q[j.idx_q + 1] = r.joint_positions[k].sin();
                }
                _ => q[j.idx_q] = r.joint_positions[k],
            }
        }
        v.rows_mut(6, na).copy_from(&r.joint_velocities);
        Ok(())
    }

    /// Base orientation and rate from the IMU (step 2 of the module doc); leaves the base at
    /// the origin with no linear velocity.
    fn base_rotation_from_imu(&mut self, r: &Readings) -> Result<(), EstimationError> {
        let (q, v) = (&mut self.state.q, &mut self.state.v);
        q.as_mut_slice()[..7].copy_from_slice(&[0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0]);
        v.as_mut_slice()[..6].fill(0.0);
        kinematics(&self.model, &mut self.data, q, v, &self.zeros)?;
        let (joint, placement) = self.imu;
        let b_m_imu = self.data.o_m_i[joint] * placement;
        // The IMU body's rate relative to the base, in the IMU frame.
        let relative = placement.rotation.transpose() * self.data.v[joint].angular;
        let [x, y, z, w] = r.imu.orientation;
        let r_imu = rotation::quat_to_matrix(x, y, z, w);
        let r_base = r_imu * b_m_imu.rotation.transpose();
        let rate = b_m_imu.rotation * (Vector3::from(r.imu.angular_velocity) - relative);
        let quat = rotation::matrix_to_quat(&orthonormal(&r_base));
        q.as_mut_slice()[3..7].copy_from_slice(&quat);
        v.as_mut_slice()[3..6].copy_from_slice(rate.as_slice());
        Ok(())
    }

    /// Each foot's and hand's wrench in its contact frame and its contact state, from the F/T
    /// readings.
    fn read_feet(&mut self, r: &Readings) -> Result<(), EstimationError> {
        let (feet, hands) = (
            self.feet.iter_mut().zip(self.state.feet.iter_mut()),
            self.hands.iter_mut().zip(self.state.hands.iter_mut()),
        );
        for (foot, estimate) in feet.chain(hands) {
            let reading = r
                .force_torque
                .get(foot.sensor)
                .ok_or(EstimationError::Dimension {
                    channel: "force_torque",
                    got: r.force_torque.len(),
                    expected: foot.sensor + 1,
                })?;
            estimate.wrench = sensor_to_sole(&foot.sole_m_sensor, reading);
            if self.settings.calibrate_foot_weight {
                estimate.wrench -= weight_below(
                    &self.model,
                    &self.data,
                    foot.sensor_joint,
                    &estimate.placement,
                    &self.settings.gravity,
                );
            }
            if let Some(f) = &mut foot.lowpass {
                estimate.wrench = f.filter(&estimate.wrench);
            }
            let fz = estimate.wrench[2];
            estimate.in_contact = if estimate.in_contact {
                fz >= self.settings.contact_off
            } else {
                fz > self.settings.contact_on
            };
        }
        Ok(())
    }

    /// CoM, sole placements and ZMP at the estimated q, v.
    fn finish(&mut self) -> Result<(), EstimationError> {
        let s = &mut self.state;
        s.com = center_of_mass(
            &self.model,
            &mut self.data,
            s.q.as_slice(),
            s.v.as_slice(),
            self.zeros.as_slice(),
        )
        .map_err(|e| EstimationError::Setup(e.to_string()))?;
        s.com_velocity = self.data.vcom;
        let (feet, hands) = (
            self.feet.iter().zip(s.feet.iter_mut()),
            self.hands.iter().zip(s.hands.iter_mut()),
        );
        for (foot, estimate) in feet.chain(hands) {
            estimate.placement = frame_placement(&self.model, &self.data, foot.sole_frame)
                .map_err(|e| EstimationError::Setup(e.to_string()))?;
        }
        s.zmp = zmp_of_feet(&s.feet);
        Ok(())
    }
}

/// The gravity wrench, in the frame `sole` (world placement), of the body of `joint` and its
/// subtree at the placements of `data`: `Σ_k (m_k g, c_k × m_k g)`, moved from the world
/// origin to the sole. What a sensor above them reads of their weight.
fn weight_below(
    model: &Model,
    data: &Data,
    joint: usize,
    sole: &Se3,
    gravity: &[f64; 3],
) -> Vector6<f64> {
    let g = Vector3::from(*gravity);
    let mut f = Force::zero();
    for k in model.subtree_joints(joint) {
        let inertia = &model.inertias[k];
        let c = data.o_m_i[k].act_point(&inertia.lever);
        let w = g * inertia.mass;
        f += Force::new(w, c.cross(&w));
    }
    sole.act_inv_force(&f).to_vector()
}

/// Forward kinematics at (q, v, a = 0), with a model error as a setup error.
fn kinematics(
    model: &Model,
    data: &mut Data,
    q: &DVector<f64>,
    v: &DVector<f64>,
    zeros: &DVector<f64>,
) -> Result<(), EstimationError> {
    forward_kinematics(model, data, q.as_slice(), v.as_slice(), zeros.as_slice())
        .map_err(|e| EstimationError::Setup(e.to_string()))
}

/// The rotation nearest `r` when rounding has moved it off SO(3) (one Gram–Schmidt pass).
fn orthonormal(r: &Matrix3<f64>) -> Matrix3<f64> {
    let x = r.column(0).normalize();
    let y = (r.column(1) - x * x.dot(&r.column(1))).normalize();
    let z = x.cross(&y);
    Matrix3::from_columns(&[x, y, z])
}

/// Which channel of `r` is not finite, if one is.
fn non_finite(r: &Readings, base: BaseSource) -> Option<&'static str> {
    let finite = |x: &[f64]| x.iter().all(|v| v.is_finite());
    if !finite(r.joint_positions.as_slice()) {
        return Some("joint_positions");
    }
    if !finite(r.joint_velocities.as_slice()) {
        return Some("joint_velocities");
    }
    if !r.force_torque.iter().all(|w| finite(w)) {
        return Some("force_torque");
    }
    match base {
        BaseSource::LegOdometry => {
            if !finite(&r.imu.orientation) || !finite(&r.imu.angular_velocity) {
                return Some("imu");
            }
        }
        BaseSource::Direct => {
            if !finite(&r.base_pose) || !finite(&r.base_twist) {
                return Some("base_pose or base_twist");
            }
        }
    }
    None
}

impl Estimator for KinematicEstimator {
    fn reset(&mut self, q: &[f64], v: &[f64]) -> Result<(), EstimationError> {
        let (nq, nv) = (self.model.nq, self.model.nv);
        for (channel, got, expected) in [("q", q.len(), nq), ("v", v.len(), nv)] {
            if got != expected {
                return Err(EstimationError::Dimension {
                    channel,
                    got,
                    expected,
                });
            }
        }
        self.state.q.copy_from_slice(q);
        self.state.v.copy_from_slice(v);
        let r = rotation::quat_to_matrix(q[3], q[4], q[5], q[6]);
        self.base_velocity_world = r * Vector3::new(v[0], v[1], v[2]);
        for foot in self.feet.iter_mut().chain(self.hands.iter_mut()) {
            foot.anchor = None;
            foot.settled = false;
            if let Some(f) = &mut foot.lowpass {
                f.reset();
            }
        }
        self.last_time = None;
        self.finish()
    }

    fn update(&mut self, r: &Readings) -> Result<(), EstimationError> {
        if let Some(channel) = non_finite(r, self.settings.base) {
            return Err(EstimationError::NonFinite { channel });
        }
        let dt = self.last_time.map_or(0.0, |t| (r.time - t).max(0.0));
        self.last_time = Some(r.time);
        self.state.time = r.time;
        self.read_joints(r)?;
        self.read_feet(r)?;
        match self.settings.base {
            BaseSource::Direct => {
                self.state.q.as_mut_slice()[..7].copy_from_slice(&r.base_pose);
                self.state.v.as_mut_slice()[..6].copy_from_slice(&r.base_twist);
            }
            BaseSource::LegOdometry => {
                let previous = Vector3::new(self.state.q[0], self.state.q[1], self.state.q[2]);
                self.base_rotation_from_imu(r)?;
                let [x, y, z, w] = r.imu.orientation;
                let specific_force =
                    rotation::quat_to_matrix(x, y, z, w) * Vector3::from(r.imu.linear_acceleration);
                self.base_translation_from_feet(previous, dt, specific_force)?;
            }
        }
        self.finish()
    }

    fn state(&self) -> &EstimatedState {
        &self.state
    }
}

impl KinematicEstimator {
    /// Base position and velocity from the feet in contact (steps 3–4), with the base at the
    /// origin in q and its previous position `previous`.
    fn base_translation_from_feet(
        &mut self,
        previous: Vector3<f64>,
        dt: f64,
        imu_acceleration: Vector3<f64>,
    ) -> Result<(), EstimationError> {
        let (q, v) = (&self.state.q, &self.state.v);
        kinematics(&self.model, &mut self.data, q, v, &self.zeros)?;
        // Each foot in contact: its sole relative to the base point, its rate, its load.
        let mut total = 0.0;
        for (foot, estimate) in self.feet.iter_mut().zip(&self.state.feet) {
            if !estimate.in_contact {
                foot.anchor = None;
                foot.settled = false;
                continue;
            }
            let sole = frame_placement(&self.model, &self.data, foot.sole_frame)
                .map_err(|e| EstimationError::Setup(e.to_string()))?;
            let rate = frame_velocity(
                &self.model,
                &self.data,
                foot.sole_frame,
                ReferenceFrame::LocalWorldAligned,
            )
            .map_err(|e| EstimationError::Setup(e.to_string()))?;
            foot.relative = sole.translation;
            foot.rate = rate.linear;
            foot.load = estimate.wrench[2].max(0.0);
            total += foot.load;
        }
        // A foot settles once it carries its share; with none settled (a landing), all do.
        let contact = |f: &Foot, e: &FootEstimate| e.in_contact && f.load > 0.0;
        let share = self.settings.settle_share;
        for (foot, estimate) in self.feet.iter_mut().zip(&self.state.feet) {
            if contact(foot, estimate) && foot.load >= share * total {
                foot.settled = true;
            }
        }
        let any_settled =
            (self.feet.iter().zip(&self.state.feet)).any(|(f, e)| contact(f, e) && f.settled);
        let (mut weight, mut position, mut velocity) = (0.0, Vector3::zeros(), Vector3::zeros());
        for (foot, estimate) in self.feet.iter_mut().zip(&self.state.feet) {
            // With a foot settled, the others wait; with none, every foot in contact counts.
            let counts = foot.settled || !any_settled;
            if !(contact(foot, estimate) && counts) {
                continue;
            }
            foot.settled = true;
            let anchor = *foot.anchor.get_or_insert(previous + foot.relative);
            weight += foot.load;
            position += (anchor - foot.relative) * foot.load;
            velocity -= foot.rate * foot.load;
        }
        let g = Vector3::from(self.settings.gravity);
        let v0 = self.base_velocity_world;
        let acceleration = imu_acceleration + g;
        let (p, pdot) = if weight > 0.0 {
            let predicted = v0 + acceleration * dt;
            let t = self.settings.velocity_fusion_time;
            let k = if t + dt > 0.0 { dt / (t + dt) } else { 1.0 };
            (
                position / weight,
                predicted + (velocity / weight - predicted) * k,
            )
        } else {
            // No foot carries the robot: the IMU's acceleration alone.
            (
                previous + v0 * dt + acceleration * (0.5 * dt * dt),
                v0 + acceleration * dt,
            )
        };
        // Feet landing but not yet settled follow the estimate.
        for (foot, estimate) in self.feet.iter_mut().zip(&self.state.feet) {
            if estimate.in_contact && !foot.settled {
                foot.anchor = Some(p + foot.relative);
            }
        }
        self.base_velocity_world = pdot;
        let q = &self.state.q;
        let r_base = rotation::quat_to_matrix(q[3], q[4], q[5], q[6]);
        let local = r_base.transpose() * pdot;
        let (q, v) = (&mut self.state.q, &mut self.state.v);
        q.as_mut_slice()[..3].copy_from_slice(p.as_slice());
        v.as_mut_slice()[..3].copy_from_slice(local.as_slice());
        Ok(())
    }
}
