//! The fixed-base passive QP of seed 000 §3.19 (Eq 6.1–6.2, Table 6.1) on an arm with a
//! tool: the passive inverse dynamics of ch. 5 ([`PassiveInverseDynamics`]) on a model
//! without a free flyer, so that q̈ and the tool's contact force are the decision variables
//! and `M q̈ + C q̇ + g = τ + J_cᵀ F` gives τ. Its stack:
//! - the end-effector task on the tool tip (SE(3), weight 100), its linear rows replaced by
//!   the tip's point contact while the tool presses (the contact is an equality, as corps
//!   keeps every contact; the thesis weighs it at 100 in the cost);
//! - the Cartesian force-contact task on that contact (weight 50), a PI+ on the clamp load
//!   cell through a first-order low-pass;
//! - the posture (weight 0.1) towards the starting posture;
//! - `F_min ≤ F⊥ ≤ F_max` and the slip pyramid `|f_slip| ≤ μ_s F⊥` on the contact, the
//!   joints' position and velocity limits as bounds on q̈, the effort limits, and the tank's
//!   power row `Ḣ ≤ −q̇ᵀτ`.
//!
//! The tip frame sits at the tool's end with its z axis pointing back along the tool, so that
//! facing the plate it is the plate's normal: the contact's normal is the frame's +z.

use super::section::DrillingScenario;
use crate::error::Result;
use corps_control::contacts::Contact;
use corps_control::formulation::{InverseDynamics, PassiveInverseDynamics};
use corps_control::passivity::{EnergyTank, TankParams};
use corps_control::tasks::{ContactForceTask, JointBoundsTask, PostureTask, Se3Reference, Se3Task};
use corps_control::{FallbackReason, RobotState};
use corps_model::spatial::{Motion, Se3};
use corps_model::Model;
use nalgebra::{DVector, Vector3, Vector6};
use std::sync::Arc;

/// Name of the tool's contact and of the end-effector task.
pub const CONTACT: &str = "tool";
pub const END_EFFECTOR: &str = "end_effector";

/// The arm's controller: the passive QP and its tool contact's force loop.
pub struct ArmController {
    model: Arc<Model>,
    pub id: InverseDynamics,
    pub passive: PassiveInverseDynamics,
    pub state: RobotState,
    tip: usize,
    /// The contact's gains and bounds, kept to make it at each touch.
    contact_kp: f64,
    slip_ratio: f64,
    f_max: f64,
    transition: f64,
    force_lowpass_hz: f64,
    safe_damping: f64,
    /// The joint torques of the last QP (na).
    pub tau: DVector<f64>,
    /// The force task with its weight, held aside while the tool is off the plate.
    force_task: Option<(ContactForceTask, f64)>,
    /// The low-passed load cell (N) and its last value, for the PI+'s derivative.
    filtered: Option<f64>,
    last_filtered: f64,
    /// The normal force the PI+ asked the QP for, and the one it solved (N).
    pub force_desired: f64,
    pub force_solved: f64,
}

impl ArmController {
    /// The controller at configuration `q0`, at rest, its end-effector task holding the tip
    /// (frame `tip`) where it is.
    pub fn new(
        model: Arc<Model>,
        tip: usize,
        q0: &DVector<f64>,
        s: &DrillingScenario,
    ) -> Result<Self> {
        let nv = model.nv;
        let na = model.na();
        let mut state = RobotState::new(&model);
        state.update(&model, q0.as_slice(), &vec![0.0; nv])?;
        let g = &s.gains;
        let w = &s.weights;
        let mut id = InverseDynamics::new(&model);
        let kd = |kp: f64| 2.0 * kp.sqrt();
        let ee = Se3Task::new(
            nv,
            tip,
            Vector6::repeat(g.end_effector),
            Vector6::repeat(kd(g.end_effector)),
            at_rest(state.frame_placement(&model, tip)?),
        );
        id.tasks.add(END_EFFECTOR, ee, 1, w.end_effector)?;
        let posture = PostureTask::new(
            &model,
            DVector::repeat(na, g.posture),
            DVector::repeat(na, kd(g.posture)),
            q0.clone(),
        );
        id.tasks.add("posture", posture, 1, w.posture)?;
        id.joint_bounds = Some(JointBoundsTask::new(&model, g.bounds_horizon));
        let limit = model
            .effort_limit
            .rows(model.first_actuated(), na)
            .into_owned();
        if limit.iter().any(|l| !(*l > 0.0 && l.is_finite())) {
            crate::error::bail!("arm.urdf: every joint needs a positive effort limit");
        }
        id.actuation = Some((-&limit, limit));
        let t = &s.tank;
        let params = TankParams {
            e_max: t.e_max,
            e_min: t.e_min,
            p_low: t.p_low,
            ..TankParams::default()
        };
        let tank = EnergyTank::new(params, t.initial)?;
        let passive = PassiveInverseDynamics::new(&model, tank, 1.0 / s.loops.qp_rate_hz)?;
        let force = ContactForceTask::new(
            CONTACT,
            Vector6::repeat(g.force_kp),
            Vector6::zeros(),
            Vector6::repeat(g.force_ki),
        );
        Ok(Self {
            force_task: Some((force, w.force)),
            id,
            passive,
            state,
            tip,
            contact_kp: g.contact,
            slip_ratio: s.clamp.slip_ratio,
            f_max: s.clamp.f_max,
            transition: g.contact_transition,
            force_lowpass_hz: g.force_lowpass_hz,
            safe_damping: g.safe_damping,
            tau: DVector::zeros(na),
            filtered: None,
            last_filtered: 0.0,
            force_desired: 0.0,
            force_solved: 0.0,
            model,
        })
    }

