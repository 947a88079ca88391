//! Sensors, as ground truth and as measured (Gaussian noise and a constant bias per channel,
//! from a seeded generator, so every run is reproducible): joint encoders, joint velocities,
//! joint torques, 6-axis force/torque sensors, an IMU, the base pose and twist, and the contact
//! wrench on each body.

use crate::actuation::first_actuated;
use crate::error::{Result, SimError};
use crate::simulator::Simulator;
pub use corps_estimation::{ImuReading, Readings};
use corps_model::spatial::{exp6, rotation, Force, Motion, Se3};
use corps_model::{JointKind, Model};
use nalgebra::{DVector, Vector3};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal};
use serde::{Deserialize, Serialize};

/// Noise of one channel: standard deviation and constant bias, in the channel's unit.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Noise {
    pub std: f64,
    pub bias: f64,
}

/// Noise of every channel; all zero by default.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SensorNoise {
    pub encoders: Noise,
    pub joint_velocities: Noise,
    pub joint_torques: Noise,
    pub force: Noise,
    pub torque: Noise,
    pub imu_orientation: Noise,
    pub imu_angular_velocity: Noise,
    pub imu_linear_acceleration: Noise,
    pub base_position: Noise,
    pub base_orientation: Noise,
    pub base_linear_velocity: Noise,
    pub base_angular_velocity: Noise,
}

impl SensorNoise {
    /// Every channel with its name, as in the scenario file.
    pub fn channels(&self) -> [(&'static str, Noise); 12] {
        [
            ("encoders", self.encoders),
            ("joint_velocities", self.joint_velocities),
            ("joint_torques", self.joint_torques),
            ("force", self.force),
            ("torque", self.torque),
            ("imu_orientation", self.imu_orientation),
            ("imu_angular_velocity", self.imu_angular_velocity),
            ("imu_linear_acceleration", self.imu_linear_acceleration),
            ("base_position", self.base_position),
            ("base_orientation", self.base_orientation),
            ("base_linear_velocity", self.base_linear_velocity),
            ("base_angular_velocity", self.base_angular_velocity),
        ]
    }
}

/// What a force/torque sensor reads.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ForceTorqueModel {
    /// The contact wrench on its body alone, as Gazebo's contact sensor that seed 000's
    /// simulations read.
    #[default]
    Contact,
    /// The wrench passed through the sensor, as a real one: the contact plus the weight and
    /// inertia of the body carrying it and that body's subtree ([`transmitted_wrench`]).
    Transmitted,
}

/// Where the sensors are: F/T sensor frames (name → frame) and the IMU frame.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SensorLayout {
    /// Named force/torque sensors and the frame each measures in.
    pub force_torque: Vec<(String, String)>,
    /// What they read.
    pub force_torque_model: ForceTorqueModel,
    /// Frame of the IMU (None: the root body).
    pub imu: Option<String>,
}

impl SensorLayout {
    /// The sensors a robot's description lists, reading as `force_torque_model` says.
    pub fn of(robot: &corps_robot::Robot, force_torque_model: ForceTorqueModel) -> Self {
        Self {
            force_torque: robot.force_torque.clone(),
            force_torque_model,
            imu: robot.imu.clone(),
        }
    }
}

/// The wrench a force/torque sensor on body `joint` measures (world frame, at the origin):
/// what the part of the robot beyond it — that body and its subtree — passes through it,
/// `Σ_k (f_contact,k − (I_k a_k + v_k ×* I_k v_k))`, with ABA's accelerations, which hold −g
/// (Featherstone's RNEA force on a subtree). So a foot's sensor reads the contact wrench plus
/// the foot's own weight and inertia, as a real ankle sensor does: in the air, the foot's
/// weight hanging from it.
fn transmitted_wrench(
    model: &Model,
    data: &corps_model::Data,
    contact: &[Force],
    joint: usize,
) -> Force {
    let mut f = Force::zero();
    for k in model.subtree_joints(joint) {
        let inertia = model.inertias[k].transformed(&data.o_m_i[k]);
        let momentum = inertia.mul_motion(&data.ov[k]);
        let inertial = inertia.mul_motion(&data.oa[k]) + data.ov[k].cross_force(&momentum);
        f += contact[k] - inertial;
    }
    f
}

