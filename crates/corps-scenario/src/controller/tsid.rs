//! TSID's inverse dynamics in the loop, in torque mode (controller C: the QP reads the measured
//! state, its torques go to the joints) or position mode (controller B: the QP reads its own
//! integrated state, `v += q̈ dt`, `q = q ⊕ v dt`, and (q, v) go to the joint servos; seed 000
//! §3.8, L4538–L4550).
//!
//! # Position mode's contacts
//!
//! In position mode the QP's contact forces are never applied: the servos make the real ground
//! reaction, and the stabilizer keeps the real ZMP in the real support (its DCM controller
//! clamps `p*` into it). The integrated model still obeys its own centroidal dynamics, though:
//! with the friction pyramids at the sole corners (Eq 4.14's force bounds) its ZMP must stay in
//! its support polygon, so it can only follow a CoM acceleration with
//! `c̈_xy = ω² (c − p_int) − (k̇ term)`, `p_int` in the sole. The stabilizer's `c̈*` (Eq 2.31,
//! `c̈_ref + K_adm (p − p*)` from the *measured* ZMP, plus the sway damping) does not respect
//! that. Measured on the 20 cm walk (dynamic filter, Table 4.3 gains): in the first single
//! support the LIPM ZMP `c − c̈*/ω²` of the model reached 0.148 m against the stance sole's
//! outer edge at 0.150 m; at the right foot's touch-down (3.55–3.60 s after the handover, the
//! measured ZMP still on the left foot) `c̈*` was (−1.3, +2.3) m/s², i.e. `p_int` at
//! (0.31, −0.21) m, outside the right sole (x 0.09…0.29, y −0.15…−0.02). The QP, where the
//! CoM weighs 1000 against the waist's 1 and the angular momentum's 0.02, made up the
//! difference with centroidal angular momentum: the model rolled its pelvis by 0.018 rad in
//! single support and 0.157 rad 0.1 s after the touch-down (IK, controller A, holds it within
//! 0.0001 rad); the servos copied it (real pelvis roll 0.046 and 0.169 rad), the real swing
//! foot landed on its edge, 1.6 mm high (4.7 mm without the dynamic filter), and the walk fell (the pelvis below 0.9 m 5.06 s after
//! the handover; simulation diverged at 7.6 s, 6.1 s without the dynamic filter). Widening the
//! model's soles ×3 and ×10 delayed the pelvis drop to 7.65 and 10.56 s: the model's sole
//! bound, not the servo loop alone, set it off.
//!
//! Hence `contacts.bilateral` (on in `config/talos/tsid_position.toml`): the model's contacts
//! keep their acceleration equalities and the bounds on the total normal force (the add/remove
//! ramps), but not the per-corner pyramids, so the model follows `c̈*` with its contact wrench
//! and its legs, as the IK does, instead of with its trunk. Torque mode applies the forces and
//! refuses the option.
//!
//! What remains (20 cm walk, bilateral): it walks (final base 20.5 mm from the plan; 15.5 mm
//! with the dynamic filter) but loosely: ZMP error avg/peak x 39.0/250.7, y 35.0/236.6 mm
//! (dynamic filter: 29.3/153.7, 28.9/216.2; IK 5.1/62.6, 8.9/31.2; thesis 28/142, 25/138);
//! the real pelvis rolls and pitches up to 0.16 and 0.14 rad in the last steps (IK 0.027 and
//! 0.018) while the model's stays within 0.032 and 0.019 rad. The waist weight is not it
//! (1000 instead of 1: ZMP x 43.6/309.3, y 33.4/236.0 mm).

use super::hand_press::{HandPress, HAND_CHANNELS};
use super::WholeBodyController;
use crate::error::Result;
use crate::gains::TsidGains;
use crate::press::PressSection;
use crate::targets::Targets;
use corps_control::contacts::Contact;
use corps_control::formulation::{InverseDynamics, PassiveInverseDynamics};
use corps_control::tasks::{AngularMomentumTask, ComTask, PostureTask, Se3Reference, Se3Task};
use corps_control::{FallbackReason, RobotState};
use corps_model::spatial::Motion;
use corps_model::{integrate_to, Model};
use corps_robot::Robot;
use corps_sim::Command;
use nalgebra::{DVector, Vector3, Vector6};
use std::sync::Arc;