    /// The end-effector task's reference.
    pub fn set_pose_reference(&mut self, reference: &Se3Reference) {
        if let Some(task) = self.id.tasks.task_mut::<Se3Task>(END_EFFECTOR) {
            task.reference.clone_from(reference);
        }
    }

    /// Whether the tool's contact is in the QP.
    pub fn in_contact(&self) -> bool {
        self.id.contacts.iter().any(|c| c.name == CONTACT)
    }

    /// Makes the tip's point contact at time `t` where the tip is (`placement`): its force
    /// bound rises over the transition; the end-effector task keeps the tool's orientation
    /// only; the force task comes in.
    pub fn make_contact(&mut self, t: f64, placement: Se3) {
        let kp = Vector3::repeat(self.contact_kp);
        let mut contact = Contact::point(
            &self.model,
            CONTACT,
            self.tip,
            Vector3::z(),
            self.slip_ratio,
            (0.0, self.f_max),
            kp,
            kp.map(|k| 2.0 * k.sqrt()),
            at_rest(placement),
        );
        contact.force_reg_weight = 1e-5;
        self.id.add_contact(contact, t, self.transition);
        if let Some(task) = self.id.tasks.task_mut::<Se3Task>(END_EFFECTOR) {
            task.mask = Vector6::new(0.0, 0.0, 0.0, 1.0, 1.0, 1.0);
        }
        if let Some(f) = self.force_task.take() {
            self.id.contact_forces.push(f);
        }
    }

    /// Sets the contact's least normal force (N): `F_min` while the force is held, 0 while it
    /// rises or falls.
    pub fn set_min_force(&mut self, f_min: f64) {
        if let Some(c) = self.id.contacts.iter_mut().find(|c| c.name == CONTACT) {
            c.fmin = f_min;
        }
    }

    /// Releases the contact at time `t` (its force bound falls over the transition); the
    /// end-effector task takes the whole pose again, from `reference`.
    pub fn release(&mut self, t: f64, reference: &Se3Reference) -> Result<()> {
        if let Some(k) = self
            .id
            .contact_forces
            .iter()
            .position(|(f, _)| f.contact == CONTACT)
        {
            self.force_task = Some(self.id.contact_forces.remove(k));
        }
        self.id.remove_contact(CONTACT, t, self.transition)?;
        if let Some(task) = self.id.tasks.task_mut::<Se3Task>(END_EFFECTOR) {
            task.mask = Vector6::repeat(1.0);
        }
        self.set_pose_reference(reference);
        self.filtered = None;
        Ok(())
    }

    /// One QP at time `t`, `dt` after the last and `until_next` before the next, at the
    /// measured state (q, v), the clamp load cell reading `load` (N) and the force reference
    /// `force_ref` (N) with its rate: the joint torques into `tau`, or the safe command and
    /// its reason.
    #[allow(clippy::too_many_arguments)]
    pub fn tick(
        &mut self,
        t: f64,
        dt: f64,
        until_next: f64,
        q: &[f64],
        v: &[f64],
        load: f64,
        force_ref: f64,
        force_rate: f64,
    ) -> Option<FallbackReason> {
        let a = 1.0 - (-std::f64::consts::TAU * self.force_lowpass_hz * dt).exp();
        let filtered = match self.filtered {
            Some(f) => f + (load - f) * a,
            None => load,
        };
        let derivative = if self.filtered.is_some() && dt > 0.0 {
            (filtered - self.last_filtered) / dt
        } else {
            0.0
        };
        self.filtered = Some(filtered);
        self.last_filtered = filtered;
        if let Some((task, _)) = self
            .id
            .contact_forces
            .iter_mut()
            .find(|(f, _)| f.contact == CONTACT)
        {
            task.reference = Vector6::new(0.0, 0.0, force_ref, 0.0, 0.0, 0.0);
            task.reference_derivative = Vector6::new(0.0, 0.0, force_rate, 0.0, 0.0, 0.0);
            let measured = Vector6::new(0.0, 0.0, filtered, 0.0, 0.0, 0.0);
            let rate = Vector6::new(0.0, 0.0, derivative, 0.0, 0.0, 0.0);
            task.update(&measured, &rate, dt);
            self.force_desired = task.desired[2];
        } else {
            self.force_desired = 0.0;
        }
        self.passive.set_periods(dt, until_next);
        let model = self.model.clone();
        let reason = self.passive.tick(
            &mut self.id,
            &model,
            &mut self.state,
            t,
            q,
            v,
            self.safe_damping,
            &mut self.tau,
        );
        self.force_solved = match self.id.contacts.iter().position(|c| c.name == CONTACT) {
            Some(k) if reason.is_none() => self.id.normal_force(k),
            _ => 0.0,
        };
        reason
    }

    /// The QP's joint accelerations of the last tick.
    pub fn acceleration(&self) -> &DVector<f64> {
        &self.id.output.dv
    }

    /// The tip frame.
    pub fn tip(&self) -> usize {
        self.tip
    }
}

/// A reference at rest at `placement`.
pub fn at_rest(placement: Se3) -> Se3Reference {
    Se3Reference {
        placement,
        velocity: Motion::zero(),
        acceleration: Motion::zero(),
    }
}
