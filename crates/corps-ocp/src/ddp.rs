//! DDP over a horizon of running models and a terminal cost. Each iteration linearises the
//! dynamics and takes the costs' gradients and Hessians along the current trajectory, then
//! a backward pass (the Gauss–Newton value recursion, second-order dynamics terms left out,
//! as Crocoddyl's `SolverDDP`):
//! `Q_x = l_x + F_xᵀV_x'`, `Q_u = l_u + F_uᵀV_x'`, `Q_xx = l_xx + F_xᵀV_xx'F_x`,
//! `Q_ux = l_xuᵀ + F_uᵀV_xx'F_x`, `Q_uu = l_uu + F_uᵀV_xx'F_u + μI`, the feed-forward
//! `k = −Q_uu⁻¹Q_u` and gain `K = −Q_uu⁻¹Q_ux`, `V_x = Q_x + Q_uxᵀk`, `V_xx = Q_xx + Q_uxᵀK`;
//! and a forward pass `u = ū + αk + K(x − x̄)` rolled out for α = 1, ½, ¼, … until the cost
//! falls by at least a tenth of the model's prediction `−(α − α²/2) Σ Q_uᵀQ_uu⁻¹Q_u` (or at
//! once when that prediction is below rounding, 1e-12, as Crocoddyl's `th_grad`). μ
//! shrinks tenfold after a full step and grows tenfold when `Q_uu` is not positive definite
//! or no step is accepted. It stops when `Σ_k ‖Q_u‖²` falls below `stop` (Crocoddyl's
//! criterion and default, 1e-9).

use crate::error::OcpError;
use nalgebra::{DMatrix, DVector};

/// One node's dynamics Jacobians and cost derivatives.
#[derive(Clone, Debug)]
pub struct ActionDerivatives {
    /// ∂f/∂x (nx × nx) and ∂f/∂u (nx × nu).
    pub fx: DMatrix<f64>,
    pub fu: DMatrix<f64>,
    /// Gradient and Hessian blocks of the cost.
    pub lx: DVector<f64>,
    pub lu: DVector<f64>,
    pub lxx: DMatrix<f64>,
    pub luu: DMatrix<f64>,
    /// ∂²l/∂x∂u (nx × nu).
    pub lxu: DMatrix<f64>,
}

impl ActionDerivatives {
    pub fn zeros(nx: usize, nu: usize) -> Self {
        Self {
            fx: DMatrix::zeros(nx, nx),
            fu: DMatrix::zeros(nx, nu),
            lx: DVector::zeros(nx),
            lu: DVector::zeros(nu),
            lxx: DMatrix::zeros(nx, nx),
            luu: DMatrix::zeros(nu, nu),
            lxu: DMatrix::zeros(nx, nu),
        }
    }
}

/// A discrete-time model with a cost: one node of the horizon.
pub trait ActionModel {
    fn nx(&self) -> usize;
    fn nu(&self) -> usize;
    /// Writes `f(x, u)` to `next` and returns `l(x, u)`.
    fn calc(&self, x: &DVector<f64>, u: &DVector<f64>, next: &mut DVector<f64>) -> f64;
    /// The derivatives at `(x, u)`.
    fn calc_diff(&self, x: &DVector<f64>, u: &DVector<f64>, d: &mut ActionDerivatives);
}

/// The cost of the last state.
pub trait TerminalCost {
    fn cost(&self, x: &DVector<f64>) -> f64;
    /// Writes the gradient and Hessian at `x`.
    fn diff(&self, x: &DVector<f64>, lx: &mut DVector<f64>, lxx: &mut DMatrix<f64>);
}

/// Stopping and regularisation settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DdpSettings {
    pub max_iterations: usize,
    /// Converged when `Σ_k ‖Q_u‖²` is below this.
    pub stop: f64,
    /// Accept a step whose cost reduction is at least this fraction of the predicted one...
    pub accept: f64,
    /// ...or any step once the predicted full-step reduction `½ Σ Q_uᵀQ_uu⁻¹Q_u` is below
    /// this, where rounding in the cost hides the reduction (Crocoddyl's `th_grad`).
    pub tiny_gradient: f64,
    /// Regularisation of `Q_uu`: start, bounds and factor.
    pub mu_init: f64,
    pub mu_min: f64,
    pub mu_max: f64,
    pub mu_factor: f64,
}