/// What sensors read of a plant's state.
pub struct SensorInput<'a> {
    /// Plant time (s).
    pub time: f64,
    /// Configuration (size nq).
    pub q: &'a [f64],
    /// Velocity (size nv).
    pub v: &'a [f64],
    /// Joint torques applied over the last period (size nv; the free-flyer's entries unused).
    pub applied_torques: &'a [f64],
    /// Kinematics at this state: `o_m_i`, and the world twists `ov` and accelerations `oa`
    /// (gravity field included) that [`corps_model::aba_with_external_forces`] leaves.
    pub data: &'a corps_model::Data,
    /// The contact wrench on each joint's body (world frame, moment about the origin).
    pub body_wrenches: &'a [Force],
}

/// A plant's sensors: encoders, joint torques, F/T sensors, IMU, base pose, with seeded noise.
#[derive(Clone)]
pub struct Sensors {
    layout: Vec<(String, usize, Se3)>,
    force_torque_model: ForceTorqueModel,
    imu: (usize, Se3),
    noise: SensorNoise,
    rng: ChaCha8Rng,
    truth: Readings,
    measured: Readings,
}

impl Sensors {
    /// Sensors for `model` with `layout` and `noise`, seeded with `seed`. Unknown frames are an
    /// error naming the sensor.
    pub fn new(
        model: &Model,
        layout: &SensorLayout,
        noise: SensorNoise,
        seed: u64,
    ) -> Result<Self> {
        let place = |name: &str, frame: &str| -> Result<(usize, Se3)> {
            let fid = model.frame_id(frame).map_err(|e| SimError::Setting {
                name: format!("sensor '{name}'"),
                reason: e.to_string(),
            })?;
            let f = &model.frames[fid];
            let joint = f.parent_joint.ok_or_else(|| SimError::Setting {
                name: format!("sensor '{name}'"),
                reason: "frame fixed to the world".into(),
            })?;
            Ok((joint, f.placement))
        };
        let mut ft = Vec::new();
        for (name, frame) in &layout.force_torque {
            let (j, p) = place(name, frame)?;
            ft.push((name.clone(), j, p));
        }
        let imu = match &layout.imu {
            Some(frame) => place("imu", frame)?,
            None => (0, Se3::identity()),
        };
        for (name, x) in noise.channels() {
            if !(x.std >= 0.0 && x.std.is_finite() && x.bias.is_finite()) {
                return Err(SimError::Setting {
                    name: format!("noise.{name}"),
                    reason: "std must be ≥ 0 and finite, bias finite".into(),
                });
            }
        }
        let na = model.nv - first_actuated(model);
        let readings = Readings {
            joint_positions: DVector::zeros(na),
            joint_velocities: DVector::zeros(na),
            joint_torques: DVector::zeros(na),
            force_torque: vec![[0.0; 6]; ft.len()],
            contact_wrenches: vec![[0.0; 6]; model.njoints()],
            ..Readings::default()
        };
        Ok(Self {
            layout: ft,
            force_torque_model: layout.force_torque_model,
            imu,
            noise,
            rng: ChaCha8Rng::seed_from_u64(seed),
            truth: readings.clone(),
            measured: readings,
        })
    }

    /// Names of the F/T sensors, in reading order.
    pub fn force_torque_names(&self) -> impl Iterator<Item = &str> {
        self.layout.iter().map(|(n, _, _)| n.as_str())
    }

    /// Ground truth at the simulator's current state.
    pub fn truth(&self) -> &Readings {
        &self.truth
    }

    /// Measured values (truth + noise + bias), drawn once per `update`.
    pub fn measured(&self) -> &Readings {
        &self.measured
    }

    /// Reads the simulator (call after each step). Allocation-free.
    pub fn update(&mut self, sim: &Simulator) {
        let input = SensorInput {
            time: sim.time(),
            q: sim.q().as_slice(),
            v: sim.v().as_slice(),
            applied_torques: sim.applied_torques().as_slice(),
            data: sim.data(),
            body_wrenches: &sim.contact().body_wrenches,
        };
        self.update_from(sim.model(), &input);
    }

