//! Position-command compensation of a joint flexibility the model lacks (seed 000 App. 4,
//! Eq 6.3): `q_cmd = q_des + Δq`, `Δq = τ / K` on the actuated joint turning about the
//! flexible axis, `τ` the torque that joint carries.
//!
//! `τ` is estimated without a joint torque sensor, from the statics of the leg below the
//! joint: the leg carries its own weight and its foot's measured contact wrench, so the joint
//! holds `τ_j = −a_j · Σ (moments about p_j of the leg's weights and of the foot wrench)`
//! (a_j the joint axis, p_j its origin, world frame). Two modes:
//! - **model**: Δq = τ̂ / K, τ̂ low-passed (the flexibility's spring `τ_f = −kθ` known to the
//!   controller, Eq 6.4 in statics);
//! - **fixed**: Δq = ±offset scaled by the leg's share of the vertical load, on the joints
//!   about which the body hanging beside the hip weighs most (within half of the leg's
//!   largest lever: a biped's hip roll joints): the thesis's constant 0.021 rad = 20 N·m /
//!   973 N·m/rad.
//!
//! The offset goes to the actuated joint about the flexibility's axis; where the flexibility
//! sits above another joint (TALOS' hip, above the hip yaw) the two axes coincide only while
//! that joint is at zero, and the estimate leaves out the bodies between them.

use crate::error::{ControlError, Result};
use crate::stabilizer::Wrench;
use corps_model::{forward_kinematics_placements, Data, JointKind, Model};
use nalgebra::{Isometry3, Vector3};

/// How the deflection is estimated.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum CompensationMode {
    /// A constant offset (rad), scaled by the leg's share of the load.
    Fixed { offset: f64 },
    /// τ̂ / K, τ̂ through a first-order low-pass of time constant `filter` (s, 0: none).
    Model { filter: f64 },
}

/// A joint to compensate: an actuated one-axis joint of the model and the stiffness of the
/// flexibility about its axis.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CompensatedJoint {
    pub joint: usize,
    /// K, N·m/rad.
    pub stiffness: f64,
}

#[derive(Clone, Debug)]
struct Entry {
    joint: usize,
    idx_q: usize,
    stiffness: f64,
    /// Index of the foot (in the `feet` given to `new`) below the joint.
    foot: usize,
    /// Axis in the joint frame.
    axis: Vector3<f64>,
    /// Direction of the deflection under load for the fixed mode (0: not offset there); the
    /// lever (m) while building.
    sign: f64,
    /// Filtered torque estimate, N·m.
    torque: f64,
    offset: f64,
}

/// The compensation of a set of joints: [`FlexibilityCompensation::update`] each tick, then
/// [`FlexibilityCompensation::apply`] to the position command.
#[derive(Clone, Debug)]
pub struct FlexibilityCompensation {
    mode: CompensationMode,
    entries: Vec<Entry>,
    data: Data,
    gravity: f64,
    started: bool,
}

impl FlexibilityCompensation {
    /// `feet`: the sole frames, one per foot; each joint must carry exactly one of them.
    /// `posture`: a standing configuration (the fixed mode's joints and signs, from the
    /// root's position about each joint's axis).
    pub fn new(
        model: &Model,
        joints: &[CompensatedJoint],
        feet: &[usize],
        posture: &[f64],
        mode: CompensationMode,
        gravity: f64,
    ) -> Result<Self> {
        let bad = |name: String, reason: String| ControlError::Config { name, reason };
        match mode {
            CompensationMode::Fixed { offset } if !offset.is_finite() => {
                return Err(bad("compensation offset".into(), format!("{offset}")))
            }
            CompensationMode::Model { filter } if !(filter.is_finite() && filter >= 0.0) => {
                return Err(bad("compensation filter".into(), format!("{filter} s")))
            }
            _ => {}
        }
        let mut data = Data::new(model);
        forward_kinematics_placements(model, &mut data, posture)?;
        let root = data.o_m_i[0].translation;
        let mut entries = Vec::with_capacity(joints.len());
        for c in joints {
            let Some(joint) = model.joints.get(c.joint) else {
                return Err(bad(
                    "compensated joint".into(),
                    format!("no joint {}", c.joint),
                ));
            };
            let name = format!("compensated joint '{}'", joint.name);
            let axis = match joint.kind {
                JointKind::Revolute { axis } => axis,
                _ => return Err(bad(name, "must be a revolute joint".into())),
            };
            if !(c.stiffness.is_finite() && c.stiffness > 0.0) {
                return Err(bad(
                    name,
                    format!("stiffness {} (must be > 0)", c.stiffness),
                ));
            }
            let below: Vec<usize> = (feet.iter().enumerate())
                .filter(|(_, &f)| {
                    (model.frames.get(f).and_then(|fr| fr.parent_joint))
                        .is_some_and(|pj| model.supports(c.joint, pj))
                })
                .map(|(k, _)| k)
                .collect();
            let [foot] = below[..] else {
                return Err(bad(
                    name,
                    format!("carries {} feet (must carry one)", below.len()),
                ));
            };
            let placement = data.o_m_i[c.joint];
            let a = placement.rotation * axis;
            let r = root - placement.translation;
            // The moment about the axis of a weight at the root, per newton: the sign of the
            // joint's torque when its leg carries the body hanging beside it.
            let lever = -a.dot(&Vector3::new(r.y, -r.x, 0.0));
            entries.push(Entry {
                joint: c.joint,
                idx_q: joint.idx_q,
                stiffness: c.stiffness,
                foot,
                axis,
                sign: lever,
                torque: 0.0,
                offset: 0.0,
            });
        }
        // The fixed offset goes to the joints of each leg whose lever is at least half the
        // leg's largest (the axis across the hip's sideways offset: the roll joints of a
        // biped whose hips sit beside the waist), with the lever's sign.
        let levers: Vec<(usize, f64)> = entries.iter().map(|e| (e.foot, e.sign)).collect();
        for e in &mut entries {
            let largest = (levers.iter())
                .filter(|(foot, _)| *foot == e.foot)
                .fold(0.0f64, |m, (_, l)| m.max(l.abs()));
            e.sign = if largest > 0.0 && e.sign.abs() >= 0.5 * largest {
                e.sign.signum()
            } else {
                0.0
            };
        }
        Ok(Self {
            mode,
            entries,
            data,
            gravity,
            started: false,
        })
    }