impl Default for DdpSettings {
    /// Crocoddyl's defaults (`th_stop` 1e-9, `th_acceptstep` 0.1, `th_grad` 1e-12,
    /// regularisation 1e-9 to 1e9 by factors of 10).
    fn default() -> Self {
        Self {
            max_iterations: 200,
            stop: 1e-9,
            accept: 0.1,
            tiny_gradient: 1e-12,
            mu_init: 1e-9,
            mu_min: 1e-9,
            mu_max: 1e9,
            mu_factor: 10.0,
        }
    }
}

/// What a solve returns.
#[derive(Clone, Debug, PartialEq)]
pub struct DdpSolution {
    /// States x_0 … x_N and controls u_0 … u_{N−1}.
    pub xs: Vec<DVector<f64>>,
    pub us: Vec<DVector<f64>>,
    pub cost: f64,
    pub iterations: usize,
    /// Whether `Σ‖Q_u‖²` fell below the threshold (else the iteration cap or μ_max ended it).
    pub converged: bool,
    /// The last `Σ‖Q_u‖²`.
    pub stop: f64,
}

/// The DDP solver.
pub struct Ddp;

impl Ddp {
    /// Minimises `Σ_k l_k(x_k, u_k) + l_N(x_N)` from `x0` over the horizon `running` (one
    /// model per node), starting from the controls `us` (zeros when `None`).
    pub fn solve(
        x0: &DVector<f64>,
        running: &[&dyn ActionModel],
        terminal: &dyn TerminalCost,
        us: Option<&[DVector<f64>]>,
        settings: &DdpSettings,
    ) -> Result<DdpSolution, OcpError> {
        let n = running.len();
        let nx = x0.len();
        if n == 0 {
            return Err(OcpError::Invalid("the horizon has no node".into()));
        }
        for (k, m) in running.iter().enumerate() {
            if m.nx() != nx {
                return Err(OcpError::Invalid(format!(
                    "node {k} has {} states, x0 has {nx}",
                    m.nx()
                )));
            }
        }
        let mut us: Vec<DVector<f64>> = match us {
            Some(us) if us.len() == n => us.to_vec(),
            Some(us) => {
                return Err(OcpError::Invalid(format!(
                    "{} initial controls for {n} nodes",
                    us.len()
                )))
            }
            None => running.iter().map(|m| DVector::zeros(m.nu())).collect(),
        };
        if let Some(k) = (0..n).find(|&k| us[k].len() != running[k].nu()) {
            return Err(OcpError::Invalid(format!(
                "initial control {k} has the wrong size"
            )));
        }
        let mut xs = vec![x0.clone(); n + 1];
        let mut cost = rollout(x0, running, terminal, &us, &mut xs)?;
        let mut d: Vec<ActionDerivatives> = running
            .iter()
            .map(|m| ActionDerivatives::zeros(nx, m.nu()))
            .collect();
        let mut gains_k: Vec<DVector<f64>> = us.clone();
        let mut gains_kk: Vec<DMatrix<f64>> =
            running.iter().map(|m| DMatrix::zeros(m.nu(), nx)).collect();
        let (mut lx_n, mut lxx_n) = (DVector::zeros(nx), DMatrix::zeros(nx, nx));
        let mut mu = settings.mu_init;
        let mut stop = f64::INFINITY;
        let (mut xs_try, mut us_try) = (xs.clone(), us.clone());
        for iteration in 0..settings.max_iterations {
            for k in 0..n {
                running[k].calc_diff(&xs[k], &us[k], &mut d[k]);
            }
            terminal.diff(&xs[n], &mut lx_n, &mut lxx_n);
            // Backward pass, μ raised until every Q_uu is positive definite.
            let predicted = loop {
                match backward(&d, &lx_n, &lxx_n, mu, &mut gains_k, &mut gains_kk) {
                    Some(b) => break b,
                    None => {
                        mu *= settings.mu_factor;
                        if mu > settings.mu_max {
                            return Ok(solution(xs, us, cost, iteration, false, stop));
                        }
                    }
                }
            };
            stop = predicted.stop;
            if !stop.is_finite() {
                return Err(OcpError::NonFinite {
                    what: "Q_u",
                    node: 0,
                });
            }
            if stop < settings.stop {
                return Ok(solution(xs, us, cost, iteration, true, stop));
            }
            // Forward pass.
            let mut accepted = false;
            let mut alpha = 1.0;
            while alpha > 1e-3 {
                xs_try[0].copy_from(x0);
                let mut c = 0.0;
                let mut next = DVector::zeros(nx);
                for k in 0..n {
                    let dx = &xs_try[k] - &xs[k];
                    us_try[k] = &us[k] + &gains_k[k] * alpha + &gains_kk[k] * dx;
                    c += running[k].calc(&xs_try[k], &us_try[k], &mut next);
                    xs_try[k + 1].copy_from(&next);
                }
                c += terminal.cost(&xs_try[n]);
                let expected = (alpha - 0.5 * alpha * alpha) * predicted.quadratic;
                let reduction = cost - c;
                let tiny = 0.5 * predicted.quadratic < settings.tiny_gradient;
                if c.is_finite() && (tiny || reduction >= settings.accept * expected) {
                    std::mem::swap(&mut xs, &mut xs_try);
                    std::mem::swap(&mut us, &mut us_try);
                    cost = c;
                    accepted = true;
                    break;
                }
                alpha *= 0.5;
            }
            if accepted && alpha == 1.0 {
                mu = (mu / settings.mu_factor).max(settings.mu_min);
            } else if !accepted {
                mu *= settings.mu_factor;
                if mu > settings.mu_max {
                    return Ok(solution(xs, us, cost, iteration + 1, false, stop));
                }
            }
        }
        Ok(solution(xs, us, cost, settings.max_iterations, false, stop))
    }
}

