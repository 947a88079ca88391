//! Seed 001's soft-tasks controller #2 (§2.6c, Eq 2.45) driven by its stepping state machine
//! (§2.7, FSM #2): one QP per tick on u = [τ; f] ([`TorqueForce`]),
//!
//! `min w_τ|τ|² + w_s|s̃̈(u)|² + Σ_T w_T|ṽ̇_T(u)|²`, T ∈ {CoM, stance, swing, neck},
//! s.t. each contact wrench in its limits (Eq 2.32–2.36),
//!
//! with the feet in contact as wrench contacts whose pose rows are soft (the stance-foot task:
//! its acceleration tracked towards the PD law, not held at zero), a swing foot out of contact
//! as an SE(3) task, the neck's orientation under the SO(3) law
//! ([`corps_control::tasks::OrientationTask`]) and the posture towards the handover's (iCub's
//! description locks its neck and wrists: the 23 joints seed 001 torque-controls, §3.1, are
//! the model's). The state machine is data
//! (`[fsm]`, [`fsm`]); every set-point change is smoothed by a minimum-jerk move
//! ([`smoothing`]). The references it tracks are what the run logs and measures
//! ([`super::WholeBodyController::tracked_targets`]).

mod config;
pub mod fsm;
mod posture_law;
mod report;
mod smoothing;
pub(crate) mod stance_ik;
mod state_gains;

pub use config::SoftTasksConfig;
pub use report::{Figure, ThesisFigures};

use super::{Measured, WholeBodyController};
use crate::error::Result;
use crate::targets::{FootTarget, Side, Targets};
use corps_control::contacts::{Contact, CopBox, WrenchLimits};
use corps_control::formulation::TorqueForce;
use corps_control::posture_consistency::ConsistentPosture;
use corps_control::tasks::{
    ComTask, OrientationTask, PostureTask, Reference, Se3Reference, Se3Task,
};
use corps_control::{FallbackReason, RobotState};
use corps_loop::Command;
use corps_model::spatial::{Motion, Se3};
use corps_model::Model;
use corps_robot::Robot;
use fsm::{FsmInput, StateMachine};
use nalgebra::{DVector, Matrix3, Vector3, Vector6};
use posture_law::PostureLaw;
use report::SteppingStats;
use smoothing::Smoothed;
use state_gains::{Handover, StateSettings};
use std::sync::Arc;

/// The controller's log columns: the state (index in the file), steps completed, the stance
/// foot (1 left, 0 right), the QP's normal forces and the distance between measured (F/T
/// through the estimator) and QP-desired contact forces per foot, that distance for a foot in
/// contact outside the switching windows (NaN inside, or for a released foot), the neck's distance δ (Eq 2.16) to its reference, the
/// smallest distance of a watched joint to its limits (degrees, negative past one) and the
/// largest distance of a leg joint to the state's postural set-point (degrees; FSM #1's e_leg).
pub const SOFT_TASKS_CHANNELS: [&str; 12] = [
    "fsm_state",
    "fsm_steps",
    "stance_left",
    "force_desired_left_z_N",
    "force_desired_right_z_N",
    "force_error_left_N",
    "force_error_right_N",
    "force_error_left_outside_switching_N",
    "force_error_right_outside_switching_N",
    "neck_distance",
    "joint_limit_margin_deg",
    "leg_error_deg",
];

struct Foot {
    contact: Contact,
    in_contact: bool,
    swing_task: String,
    rotation0: Matrix3<f64>,
}

pub struct SoftTasksController {
    model: Arc<Model>,
    config: SoftTasksConfig,
    tf: TorqueForce,
    state: RobotState,
    fsm: StateMachine,
    com_ref: Smoothed,
    foot_ref: [Smoothed; 2],
    feet: [Foot; 2],
    targets: Targets,
    tau: DVector<f64>,
    command: Command,
    /// Time of the last contact change (s).
    last_switch: f64,
    /// The posture's law (classical or re-parametrised), its accelerations (na) and Eq B.3's
    /// workspace when the posture's reference is made consistent with the Cartesian tasks.
    posture: (PostureLaw, DVector<f64>, Option<ConsistentPosture>),
    /// The states' gains and postural set-points, and the switch under way.
    settings: StateSettings,
    signals: [f64; 12],
    stats: SteppingStats,
    steps_seen: usize,
}

