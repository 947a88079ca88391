//! The passive inverse dynamics of seed 000 ch. 5: TSID's weighted inverse dynamics
//! ([`InverseDynamics`]) under a global energy tank, as the two-stage "alternating" QP of
//! Eq 5.34:
//! 1. at the measured state, the stacked task energy ([`StackedTaskEnergy`]) gives S, Ṡ and
//!    the task power; with the force tasks' power they make `B_σ` (Eq 5.18); `B_φ = vᵀ[h −
//!    Σ_k J_kᵀ f_k]` (Eq 5.19, the contacts' wrenches of the last solution); the tank's
//!    valves give α, β, γ (and β_φ, see [`crate::passivity::EnergyTank`]) and
//!    `Ḣ = βγ Ṡ + (1 − α)(βγ B_σ − β_φ B_φ)` (Eq 5.26);
//! 2. the QP with every motion reference and force-task wrench scaled by βγ (Eq 5.24) and
//!    the power row `Ḣ ≤ −q̇_jᵀτ`.
//!
//! The tank then integrates `Ė_tank = (1 − α)(βγ B_σ − β_φ B_φ)` (Eq 5.22). What the
//! equations leave out is charged to it as well, so that the storage `H = βγ S + E_tank`
//! changes by exactly `Ḣ dt` per tick: the spring energy that appears or goes between ticks outside `βγ Ṡ dt` (βγ rising
//! brings back `Δ(βγ)·S`, a reference step or a task entering the stack adds to S, the
//! discretization). γ is lowered until the tank can pay it. Measured without this charge
//! (`tests/passive_closed_loop.rs`): a 5 cm CoM step gave the robot 5.96 J more than H lost
//! (the spring energy the step creates), a 2 cm step under ten times the CoM gains 9.60 J.
//!
//! The power row bounds `−q̇_jᵀτ` at the tick's velocity, but over the step the torques,
//! held, give the robot `τᵀΔq_j`, which differs where the joints accelerate (under a push
//! on the stiff contact, by tens of watts). The next tick books the difference into the
//! tank from the encoders' Δq, so the tank pays what the robot really received; a safe
//! command's whole step is booked the same way. What an empty tank cannot pay
//! ([`PassiveSignals::unpaid`]) is energy the robot received beyond the storage's loss: the
//! row bounds the power at the tick, not over the step.
//!
//! corps keeps the feet contacts as the equalities of TSID's formulation (the thesis weighs
//! them at 100 in the cost and also holds `J_c q̈ = −J̇_c v`); they enter the stacked energy
//! and, so that one scale makes the power balance exact, their references (PD and drift) are
//! scaled by βγ like every task's: at βγ = 0 the QP holds `J_c q̈ = 0` instead of `−J̇_c v`,
//! which differ by the feet's drift acceleration. The stacked energy's left inverse weighs
//! each task's rows by the task's weight in the QP, the contacts by [`CONTACT_WEIGHT`]
//! ([`LeftInverse::Weighted`], the default), or is Eq 5.9's `(JᵀJ)⁻¹Jᵀ`
//! ([`LeftInverse::Unweighted`]); [`StackedTaskEnergy`] says what each does. Measured on
//! TALOS (`tests/passive_closed_loop.rs`, a 5 cm CoM step): with Eq 5.9's the power row
//! binds at most ticks, the torques chatter, the tank empties and the robot drifts off its
//! reference; with the weighted one the CoM reaches it.
//!
//! A tick whose stage 1 or QP fails gives the safe command and its reason; the next tick
//! books that command's step, takes no Λ̇, and pays the tasks' whole spring energy when they
//! come back (the safe command holds none).

use super::qp_terms::torque_tick;
use super::InverseDynamics;
use crate::error::{ControlError, Result};
use crate::passivity::{EnergyTank, StackedTaskEnergy, TaskPower, Valves};
use crate::robot_state::RobotState;
use crate::FallbackReason;
use corps_model::{difference_to, Model};
use nalgebra::{DVector, Vector6};

/// The tank's signals of one tick, for the log (seed 000 §4.5's figures).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PassiveSignals {
    /// E_tank at the start of the tick, after booking the last step (J).
    pub tank_energy: f64,
    pub valves: Valves,
    /// B_σ and B_φ (W).
    pub b_sigma: f64,
    pub b_phi: f64,
    /// Ḣ, the storage rate the QP was held to (W); NaN on a tick that fell back.
    pub h_dot: f64,
    /// −q̇_jᵀτ of the command sent (W): the power the robot port gives the controller.
    pub passivity_bound: f64,
    /// S and the other task energy figures (unscaled).
    pub task: TaskPower,
    /// Energy the tank paid the spring at the start of the tick, u (J; negative: received).
    pub spring_payment: f64,
    /// Energy the controller received from the robot over the last step, −τᵀΔq_j (J), of
    /// the torques held over the step and the joints' motion; the tank has taken the
    /// difference with what the last tick expected.
    pub port_energy: f64,
    /// Energy booked this tick that the empty tank could not pay (J, ≥ 0): what the robot
    /// received beyond the storage's loss.
    pub unpaid: f64,
}

