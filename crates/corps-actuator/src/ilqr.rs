//! iLQR on the single-joint problem of [`crate::current_ocp`] (seed 000 §3.13, Appendix 2
//! Algorithm 1 with its index typos fixed): backward pass
//! `Q_x = l_x + f_xᵀV_x'`, `Q_u = l_u + f_uᵀV_x'`, `Q_xx = l_xx + f_xᵀV_xx'f_x`,
//! `Q_ux = f_uᵀV_xx'f_x`, `Q_uu = l_uu + f_uᵀV_xx'f_u + μ`, `k = −Q_u/Q_uu`,
//! `K = −Q_ux/Q_uu`, `V_x = Q_x + Q_uxᵀk`, `V_xx = Q_xx + Q_uxᵀK`; forward pass
//! `u = ū + αk + K(x − x̄)` for α = 1, ½, ¼, … until the cost falls by a tenth of the
//! predicted `(α − α²/2) Σ Q_u²/Q_uu`. Regularisation μ shrinks tenfold after a full step,
//! grows tenfold on a non-positive `Q_uu` or a rejected step. Stops when `Σ Q_u²` is below
//! the threshold or after `max_iterations` (warm-started MPC runs a few).
//! Fixed-size arithmetic and buffers sized once: a solve allocates nothing.

use crate::current_ocp::{CurrentLimitingOcp, NodeDerivatives};
use crate::error::ActuatorError;
use nalgebra::{Matrix2, RowVector2, Vector2};

/// Stopping and regularisation settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct IlqrSettings {
    pub max_iterations: usize,
    /// Converged when `Σ_k Q_u²` is below this.
    pub stop: f64,
    /// Accepted when the cost falls by at least this fraction of the prediction.
    pub accept: f64,
    pub mu_init: f64,
    pub mu_min: f64,
    pub mu_max: f64,
    pub mu_factor: f64,
}

impl Default for IlqrSettings {
    fn default() -> Self {
        Self {
            max_iterations: 100,
            stop: 1e-9,
            accept: 0.1,
            mu_init: 1e-9,
            mu_min: 1e-9,
            mu_max: 1e9,
            mu_factor: 10.0,
        }
    }
}

/// What a solve did.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct IlqrReport {
    pub cost: f64,
    pub iterations: usize,
    pub converged: bool,
    /// The last `Σ Q_u²`.
    pub stop: f64,
}

/// The solver with its trajectory (the warm start of the next solve).
#[derive(Clone, Debug)]
pub struct Ilqr {
    pub settings: IlqrSettings,
    xs: Vec<Vector2<f64>>,
    us: Vec<f64>,
    xs_try: Vec<Vector2<f64>>,
    us_try: Vec<f64>,
    d: Vec<NodeDerivatives>,
    k_ff: Vec<f64>,
    k_fb: Vec<RowVector2<f64>>,
    value_gradient: Vector2<f64>,
}

impl Ilqr {
    /// A solver for `horizon` nodes, controls initialised to zero.
    pub fn new(horizon: usize, settings: IlqrSettings) -> Self {
        let n = horizon.max(1);
        Self {
            settings,
            xs: vec![Vector2::zeros(); n + 1],
            us: vec![0.0; n],
            xs_try: vec![Vector2::zeros(); n + 1],
            us_try: vec![0.0; n],
            d: vec![NodeDerivatives::default(); n],
            k_ff: vec![0.0; n],
            k_fb: vec![RowVector2::zeros(); n],
            value_gradient: Vector2::zeros(),
        }
    }

    pub fn horizon(&self) -> usize {
        self.us.len()
    }

    /// The controls (the warm start of the next solve).
    pub fn us(&self) -> &[f64] {
        &self.us
    }

    pub fn us_mut(&mut self) -> &mut [f64] {
        &mut self.us
    }

    /// The states of the last solve, `x_0 … x_N`.
    pub fn xs(&self) -> &[Vector2<f64>] {
        &self.xs
    }

    /// `V_x` at node 0 from the last backward pass (at convergence: ∂J*/∂x_0).
    pub fn value_gradient(&self) -> Vector2<f64> {
        self.value_gradient
    }

    /// Drops the first control and repeats the last: the warm start one node later.
    pub fn shift(&mut self) {
        let n = self.us.len();
        self.us.copy_within(1.., 0);
        self.us[n - 1] = self.us[n.saturating_sub(2)];
    }