fn at_rest(placement: Se3) -> Se3Reference {
    Se3Reference {
        placement,
        velocity: Motion::zero(),
        acceleration: Motion::zero(),
    }
}

impl SoftTasksController {
    /// The controller for `robot` at the measured state (q, v), both feet on the ground,
    /// ticking every `dt` seconds.
    pub fn new(
        robot: &Robot,
        config: SoftTasksConfig,
        dt: f64,
        q: &DVector<f64>,
        v: &DVector<f64>,
    ) -> Result<Self> {
        config.check()?;
        let model = robot.model.clone();
        let soles = super::two_feet(robot)?;
        let (nv, na) = (model.nv, model.na());
        let mut state = RobotState::new(&model);
        state.update(&model, q.as_slice(), v.as_slice())?;
        let mut tf = TorqueForce::new(&model);
        tf.torque_weight = config.weights.torque;
        let w = &config.weights;
        let mut com = ComTask::new(
            nv,
            Vector3::repeat(config.com.kp),
            Vector3::repeat(config.com.kd()),
        );
        com.reference = Reference::constant(DVector::from_column_slice(state.data.com.as_slice()));
        let cartesian = config.cartesian_priority();
        tf.tasks.add("com", com, cartesian, w.com)?;
        let neck_frame = model.frame_id(&config.neck.frame)?;
        let neck = OrientationTask::new(
            nv,
            neck_frame,
            config.neck.kp,
            config.neck.kd.unwrap_or(2.0 * config.neck.kp.sqrt()),
            at_rest(state.frame_placement(&model, neck_frame)?),
        );
        tf.tasks.add("neck", neck, cartesian, w.neck)?;
        let kp = config.posture.kp_per_joint(&model)?;
        let kd = kp.map(|k| 2.0 * k.sqrt());
        let law = PostureLaw::new(
            &model,
            kp,
            kd,
            q,
            &config.posture_reference_deg,
            config.joint_limits.as_ref(),
        )?;
        let merge = (config.posture_consistency.as_ref())
            .map(|p| ConsistentPosture::new(nv, p.weight, p.base_gain));
        let posture_law = (law, DVector::zeros(na), merge);
        // The posture task tracks the law's accelerations (or Eq B.3's s̈*): no PD of its own.
        let posture = PostureTask::new(&model, DVector::zeros(na), DVector::zeros(na), q.clone());
        tf.tasks.add("posture", posture, 1, config.posture.weight)?;
        if config.actuation_bounds {
            let cap = config.torque_limit.unwrap_or(f64::INFINITY);
            let limit = (model.effort_limit.rows(model.first_actuated(), na)).map(|e| e.min(cap));
            tf.actuation = Some((-&limit, limit));
        }
        tf.torque_step = config.torque_rate.map(|rate| rate * dt);
        let c = &config.contacts;
        let f = &config.feet;
        let kp = Vector6::new(
            f.linear.kp,
            f.linear.kp,
            f.linear.kp,
            f.angular.kp,
            f.angular.kp,
            f.angular.kp,
        );
        let kd = Vector6::new(
            f.linear.kd(),
            f.linear.kd(),
            f.linear.kd(),
            f.angular.kd(),
            f.angular.kd(),
            f.angular.kd(),
        );
        let mut feet = Vec::with_capacity(2);
        let mut feet0 = [Vector3::zeros(); 2];
        for (k, sole) in soles.iter().enumerate() {
            let limits = WrenchLimits {
                mu: c.mu,
                mu_torsion: c.mu_torsion,
                vertices_per_quadrant: c.vertices_per_quadrant,
                cop: CopBox {
                    x_min: -sole.sole.back,
                    x_max: sole.sole.front,
                    y_min: -sole.sole.right,
                    y_max: sole.sole.left,
                },
            };
            limits
                .check()
                .map_err(|e| crate::error::invalid!("contacts ({}): {e}", sole.label))?;
            let placement = state.frame_placement(&model, sole.frame)?;
            feet0[k] = placement.translation;
            let mut contact = Contact::with_wrench(
                &model,
                &sole.frame_name,
                sole.frame,
                limits,
                (c.fz_min, c.fz_max),
                kp,
                kd,
                at_rest(placement),
            );
            contact.soft = (!config.strict).then_some(w.stance);
            tf.contacts.push(contact.clone());
            // Its swing task enters the stack while the foot is in the air.
            let swing_task = format!("swing {}", sole.frame_name);
            feet.push(Foot {
                contact,
                in_contact: true,
                swing_task,
                rotation0: placement.rotation,
            });
        }
        let [left, right]: [Foot; 2] = feet.try_into().unwrap_or_else(|_| unreachable!());
        let com0 = state.data.com;
        let fsm = StateMachine::new(config.fsm.clone(), 0.0, com0, feet0);
        let settings = StateSettings::new(&Handover {
            model: &model,
            config: &config,
            law: &posture_law.0,
            soles: [left.contact.frame, right.contact.frame],
            fsm: &fsm,
            q,
        })?;
        let targets = Targets::at_rest(
            &com0,
            &[
                left.contact.motion.reference.placement,
                right.contact.motion.reference.placement,
            ],
        );
        Ok(Self {
            tf,
            state,
            fsm,
            com_ref: Smoothed::at(com0),
            foot_ref: feet0.map(Smoothed::at),
            feet: [left, right],
            targets,
            tau: DVector::zeros(na),
            command: Command::Torque(DVector::zeros(na)),
            last_switch: f64::NEG_INFINITY,
            posture: posture_law,
            settings,
            signals: [f64::NAN; 12],
            stats: SteppingStats::new(config.thesis.clone()),
            steps_seen: 0,
            config,
            model,
        })
    }