/// Torque or position output.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TsidMode {
    Torque,
    Position,
}

/// One foot: its contact (a template re-added at each touch-down) and whether it is active.
struct Foot {
    frame: usize,
    contact: Contact,
    in_contact: bool,
    /// Name of its swing task in the stack.
    swing_task: String,
}

pub struct TsidController {
    model: Arc<Model>,
    mode: TsidMode,
    dt: f64,
    id: InverseDynamics,
    state: RobotState,
    feet: [Foot; 2],
    /// Whether the stack has a waist orientation task ("waist"), and its starting orientation.
    waist: bool,
    waist_rotation0: nalgebra::Matrix3<f64>,
    gains: TsidGains,
    /// Position mode: the integrated state.
    q_int: DVector<f64>,
    v_int: DVector<f64>,
    step: DVector<f64>,
    q_prev: DVector<f64>,
    tau: DVector<f64>,
    command: Command,
    /// The energy tank over the QP (the passive controller, torque mode).
    passive: Option<PassiveInverseDynamics>,
    /// The posture task's starting reference (a posture wave moves about it).
    q_posture0: DVector<f64>,
    /// Whether the log carries [`POSTURE_CHANNELS`].
    posture_log: bool,
    /// A hand's tool pressing on a surface (torque mode).
    hand: Option<HandPress>,
}

/// The energy tank's log columns (seed 000 §4.5's figures): E_tank at the start of the tick,
/// the valves, B_σ, B_φ, Ḣ and the bound −q̇_jᵀτ it is held to, the stacked task energy S and
/// the energy u the tank paid the spring at the start of the tick (the storage after it is
/// `beta·gamma·task_energy_J + tank_energy_J − spring_payment_J`), and the energy the
/// controller received over the last step, −τᵀΔq_j (`port_energy_J`; the tank has booked
/// it), and what of the bookings an empty tank could not pay (`unpaid_J`).
pub const TANK_CHANNELS: [&str; 13] = [
    "tank_energy_J",
    "alpha",
    "beta",
    "gamma",
    "beta_phi",
    "b_sigma_W",
    "b_phi_W",
    "h_dot_W",
    "passivity_bound_W",
    "task_energy_J",
    "spring_payment_J",
    "port_energy_J",
    "unpaid_J",
];

/// Log columns of a posture motion: the posture task's error over the actuated one-dof
/// joints (RMS and largest, measured q against the reference), the largest joint speed and
/// the largest commanded torque.
pub const POSTURE_CHANNELS: [&str; 4] = [
    "posture_error_rms_rad",
    "posture_error_max_rad",
    "joint_speed_max_rad_s",
    "torque_max_Nm",
];

impl TsidController {
    /// Logs [`POSTURE_CHANNELS`] (for a run whose motion drives the posture).
    pub fn with_posture_channels(mut self) -> Self {
        self.posture_log = true;
        self
    }

