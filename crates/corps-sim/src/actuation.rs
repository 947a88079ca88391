//! Actuation modes: joint torques, joint positions through a PD servo (TALOS' high-gain
//! position control) or a PID servo with clamps (as Gazebo's joint position controllers),
//! joint velocities. Torques are always clamped at the URDF effort limits.

use crate::drive::{Drives, FlexibleDrive};
use crate::error::{Result, SimError};
use corps_model::{difference_to, Data, Model};
use nalgebra::DVector;

pub use corps_loop::Command;

/// Hard-ish stops at the URDF position limits, as Gazebo's joints have: past a limit a joint
/// feels `τ = −k (q − limit) − d q̇` (the implicit step takes both as it takes a servo's).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct JointStops {
    /// N·m/rad (N/m for a prismatic joint).
    pub stiffness: f64,
    /// N·m·s/rad.
    pub damping: f64,
}

/// Per-joint PD gains of the servo (size na each), and optionally an integral term.
#[derive(Clone, Debug, PartialEq)]
pub struct ServoGains {
    pub kp: DVector<f64>,
    pub kd: DVector<f64>,
    /// The integral term and clamps of a PID servo (position commands only).
    pub integral: Option<IntegralTerm>,
}

/// The integral part of a PID position servo, per actuated joint (size na each), as ROS'
/// `control_toolbox::Pid` behind Gazebo's position controllers: the integral torque
/// `τ_i ← clamp(τ_i + ki e dt, ±i_clamp)` advances once per control period, and the servo's
/// whole torque `kp e + kd ė + τ_i` is clamped at `torque_clamp` (then the effort limit).
#[derive(Clone, Debug, PartialEq)]
pub struct IntegralTerm {
    pub ki: DVector<f64>,
    pub i_clamp: DVector<f64>,
    pub torque_clamp: DVector<f64>,
}

impl ServoGains {
    /// A stiff position servo, as TALOS' high-gain joint position control: each joint reaches
    /// its effort limit at an error of `saturation_angle` (kp = τ_max / θ_sat) and is damped
    /// with ratio `damping_ratio` on the inertia it actually feels, the apparent inertia
    /// m_j = 1 / (M⁻¹)_jj (every other joint free): kd = 2 ζ √(kp m_j). Sizing the damping on
    /// the diagonal M_jj instead over-damps joints whose neighbours move with them (TALOS'
    /// arm_3: M_jj = 0.086, m_j = 0.009 kg·m²) and drives RK4 at 1 ms past its stability
    /// boundary (the arms then drift at a spurious constant speed).
    pub fn high_gain(
        model: &Model,
        q: &[f64],
        saturation_angle: f64,
        damping_ratio: f64,
    ) -> Result<ServoGains> {
        if !(saturation_angle > 0.0 && saturation_angle.is_finite()) {
            return Err(SimError::Setting {
                name: "servo saturation angle".into(),
                reason: format!("{saturation_angle} rad"),
            });
        }
        if !(damping_ratio >= 0.0 && damping_ratio.is_finite()) {
            return Err(SimError::Setting {
                name: "servo damping ratio".into(),
                reason: format!("{damping_ratio}"),
            });
        }
        let mut data = Data::new(model);
        let minv = corps_model::compute_minverse_factorized(model, &mut data, q)?;
        let first = first_actuated(model);
        let na = model.nv - first;
        let kp = DVector::from_fn(na, |k, _| {
            let effort = model.effort_limit[first + k];
            if effort.is_finite() {
                effort / saturation_angle
            } else {
                0.0
            }
        });
        let kd = DVector::from_fn(na, |k, _| {
            let apparent = 1.0 / minv[(first + k, first + k)];
            2.0 * damping_ratio * (kp[k] * apparent).sqrt()
        });
        Ok(ServoGains {
            kp,
            kd,
            integral: None,
        })
    }