/// The energy tank and its stage-1 workspace; it runs an [`InverseDynamics`] it does not own.
pub struct PassiveInverseDynamics {
    pub tank: EnergyTank,
    energy: StackedTaskEnergy,
    /// Wrenches of the last solution, by contact frame (for B_φ).
    last_wrenches: Vec<(usize, Vector6<f64>)>,
    frame_velocity: Vector6<f64>,
    /// βγ, S and Ṡ of the last tick (None before the first; zeros after a fallback, whose
    /// safe command holds no spring).
    prev: Option<(f64, f64, f64)>,
    /// The last tick's configuration and joint torques, and the energy it expected to
    /// receive over its step (−q̇_jᵀτ dt; 0 for a safe command): the next tick books the
    /// difference with what it received, −τᵀΔq_j.
    last_q: DVector<f64>,
    last_tau: DVector<f64>,
    last_expected: Option<f64>,
    dq: DVector<f64>,

    /// The interval to the next tick and since the last one (s): the control period unless
    /// [`PassiveInverseDynamics::set_periods`] says otherwise.
    dt: f64,
    last_dt: f64,
    /// Which left inverse of the stacked Jacobian defines Λ. Default: the weighted one.
    pub left_inverse: LeftInverse,
    /// Weight of the contacts' motion rows (and of priority-0 tasks) in `J†_W` (see
    /// [`StackedTaskEnergy`]): they are equalities of the QP, so heavier than any weighted
    /// task. Default [`CONTACT_WEIGHT`].
    pub contact_weight: f64,
    pub signals: PassiveSignals,
}

/// The left inverse `J†` of the stacked task Jacobian in `Λ = J†ᵀ M J†`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum LeftInverse {
    /// `(JᵀJ)⁻¹Jᵀ`, seed 000 Eq 5.9.
    Unweighted,
    /// `(JᵀWJ)⁻¹JᵀW`, W the tasks' weights in the QP (contacts [`CONTACT_WEIGHT`]).
    #[default]
    Weighted,
}

/// Default weight of the contacts' rows in `J†_W`: 10⁴, a hundred times the heaviest task
/// weight of seed 000 Tables 5.1 and 5.3 (feet contacts and feet tracking, 100).
pub const CONTACT_WEIGHT: f64 = 1e4;

impl PassiveInverseDynamics {
    /// A passive layer over any inverse dynamics of `model`, control period `dt` (s).
    pub fn new(model: &Model, tank: EnergyTank, dt: f64) -> Result<Self> {
        if !(dt > 0.0 && dt.is_finite()) {
            return Err(ControlError::Config {
                name: "energy tank".into(),
                reason: format!("control period must be finite and > 0, got {dt} s"),
            });
        }
        Ok(Self {
            tank,
            energy: StackedTaskEnergy::new(model.nv, 2 * model.nv),
            last_wrenches: Vec::with_capacity(16),
            frame_velocity: Vector6::zeros(),
            prev: None,
            last_q: DVector::zeros(model.nq),
            last_tau: DVector::zeros(model.na()),
            last_expected: None,
            dq: DVector::zeros(model.nv),
            dt,
            last_dt: dt,
            left_inverse: LeftInverse::default(),
            contact_weight: CONTACT_WEIGHT,
            signals: PassiveSignals::default(),
        })
    }

    /// Sets the intervals around the next tick (s) for a loop whose ticks come at irregular
    /// times (a best-effort high-level loop): `since_last` since the previous tick (Λ̇'s
    /// finite difference and the spring energy the previous tick predicted) and `until_next`
    /// to the following one (the tank's Euler step, the energy the port is expected to give
    /// and the bounds of one step). `H` changes by exactly `Ḣ dt` per tick when each tick's
    /// `since_last` is the previous tick's `until_next`; a real best-effort loop knows the
    /// next interval only approximately, and what the robot really received over the true
    /// interval is booked at the next tick from Δq either way. Intervals that are not finite
    /// and positive are ignored.
    pub fn set_periods(&mut self, since_last: f64, until_next: f64) {
        if since_last > 0.0 && since_last.is_finite() {
            self.last_dt = since_last;
        }
        if until_next > 0.0 && until_next.is_finite() {
            self.dt = until_next;
        }
    }

