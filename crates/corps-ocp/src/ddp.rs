//! DDP over a horizon of running models and a terminal cost. Each iteration linearises the
//! dynamics and takes the costs' gradients and Hessians along the current trajectory, then
//! a backward pass (the Gauss–Newton value recursion, second-order dynamics terms left out,
//! as Crocoddyl's `SolverDDP`):
//! `Q_x = l_x + F_xᵀV_x'`, `Q_u = l_u + F_uᵀV_x'`, `Q_xx = l_xx + F_xᵀV_xx'F_x`,
//! `Q_ux = l_xuᵀ + F_uᵀV_xx'F_x`, `Q_uu = l_uu + F_uᵀV_xx'F_u + μI`, the feed-forward
//! `k = −Q_uu⁻¹Q_u` and gain `K = −Q_uu⁻¹Q_ux`, `V_x = Q_x + Q_uxᵀk`, `V_xx = Q_xx + Q_uxᵀK`;
//! and a forward pass `u = ū + αk + K(x − x̄)` rolled out for α = 1, ½, ¼, … 2⁻⁹ until the
//! cost falls by at least a tenth of the model's prediction `−(α − α²/2) Σ Q_uᵀQ_uu⁻¹Q_u`
//! (or at once when that prediction is below rounding, 1e-12, as Crocoddyl's `th_grad`).
//! The regularisation μ, added to `Q_uu`'s diagonal, shrinks tenfold after a full step and
//! grows tenfold when a `Q_uu` is not positive definite or the step taken is at most
//! `raise_at_step` (0.01, none taken included); the solve gives up, unconverged, once μ
//! reaches `mu_max`: Crocoddyl 3's schedule, except that Crocoddyl also adds μ to `V_xx`'s
//! diagonal (measured on the recorded walks' predictions at a quarter of the walk, with this
//! solver on dynamic-size blocks: 172 of 233 converged with it, 180 without, and one
//! prediction at half the walk landed 12 m off; left out here). It stops when `Σ_k ‖Q_u‖²` falls below `stop` (1e-9; Crocoddyl 1.x's
//! criterion, Crocoddyl 3 stops on the expected improvement instead).
//!
//! The state and control sizes are compile-time constants (`NX`, `NU`): a node's blocks are
//! a few by a few, where fixed-size arithmetic is unrolled and lives on the stack.
//! [`DdpWorkspace`] keeps the trajectories, derivatives and gains between solves: past the
//! first solve of a horizon as long, a solve allocates nothing.

use crate::error::OcpError;
use nalgebra::{SMatrix, SVector};

/// One node's dynamics Jacobians and cost derivatives.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ActionDerivatives<const NX: usize, const NU: usize> {
    /// ∂f/∂x and ∂f/∂u.
    pub fx: SMatrix<f64, NX, NX>,
    pub fu: SMatrix<f64, NX, NU>,
    /// Gradient and Hessian blocks of the cost.
    pub lx: SVector<f64, NX>,
    pub lu: SVector<f64, NU>,
    pub lxx: SMatrix<f64, NX, NX>,
    pub luu: SMatrix<f64, NU, NU>,
    /// ∂²l/∂x∂u.
    pub lxu: SMatrix<f64, NX, NU>,
}

impl<const NX: usize, const NU: usize> Default for ActionDerivatives<NX, NU> {
    fn default() -> Self {
        Self {
            fx: SMatrix::zeros(),
            fu: SMatrix::zeros(),
            lx: SVector::zeros(),
            lu: SVector::zeros(),
            lxx: SMatrix::zeros(),
            luu: SMatrix::zeros(),
            lxu: SMatrix::zeros(),
        }
    }
}

/// A discrete-time model with a cost, `NX` states and `NU` controls: one node of the horizon.
pub trait ActionModel<const NX: usize, const NU: usize> {
    /// Writes `f(x, u)` to `next` and returns `l(x, u)`.
    fn calc(&self, x: &SVector<f64, NX>, u: &SVector<f64, NU>, next: &mut SVector<f64, NX>) -> f64;
    /// The derivatives at `(x, u)`.
    fn calc_diff(
        &self,
        x: &SVector<f64, NX>,
        u: &SVector<f64, NU>,
        d: &mut ActionDerivatives<NX, NU>,
    );
}