fn solution(
    xs: Vec<DVector<f64>>,
    us: Vec<DVector<f64>>,
    cost: f64,
    iterations: usize,
    converged: bool,
    stop: f64,
) -> DdpSolution {
    DdpSolution {
        xs,
        us,
        cost,
        iterations,
        converged,
        stop,
    }
}

/// Rolls `us` out from `x0` into `xs` and returns the total cost.
fn rollout(
    x0: &DVector<f64>,
    running: &[&dyn ActionModel],
    terminal: &dyn TerminalCost,
    us: &[DVector<f64>],
    xs: &mut [DVector<f64>],
) -> Result<f64, OcpError> {
    xs[0].copy_from(x0);
    let mut cost = 0.0;
    let mut next = DVector::zeros(x0.len());
    for (k, m) in running.iter().enumerate() {
        cost += m.calc(&xs[k], &us[k], &mut next);
        if !next.iter().all(|v| v.is_finite()) {
            return Err(OcpError::NonFinite {
                what: "state",
                node: k + 1,
            });
        }
        xs[k + 1].copy_from(&next);
    }
    cost += terminal.cost(&xs[running.len()]);
    if !cost.is_finite() {
        return Err(OcpError::NonFinite {
            what: "cost",
            node: running.len(),
        });
    }
    Ok(cost)
}

/// What a backward pass predicts: `Σ Q_uᵀQ_uu⁻¹Q_u` (the full step's cost reduction is its
/// half) and `Σ‖Q_u‖²`.
struct Prediction {
    quadratic: f64,
    stop: f64,
}