    /// Minimises the cost from `x0` along `reference` (`x*_0 … x*_N`, N + 1 states),
    /// starting from the stored controls. A start beyond a barrier's bound is an error.
    pub fn solve(
        &mut self,
        ocp: &CurrentLimitingOcp,
        x0: &Vector2<f64>,
        reference: &[Vector2<f64>],
    ) -> Result<IlqrReport, ActuatorError> {
        let n = self.us.len();
        if reference.len() != n + 1 {
            return Err(ActuatorError::Ilqr(format!(
                "{} reference states for a horizon of {n} nodes (need {})",
                reference.len(),
                n + 1
            )));
        }
        if !(x0[0].is_finite() && x0[1].is_finite()) {
            return Err(ActuatorError::Ilqr(
                "the initial state is not finite".into(),
            ));
        }
        if let Some(b) = &ocp.barriers {
            // The position barrier guards the joint's mechanical limits: a start beyond
            // them has no feasible motion. The velocity and current barriers are soft.
            if x0[0] < b[0].lower || x0[0] > b[0].upper {
                return Err(ActuatorError::Ilqr(format!(
                    "infeasible start: position {} rad is beyond its barrier [{}, {}]",
                    x0[0], b[0].lower, b[0].upper
                )));
            }
        }
        let s = self.settings;
        let mut cost = rollout(ocp, x0, reference, &self.us, &mut self.xs);
        if !cost.is_finite() {
            return Err(ActuatorError::Ilqr("the initial rollout diverges".into()));
        }
        let mut mu = s.mu_init;
        let mut stop = f64::INFINITY;
        for iteration in 0..s.max_iterations {
            for (k, r) in reference[..n].iter().enumerate() {
                self.d[k] = ocp.running_diff(&self.xs[k], self.us[k], r);
            }
            let (vx_n, vxx_n) = ocp.terminal_diff(&self.xs[n], &reference[n]);
            let (quadratic, q_u) = loop {
                match self.backward(vx_n, vxx_n, mu) {
                    Some(p) => break p,
                    None => {
                        mu *= s.mu_factor;
                        if mu > s.mu_max {
                            return Ok(report(cost, iteration, false, stop));
                        }
                    }
                }
            };
            stop = q_u;
            if !stop.is_finite() {
                return Err(ActuatorError::Ilqr("non-finite gradient".into()));
            }
            if stop < s.stop {
                return Ok(report(cost, iteration, true, stop));
            }
            let mut alpha = 1.0;
            let mut accepted = false;
            while alpha > 1e-3 {
                self.xs_try[0] = *x0;
                let mut c = 0.0;
                for (k, r) in reference[..n].iter().enumerate() {
                    let dx = self.xs_try[k] - self.xs[k];
                    let u = self.us[k] + alpha * self.k_ff[k] + (self.k_fb[k] * dx)[0];
                    self.us_try[k] = u;
                    let (l, next) = ocp.running(&self.xs_try[k], u, r);
                    c += l;
                    self.xs_try[k + 1] = next;
                }
                c += ocp.terminal(&self.xs_try[n], &reference[n]);
                let expected = (alpha - 0.5 * alpha * alpha) * quadratic;
                if c.is_finite() && (0.5 * quadratic < 1e-12 || cost - c >= s.accept * expected) {
                    std::mem::swap(&mut self.xs, &mut self.xs_try);
                    std::mem::swap(&mut self.us, &mut self.us_try);
                    cost = c;
                    accepted = true;
                    break;
                }
                alpha *= 0.5;
            }
            if accepted && alpha == 1.0 {
                mu = (mu / s.mu_factor).max(s.mu_min);
            } else if !accepted {
                mu *= s.mu_factor;
                if mu > s.mu_max {
                    return Ok(report(cost, iteration + 1, false, stop));
                }
            }
        }
        Ok(report(cost, s.max_iterations, false, stop))
    }

    /// The backward pass at regularisation `mu`: `(Σ Q_u²/Q_uu, Σ Q_u²)`, or None when a
    /// `Q_uu` is not positive.
    fn backward(&mut self, vx_n: Vector2<f64>, vxx_n: Matrix2<f64>, mu: f64) -> Option<(f64, f64)> {
        let (mut vx, mut vxx) = (vx_n, vxx_n);
        let (mut quadratic, mut stop) = (0.0, 0.0);
        for k in (0..self.us.len()).rev() {
            let d = &self.d[k];
            let qx = d.lx + d.fx.tr_mul(&vx);
            let qu = d.lu + d.fu.dot(&vx);
            let vxx_fx = vxx * d.fx;
            let qxx = d.lxx + d.fx.tr_mul(&vxx_fx);
            let qux: RowVector2<f64> = d.fu.tr_mul(&vxx_fx);
            let quu = d.luu + d.fu.dot(&(vxx * d.fu)) + mu;
            if quu.is_nan() || quu <= 0.0 {
                return None;
            }
            let k_ff = -qu / quu;
            let k_fb = -qux / quu;
            self.k_ff[k] = k_ff;
            self.k_fb[k] = k_fb;
            quadratic += qu * qu / quu;
            stop += qu * qu;
            vx = qx + qux.transpose() * k_ff;
            vxx = qxx + qux.transpose() * k_fb;
            vxx = (vxx + vxx.transpose()) * 0.5;
        }
        self.value_gradient = vx;
        Some((quadratic, stop))
    }
}

fn report(cost: f64, iterations: usize, converged: bool, stop: f64) -> IlqrReport {
    IlqrReport {
        cost,
        iterations,
        converged,
        stop,
    }
}

/// Rolls `us` out from `x0` into `xs`; the total cost.
pub fn rollout(
    ocp: &CurrentLimitingOcp,
    x0: &Vector2<f64>,
    reference: &[Vector2<f64>],
    us: &[f64],
    xs: &mut [Vector2<f64>],
) -> f64 {
    xs[0] = *x0;
    let mut cost = 0.0;
    for (k, &u) in us.iter().enumerate() {
        let (l, next) = ocp.running(&xs[k], u, &reference[k]);
        cost += l;
        xs[k + 1] = next;
    }
    cost + ocp.terminal(&xs[us.len()], &reference[us.len()])
}