    /// Moves the references to the machine's set-points and switches contacts.
    fn follow_fsm(&mut self, t: f64) -> std::result::Result<(), FallbackReason> {
        let ts = self.fsm.t_smooth();
        self.com_ref.go_to(t, self.fsm.com_setpoint(), ts);
        for side in [Side::Left, Side::Right] {
            let k = side.index();
            self.foot_ref[k].go_to(t, self.fsm.foot_setpoint(side), ts);
            let wanted = side == self.fsm.stance() || self.fsm.swing_in_contact();
            let foot = &mut self.feet[k];
            if wanted == foot.in_contact {
                continue;
            }
            let err = FallbackReason::Controller;
            let placement = Se3::new(foot.rotation0, self.foot_ref[k].target());
            if wanted {
                self.tf.tasks.remove(&foot.swing_task).map_err(err)?;
                let mut contact = foot.contact.clone();
                contact.motion.reference = at_rest(placement);
                self.tf.contacts.push(contact);
            } else {
                self.tf.contacts.retain(|c| c.name != foot.contact.name);
                let m = &foot.contact.motion;
                let swing = Se3Task::new(self.model.nv, m.frame, m.kp, m.kd, at_rest(placement));
                let weight = self.config.weights.swing;
                let priority = self.config.cartesian_priority();
                self.tf
                    .tasks
                    .add(&foot.swing_task, swing, priority, weight)
                    .map_err(err)?;
            }
            foot.in_contact = wanted;
            self.last_switch = t;
        }
        Ok(())
    }

    /// The state's gains at `t` into the tasks, when the states give their own (Kd = 2√Kp):
    /// the stance foot's and the swing foot's, whether a contact or a task.
    fn set_gains(&mut self, t: f64) {
        let ts = self.fsm.t_smooth();
        self.settings.update(t, ts);
        if !self.settings.varies {
            return;
        }
        let g = &self.settings.now;
        let damping = |p: f64| 2.0 * p.max(0.0).sqrt();
        if let Some(com) = self.tf.tasks.task_mut::<ComTask>("com") {
            com.kp = g.com;
            com.kd = g.com.map(damping);
        }
        if let Some(o) = self.tf.tasks.task_mut::<OrientationTask>("neck") {
            o.k0 = g.orientation;
            o.k1 = damping(g.orientation);
        }
        for side in [Side::Left, Side::Right] {
            let [lin, ang] = if side == self.fsm.stance() {
                g.stance
            } else {
                g.swing
            };
            let kp = Vector6::new(lin, lin, lin, ang, ang, ang);
            let kd = kp.map(damping);
            let foot = &self.feet[side.index()];
            if foot.in_contact {
                let name = &foot.contact.name;
                if let Some(c) = self.tf.contacts.iter_mut().find(|c| &c.name == name) {
                    c.motion.kp = kp;
                    c.motion.kd = kd;
                }
            } else if let Some(task) = self.tf.tasks.task_mut::<Se3Task>(&foot.swing_task) {
                task.kp = kp;
                task.kd = kd;
            }
        }
        self.posture.0.set_gains(&g.posture);
    }

