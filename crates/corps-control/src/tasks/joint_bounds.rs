//! Joint position, velocity and acceleration bounds as bounds on the joint accelerations
//! (seed 000 Eq 2.55: `q_min ≤ q ≤ q_max`, `|q̇| ≤ q̇_max`, here with `|q̈| ≤ q̈_max`), for
//! the actuated joints. Over a look-ahead `h` at constant acceleration,
//! - velocity: `|v + h q̈| ≤ v_max`  ⇒  `(−v_max − v)/h ≤ q̈ ≤ (v_max − v)/h`;
//! - position: `q + h v + ½ h² q̈ ∈ [q_min, q_max]`
//!   ⇒  `2(q_min − q − h v)/h² ≤ q̈ ≤ 2(q_max − q − h v)/h²`.
//!
//! (TSID's `TaskJointPosVelAccBounds` goes further and keeps the state viable, Del Prete 2018;
//! this is the one-step look-ahead.) When the bounds cross (a joint already beyond a limit, or
//! too fast to stop in `h`), the interval collapses to whichever of the two asks for the
//! smaller acceleration, so the QP stays feasible.

use crate::robot_state::RobotState;
use corps_model::{JointKind, Model};
use nalgebra::DVector;

#[derive(Clone, Debug)]
pub struct JointBoundsTask {
    /// Look-ahead (s). A few control periods: at one period the position bound only acts
    /// when the joint is within `h·v` of its limit.
    pub horizon: f64,
    /// Acceleration limit per actuated joint (rad/s², +∞ for none).
    pub a_max: DVector<f64>,
    first: usize,
    /// Per actuated joint: (configuration index, q_min, q_max) when it has position limits.
    limits: Vec<Option<(usize, f64, f64)>>,
    v_max: DVector<f64>,
    /// The bounds of the last `compute`, per actuated joint.
    pub lower: DVector<f64>,
    pub upper: DVector<f64>,
}

impl JointBoundsTask {
    /// Bounds from the model's URDF limits (a zero or missing velocity limit = none).
    pub fn new(model: &Model, horizon: f64) -> Self {
        let first = if model.has_free_flyer() { 6 } else { 0 };
        let na = model.nv - first;
        let mut limits = vec![None; na];
        for j in &model.joints {
            if let JointKind::Revolute { .. } | JointKind::Prismatic { .. } = j.kind {
                let (lo, hi) = (
                    model.lower_position_limit[j.idx_q],
                    model.upper_position_limit[j.idx_q],
                );
                if lo.is_finite() && hi.is_finite() && lo < hi {
                    limits[j.idx_v - first] = Some((j.idx_q, lo, hi));
                }
            }
        }
        let v_max = DVector::from_fn(na, |k, _| {
            let l = model.velocity_limit[first + k];
            if l > 0.0 && l.is_finite() {
                l
            } else {
                f64::INFINITY
            }
        });
        Self {
            horizon,
            a_max: DVector::repeat(na, f64::INFINITY),
            first,
            limits,
            v_max,
            lower: DVector::zeros(na),
            upper: DVector::zeros(na),
        }
    }

    /// The acceleration bounds at the state, into `lower` / `upper`.
    pub fn compute(&mut self, s: &RobotState) {
        let h = self.horizon;
        for k in 0..self.lower.len() {
            let v = s.v[self.first + k];
            let mut lo = (-self.v_max[k] - v) / h;
            let mut hi = (self.v_max[k] - v) / h;
            if let Some((iq, q_min, q_max)) = self.limits[k] {
                let q = s.q[iq];
                lo = lo.max(2.0 * (q_min - q - h * v) / (h * h));
                hi = hi.min(2.0 * (q_max - q - h * v) / (h * h));
            }
            lo = lo.max(-self.a_max[k]);
            hi = hi.min(self.a_max[k]);
            if lo > hi {
                let x = if lo.abs() < hi.abs() { lo } else { hi };
                (lo, hi) = (x, x);
            }
            self.lower[k] = lo;
            self.upper[k] = hi;
        }
    }
}