    /// One torque-mode tick of `id` under the tank (see the module): writes the joint torques
    /// (na) to `tau`, or the safe command and its reason. `id`'s reference scale and power
    /// row hold for this tick only: it leaves them at 1 and none.
    #[allow(clippy::too_many_arguments)]
    pub fn tick(
        &mut self,
        id: &mut InverseDynamics,
        model: &Model,
        state: &mut RobotState,
        t: f64,
        q: &[f64],
        v: &[f64],
        safe_damping: f64,
        tau: &mut DVector<f64>,
    ) -> Option<FallbackReason> {
        self.book_last_step(model, q);
        self.signals.tank_energy = self.tank.energy();
        let mut step = (0.0, 0.0);
        let reason = torque_tick(model, state, q, v, safe_damping, tau, |state, tau| {
            id.update_transitions(t);
            step = self.stage_one(id, model, state)?;
            tau.copy_from(&id.compute(model, state)?.tau);
            Ok(())
        });
        id.rows_current = false;
        id.reference_scale = 1.0;
        id.passivity = None;

        let first = model.nv.saturating_sub(tau.len());
        self.signals.passivity_bound = -(0..tau.len())
            .map(|k| v.get(first + k).copied().unwrap_or(0.0) * tau[k])
            .sum::<f64>();
        let expected = self.signals.passivity_bound * self.dt;
        let shapes_match = self.last_q.len() == q.len() && self.last_tau.len() == tau.len();
        self.last_expected = if shapes_match && q.iter().all(|x| x.is_finite()) {
            self.last_q.copy_from_slice(q);
            self.last_tau.copy_from(tau);
            Some(if reason.is_some() { 0.0 } else { expected })
        } else {
            None
        };
        if reason.is_some() {
            // The safe command holds no task spring: when the tasks come back, the tank
            // pays their whole spring energy.
            self.signals.h_dot = f64::NAN;
            self.signals.spring_payment = 0.0;
            self.energy.forget();
            self.prev = Some((0.0, 0.0, 0.0));
        } else {
            let (rate, paid) = step;
            self.signals.unpaid += self.tank.transfer(-paid);
            self.tank.integrate(rate, self.dt);
            let s = &self.signals;
            self.prev = Some((s.valves.scale(), s.task.storage, s.task.storage_rate));
            self.keep_wrenches(id);
        }
        reason
    }