/// The cost of the last state.
pub trait TerminalCost<const NX: usize> {
    fn cost(&self, x: &SVector<f64, NX>) -> f64;
    /// Writes the gradient and Hessian at `x`.
    fn diff(&self, x: &SVector<f64, NX>, lx: &mut SVector<f64, NX>, lxx: &mut SMatrix<f64, NX, NX>);
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
    /// μ grows after a step of at most this length, accepted or not (Crocoddyl's
    /// `th_stepinc`): a solve that only creeps reaches `mu_max` and gives up instead of
    /// running to the iteration cap.
    pub raise_at_step: f64,
}

impl Default for DdpSettings {
    /// Crocoddyl's defaults (`th_stop` 1e-9, `th_acceptstep` 0.1, `th_grad` 1e-12,
    /// regularisation 1e-9 to 1e9 by factors of 10, `th_stepinc` 0.01).
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
            raise_at_step: 0.01,
        }
    }
}

/// What a solve returns.
#[derive(Clone, Debug, PartialEq)]
pub struct DdpSolution<const NX: usize, const NU: usize> {
    /// States x_0 … x_N and controls u_0 … u_{N−1}.
    pub xs: Vec<SVector<f64, NX>>,
    pub us: Vec<SVector<f64, NU>>,
    pub cost: f64,
    pub iterations: usize,
    /// Whether `Σ‖Q_u‖²` fell below the threshold (else the iteration cap or μ_max ended it).
    pub converged: bool,
    /// The last `Σ‖Q_u‖²`.
    pub stop: f64,
}

/// How a solve in a [`DdpWorkspace`] ended; the trajectory stays in the workspace
/// ([`DdpWorkspace::xs`], [`DdpWorkspace::us`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DdpOutcome {
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
    /// model per node), starting from the controls `us` (zeros when `None`), in a workspace
    /// of its own.
    pub fn solve<const NX: usize, const NU: usize>(
        x0: &SVector<f64, NX>,
        running: &[&dyn ActionModel<NX, NU>],
        terminal: &dyn TerminalCost<NX>,
        us: Option<&[SVector<f64, NU>]>,
        settings: &DdpSettings,
    ) -> Result<DdpSolution<NX, NU>, OcpError> {
        let mut workspace = DdpWorkspace::default();
        let o = workspace.solve(x0, running, terminal, us, settings)?;
        Ok(DdpSolution {
            xs: workspace.xs().to_vec(),
            us: workspace.us().to_vec(),
            cost: o.cost,
            iterations: o.iterations,
            converged: o.converged,
            stop: o.stop,
        })
    }
}

/// The trajectories, derivatives and gains of a solve, kept for the next.
pub struct DdpWorkspace<const NX: usize, const NU: usize> {
    nodes: usize,
    /// Nodes of the last solve that ended without an error.
    solved: Option<usize>,
    xs: Vec<SVector<f64, NX>>,
    us: Vec<SVector<f64, NU>>,
    xs_try: Vec<SVector<f64, NX>>,
    us_try: Vec<SVector<f64, NU>>,
    d: Vec<ActionDerivatives<NX, NU>>,
    k_ff: Vec<SVector<f64, NU>>,
    k_fb: Vec<SMatrix<f64, NU, NX>>,
    lx_n: SVector<f64, NX>,
    lxx_n: SMatrix<f64, NX, NX>,
}

impl<const NX: usize, const NU: usize> Default for DdpWorkspace<NX, NU> {
    fn default() -> Self {
        Self {
            nodes: 0,
            solved: None,
            xs: Vec::new(),
            us: Vec::new(),
            xs_try: Vec::new(),
            us_try: Vec::new(),
            d: Vec::new(),
            k_ff: Vec::new(),
            k_fb: Vec::new(),
            lx_n: SVector::zeros(),
            lxx_n: SMatrix::zeros(),
        }
    }
}