    fn posture_signals(&self) -> [f64; 4] {
        let model = &self.model;
        let first = model.first_actuated();
        let Some(p) = self.id.tasks.task::<PostureTask>("posture") else {
            return [f64::NAN; 4];
        };
        let (mut sum, mut max, mut n) = (0.0f64, 0.0f64, 0usize);
        let mut speed = 0.0f64;
        for j in model
            .joints
            .iter()
            .filter(|j| j.nv() == 1 && j.idx_v >= first)
        {
            let e = self.state.q[j.idx_q] - p.q_ref[j.idx_q];
            sum += e * e;
            max = max.max(e.abs());
            n += 1;
            speed = speed.max(self.state.v[j.idx_v].abs());
        }
        let torque = self.tau.iter().fold(0.0f64, |m, t| m.max(t.abs()));
        [(sum / n.max(1) as f64).sqrt(), max, speed, torque]
    }
    /// The controller for `robot` at the measured state (q, v): CoM, posture (towards
    /// `q_posture`), angular momentum, optional waist orientation, both soles in contact
    /// (contact points at the description's sole corners).
    pub fn new(
        robot: &Robot,
        mode: TsidMode,
        gains: TsidGains,
        dt: f64,
        q: &DVector<f64>,
        v: &DVector<f64>,
        q_posture: &DVector<f64>,
    ) -> Result<Self> {
        gains.check()?;
        if gains.contacts.bilateral && mode == TsidMode::Torque {
            crate::error::bail!(
                "contacts.bilateral: torque mode applies the QP's contact forces, which must \
                 stay in the friction pyramids"
            );
        }
        let model = robot.model.clone();
        let soles = super::two_feet(robot)?;
        let nv = model.nv;
        let na = model.na();
        let mut state = RobotState::new(&model);
        state.update(&model, q.as_slice(), v.as_slice())?;
        let mut id = InverseDynamics::new(&model);
        let g = &gains;
        let com = ComTask::new(nv, Vector3::repeat(g.com.kp), Vector3::repeat(g.com.kd()));
        id.tasks.add("com", com, 1, g.com.weight)?;
        let kp = g.posture_kp(&model)?;
        let kd = kp.map(|k| 2.0 * k.sqrt());
        let posture = PostureTask::new(&model, kp, kd, q_posture.clone());
        id.tasks.add("posture", posture, 1, g.posture.weight)?;
        let momentum = AngularMomentumTask::new(nv, Vector3::repeat(g.angular_momentum.kp));
        (id.tasks).add("angular_momentum", momentum, 1, g.angular_momentum.weight)?;
        let (mut waist, mut waist_rotation0) = (false, nalgebra::Matrix3::identity());
        if let Some(w) = &g.waist {
            let frame = robot.base;
            let mut task = Se3Task::new(
                nv,
                frame,
                Vector6::repeat(w.kp),
                Vector6::repeat(w.kd()),
                at_rest(state.frame_placement(&model, frame)?),
            );
            task.mask = Vector6::new(0.0, 0.0, 0.0, 1.0, 1.0, 1.0);
            waist_rotation0 = task.reference.placement.rotation;
            waist = true;
            id.tasks.add("waist", task, 1, w.weight)?;
        }
        let c = &g.contacts;
        let contact_kd = c.kd.unwrap_or(2.0 * c.kp.sqrt());
        let mut feet = Vec::with_capacity(2);
        for foot in soles {
            let frame = foot.frame;
            let mut contact = Contact::new(
                &model,
                &foot.frame_name,
                frame,
                foot.corners,
                Vector3::z(),
                c.mu,
                (c.fmin, c.fmax),
                Vector6::repeat(c.kp),
                Vector6::repeat(contact_kd),
                at_rest(state.frame_placement(&model, frame)?),
            );
            contact.force_reg_weight = c.force_regularization;
            contact.bilateral = c.bilateral;
            id.contacts.push(contact.clone());
            feet.push(Foot {
                frame,
                swing_task: format!("swing {}", foot.frame_name),
                contact,
                in_contact: true,
            });
        }
        if g.actuation_bounds {
            let limit = model
                .effort_limit
                .rows(model.first_actuated(), na)
                .into_owned();
            id.actuation = Some((-&limit, limit));
        }
        let passive = match &g.tank {
            Some(_) if mode == TsidMode::Position => crate::error::bail!(
                "tank: the energy tank bounds the torques' power; it is for torque mode"
            ),
            Some(t) => {
                let mut p = PassiveInverseDynamics::new(&model, t.tank()?, dt)?;
                p.left_inverse = t.left_inverse.into();
                Some(p)
            }
            None => None,
        };
        let command = match mode {
            TsidMode::Torque => Command::Torque(DVector::zeros(na)),
            TsidMode::Position => Command::Position {
                q_ref: q.clone(),
                v_ref: v.rows(model.first_actuated(), na).into_owned(),
            },
        };
        let [left, right]: [Foot; 2] = feet
            .try_into()
            .unwrap_or_else(|_| unreachable!("two soles"));
        Ok(Self {
            mode,
            dt,
            id,
            state,
            feet: [left, right],
            waist,
            waist_rotation0,
            q_int: q.clone(),
            v_int: v.clone(),
            step: DVector::zeros(nv),
            q_prev: q.clone(),
            tau: DVector::zeros(na),
            command,
            gains,
            q_posture0: q_posture.clone(),
            posture_log: false,
            model,
            passive,
            hand: None,
        })
    }