    /// Writes the smoothed references into the tasks and into [`Self::targets`].
    fn set_references(&mut self, t: f64) {
        self.posture.0.sample(t);
        let [p, v, a] = self.com_ref.sample(t);
        let r = &mut self.targets.com;
        r.pos.copy_from(&p);
        r.vel.copy_from(&v);
        r.acc.copy_from(&a);
        if let Some(com) = self.tf.tasks.task_mut::<ComTask>("com") {
            com.reference.pos.copy_from(&p);
            com.reference.vel.copy_from(&v);
            com.reference.acc.copy_from(&a);
        }
        for k in 0..2 {
            let [p, v, a] = self.foot_ref[k].sample(t);
            let foot = &self.feet[k];
            let reference = Se3Reference {
                placement: Se3::new(foot.rotation0, p),
                velocity: Motion::new(v, Vector3::zeros()),
                acceleration: Motion::new(a, Vector3::zeros()),
            };
            if foot.in_contact {
                if let Some(c) = self
                    .tf
                    .contacts
                    .iter_mut()
                    .find(|c| c.name == foot.contact.name)
                {
                    c.motion.reference = reference.clone();
                }
            } else if let Some(task) = self.tf.tasks.task_mut::<Se3Task>(&foot.swing_task) {
                task.reference = reference.clone();
            }
            self.targets.feet[k] = FootTarget {
                reference,
                in_contact: foot.in_contact,
                supporting: foot.in_contact,
            };
        }
    }

    /// The log signals of the tick (see [`SOFT_TASKS_CHANNELS`]).
    fn record(&mut self, t: f64, measured: &Measured<'_>, solved: bool) {
        let mut desired = [Vector6::zeros(); 2];
        if solved {
            let mut offset = 0;
            for c in &self.tf.contacts {
                let n = c.n_force();
                let f = &self.tf.output.forces.as_slice()[offset..offset + n];
                if let Some(k) = self
                    .feet
                    .iter()
                    .position(|foot| foot.contact.name == c.name)
                {
                    desired[k] = c.wrench(f);
                }
                offset += n;
            }
        }
        let outside = t - self.last_switch > self.config.switching_window;
        let s = &mut self.signals;
        s[0] = self.fsm.current() as f64;
        s[1] = self.fsm.steps as f64;
        s[2] = if self.fsm.stance() == Side::Left {
            1.0
        } else {
            0.0
        };
        for k in 0..2 {
            let measured_force = measured.foot_wrenches[k].force;
            let error = if solved {
                (measured_force - desired[k].fixed_rows::<3>(0)).norm()
            } else {
                f64::NAN
            };
            s[3 + k] = if solved { desired[k][2] } else { f64::NAN };
            s[5 + k] = error;
            // Outside switching, between a contact's forces and the QP's: a released foot
            // has no QP force to compare with (its early touch is counted apart).
            let contact = self.feet[k].in_contact;
            s[7 + k] = if outside && contact { error } else { f64::NAN };
            if !contact && outside {
                self.stats.released_foot_force(measured_force.z);
            }
        }
        let com_error = measured.com - Vector3::from_column_slice(self.targets.com.pos.as_slice());
        let foot_errors = [0, 1].map(|k| {
            measured.feet[k].translation.vector
                - self.targets.feet[k].reference.placement.translation
        });
        let contacts = [0, 1].map(|k| {
            if self.feet[k].in_contact {
                s[5 + k]
            } else {
                f64::NAN
            }
        });
        self.stats.push(com_error, foot_errors, contacts, outside);
        if self.fsm.steps != self.steps_seen {
            self.steps_seen = self.fsm.steps;
            self.stats.swapped(t);
        }
        let (margin, joint) = self.posture.0.margin(&self.state.q);
        s[10] = margin.to_degrees();
        self.stats.joint_margin(margin, joint);
        s[9] = match self.tf.tasks.task::<OrientationTask>("neck") {
            Some(neck) => neck.distance(&self.model, &self.state).unwrap_or(f64::NAN),
            None => f64::NAN,
        };
    }
}