impl<const NX: usize, const NU: usize> DdpWorkspace<NX, NU> {
    /// States x_0 … x_N of the last solve that returned an outcome (empty before one).
    pub fn xs(&self) -> &[SVector<f64, NX>] {
        self.solved.map_or(&[], |n| &self.xs[..=n])
    }

    /// Controls u_0 … u_{N−1} of the last solve that returned an outcome (empty before one).
    pub fn us(&self) -> &[SVector<f64, NU>] {
        self.solved.map_or(&[], |n| &self.us[..n])
    }

    /// Sizes the buffers for `n` nodes (allocating only to grow), zeroes the derivatives (a
    /// model may write only its non-zero entries) and sets the initial controls.
    fn prepare(
        &mut self,
        n: usize,
        us: Option<&[SVector<f64, NU>]>,
        settings: &DdpSettings,
    ) -> Result<(), OcpError> {
        if n == 0 {
            return Err(OcpError::Invalid("the horizon has no node".into()));
        }
        let s = settings;
        if !(s.mu_min > 0.0
            && s.mu_min <= s.mu_init
            && s.mu_init <= s.mu_max
            && s.mu_max.is_finite()
            && s.mu_factor > 1.0
            && s.mu_factor.is_finite())
        {
            return Err(OcpError::Invalid(format!(
                "regularisation: need 0 < mu_min ≤ mu_init ≤ mu_max < ∞ and mu_factor > 1, got {} ≤ {} ≤ {}, factor {}",
                s.mu_min, s.mu_init, s.mu_max, s.mu_factor
            )));
        }
        if let Some(us) = us {
            if us.len() != n {
                return Err(OcpError::Invalid(format!(
                    "{} initial controls for {n} nodes",
                    us.len()
                )));
            }
        }
        if self.xs.len() < n + 1 {
            self.xs.resize(n + 1, SVector::zeros());
            self.xs_try.resize(n + 1, SVector::zeros());
            self.us.resize(n, SVector::zeros());
            self.us_try.resize(n, SVector::zeros());
            self.d.resize(n, ActionDerivatives::default());
            self.k_ff.resize(n, SVector::zeros());
            self.k_fb.resize(n, SMatrix::zeros());
        }
        match us {
            Some(us) => self.us[..n].copy_from_slice(us),
            None => self.us[..n].fill(SVector::zeros()),
        }
        self.d[..n].fill(ActionDerivatives::default());
        self.lx_n = SVector::zeros();
        self.lxx_n = SMatrix::zeros();
        self.nodes = n;
        Ok(())
    }