/// The backward pass at regularisation `mu`; None when a `Q_uu` is not positive definite.
fn backward(
    d: &[ActionDerivatives],
    lx_n: &DVector<f64>,
    lxx_n: &DMatrix<f64>,
    mu: f64,
    k_ff: &mut [DVector<f64>],
    k_fb: &mut [DMatrix<f64>],
) -> Option<Prediction> {
    let mut vx = lx_n.clone();
    let mut vxx = lxx_n.clone();
    let (mut quadratic, mut stop) = (0.0, 0.0);
    for k in (0..d.len()).rev() {
        let dk = &d[k];
        let qx = &dk.lx + dk.fx.tr_mul(&vx);
        let qu = &dk.lu + dk.fu.tr_mul(&vx);
        let vxx_fx = &vxx * &dk.fx;
        let vxx_fu = &vxx * &dk.fu;
        let qxx = &dk.lxx + dk.fx.tr_mul(&vxx_fx);
        let qux = dk.lxu.transpose() + dk.fu.tr_mul(&vxx_fx);
        let mut quu = &dk.luu + dk.fu.tr_mul(&vxx_fu);
        for i in 0..quu.nrows() {
            quu[(i, i)] += mu;
        }
        let chol = quu.clone().cholesky()?;
        k_ff[k] = -chol.solve(&qu);
        k_fb[k] = -chol.solve(&qux);
        quadratic += -qu.dot(&k_ff[k]);
        stop += qu.norm_squared();
        vx = &qx + qux.tr_mul(&k_ff[k]);
        vxx = &qxx + qux.tr_mul(&k_fb[k]);
        vxx = (&vxx + vxx.transpose()) * 0.5;
    }
    Some(Prediction { quadratic, stop })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A double integrator with quadratic costs: a linear-quadratic problem, which one full
    /// step solves exactly (the second iteration finds Q_u = 0).
    struct Lq;
    impl ActionModel for Lq {
        fn nx(&self) -> usize {
            2
        }
        fn nu(&self) -> usize {
            1
        }
        fn calc(&self, x: &DVector<f64>, u: &DVector<f64>, next: &mut DVector<f64>) -> f64 {
            let dt = 0.1;
            next[0] = x[0] + dt * x[1];
            next[1] = x[1] + dt * u[0];
            x[0] * x[0] + 0.1 * x[1] * x[1] + 0.01 * u[0] * u[0]
        }
        fn calc_diff(&self, x: &DVector<f64>, u: &DVector<f64>, d: &mut ActionDerivatives) {
            let dt = 0.1;
            d.fx = DMatrix::from_row_slice(2, 2, &[1.0, dt, 0.0, 1.0]);
            d.fu = DMatrix::from_row_slice(2, 1, &[0.0, dt]);
            d.lx = DVector::from_vec(vec![2.0 * x[0], 0.2 * x[1]]);
            d.lu = DVector::from_vec(vec![0.02 * u[0]]);
            d.lxx = DMatrix::from_diagonal(&DVector::from_vec(vec![2.0, 0.2]));
            d.luu = DMatrix::from_element(1, 1, 0.02);
        }
    }
    struct LqEnd;
    impl TerminalCost for LqEnd {
        fn cost(&self, x: &DVector<f64>) -> f64 {
            10.0 * x.norm_squared()
        }
        fn diff(&self, x: &DVector<f64>, lx: &mut DVector<f64>, lxx: &mut DMatrix<f64>) {
            *lx = x * 20.0;
            *lxx = DMatrix::identity(2, 2) * 20.0;
        }
    }

    #[test]
    fn a_linear_quadratic_problem_is_solved_by_one_full_step() {
        let model = Lq;
        let running: Vec<&dyn ActionModel> = vec![&model; 30];
        let x0 = DVector::from_vec(vec![1.0, 0.0]);
        let s = Ddp::solve(&x0, &running, &LqEnd, None, &DdpSettings::default()).unwrap();
        assert!(
            s.converged && s.iterations == 1,
            "{} iterations",
            s.iterations
        );
        // The optimum's stationarity, checked by perturbing each control.
        let cost_of = |us: &[DVector<f64>]| {
            let mut xs = vec![x0.clone(); 31];
            rollout(&x0, &running, &LqEnd, us, &mut xs).unwrap()
        };
        for k in [0, 10, 29] {
            let mut us = s.us.clone();
            us[k][0] += 1e-4;
            let up = cost_of(&us);
            us[k][0] -= 2e-4;
            let down = cost_of(&us);
            assert!(((up - down) / 2e-4).abs() < 1e-7, "gradient at {k}");
            assert!(up > s.cost && down > s.cost);
        }
    }

    #[test]
    fn bad_sizes_are_errors() {
        let model = Lq;
        let x0 = DVector::from_vec(vec![1.0, 0.0, 0.0]);
        let e = Ddp::solve(&x0, &[&model], &LqEnd, None, &DdpSettings::default());
        assert!(matches!(e, Err(OcpError::Invalid(_))));
        let e = Ddp::solve(&x0, &[], &LqEnd, None, &DdpSettings::default());
        assert!(matches!(e, Err(OcpError::Invalid(_))));
    }
}