    /// Stage 1: the task energy, B_σ, B_φ, the valves and Ḣ; sets `id`'s reference scale
    /// and power row. Returns Ė_tank and the energy u the tank pays the spring at once.
    fn stage_one(
        &mut self,
        id: &mut InverseDynamics,
        model: &Model,
        s: &RobotState,
    ) -> Result<(f64, f64)> {
        let nv = model.nv;
        let e = &mut self.energy;
        e.clear();
        for entry in id.tasks.entries_mut() {
            // A priority-0 task is an equality of the QP: it weighs as a contact.
            let weight = match (self.left_inverse, entry.priority) {
                (LeftInverse::Unweighted, _) => 1.0,
                (LeftInverse::Weighted, 0) => self.contact_weight,
                (LeftInverse::Weighted, _) => entry.weight,
            };
            let n = {
                let rows = entry.task.compute(model, s)?;
                if rows.a.ncols() != nv || rows.a.nrows() < rows.rows() {
                    return Err(size_error(&entry.name, "its Jacobian rows", nv));
                }
                e.push_jacobian(&rows.a, rows.rows(), weight);
                rows.rows()
            };
            let terms = entry
                .task
                .error_terms()
                .ok_or_else(|| ControlError::Config {
                    name: format!("task '{}'", entry.name),
                    reason: "the energy tank needs each task's error and gains (E, Ė, K_P, K_D), \
                         which this task does not give"
                        .into(),
                })?;
            if terms.rows() < n {
                return Err(size_error(&entry.name, "its error terms", n));
            }
            e.push_terms(n, terms);
        }
        let mut signature = id.tasks.structure();
        for contact in &mut id.contacts {
            contact.compute(model, s)?;
            let n = contact.n_motion();
            let weight = match self.left_inverse {
                LeftInverse::Unweighted => 1.0,
                LeftInverse::Weighted => self.contact_weight,
            };
            e.push(&contact.motion_rows().a, n, weight, contact.motion.terms());
            signature = signature
                .wrapping_mul(1_000_003)
                .wrapping_add(contact.frame as u64 + 1);
        }
        let v = &s.v;
        let task = e.compute(&s.data.m, v, signature, self.last_dt)?;
        // Force tasks' power vᵀ J_Fᵀ T_Fᵀ F_F (their wanted wrench, contact frame) and the
        // other contacts' power vᵀ J_kᵀ T_kᵀ f_k (last solution).
        let (mut force_power, mut contact_power) = (0.0, 0.0);
        for contact in &id.contacts {
            let a = &contact.motion_rows().a;
            for r in 0..6 {
                self.frame_velocity[r] = (0..nv).map(|c| a[(r, c)] * v[c]).sum();
            }
            let mut under_force_task = false;
            for (f, _) in id
                .contact_forces
                .iter()
                .filter(|(f, _)| f.contact == contact.name)
            {
                force_power += f.desired.dot(&self.frame_velocity);
                under_force_task = true;
            }
            if !under_force_task {
                if let Some((_, w)) = self.last_wrenches.iter().find(|(k, _)| *k == contact.frame) {
                    contact_power += w.dot(&self.frame_velocity);
                }
            }
        }
        let b_sigma = task.b_sigma_tasks + force_power;
        let b_phi = v.dot(&s.data.nle) - contact_power;
        if !(b_sigma.is_finite() && b_phi.is_finite() && task.storage.is_finite()) {
            return Err(ControlError::NonFinite("energy tank power"));
        }
        let mut valves = self.tank.valves(b_sigma, b_phi);
        // The spring's energy βγS changes over the step by βγ Ṡ dt in Ḣ; whatever else it
        // gained since the last tick (βγ rising, a reference step, a task or contact entering
        // the stack, the discretization) the tank pays, and whatever it lost the tank takes:
        // u = βγ_k S_k − βγ_{k−1} (S_{k−1} + Ṡ_{k−1} dt). Then H = βγS + E_tank changes by
        // exactly Ḣ dt per tick. γ is lowered until the tank can pay u.
        let energy = self.tank.energy();
        let storage = task.storage;
        let base = self
            .prev
            .map(|(scale, s, s_dot)| scale * (s + s_dot * self.last_dt));
        if let Some(base) = base.filter(|_| storage > 0.0) {
            let cap = ((energy + base) / storage).max(0.0);
            if cap < valves.scale() {
                valves.gamma = if valves.beta > 0.0 {
                    (cap / valves.beta).clamp(0.0, valves.gamma)
                } else {
                    0.0
                };
            }
        }
        let scale = valves.scale();
        let paid = base.map_or(0.0, |base| scale * storage - base);
        // The tank after paying u, then one Euler step that neither pays more than it holds
        // nor fills it past E_max: β_φ and α close it smoothly, but under a fall or a hard
        // push B_σ and B_φ reach kW and one step would overshoot. Lowering the rate lowers
        // Ḣ, which only loosens the power row; raising it (the drain bound) tightens the row,
        // so the QP then injects no more than the tank holds, or fails to the safe command.
        let after = (energy - paid).clamp(0.0, self.tank.params.e_max);
        let room = self.tank.params.e_max - after;
        let rate = EnergyTank::rate(&valves, b_sigma, b_phi)
            .min(room / self.dt)
            .max(-after / self.dt);
        let h_dot = scale * task.storage_rate + rate;
        if !(rate.is_finite() && h_dot.is_finite() && paid.is_finite()) {
            return Err(ControlError::NonFinite("energy tank rate"));
        }
        id.reference_scale = scale;
        id.passivity = Some(h_dot);
        id.rows_current = true;

        self.signals = PassiveSignals {
            tank_energy: energy,
            valves,
            b_sigma,
            b_phi,
            h_dot,
            passivity_bound: 0.0,
            task,
            spring_payment: paid,
            port_energy: self.signals.port_energy,
            unpaid: self.signals.unpaid,
        };
        Ok((rate, paid))
    }

    /// Books into the tank the difference between the energy the last step gave the
    /// controller, `−τᵀΔq_j` (exact for torques held over the step), and what its tick
    /// expected, `−q̇_jᵀτ dt`: the power row bounds the latter only.
    fn book_last_step(&mut self, model: &Model, q: &[f64]) {
        self.signals.port_energy = 0.0;
        self.signals.unpaid = 0.0;
        let Some(expected) = self.last_expected.take() else {
            return;
        };
        if difference_to(model, self.last_q.as_slice(), q, self.dq.as_mut_slice()).is_err() {
            return;
        }
        let first = model.nv - self.last_tau.len();
        let received = -(0..self.last_tau.len())
            .map(|k| self.last_tau[k] * self.dq[first + k])
            .sum::<f64>();
        if received.is_finite() {
            self.signals.port_energy = received;
            self.signals.unpaid = self.tank.transfer(received - expected);
        }
    }

    fn keep_wrenches(&mut self, id: &InverseDynamics) {
        self.last_wrenches.clear();
        for (k, contact) in id.contacts.iter().enumerate() {
            self.last_wrenches
                .push((contact.frame, id.contact_wrench(k)));
        }
    }
}

fn size_error(task: &str, what: &str, expected: usize) -> ControlError {
    ControlError::Config {
        name: format!("task '{task}'"),
        reason: format!("{what} do not match the model: expected {expected}"),
    }
}
