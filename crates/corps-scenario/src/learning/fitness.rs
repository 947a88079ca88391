//! Seed 001's fitness functions (Eq 5.17–5.18) and constraints (§5.3.2) from a rollout's
//! sums ([`crate::metrics::RunSums`]):
//! `ϕp = −Σ_t Σ_T |X̃_T|² / X_Tmax − 1e-4 Σ_t |τ|² / τ_max`, `ϕr = −Σ_t |P_ZMP − O_SP|² /
//! P_ZMPmax`, `ϕpr = (ϕp + ϕr)/2`, with `X_Tmax = 4 n_s`, `τ_max = 2000 n_s`,
//! `P_ZMPmax = 0.005 n_s` (n_s the rollout's samples); the tasks X_T are the CoM and both
//! feet (positions, m); the penalty is added when the rollout ends early (a fall, a failed QP).

use super::rollout::RolloutOutcome;
use super::{FitnessKind, LearnConfig};

/// ϕ of one rollout (higher is better).
pub fn fitness(kind: FitnessKind, outcome: &RolloutOutcome, penalty: f64) -> f64 {
    let s = &outcome.metrics.sums;
    let n = s.samples.max(1) as f64;
    let performance =
        -s.task_error_square_sum / (4.0 * n) - 1e-4 * s.torque_square_sum / (2000.0 * n);
    let robustness = -s.zmp_support_square_sum / (0.005 * n);
    let phi = match kind {
        FitnessKind::Performance => performance,
        FitnessKind::Robustness => robustness,
        FitnessKind::PerformanceRobustness => 0.5 * (performance + robustness),
    };
    // A rollout whose sums are not finite is the worst there is.
    if !phi.is_finite() {
        return f64::NEG_INFINITY;
    }
    if outcome.failed {
        phi + penalty
    } else {
        phi
    }
}

/// The rollout's constraint values, feasible where ≤ 0: the joints' largest excursion past
/// their URDF limits over the tolerance (rad) and the largest |τ| over the limit (N·m).
pub fn rollout_constraints(config: &LearnConfig, outcome: &RolloutOutcome) -> [f64; 2] {
    let s = &outcome.metrics.sums;
    [
        s.joint_limit_excess - config.joint_limit_tolerance,
        s.torque_peak - config.torque_limit,
    ]
}