    /// Holds the tool tip `frame` on the surface it touches and presses as `section` says
    /// ([`HandPress`]); torque mode only.
    pub fn with_press(mut self, frame: usize, section: &PressSection) -> Result<Self> {
        if self.mode != TsidMode::Torque {
            crate::error::bail!(
                "press: the force task drives the contact force, which only torque mode applies"
            );
        }
        let hand = HandPress::new(
            &self.model,
            &mut self.id,
            &self.state,
            frame,
            section,
            &self.gains,
        )?;
        self.hand = Some(hand);
        Ok(self)
    }

    /// When the hand's contact was removed (s since the handover), if it was.
    pub fn hand_released_at(&self) -> Option<f64> {
        self.hand.as_ref().and_then(|h| h.released_at)
    }

    /// Adds or removes foot contacts and swing-foot tasks where the targets changed.
    fn switch_contacts(&mut self, t: f64, targets: &Targets) -> Result<(), FallbackReason> {
        let transition = self.gains.contacts.transition;
        let nv = self.model.nv;
        for (k, foot) in self.feet.iter_mut().enumerate() {
            let target = &targets.feet[k];
            if target.in_contact == foot.in_contact {
                continue;
            }
            let name = foot.contact.name.clone();
            if target.in_contact {
                // Touch-down: drop the swing task, add the contact where the foot is aimed.
                if self.id.tasks.contains(&foot.swing_task) {
                    (self.id.tasks.remove(&foot.swing_task)).map_err(FallbackReason::Controller)?;
                }
                let mut contact = foot.contact.clone();
                contact.motion.reference = at_rest(target.reference.placement);
                self.id.add_contact(contact, t, transition);
            } else {
                self.id
                    .remove_contact(&name, t, transition)
                    .map_err(FallbackReason::Controller)?;
                let g = &self.gains.feet;
                let task = Se3Task::new(
                    nv,
                    foot.frame,
                    Vector6::repeat(g.kp),
                    Vector6::repeat(g.kd()),
                    target.reference.clone(),
                );
                (self.id.tasks)
                    .add(&foot.swing_task, task, 1, g.weight)
                    .map_err(FallbackReason::Controller)?;
            }
            foot.in_contact = target.in_contact;
        }
        Ok(())
    }

    /// Copies the targets into the tasks.
    fn set_references(&mut self, targets: &Targets) {
        if let Some(wave) = &targets.posture {
            let (q0, model) = (&self.q_posture0, &self.model);
            if let Some(p) = self.id.tasks.task_mut::<PostureTask>("posture") {
                let first = model.first_actuated();
                let [s, ds, dds] = wave.wave;
                for j in model
                    .joints
                    .iter()
                    .filter(|j| j.nv() == 1 && j.idx_v >= first)
                {
                    let (k, a) = (j.idx_v - first, wave.amplitude[j.idx_v - first]);
                    p.q_ref[j.idx_q] = q0[j.idx_q] + a * s;
                    p.v_ref[k] = a * ds;
                    p.a_ref[k] = a * dds;
                }
            }
        }
        if self.waist {
            if let Some(waist) = self.id.tasks.task_mut::<Se3Task>("waist") {
                let yaw =
                    nalgebra::Rotation3::from_axis_angle(&Vector3::z_axis(), targets.waist_yaw);
                waist.reference.placement.rotation = yaw.matrix() * self.waist_rotation0;
            }
        }
        if let Some(com) = self.id.tasks.task_mut::<ComTask>("com") {
            com.reference.pos.copy_from(&targets.com.pos);
            com.reference.vel.copy_from(&targets.com.vel);
            com.reference.acc.copy_from(&targets.com.acc);
        }
        for (k, foot) in self.feet.iter().enumerate() {
            if foot.in_contact {
                continue;
            }
            if let Some(task) = self.id.tasks.task_mut::<Se3Task>(&foot.swing_task) {
                task.reference.clone_from(&targets.feet[k].reference);
            }
        }
    }
}