    /// Updates the offsets from configuration `q` (the controller's), the feet's sole
    /// placements and their measured ground-on-foot wrenches (sole frame, about its origin),
    /// over a control period `dt`.
    pub fn update(
        &mut self,
        model: &Model,
        q: &[f64],
        feet: &[Isometry3<f64>],
        wrenches: &[Wrench],
        dt: f64,
    ) -> Result<()> {
        if q.iter().any(|x| !x.is_finite()) {
            return Err(ControlError::NonFinite("configuration"));
        }
        forward_kinematics_placements(model, &mut self.data, q)?;
        let total_fz: f64 = wrenches.iter().map(|w| w.force.z.max(0.0)).sum();
        let g = Vector3::new(0.0, 0.0, -self.gravity);
        for e in &mut self.entries {
            let (Some(sole), Some(w)) = (feet.get(e.foot), wrenches.get(e.foot)) else {
                continue;
            };
            if !(w.force.iter().chain(w.torque.iter()).all(|x| x.is_finite())) {
                continue;
            }
            let placement = self.data.o_m_i[e.joint];
            let (p, a) = (placement.translation, placement.rotation * e.axis);
            let mut moment = Vector3::zeros();
            for b in model.subtree_joints(e.joint) {
                let inertia = &model.inertias[b];
                let c = self.data.o_m_i[b].act_point(&inertia.lever);
                moment += (c - p).cross(&(g * inertia.mass));
            }
            let f = sole.rotation * w.force;
            let n = sole.rotation * w.torque;
            moment += (sole.translation.vector - p).cross(&f) + n;
            let torque = -a.dot(&moment);
            match self.mode {
                CompensationMode::Model { filter } => {
                    let alpha = if filter > 0.0 && self.started {
                        (dt / (filter + dt)).min(1.0)
                    } else {
                        1.0
                    };
                    e.torque += alpha * (torque - e.torque);
                    e.offset = e.torque / e.stiffness;
                }
                CompensationMode::Fixed { offset } => {
                    e.torque = torque;
                    let share = if total_fz > 1e-6 {
                        (w.force.z.max(0.0) / total_fz).clamp(0.0, 1.0)
                    } else {
                        0.0
                    };
                    e.offset = offset * e.sign * share;
                }
            }
        }
        self.started = true;
        Ok(())
    }

    /// Adds the offsets to the position command `q_ref` (a configuration of the model).
    pub fn apply(&self, q_ref: &mut [f64]) {
        for e in &self.entries {
            if let Some(x) = q_ref.get_mut(e.idx_q) {
                *x += e.offset;
            }
        }
    }

    /// The current offsets (rad) and torque estimates (N·m), in the joints' order.
    pub fn offsets(&self) -> impl Iterator<Item = (f64, f64)> + '_ {
        self.entries.iter().map(|e| (e.offset, e.torque))
    }
}

/// The ground-on-foot wrenches a plan implies (sole frames, about each sole's origin), for a
/// compensation that needs no force sensor: the whole robot's `m (c̈ − g)` through the
/// reference ZMP `zmp` (world x, y, on the supporting soles' plane), all on the one
/// supporting foot, or split between two along the segment joining their origins (the
/// share of each foot from where the ZMP projects on it). `gravity` > 0 points down.
pub fn planned_wrenches(
    mass: f64,
    gravity: f64,
    com_acc: &Vector3<f64>,
    zmp: [f64; 2],
    feet: &[Isometry3<f64>; 2],
    supporting: [bool; 2],
) -> [Wrench; 2] {
    let zero = Wrench::new(Vector3::zeros(), Vector3::zeros());
    let total = Vector3::new(
        mass * com_acc.x,
        mass * com_acc.y,
        mass * (gravity + com_acc.z),
    );
    let p = feet.map(|f| f.translation.vector);
    let (shares, base) = match supporting {
        [true, true] => {
            let d = p[1] - p[0];
            let dxy = d.xy();
            let lambda = if dxy.norm_squared() > 1e-12 {
                ((Vector3::new(zmp[0], zmp[1], 0.0) - p[0]).xy().dot(&dxy) / dxy.norm_squared())
                    .clamp(0.0, 1.0)
            } else {
                0.5
            };
            ([1.0 - lambda, lambda], p[0] + d * lambda)
        }
        [true, false] => ([1.0, 0.0], p[0]),
        [false, true] => ([0.0, 1.0], p[1]),
        [false, false] => return [zero, zero],
    };
    let shift = Vector3::new(zmp[0] - base.x, zmp[1] - base.y, 0.0);
    [0, 1].map(|k| {
        if shares[k] == 0.0 {
            return zero;
        }
        let f = total * shares[k];
        let r = feet[k].rotation.inverse();
        Wrench::new(r * f, r * shift.cross(&f))
    })
}