    /// Gains giving each joint, alone, a critically damped response at `bandwidth_hz`, scaled
    /// by its diagonal of M(q): kp = M_ii ω², kd = 2 M_ii ω. Scaling by inertia keeps light
    /// joints (grippers) as stable as heavy ones at a 1 ms step.
    pub fn from_bandwidth(model: &Model, q: &[f64], bandwidth_hz: f64) -> Result<ServoGains> {
        if !(bandwidth_hz > 0.0 && bandwidth_hz.is_finite()) {
            return Err(SimError::Setting {
                name: "servo bandwidth".into(),
                reason: format!("{bandwidth_hz} Hz"),
            });
        }
        let mut data = Data::new(model);
        let m = corps_model::crba(model, &mut data, q)?;
        let w = std::f64::consts::TAU * bandwidth_hz;
        let first = first_actuated(model);
        let diag = DVector::from_fn(model.nv - first, |k, _| m[(first + k, first + k)]);
        Ok(ServoGains {
            kp: &diag * (w * w),
            kd: &diag * (2.0 * w),
            integral: None,
        })
    }
}

/// Index of the first actuated velocity entry (6 with a free-flyer, else 0).
pub fn first_actuated(model: &Model) -> usize {
    model.first_actuated()
}

/// Workspace that turns a command into joint torques at a given state.
#[derive(Clone, Debug)]
pub struct Actuators {
    pub gains: ServoGains,
    error: DVector<f64>,
    /// The PID servo's integral torque per actuated joint (zero without one).
    integral: DVector<f64>,
    first: usize,
    /// Flexible drives of torque commands (None: ideal torques everywhere).
    drives: Option<Drives>,
    /// Per actuated joint, its index in q (drives need one-dof joints).
    drive_q: Vec<usize>,
    /// How the drives' torques are taken: `lead` s into an explicit step (the motors move
    /// on meanwhile), or at the end of a linearly implicit step of `implicit_step` s.
    drive_lead: f64,
    implicit_step: Option<f64>,
    /// Passive spring-dampers `τ = −k q − d q̇` (seed 000 Eq 6.4): (actuated index, index in
    /// q, k, d). They take no command.
    passive: Vec<(usize, usize, f64, f64)>,
    /// Joint stops: their gains, and per limited one-dof actuated joint (actuated index,
    /// index in q, lower, upper) with whether it is past a limit now.
    stops: Option<JointStops>,
    stop_joints: Vec<(usize, usize, f64, f64)>,
    stop_active: Vec<bool>,
    /// The stops' torque of the last [`Actuators::torques`], per actuated joint.
    stop_torque: Vec<f64>,
    /// The actuated joints' positions, velocities and torque command (scratch).
    q_a: Vec<f64>,
    v_a: Vec<f64>,
    tau_a: Vec<f64>,
}

impl Actuators {
    pub fn new(model: &Model, gains: ServoGains) -> Self {
        let first = first_actuated(model);
        let na = model.nv - first;
        Self {
            gains,
            error: DVector::zeros(model.nv),
            integral: DVector::zeros(na),
            first,
            drives: None,
            drive_q: Vec::new(),
            drive_lead: 0.0,
            implicit_step: None,
            passive: Vec::new(),
            stops: None,
            stop_joints: Vec::new(),
            stop_active: Vec::new(),
            stop_torque: Vec::new(),
            q_a: vec![0.0; na],
            v_a: vec![0.0; na],
            tau_a: vec![0.0; na],
        }
    }

    /// Puts a flexible drive on the actuated joints given one (`drives[k]` for actuated
    /// joint `k`; None keeps an ideal torque). Only one-dof joints take a drive.
    pub fn set_drives(&mut self, model: &Model, drives: Vec<Option<FlexibleDrive>>) -> Result<()> {
        let f = self.first;
        let na = model.nv - f;
        if drives.len() != na {
            return Err(SimError::Setting {
                name: "drives".into(),
                reason: format!("{} entries for {na} actuated joints", drives.len()),
            });
        }
        let mut names = Vec::with_capacity(na);
        let mut drive_q = Vec::with_capacity(na);
        for (k, drive) in drives.iter().enumerate() {
            let joint = &model.joints[model.dof_joint[f + k]];
            names.push(joint.name.clone());
            drive_q.push(joint.idx_q);
            if drive.is_some() && (joint.nq() != 1 || joint.nv() != 1) {
                return Err(SimError::Setting {
                    name: format!("drive of {}", joint.name),
                    reason: "a flexible drive needs a one-dof joint".into(),
                });
            }
        }
        self.drives = if drives.iter().any(Option::is_some) {
            Some(Drives::new(drives, &names)?)
        } else {
            None
        };
        self.drive_q = drive_q;
        Ok(())
    }