/// Sets the stack's posture reference acceleration: the law's, or, with `merge`, s̈* of the
/// rebuilt Eq B.3 ([`corps_control::posture_consistency`]), the law's accelerations merged
/// with every priority-1 task but the posture and every soft contact, at their QP weights.
fn posture_reference(
    model: &Model,
    tf: &mut TorqueForce,
    s: &RobotState,
    (law, out, merge): &mut (PostureLaw, DVector<f64>, Option<ConsistentPosture>),
) -> corps_control::Result<()> {
    law.accelerations(s, out)
        .map_err(|e| corps_control::ControlError::Config {
            name: "posture".into(),
            reason: e.to_string(),
        })?;
    let Some(merge) = merge else {
        if let Some(posture) = tf.tasks.task_mut::<PostureTask>("posture") {
            posture.a_ref.copy_from(out);
        }
        return Ok(());
    };
    let first = model.first_actuated();
    merge.begin(&s.v, first, out);
    for entry in tf.tasks.entries_mut() {
        if entry.priority == 1 && entry.name != "posture" {
            let w = entry.weight;
            merge.add_task(entry.task.compute(model, s)?, w);
        }
    }
    for contact in &mut tf.contacts {
        if let Some(w) = contact.soft {
            merge.add_task(contact.compute(model, s)?, w);
        }
    }
    merge.solve(first, out)?;
    if let Some(posture) = tf.tasks.task_mut::<PostureTask>("posture") {
        posture.a_ref.copy_from(out);
    }
    Ok(())
}

impl WholeBodyController for SoftTasksController {
    fn tick(
        &mut self,
        t: f64,
        q: &[f64],
        v: &[f64],
        _targets: &Targets,
        measured: &Measured<'_>,
    ) -> Option<FallbackReason> {
        let input = FsmInput {
            t,
            com: measured.com,
            feet: measured.feet.map(|f| f.translation.vector),
            normal_forces: measured.foot_wrenches.map(|w| w.force.z),
            leg_errors: self.settings.leg_errors(q, &self.posture.0),
        };
        self.signals[11] = input.leg_errors[0].max(input.leg_errors[1]).to_degrees();
        self.fsm.update(&input);
        let ts = self.fsm.t_smooth();
        let (k, stance) = (self.fsm.current(), self.fsm.stance());
        (self.settings).enter(k, stance, t, ts, &mut self.posture.0);
        if let Err(reason) = self.follow_fsm(t) {
            let model = self.model.clone();
            let damping = self.config.safe_damping;
            corps_control::safe_torques(&model, &mut self.state.data, q, v, damping, &mut self.tau);
            if let Command::Torque(tau) = &mut self.command {
                tau.copy_from(&self.tau);
            }
            return Some(reason);
        }
        self.set_references(t);
        self.set_gains(t);
        let model = self.model.clone();
        let posture = &mut self.posture;
        let reason = self.tf.tick_with(
            &model,
            &mut self.state,
            t,
            (q, v),
            self.config.safe_damping,
            &mut self.tau,
            |tf, s| posture_reference(&model, tf, s, posture),
        );
        if let Command::Torque(tau) = &mut self.command {
            tau.copy_from(&self.tau);
        }
        self.record(t, measured, reason.is_none());
        reason
    }

    fn command(&self) -> &Command {
        &self.command
    }

    fn controller_com(&self) -> Vector3<f64> {
        self.state.data.com
    }

    fn tracked_targets(&self) -> Option<&Targets> {
        Some(&self.targets)
    }

    fn report(&self) -> Vec<crate::metrics::ReportLine> {
        let law = &self.posture.0;
        let mut lines = self.stats.lines();
        if let Some((margin, joint)) = self.stats.smallest_margin() {
            let (thesis, met) = match law.law() {
                config::Law::Reparametrised => (
                    "the re-parametrised law never leaves the limits (seed 001 L4432–L4488)",
                    Some(margin > 0.0),
                ),
                config::Law::Classical => (
                    "classical PD: the elbow passes its limit under a −15 N push (seed 001 L4432–L4488)",
                    None,
                ),
            };
            lines.push(crate::metrics::ReportLine {
                figure: format!("smallest distance to a joint limit ({})", law.name(joint)),
                value: margin.to_degrees(),
                unit: "°".into(),
                thesis: self
                    .config
                    .joint_limits
                    .as_ref()
                    .map(|_| thesis.to_string()),
                met: met.filter(|_| self.config.joint_limits.is_some()),
            });
        }
        lines
    }

    fn channels(&self) -> Vec<&'static str> {
        SOFT_TASKS_CHANNELS.to_vec()
    }

    fn push_channels(&self, row: &mut Vec<f64>) {
        row.extend_from_slice(&self.signals);
    }
}