fn at_rest(placement: corps_model::spatial::Se3) -> Se3Reference {
    Se3Reference {
        placement,
        velocity: Motion::zero(),
        acceleration: Motion::zero(),
    }
}

impl WholeBodyController for TsidController {
    fn tick(
        &mut self,
        t: f64,
        q: &[f64],
        v: &[f64],
        targets: &Targets,
        measured: &super::Measured,
    ) -> Option<FallbackReason> {
        if let Err(reason) = self.switch_contacts(t, targets) {
            return Some(reason);
        }
        if let Some(hand) = &mut self.hand {
            let wrench = measured.hands.first().map(|h| &h.wrench);
            let model = &self.model;
            if let Err(reason) = hand.update(t, self.dt, model, &mut self.id, &self.state, wrench) {
                return Some(reason);
            }
        }
        self.set_references(targets);
        let model = self.model.clone();
        let damping = self.gains.safe_damping;
        match self.mode {
            TsidMode::Torque => {
                let reason = match &mut self.passive {
                    Some(p) => p.tick(
                        &mut self.id,
                        &model,
                        &mut self.state,
                        t,
                        q,
                        v,
                        damping,
                        &mut self.tau,
                    ),
                    None => self
                        .id
                        .tick(&model, &mut self.state, t, q, v, damping, &mut self.tau),
                };
                if let Command::Torque(tau) = &mut self.command {
                    tau.copy_from(&self.tau);
                }
                if let Some(hand) = &mut self.hand {
                    hand.after_tick(&self.id);
                }
                reason
            }
            TsidMode::Position => {
                let reason = self.id.tick(
                    &model,
                    &mut self.state,
                    t,
                    self.q_int.as_slice(),
                    self.v_int.as_slice(),
                    damping,
                    &mut self.tau,
                );
                if reason.is_some() {
                    // Hold the last target at rest.
                    self.v_int.fill(0.0);
                } else {
                    let dt = self.dt;
                    self.v_int.axpy(dt, &self.id.output.dv, 1.0);
                    self.step.copy_from(&self.v_int);
                    self.step.scale_mut(dt);
                    self.q_prev.copy_from(&self.q_int);
                    if let Err(e) = integrate_to(
                        &model,
                        self.q_prev.as_slice(),
                        self.step.as_slice(),
                        self.q_int.as_mut_slice(),
                    ) {
                        return Some(FallbackReason::BadState(e.to_string()));
                    }
                }
                if let Command::Position { q_ref, v_ref } = &mut self.command {
                    q_ref.copy_from(&self.q_int);
                    v_ref.copy_from(&self.v_int.rows(model.first_actuated(), model.na()));
                }
                reason
            }
        }
    }

    fn command(&self) -> &Command {
        &self.command
    }

    fn controller_com(&self) -> Vector3<f64> {
        self.state.data.com
    }

    fn channels(&self) -> Vec<&'static str> {
        let mut names = Vec::new();
        if self.passive.is_some() {
            names.extend(TANK_CHANNELS);
        }
        if self.hand.is_some() {
            names.extend(HAND_CHANNELS);
        }
        if self.posture_log {
            names.extend(POSTURE_CHANNELS);
        }
        names
    }

    fn push_channels(&self, row: &mut Vec<f64>) {
        if let Some(p) = &self.passive {
            let s = &p.signals;
            row.extend([
                s.tank_energy,
                s.valves.alpha,
                s.valves.beta,
                s.valves.gamma,
                s.valves.beta_phi,
                s.b_sigma,
                s.b_phi,
                s.h_dot,
                s.passivity_bound,
                s.task.storage,
                s.spring_payment,
                s.port_energy,
                s.unpaid,
            ]);
        }
        if let Some(h) = &self.hand {
            row.extend(h.channels());
        }
        if self.posture_log {
            row.extend(self.posture_signals());
        }
    }
}