    /// Makes the one-dof joints `joints` (model joint index, k in N·m/rad, d in N·m·s/rad)
    /// passive spring-dampers, `τ = −k q − d q̇`, whatever the command says of them.
    pub fn set_passive(&mut self, model: &Model, joints: &[(usize, f64, f64)]) -> Result<()> {
        let mut passive = Vec::with_capacity(joints.len());
        for &(j, k, d) in joints {
            let Some(joint) = model.joints.get(j) else {
                return Err(SimError::Setting {
                    name: "passive joint".into(),
                    reason: format!("no joint {j}"),
                });
            };
            let bad = |reason: String| SimError::Setting {
                name: format!("passive joint {}", joint.name),
                reason,
            };
            if joint.nq() != 1 || joint.nv() != 1 || joint.idx_v < self.first {
                return Err(bad("must be a one-dof joint below the root".into()));
            }
            if !(k.is_finite() && k > 0.0) {
                return Err(bad(format!("stiffness {k} (must be finite and > 0)")));
            }
            if !(d.is_finite() && d >= 0.0) {
                return Err(bad(format!("damping {d} (must be finite and ≥ 0)")));
            }
            passive.push((joint.idx_v - self.first, joint.idx_q, k, d));
        }
        self.passive = passive;
        Ok(())
    }

    /// Puts stops at the position limits of every one-dof actuated joint with finite limits.
    pub fn set_stops(&mut self, model: &Model, stops: Option<JointStops>) -> Result<()> {
        if let Some(st) = stops {
            if !(st.stiffness.is_finite() && st.stiffness > 0.0) {
                return Err(SimError::Setting {
                    name: "joint_stops.stiffness".into(),
                    reason: format!("{} (must be finite and > 0)", st.stiffness),
                });
            }
            if !(st.damping.is_finite() && st.damping >= 0.0) {
                return Err(SimError::Setting {
                    name: "joint_stops.damping".into(),
                    reason: format!("{} (must be finite and ≥ 0)", st.damping),
                });
            }
        }
        self.stops = stops;
        self.stop_joints.clear();
        if stops.is_some() {
            for joint in &model.joints {
                let (lo, up) = (
                    model.lower_position_limit.get(joint.idx_q).copied(),
                    model.upper_position_limit.get(joint.idx_q).copied(),
                );
                if joint.nq() != 1 || joint.nv() != 1 || joint.idx_v < self.first {
                    continue;
                }
                if let (Some(lo), Some(up)) = (lo, up) {
                    if lo.is_finite() && up.is_finite() && lo < up {
                        self.stop_joints
                            .push((joint.idx_v - self.first, joint.idx_q, lo, up));
                    }
                }
            }
        }
        self.stop_active = vec![false; self.stop_joints.len()];
        self.stop_torque = vec![0.0; self.q_a.len()];
        Ok(())
    }

    /// The next [`Actuators::torques`] are taken `lead` s into an explicit physics step.
    pub fn set_drive_lead(&mut self, lead: f64) {
        self.drive_lead = lead;
        self.implicit_step = None;
    }

    /// The next [`Actuators::torques`] and [`Actuators::linearization`] are those of a
    /// linearly implicit step of `h` s (drive and link solved together).
    pub fn set_implicit_step(&mut self, h: f64) {
        self.implicit_step = Some(h);
    }

    /// The flexible drives, if any.
    pub fn drives(&self) -> Option<&Drives> {
        self.drives.as_ref()
    }

    /// Whether torque commands go through flexible drives (their state changes every step).
    pub fn has_drives(&self) -> bool {
        self.drives.is_some()
    }

    /// Restarts the drives' motors on their links (after the state was set).
    pub fn restart_drives(&mut self) {
        if let Some(d) = &mut self.drives {
            d.restart();
        }
    }

