//! The optimal-control model of a person walking to a goal (Maroger, Stasse, Watier, IROS
//! 2020; RA-L 6(4) 2021; seed 000 §3.17), as the authors' estimation code defines it
//! (github.com/imaroger/human_walking_trajectory_prediction, `estimation_oc.py`, and their
//! Crocoddyl action models): the state is `(x, y, θ, v_f, ω, v_o)` (position, heading,
//! forward, angular and orthogonal speeds), the controls are the three accelerations, and
//! one step of `dt` is
//! `x⁺ = x + (v_f cos θ − v_o sin θ) dt`, `y⁺ = y + (v_f sin θ + v_o cos θ) dt`,
//! `θ⁺ = θ + ω dt`, `(v_f, ω, v_o)⁺ = (v_f, ω, v_o) + u dt`. The running cost is
//! `w₀ + w₁u_f² + w₂u_ω² + w₃u_o² + w₄(atan2(y_g − y, x_g − x) − θ)²` (no angle wrapping,
//! as the source), the terminal cost
//! `t₀((x_g − x)² + (y_g − y)²) + t₁ wrap(θ_g − θ)² + t₂(v_f² + ω²) + t₃v_o²`.
//! The derivatives are analytic here (the source takes the cost's by finite differences).

use crate::ddp::{ActionDerivatives, ActionModel, TerminalCost};
use nalgebra::{SMatrix, Vector3, Vector6};
use std::f64::consts::PI;

/// The running weights of the authors' estimation code (w₀ … w₄).
pub const RUNNING_WEIGHTS: [f64; 5] = [7.86951486, 4.00027971, 20.1459991, 1e-6, 9.99999967];
/// The terminal weights of the authors' estimation code (t₀ … t₃).
pub const TERMINAL_WEIGHTS: [f64; 4] = [9.98999939, 9.98999934, 0.379999984, 3.35999389];
/// The step of the authors' running model (s).
pub const DT: f64 = 0.1;
/// States (x, y, θ, v_f, ω, v_o) and controls (the three accelerations).
pub const NX: usize = 6;
pub const NU: usize = 3;

/// One step of the walking model towards `goal` = (x_g, y_g, θ_g).
#[derive(Clone, Debug, PartialEq)]
pub struct HumanWalkStep {
    pub dt: f64,
    pub weights: [f64; 5],
    pub goal: [f64; 3],
}

/// The terminal cost towards `goal`.
#[derive(Clone, Debug, PartialEq)]
pub struct HumanWalkEnd {
    pub weights: [f64; 4],
    pub goal: [f64; 3],
}

impl HumanWalkStep {
    /// The authors' step and weights towards `goal`.
    pub fn new(goal: [f64; 3]) -> Self {
        Self {
            dt: DT,
            weights: RUNNING_WEIGHTS,
            goal,
        }
    }

    /// The heading error `h = atan2(y_g − y, x_g − x) − θ` and its gradient and Hessian in
    /// (x, y, θ): with `d = (x_g − x, y_g − y)`, `r² = |d|²`, `∂φ/∂x = d_y/r²`,
    /// `∂φ/∂y = −d_x/r²`, `∂²φ/∂x² = 2d_xd_y/r⁴ = −∂²φ/∂y²`, `∂²φ/∂x∂y = (d_y² − d_x²)/r⁴`.
    fn heading(&self, x: &Vector6<f64>) -> (f64, [f64; 3], [[f64; 3]; 3]) {
        let (dx, dy) = (self.goal[0] - x[0], self.goal[1] - x[1]);
        let r2 = (dx * dx + dy * dy).max(1e-12);
        let r4 = r2 * r2;
        let h = dy.atan2(dx) - x[2];
        let grad = [dy / r2, -dx / r2, -1.0];
        let (hxx, hxy) = (2.0 * dx * dy / r4, (dy * dy - dx * dx) / r4);
        let hess = [[hxx, hxy, 0.0], [hxy, -hxx, 0.0], [0.0, 0.0, 0.0]];
        (h, grad, hess)
    }
}

impl ActionModel<NX, NU> for HumanWalkStep {
    fn calc(&self, x: &Vector6<f64>, u: &Vector3<f64>, next: &mut Vector6<f64>) -> f64 {
        let (c, s, dt) = (x[2].cos(), x[2].sin(), self.dt);
        next[0] = x[0] + (c * x[3] - s * x[5]) * dt;
        next[1] = x[1] + (s * x[3] + c * x[5]) * dt;
        next[2] = x[2] + x[4] * dt;
        next[3] = x[3] + u[0] * dt;
        next[4] = x[4] + u[1] * dt;
        next[5] = x[5] + u[2] * dt;
        let w = &self.weights;
        let (h, _, _) = self.heading(x);
        w[0] + w[1] * u[0] * u[0] + w[2] * u[1] * u[1] + w[3] * u[2] * u[2] + w[4] * h * h
    }

