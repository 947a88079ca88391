//! The safe command when the controller cannot produce one: a failed QP or a non-finite state
//! never reaches the motors; instead the joints get gravity compensation with damping
//! (τ = g_a(q) − d·v_a, clamped at the effort limits), or pure damping when q is unusable, or
//! zero torque when nothing is measured. The reason is returned with the command.

use crate::error::ControlError;
use corps_model::{generalized_gravity, Data, Model};
use nalgebra::DVector;

/// Why the safe command was used.
#[derive(Clone, Debug, PartialEq)]
pub enum FallbackReason {
    /// The state (q or v) holds NaN or infinity, or has the wrong size.
    BadState(String),
    /// The controller failed (infeasible QP, iteration limit, ...).
    Controller(ControlError),
}

impl std::fmt::Display for FallbackReason {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            FallbackReason::BadState(s) => write!(f, "bad state: {s}"),
            FallbackReason::Controller(e) => write!(f, "controller failed: {e}"),
        }
    }
}

/// Computes safe joint torques (na) into `tau`.
pub fn safe_torques(
    model: &Model,
    data: &mut Data,
    q: &[f64],
    v: &[f64],
    damping: f64,
    tau: &mut DVector<f64>,
) {
    let first = if model.has_free_flyer() { 6 } else { 0 };
    tau.fill(0.0);
    let q_ok = model.check_configuration(q).is_ok();
    if q_ok {
        if let Ok(g) = generalized_gravity(model, data, q) {
            for k in 0..tau.len() {
                tau[k] = g[first + k];
            }
        }
    }
    if model.check_tangent("velocity v", v).is_ok() {
        for k in 0..tau.len() {
            tau[k] -= damping * v[first + k];
        }
    }
    for k in 0..tau.len() {
        let lim = model.effort_limit[first + k];
        tau[k] = tau[k].clamp(-lim, lim);
    }
}