    /// [`Ddp::solve`] in this workspace: the optimum's trajectory stays here.
    pub fn solve(
        &mut self,
        x0: &SVector<f64, NX>,
        running: &[&dyn ActionModel<NX, NU>],
        terminal: &dyn TerminalCost<NX>,
        us: Option<&[SVector<f64, NU>]>,
        settings: &DdpSettings,
    ) -> Result<DdpOutcome, OcpError> {
        let n = running.len();
        self.solved = None;
        self.prepare(n, us, settings)?;
        let mut cost = rollout(x0, running, terminal, &self.us[..n], &mut self.xs[..=n])?;
        let mut mu = settings.mu_init;
        let mut stop = f64::INFINITY;
        let mut moved = true;
        // μ one factor up, capped; true once it sits at the cap (give up).
        let raise = |mu: &mut f64| {
            *mu = (*mu * settings.mu_factor).min(settings.mu_max);
            *mu >= settings.mu_max
        };
        let done = |cost, iterations, converged, stop| DdpOutcome {
            cost,
            iterations,
            converged,
            stop,
        };
        self.solved = Some(n);
        for iteration in 0..settings.max_iterations {
            if moved {
                for (k, model) in running.iter().enumerate() {
                    model.calc_diff(&self.xs[k], &self.us[k], &mut self.d[k]);
                }
                terminal.diff(&self.xs[n], &mut self.lx_n, &mut self.lxx_n);
                moved = false;
            }
            // Backward pass, μ raised until every Q_uu is positive definite.
            let predicted = loop {
                match self.backward(mu) {
                    Some(b) => break b,
                    None if raise(&mut mu) => return Ok(done(cost, iteration, false, stop)),
                    None => {}
                }
            };
            stop = predicted.stop;
            if !stop.is_finite() {
                self.solved = None;
                return Err(OcpError::NonFinite {
                    what: "Q_u",
                    node: 0,
                });
            }
            if stop < settings.stop {
                return Ok(done(cost, iteration, true, stop));
            }
            // Forward pass: α = 1, ½, … 2⁻⁹.
            let mut step = None;
            let mut alpha = 1.0;
            while alpha > 1e-3 {
                let c = self.try_step(x0, running, terminal, alpha);
                let expected = (alpha - 0.5 * alpha * alpha) * predicted.quadratic;
                let tiny = 0.5 * predicted.quadratic < settings.tiny_gradient;
                if c.is_finite() && (tiny || cost - c >= settings.accept * expected) {
                    std::mem::swap(&mut self.xs, &mut self.xs_try);
                    std::mem::swap(&mut self.us, &mut self.us_try);
                    cost = c;
                    moved = true;
                    step = Some(alpha);
                    break;
                }
                alpha *= 0.5;
            }
            if step == Some(1.0) {
                mu = (mu / settings.mu_factor).max(settings.mu_min);
            }
            if step.is_none_or(|a| a <= settings.raise_at_step) && raise(&mut mu) {
                return Ok(done(cost, iteration + 1, false, stop));
            }
        }
        Ok(done(cost, settings.max_iterations, false, stop))
    }

    /// Rolls `u = ū + αk + K(x − x̄)` out into `xs_try`/`us_try`; returns its cost.
    fn try_step(
        &mut self,
        x0: &SVector<f64, NX>,
        running: &[&dyn ActionModel<NX, NU>],
        terminal: &dyn TerminalCost<NX>,
        alpha: f64,
    ) -> f64 {
        let n = running.len();
        self.xs_try[0] = *x0;
        let mut c = 0.0;
        for (k, model) in running.iter().enumerate() {
            let x = self.xs_try[k];
            self.us_try[k] = self.us[k] + self.k_ff[k] * alpha + self.k_fb[k] * (x - self.xs[k]);
            c += model.calc(&x, &self.us_try[k], &mut self.xs_try[k + 1]);
        }
        c + terminal.cost(&self.xs_try[n])
    }

    /// The backward pass at regularisation `mu` into the gains; None when a `Q_uu` is not
    /// positive definite.
    fn backward(&mut self, mu: f64) -> Option<Prediction> {
        let mut vx = self.lx_n;
        let mut vxx = self.lxx_n;
        let (mut quadratic, mut stop) = (0.0, 0.0);
        for k in (0..self.nodes).rev() {
            let dk = &self.d[k];
            let qx = dk.lx + dk.fx.tr_mul(&vx);
            let qu = dk.lu + dk.fu.tr_mul(&vx);
            let vxx_fx = vxx * dk.fx;
            let qxx = dk.lxx + dk.fx.tr_mul(&vxx_fx);
            let qux = dk.lxu.transpose() + dk.fu.tr_mul(&vxx_fx);
            let mut quu = dk.luu + dk.fu.tr_mul(&(vxx * dk.fu));
            for i in 0..NU {
                quu[(i, i)] += mu;
            }
            let chol = quu.cholesky()?;
            let k_ff = -chol.solve(&qu);
            let k_fb = -chol.solve(&qux);
            quadratic -= qu.dot(&k_ff);
            stop += qu.norm_squared();
            vx = qx + qux.tr_mul(&k_ff);
            vxx = qxx + qux.tr_mul(&k_fb);
            vxx = (vxx + vxx.transpose()) * 0.5;
            self.k_ff[k] = k_ff;
            self.k_fb[k] = k_fb;
        }
        Some(Prediction { quadratic, stop })
    }
}

