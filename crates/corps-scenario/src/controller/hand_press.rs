//! A hand's tool held on a surface as a point contact with a force task on it (the
//! `[press]` of a scenario; seed 000 §5.4.1): the force reference follows the schedule, the
//! PI+ task reads the hand's F/T sensor through the estimator and a first-order low-pass
//! (`force_lowpass_hz`, whose docs say why), and `loss_delay` after the tip has dropped
//! `loss_drop` below where it touched the contact and the task are removed (the thesis's
//! hand-coded emergency action, L6478–L6486).

use crate::error::Result;
use crate::gains::TsidGains;
use crate::press::PressSection;
use corps_control::contacts::Contact;
use corps_control::formulation::InverseDynamics;
use corps_control::tasks::{ContactForceTask, Se3Reference};
use corps_control::{FallbackReason, RobotState};
use corps_model::spatial::Motion;
use corps_model::Model;
use nalgebra::{Vector3, Vector6};

/// The hand's log columns: the force reference F* and the measured (filtered) force along the
/// contact normal, what the task asks the QP for (PI+ output), whether the contact is held, and how
/// far the tip is below where it touched.
pub const HAND_CHANNELS: [&str; 6] = [
    "hand_force_ref_N",
    "hand_force_N",
    "hand_force_desired_N",
    "hand_force_qp_N",
    "hand_contact",
    "tool_drop_m",
];

pub struct HandPress {
    name: String,
    frame: usize,
    section: PressSection,
    transition: f64,
    /// Tip height where the contact was made (m).
    touch_z: f64,
    active: bool,
    /// When the loss was seen and when the contact was removed (s since the handover).
    pub lost_at: Option<f64>,
    pub released_at: Option<f64>,
    reference: f64,
    measured: f64,
    desired: f64,
    /// The normal force of the hand's contact in the last QP solution.
    solved: f64,
    drop: f64,
    /// The filtered wrench, None before the first reading.
    filtered: Option<Vector6<f64>>,
    /// The last filtered wrench, for the derivative term.
    last_wrench: Option<Vector6<f64>>,
    /// The force read at the first update, where the reference starts.
    start_force: Option<f64>,
}

impl HandPress {
    /// Adds the contact at the tool tip `frame` (held where it is in `state`) and its force
    /// task (gains `[force_contact]`) to `id`.
    pub fn new(
        model: &Model,
        id: &mut InverseDynamics,
        state: &RobotState,
        frame: usize,
        section: &PressSection,
        gains: &TsidGains,
    ) -> Result<Self> {
        let Some(force) = &gains.force_contact else {
            crate::error::bail!(
                "controller.gains: [press] needs a [force_contact] section (the force task's gains)"
            );
        };
        let placement = state.frame_placement(model, frame)?;
        let c = &gains.contacts;
        let kp = Vector3::repeat(c.kp);
        let kd = Vector3::repeat(c.kd.unwrap_or(2.0 * c.kp.sqrt()));
        let name = format!("{}_tool", section.hand);
        let mut contact = Contact::point(
            model,
            &name,
            frame,
            Vector3::z(),
            c.mu,
            (0.0, c.fmax),
            kp,
            kd,
            Se3Reference {
                placement,
                velocity: Motion::zero(),
                acceleration: Motion::zero(),
            },
        );
        contact.force_reg_weight = c.force_regularization;
        id.contacts.push(contact);
        let mut task = ContactForceTask::new(
            &name,
            Vector6::repeat(force.kp),
            Vector6::repeat(force.kd),
            Vector6::repeat(force.ki),
        );
        task.leak = force.leak;
        id.contact_forces.push((task, force.weight));
        Ok(Self {
            name,
            frame,
            section: section.clone(),
            transition: c.transition,
            touch_z: placement.translation.z,
            active: true,
            lost_at: None,
            released_at: None,
            reference: 0.0,
            measured: 0.0,
            desired: 0.0,
            solved: 0.0,
            drop: 0.0,
            filtered: None,
            last_wrench: None,
            start_force: None,
        })
    }

    /// Before the QP at `t`: the force reference, the PI+ update from `wrench` (the hand's
    /// contact wrench in the tip frame, None without a reading) over `dt`, and the emergency
    /// removal when the tip (in `state`, the last tick's kinematics) has dropped too far.
    pub fn update(
        &mut self,
        t: f64,
        dt: f64,
        model: &Model,
        id: &mut InverseDynamics,
        state: &RobotState,
        wrench: Option<&Vector6<f64>>,
    ) -> Result<(), FallbackReason> {
        let z = state
            .frame_placement(model, self.frame)
            .map_err(|e| FallbackReason::BadState(e.to_string()))?
            .translation
            .z;
        self.drop = self.touch_z - z;
        let a = 1.0 - (-2.0 * std::f64::consts::PI * self.section.force_lowpass_hz * dt).exp();
        let read = wrench.copied().unwrap_or_else(Vector6::zeros);
        let filtered = match self.filtered {
            Some(f) => f + (read - f) * a,
            None => read,
        };
        self.filtered = Some(filtered);
        self.measured = filtered[2];
        if !self.active {
            return Ok(());
        }
        if self.lost_at.is_none() && self.drop > self.section.loss_drop {
            self.lost_at = Some(t);
        }
        if self
            .lost_at
            .is_some_and(|lost| t >= lost + self.section.loss_delay)
        {
            self.active = false;
            self.released_at = Some(t);
            self.reference = 0.0;
            self.desired = 0.0;
            id.contact_forces.retain(|(f, _)| f.contact != self.name);
            return id
                .remove_contact(&self.name, t, self.transition)
                .map_err(FallbackReason::Controller);
        }
        let f0 = *self.start_force.get_or_insert(self.measured);
        let (f, rate) = self.section.force_at(t, f0);
        self.reference = f;
        let measured = filtered;
        let derivative = match self.last_wrench {
            Some(last) if dt > 0.0 => (measured - last) / dt,
            _ => Vector6::zeros(),
        };
        self.last_wrench = Some(measured);
        if let Some((task, _)) = id
            .contact_forces
            .iter_mut()
            .find(|(task, _)| task.contact == self.name)
        {
            task.reference = Vector6::new(0.0, 0.0, f, 0.0, 0.0, 0.0);
            task.reference_derivative = Vector6::new(0.0, 0.0, rate, 0.0, 0.0, 0.0);
            task.update(&measured, &derivative, dt);
            self.desired = task.desired[2];
        }
        Ok(())
    }

    /// After the QP: reads the hand's force in its solution.
    pub fn after_tick(&mut self, id: &InverseDynamics) {
        self.solved = match id.contacts.iter().position(|c| c.name == self.name) {
            Some(k) => id.normal_force(k),
            None => 0.0,
        };
    }

    /// The values of [`HAND_CHANNELS`].
    pub fn channels(&self) -> [f64; 6] {
        [
            self.reference,
            self.measured,
            self.desired,
            self.solved,
            if self.active { 1.0 } else { 0.0 },
            self.drop,
        ]
    }
}
