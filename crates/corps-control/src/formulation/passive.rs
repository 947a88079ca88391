//! The passive inverse dynamics of seed 000 ch. 5: TSID's weighted inverse dynamics
//! ([`InverseDynamics`]) under a global energy tank, as the two-stage "alternating" QP of
//! Eq 5.34:
//! 1. at the measured state, the stacked task energy ([`StackedTaskEnergy`]) gives Ṡ and the
//!    task power; with the force tasks' power they make `B_σ` (Eq 5.18); `B_φ = vᵀ[h − Σ_k
//!    J_kᵀ f_k]` (Eq 5.19, the contacts' wrenches of the last solution); the tank's valves
//!    give α, β, γ and `Ḣ = βγ Ṡ + (1 − α)(βγ B_σ − B_φ)` (Eq 5.26);
//! 2. the QP with every motion reference and force-task wrench scaled by βγ (Eq 5.24) and
//!    the passivity row `Ḣ ≤ −q̇_jᵀτ`.
//!
//! The stacked energy's left inverse is Eq 5.9's `(JᵀJ)⁻¹Jᵀ` by default, or
//! ([`LeftInverse::Weighted`]) the one that weighs each task's rows by the task's weight in the
//! QP, the contacts by [`CONTACT_WEIGHT`] (see [`StackedTaskEnergy`] for what each does).
//!
//! The tank then integrates `Ė_tank = (1 − α)(βγ B_σ − B_φ)` (Eq 5.22). corps keeps the feet
//! contacts as the equalities of TSID's formulation (the thesis weighs them at 100 in the
//! cost); they enter the stacked energy and their references are scaled like every task's.
//! A tick whose stage 1 or QP fails gives the safe command and its reason, and the tank
//! holds its energy.

use super::qp_terms::torque_tick;
use super::InverseDynamics;
use crate::error::{ControlError, Result};
use crate::passivity::{EnergyTank, StackedTaskEnergy, TaskPower, Valves};
use crate::robot_state::RobotState;
use crate::FallbackReason;
use corps_model::Model;
use nalgebra::{DVector, Vector6};

/// The tank's signals of one tick, for the log (seed 000 §4.5's figures).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PassiveSignals {
    /// E_tank at the start of the tick (J).
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
}

/// The energy tank and its stage-1 workspace; it runs an [`InverseDynamics`] it does not own.
pub struct PassiveInverseDynamics {
    pub tank: EnergyTank,
    energy: StackedTaskEnergy,
    /// Wrenches of the last solution, by contact frame (for B_φ).
    last_wrenches: Vec<(usize, Vector6<f64>)>,
    frame_velocity: Vector6<f64>,
    dt: f64,
    /// Which left inverse of the stacked Jacobian defines Λ. Default: Eq 5.9's.
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
    #[default]
    Unweighted,
    /// `(JᵀWJ)⁻¹JᵀW`, W the tasks' weights in the QP (contacts [`CONTACT_WEIGHT`]).
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
            dt,
            left_inverse: LeftInverse::default(),
            contact_weight: CONTACT_WEIGHT,
            signals: PassiveSignals::default(),
        })
    }

    /// One torque-mode tick of `id` under the tank (see the module): writes the joint torques
    /// (na) to `tau`, or the safe command and its reason.
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
        self.signals.tank_energy = self.tank.energy();
        let mut rate = 0.0;
        let reason = torque_tick(model, state, q, v, safe_damping, tau, |state, tau| {
            id.update_transitions(t);
            rate = self.stage_one(id, model, state)?;
            tau.copy_from(&id.compute(model, state)?.tau);
            Ok(())
        });
        let first = model.nv - tau.len();
        self.signals.passivity_bound = -(0..tau.len())
            .map(|k| v.get(first + k).copied().unwrap_or(0.0) * tau[k])
            .sum::<f64>();
        if reason.is_some() {
            self.signals.h_dot = f64::NAN;
            id.passivity = None;
            id.reference_scale = 1.0;
        } else {
            self.tank.integrate(rate, self.dt);
            self.keep_wrenches(id);
        }
        reason
    }

    /// Stage 1: the task energy, B_σ, B_φ, the valves and Ḣ; sets `id`'s reference scale
    /// and passivity row. Returns Ė_tank.
    fn stage_one(
        &mut self,
        id: &mut InverseDynamics,
        model: &Model,
        s: &RobotState,
    ) -> Result<f64> {
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
        let task = e.compute(&s.data.m, v, signature, self.dt)?;
        // Force tasks' power vᵀ J_Fᵀ T_Fᵀ F_F (their wanted wrench, contact frame) and the
        // other contacts' power vᵀ J_kᵀ T_kᵀ f_k (last solution).
        let (mut force_power, mut contact_power) = (0.0, 0.0);
        for contact in &id.contacts {
            let a = &contact.motion_rows().a;
            for r in 0..6 {
                self.frame_velocity[r] = (0..model.nv).map(|c| a[(r, c)] * v[c]).sum();
            }
            let task = id
                .contact_forces
                .iter()
                .find(|(f, _)| f.contact == contact.name);
            match task {
                Some((f, _)) => force_power += f.desired.dot(&self.frame_velocity),
                None => {
                    if let Some((_, w)) =
                        self.last_wrenches.iter().find(|(k, _)| *k == contact.frame)
                    {
                        contact_power += w.dot(&self.frame_velocity);
                    }
                }
            }
        }
        let b_sigma = task.b_sigma_tasks + force_power;
        let b_phi = v.dot(&s.data.nle) - contact_power;
        let valves = self.tank.valves(b_sigma, b_phi);
        // One Euler step neither pays more than the tank holds nor fills it past E_max (β_φ
        // and α close the tank smoothly; under a fall or a hard push B_σ, B_φ reach kW and
        // one step would overshoot). Discarding energy only lowers Ḣ, so the bound holds.
        let e = self.tank.energy();
        let room = (self.tank.params.e_max - e).max(0.0);
        let rate = EnergyTank::rate(&valves, b_sigma, b_phi)
            .min(room / self.dt)
            .max(-e / self.dt);
        let h_dot = valves.scale() * task.storage_rate + rate;
        id.reference_scale = valves.scale();
        id.passivity = Some(h_dot);
        id.rows_current = true;
        self.signals = PassiveSignals {
            tank_energy: self.tank.energy(),
            valves,
            b_sigma,
            b_phi,
            h_dot,
            passivity_bound: 0.0,
            task,
        };
        Ok(rate)
    }

    fn keep_wrenches(&mut self, id: &InverseDynamics) {
        self.last_wrenches.clear();
        for (k, contact) in id.contacts.iter().enumerate() {
            if self.last_wrenches.len() < self.last_wrenches.capacity() {
                self.last_wrenches
                    .push((contact.frame, id.contact_wrench(k)));
            }
        }
    }
}