/// Rolls `us` out from `x0` into `xs` and returns the total cost.
fn rollout<const NX: usize, const NU: usize>(
    x0: &SVector<f64, NX>,
    running: &[&dyn ActionModel<NX, NU>],
    terminal: &dyn TerminalCost<NX>,
    us: &[SVector<f64, NU>],
    xs: &mut [SVector<f64, NX>],
) -> Result<f64, OcpError> {
    xs[0] = *x0;
    let mut cost = 0.0;
    for (k, m) in running.iter().enumerate() {
        let x = xs[k];
        cost += m.calc(&x, &us[k], &mut xs[k + 1]);
        if !xs[k + 1].iter().all(|v| v.is_finite()) {
            return Err(OcpError::NonFinite {
                what: "state",
                node: k + 1,
            });
        }
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

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{Matrix2, Vector1, Vector2};

    /// A double integrator with quadratic costs: a linear-quadratic problem, which one full
    /// step solves exactly (the second iteration finds Q_u = 0).
    struct Lq;
    impl ActionModel<2, 1> for Lq {
        fn calc(&self, x: &Vector2<f64>, u: &Vector1<f64>, next: &mut Vector2<f64>) -> f64 {
            let dt = 0.1;
            next[0] = x[0] + dt * x[1];
            next[1] = x[1] + dt * u[0];
            x[0] * x[0] + 0.1 * x[1] * x[1] + 0.01 * u[0] * u[0]
        }
        fn calc_diff(&self, x: &Vector2<f64>, u: &Vector1<f64>, d: &mut ActionDerivatives<2, 1>) {
            let dt = 0.1;
            d.fx = Matrix2::new(1.0, dt, 0.0, 1.0);
            d.fu = Vector2::new(0.0, dt);
            d.lx = Vector2::new(2.0 * x[0], 0.2 * x[1]);
            d.lu = Vector1::new(0.02 * u[0]);
            d.lxx = Matrix2::new(2.0, 0.0, 0.0, 0.2);
            d.luu = Vector1::new(0.02);
        }
    }
    struct LqEnd;
    impl TerminalCost<2> for LqEnd {
        fn cost(&self, x: &Vector2<f64>) -> f64 {
            10.0 * x.norm_squared()
        }
        fn diff(&self, x: &Vector2<f64>, lx: &mut Vector2<f64>, lxx: &mut Matrix2<f64>) {
            *lx = x * 20.0;
            *lxx = Matrix2::identity() * 20.0;
        }
    }

    #[test]
    fn a_linear_quadratic_problem_is_solved_by_one_full_step() {
        let model = Lq;
        let running: Vec<&dyn ActionModel<2, 1>> = vec![&model; 30];
        let x0 = Vector2::new(1.0, 0.0);
        let s = Ddp::solve(&x0, &running, &LqEnd, None, &DdpSettings::default()).unwrap();
        assert!(
            s.converged && s.iterations == 1,
            "{} iterations",
            s.iterations
        );
        // The optimum's stationarity, checked by perturbing each control.
        let cost_of = |us: &[Vector1<f64>]| {
            let mut xs = vec![x0; 31];
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
        let x0 = Vector2::new(1.0, 0.0);
        let none: [&dyn ActionModel<2, 1>; 0] = [];
        let e = Ddp::solve(&x0, &none, &LqEnd, None, &DdpSettings::default());
        assert!(matches!(e, Err(OcpError::Invalid(_))));
        let us = [Vector1::new(0.0)];
        let e = Ddp::solve(
            &x0,
            &[&model, &model],
            &LqEnd,
            Some(&us),
            &DdpSettings::default(),
        );
        assert!(matches!(e, Err(OcpError::Invalid(_))));
    }
}