    fn gather(&mut self, q: &[f64], v: &[f64]) {
        for k in 0..self.q_a.len() {
            self.q_a[k] = self.drive_q.get(k).map_or(0.0, |&i| q[i]);
            self.v_a[k] = v[self.first + k];
        }
    }

    /// A drive's linearization: the spring and damper for an explicit step; for an implicit
    /// one, no stiffness and the damping `c` of [`Drives::implicit_link_torque`] (its motor
    /// state enters it, not the link position).
    fn drive_gains(&self, k: usize, drive: Option<&FlexibleDrive>) -> (f64, f64) {
        let (Some(p), Some(d)) = (drive, &self.drives) else {
            return (0.0, 0.0);
        };
        match self.implicit_step {
            Some(h) => d
                .implicit_link_torque(k, h, 0.0, 0.0)
                .map_or((0.0, 0.0), |(_, c)| (0.0, c)),
            None => (p.stiffness, p.damping),
        }
    }

    /// Starts a control period: a torque command enters the drives (delayed by them).
    pub fn begin_period(&mut self, cmd: &Command, q: &[f64], v: &[f64]) {
        let Command::Torque(t) = cmd else { return };
        if self.drives.is_none() {
            return;
        }
        self.gather(q, v);
        self.tau_a.copy_from_slice(t.as_slice());
        if let Some(d) = &mut self.drives {
            d.begin_period(&self.tau_a, &self.q_a, &self.v_a);
        }
    }

    /// Advances the drives' motors by `h` with the links at `(q, v)`.
    pub fn advance_drives(&mut self, cmd: &Command, h: f64, q: &[f64], v: &[f64]) {
        if self.drives.is_none() || !matches!(cmd, Command::Torque(_)) {
            return;
        }
        self.gather(q, v);
        if let Some(d) = &mut self.drives {
            d.advance(h, &self.q_a, &self.v_a);
        }
    }

    /// Advances the PID servo's integral torque over one control period `dt` under `cmd` at
    /// configuration `q`; returns whether it changed (nothing happens without an integral
    /// term or a position command).
    pub fn integrate(&mut self, model: &Model, cmd: &Command, q: &[f64], dt: f64) -> bool {
        let (Some(pid), Command::Position { q_ref, .. }) = (&self.gains.integral, cmd) else {
            return false;
        };
        let _ = difference_to(model, q, q_ref.as_slice(), self.error.as_mut_slice());
        let f = self.first;
        let mut changed = false;
        for k in 0..model.nv - f {
            let before = self.integral[k];
            let c = pid.i_clamp[k];
            self.integral[k] = (before + pid.ki[k] * self.error[f + k] * dt).clamp(-c, c);
            changed |= self.integral[k] != before;
        }
        changed
    }