    fn calc_diff(&self, x: &Vector6<f64>, u: &Vector3<f64>, d: &mut ActionDerivatives<NX, NU>) {
        let (c, s, dt) = (x[2].cos(), x[2].sin(), self.dt);
        d.fx.fill_with_identity();
        d.fx[(0, 2)] = (-s * x[3] - c * x[5]) * dt;
        d.fx[(0, 3)] = c * dt;
        d.fx[(0, 5)] = -s * dt;
        d.fx[(1, 2)] = (c * x[3] - s * x[5]) * dt;
        d.fx[(1, 3)] = s * dt;
        d.fx[(1, 5)] = c * dt;
        d.fx[(2, 4)] = dt;
        d.fu.fill(0.0);
        for i in 0..3 {
            d.fu[(3 + i, i)] = dt;
        }
        let w = &self.weights;
        let (h, g, hh) = self.heading(x);
        d.lx.fill(0.0);
        d.lxx.fill(0.0);
        for i in 0..3 {
            d.lx[i] = 2.0 * w[4] * h * g[i];
            for j in 0..3 {
                d.lxx[(i, j)] = 2.0 * w[4] * (g[i] * g[j] + h * hh[i][j]);
            }
        }
        for i in 0..3 {
            d.lu[i] = 2.0 * w[1 + i] * u[i];
        }
        d.luu.fill(0.0);
        for i in 0..3 {
            d.luu[(i, i)] = 2.0 * w[1 + i];
        }
        d.lxu.fill(0.0);
    }
}

impl HumanWalkEnd {
    /// The authors' terminal weights towards `goal`.
    pub fn new(goal: [f64; 3]) -> Self {
        Self {
            weights: TERMINAL_WEIGHTS,
            goal,
        }
    }
}

/// `a` wrapped into [−π, π] (the source's `normalizeAngle`).
pub fn wrap_angle(mut a: f64) -> f64 {
    while a > PI {
        a -= 2.0 * PI;
    }
    while a < -PI {
        a += 2.0 * PI;
    }
    a
}

impl TerminalCost<NX> for HumanWalkEnd {
    fn cost(&self, x: &Vector6<f64>) -> f64 {
        let (t, g) = (&self.weights, &self.goal);
        let dth = wrap_angle(g[2] - x[2]);
        t[0] * ((g[0] - x[0]).powi(2) + (g[1] - x[1]).powi(2))
            + t[1] * dth * dth
            + t[2] * (x[3] * x[3] + x[4] * x[4])
            + t[3] * x[5] * x[5]
    }

    fn diff(&self, x: &Vector6<f64>, lx: &mut Vector6<f64>, lxx: &mut SMatrix<f64, NX, NX>) {
        let (t, g) = (&self.weights, &self.goal);
        let dth = wrap_angle(g[2] - x[2]);
        lx.fill(0.0);
        lxx.fill(0.0);
        lx[0] = -2.0 * t[0] * (g[0] - x[0]);
        lx[1] = -2.0 * t[0] * (g[1] - x[1]);
        lx[2] = -2.0 * t[1] * dth;
        lx[3] = 2.0 * t[2] * x[3];
        lx[4] = 2.0 * t[2] * x[4];
        lx[5] = 2.0 * t[3] * x[5];
        for (i, w) in [t[0], t[0], t[1], t[2], t[2], t[3]].into_iter().enumerate() {
            lxx[(i, i)] = 2.0 * w;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn x() -> Vector6<f64> {
        Vector6::new(-2.0, 1.3, -0.4, 0.8, 0.2, -0.1)
    }

    /// The analytic derivatives against central finite differences.
    #[test]
    fn derivatives_match_finite_differences() {
        let m = HumanWalkStep::new([0.5, -0.3, 1.2]);
        let (x0, u0) = (x(), Vector3::new(0.3, -0.7, 0.1));
        let mut d = ActionDerivatives::default();
        m.calc_diff(&x0, &u0, &mut d);
        let h = 1e-6;
        let eval = |x: &Vector6<f64>, u: &Vector3<f64>| {
            let mut next = Vector6::zeros();
            let c = m.calc(x, u, &mut next);
            (next, c)
        };
        let grad = |x: &Vector6<f64>, u: &Vector3<f64>| {
            let mut d = ActionDerivatives::default();
            m.calc_diff(x, u, &mut d);
            d.lx
        };
        for i in 0..6 {
            let (mut xp, mut xm) = (x0, x0);
            xp[i] += h;
            xm[i] -= h;
            let ((np, cp), (nm, cm)) = (eval(&xp, &u0), eval(&xm, &u0));
            let col = (np - nm) / (2.0 * h);
            assert!((col - d.fx.column(i)).norm() < 1e-8, "Fx column {i}");
            assert!(((cp - cm) / (2.0 * h) - d.lx[i]).abs() < 1e-6, "Lx {i}");
            let hess_col = (grad(&xp, &u0) - grad(&xm, &u0)) / (2.0 * h);
            assert!((hess_col - d.lxx.column(i)).norm() < 1e-5, "Lxx column {i}");
        }
        for i in 0..3 {
            let (mut up, mut um) = (u0, u0);
            up[i] += h;
            um[i] -= h;
            let ((np, cp), (nm, cm)) = (eval(&x0, &up), eval(&x0, &um));
            assert!(((np - nm) / (2.0 * h) - d.fu.column(i)).norm() < 1e-8);
            assert!(((cp - cm) / (2.0 * h) - d.lu[i]).abs() < 1e-6);
        }
        let end = HumanWalkEnd::new([0.5, -0.3, 1.2]);
        let (mut lx, mut lxx) = (Vector6::zeros(), SMatrix::zeros());
        end.diff(&x0, &mut lx, &mut lxx);
        for i in 0..6 {
            let (mut xp, mut xm) = (x0, x0);
            xp[i] += h;
            xm[i] -= h;
            assert!(((end.cost(&xp) - end.cost(&xm)) / (2.0 * h) - lx[i]).abs() < 1e-6);
        }
    }
}