    /// Reads a plant's state (any plant: the simulator, another engine). Allocation-free.
    pub fn update_from(&mut self, model: &Model, input: &SensorInput<'_>) {
        let (q, v, data) = (input.q, input.v, input.data);
        let first = first_actuated(model);
        let na = model.nv - first;
        let t = &mut self.truth;
        t.time = input.time;
        for j in &model.joints {
            if j.idx_v < first {
                continue;
            }
            let k = j.idx_v - first;
            t.joint_positions[k] = match j.kind {
                JointKind::RevoluteUnbounded { .. } => q[j.idx_q + 1].atan2(q[j.idx_q]),
                _ => q[j.idx_q],
            };
        }
        t.joint_velocities
            .as_mut_slice()
            .copy_from_slice(&v[first..first + na]);
        t.joint_torques
            .as_mut_slice()
            .copy_from_slice(&input.applied_torques[first..first + na]);
        let wrenches = input.body_wrenches;
        for ((_, joint, placement), out) in self.layout.iter().zip(t.force_torque.iter_mut()) {
            let o_m_s = data.o_m_i[*joint] * *placement;
            let read = match self.force_torque_model {
                ForceTorqueModel::Contact => wrenches[*joint],
                ForceTorqueModel::Transmitted => transmitted_wrench(model, data, wrenches, *joint),
            };
            *out = force6(&o_m_s.act_inv_force(&read));
        }
        for (w, out) in wrenches.iter().zip(t.contact_wrenches.iter_mut()) {
            *out = force6(w);
        }
        // IMU: proper acceleration of its point. ABA's world accelerations already hold −g.
        let (ij, ip) = self.imu;
        let o_m_imu = data.o_m_i[ij] * ip;
        let (ov, oa): (Motion, Motion) = (data.ov[ij], data.oa[ij]);
        let p = o_m_imu.translation;
        let vp = ov.point_velocity(&p);
        let acc = oa.point_velocity(&p) + ov.angular.cross(&vp);
        let r = o_m_imu.rotation;
        t.imu = ImuReading {
            orientation: rotation::matrix_to_quat(&r),
            angular_velocity: (r.transpose() * ov.angular).into(),
            linear_acceleration: (r.transpose() * acc).into(),
        };
        if model.has_free_flyer() {
            t.base_pose.copy_from_slice(&q[..7]);
            t.base_twist.copy_from_slice(&v[..6]);
        }
        self.measured.copy_from(&self.truth);
        self.add_noise();
    }

    fn add_noise(&mut self) {
        let n = &self.noise;
        let rng = &mut self.rng;
        let mut draw = |x: &mut f64, c: Noise| {
            if c.std > 0.0 {
                *x += Normal::new(0.0, c.std)
                    .map(|d| d.sample(rng))
                    .unwrap_or(0.0);
            }
            *x += c.bias;
        };
        let m = &mut self.measured;
        m.joint_positions
            .iter_mut()
            .for_each(|x| draw(x, n.encoders));
        m.joint_velocities
            .iter_mut()
            .for_each(|x| draw(x, n.joint_velocities));
        m.joint_torques
            .iter_mut()
            .for_each(|x| draw(x, n.joint_torques));
        for w in &mut m.force_torque {
            w[..3].iter_mut().for_each(|x| draw(x, n.force));
            w[3..].iter_mut().for_each(|x| draw(x, n.torque));
        }
        m.imu
            .angular_velocity
            .iter_mut()
            .for_each(|x| draw(x, n.imu_angular_velocity));
        m.imu
            .linear_acceleration
            .iter_mut()
            .for_each(|x| draw(x, n.imu_linear_acceleration));
        m.imu.orientation = perturb_quat(m.imu.orientation, n.imu_orientation, &mut draw);
        m.base_pose[..3]
            .iter_mut()
            .for_each(|x| draw(x, n.base_position));
        let q: [f64; 4] = m.base_pose[3..].try_into().unwrap_or([0.0, 0.0, 0.0, 1.0]);
        if q != [0.0; 4] {
            m.base_pose[3..].copy_from_slice(&perturb_quat(q, n.base_orientation, &mut draw));
        }
        m.base_twist[..3]
            .iter_mut()
            .for_each(|x| draw(x, n.base_linear_velocity));
        m.base_twist[3..]
            .iter_mut()
            .for_each(|x| draw(x, n.base_angular_velocity));
    }
}

fn force6(f: &Force) -> [f64; 6] {
    [
        f.linear.x,
        f.linear.y,
        f.linear.z,
        f.angular.x,
        f.angular.y,
        f.angular.z,
    ]
}

/// Rotates quaternion `q` by a small random rotation whose components have the channel's noise.
fn perturb_quat(q: [f64; 4], c: Noise, draw: &mut impl FnMut(&mut f64, Noise)) -> [f64; 4] {
    if c.std == 0.0 && c.bias == 0.0 {
        return q;
    }
    let mut w = [0.0; 3];
    w.iter_mut().for_each(|x| draw(x, c));
    let r = rotation::quat_to_matrix(q[0], q[1], q[2], q[3])
        * exp6(&Motion::new(Vector3::zeros(), Vector3::from(w))).rotation;
    rotation::matrix_to_quat(&r)
}