    /// Checks a command's sizes and values.
    pub fn check(&self, model: &Model, cmd: &Command) -> Result<()> {
        let na = model.nv - self.first;
        let chk = |what: &'static str, x: &DVector<f64>, n: usize| -> Result<()> {
            if x.len() != n {
                return Err(SimError::Command {
                    what,
                    reason: format!("size {}, expected {n}", x.len()),
                });
            }
            if let Some(i) = x.iter().position(|v| !v.is_finite()) {
                return Err(SimError::Command {
                    what,
                    reason: format!("non-finite entry at {i}"),
                });
            }
            Ok(())
        };
        match cmd {
            Command::Torque(t) => chk("torque", t, na),
            Command::Position { q_ref, v_ref } => {
                chk("position target", q_ref, model.nq)?;
                chk("velocity target", v_ref, na)
            }
            Command::Velocity(v) => chk("velocity target", v, na),
        }
    }

    /// Writes the generalized force (size nv, zero on the free-flyer) for `cmd` at (q, v),
    /// clamped at the effort limits.
    pub fn torques(&mut self, model: &Model, cmd: &Command, q: &[f64], v: &[f64], tau: &mut [f64]) {
        let f = self.first;
        tau[..f].iter_mut().for_each(|t| *t = 0.0);
        match cmd {
            Command::Torque(t) => tau[f..].copy_from_slice(t.as_slice()),
            Command::Position { q_ref, v_ref } => {
                // Both configurations were checked; the difference cannot fail.
                let _ = difference_to(model, q, q_ref.as_slice(), self.error.as_mut_slice());
                for k in 0..model.nv - f {
                    tau[f + k] = self.gains.kp[k] * self.error[f + k]
                        + self.gains.kd[k] * (v_ref[k] - v[f + k]);
                }
                if let Some(pid) = &self.gains.integral {
                    for k in 0..model.nv - f {
                        let c = pid.torque_clamp[k];
                        tau[f + k] = (tau[f + k] + self.integral[k]).clamp(-c, c);
                    }
                }
            }
            Command::Velocity(vr) => {
                for k in 0..model.nv - f {
                    tau[f + k] = self.gains.kd[k] * (vr[k] - v[f + k]);
                }
            }
        }
        for (t, lim) in tau[f..].iter_mut().zip(&model.effort_limit.as_slice()[f..]) {
            *t = t.clamp(-lim, *lim);
        }
        // A flexible drive passes its spring's torque (the current limit bounds the motor).
        if let (Some(d), Command::Torque(_)) = (&self.drives, cmd) {
            for k in 0..model.nv - f {
                let (qk, vk) = (q[self.drive_q[k]], v[f + k]);
                let t = match self.implicit_step {
                    Some(h) => d.implicit_link_torque(k, h, qk, vk).map(|(t, _)| t),
                    None => d.link_torque(k, qk, vk, self.drive_lead),
                };
                if let Some(t) = t {
                    tau[f + k] = t;
                }
            }
        }
        for &(k, iq, stiffness, damping) in &self.passive {
            tau[f + k] = -stiffness * q[iq] - damping * v[f + k];
        }
        if let Some(st) = self.stops {
            for (s, &(k, iq, lo, up)) in self.stop_active.iter_mut().zip(&self.stop_joints) {
                let past = if q[iq] > up {
                    q[iq] - up
                } else if q[iq] < lo {
                    q[iq] - lo
                } else {
                    0.0
                };
                *s = past != 0.0;
                let t = if *s {
                    -st.stiffness * past - st.damping * v[f + k]
                } else {
                    0.0
                };
                self.stop_torque[k] = t;
                tau[f + k] += t;
            }
        }
    }

    /// The servo's linearization for an implicit step, over the actuated joints: writes
    /// `stiffness[k] = −∂τ_k/∂q_k` and `damping[k] = −∂τ_k/∂q̇_k` (kp and kd for a position
    /// command, kd for a velocity command, zero for torques), and zero wherever `tau` (from
    /// [`Actuators::torques`]) sits on the effort limit, where the clamp holds it constant.
    pub fn linearization(
        &self,
        model: &Model,
        cmd: &Command,
        tau: &[f64],
        stiffness: &mut [f64],
        damping: &mut [f64],
    ) {
        let f = self.first;
        for k in 0..model.nv - f {
            let clamp = match (&self.gains.integral, cmd) {
                (Some(pid), Command::Position { .. }) => {
                    pid.torque_clamp[k].min(model.effort_limit[f + k])
                }
                _ => model.effort_limit[f + k],
            };
            // The servo's own torque (a stop's reaction is not the motor's).
            let stop = self.stop_torque.get(k).copied().unwrap_or(0.0);
            let saturated = (tau[f + k] - stop).abs() >= clamp;
            let drive = match (&self.drives, cmd) {
                (Some(d), Command::Torque(_)) => d.drive(k),
                _ => None,
            };
            let (kp, kd) = match cmd {
                _ if drive.is_some() => self.drive_gains(k, drive),
                _ if saturated => (0.0, 0.0),
                Command::Torque(_) => (0.0, 0.0),
                Command::Position { .. } => (self.gains.kp[k], self.gains.kd[k]),
                Command::Velocity(_) => (0.0, self.gains.kd[k]),
            };
            stiffness[k] = kp;
            damping[k] = kd;
        }
        for &(k, _, kp, kd) in &self.passive {
            stiffness[k] = kp;
            damping[k] = kd;
        }
        if let Some(st) = self.stops {
            for (&active, &(k, ..)) in self.stop_active.iter().zip(&self.stop_joints) {
                if active {
                    stiffness[k] += st.stiffness;
                    damping[k] += st.damping;
                }
            }
        }
    }
}
