//! The current-limiting optimal-control problem of seed 000 §3.13 on one joint:
//! state `x = [q, q̇]`, control `u = i` (motor current), dynamics Eq 3.13 with the dry
//! friction smoothed to `F_s tanh(μ q̇)`, μ = 1000 (Eq 3.18), discretised by one RK4 step;
//! running cost (Eq 3.15, 3.22–3.23)
//! `l = (x − x*)ᵀ Q (x − x*) + R u² + Σ W_i C_s(x_i)² + P C_s(τ_m)²`, `τ_m = R K_m u`,
//! with the barriers `C_s` of Eq 3.14; the terminal cost keeps the state terms.
//! Derivatives are analytic (RK4 differentiated stage by stage); the cost Hessian is exact,
//! the dynamics' second derivatives are left out (Gauss–Newton, as the thesis's iLQR).

use crate::barrier::Barrier;
use crate::elbow::{ElbowParameters, Limits, Payload, G};
use nalgebra::{Matrix2, Vector2};

/// The thesis's weights and barrier steepness (seed 000 §3.13, L3820).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CurrentLimitingWeights {
    /// `Q = diag(40, 0.01)` on the tracking error.
    pub q: [f64; 2],
    /// `R = 1e-4` on the current.
    pub r: f64,
    /// `W = diag(1, 0.1)` on the position and velocity barriers.
    pub w: [f64; 2],
    /// `P = 10` on the motor-torque barrier.
    pub p: f64,
    /// λ of the position, velocity and motor-torque barriers: 10, 1, 0.5.
    pub lambda: [f64; 3],
    /// μ of `tanh(μ q̇)`: 1000.
    pub friction_sharpness: f64,
}

impl Default for CurrentLimitingWeights {
    fn default() -> Self {
        Self {
            q: [40.0, 0.01],
            r: 1e-4,
            w: [1.0, 0.1],
            p: 10.0,
            lambda: [10.0, 1.0, 0.5],
            friction_sharpness: 1000.0,
        }
    }
}

/// Derivatives of one node.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct NodeDerivatives {
    pub fx: Matrix2<f64>,
    pub fu: Vector2<f64>,
    pub lx: Vector2<f64>,
    pub lu: f64,
    pub lxx: Matrix2<f64>,
    pub luu: f64,
}

/// The problem's model: joint, payload, limits, weights and step.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CurrentLimitingOcp {
    pub joint: ElbowParameters,
    pub payload: Payload,
    pub weights: CurrentLimitingWeights,
    /// Node duration, s.
    pub dt: f64,
    /// Barriers on q, q̇ and τ_m; None drops them (the comparison without barrier).
    pub barriers: Option<[Barrier; 3]>,
}

impl CurrentLimitingOcp {
    /// The problem with the thesis's weights, barriers on `limits` (the current limit as a
    /// motor-torque limit `R K_m i`), or without barriers.
    pub fn new(
        joint: ElbowParameters,
        payload: Payload,
        limits: &Limits,
        dt: f64,
        with_barriers: bool,
    ) -> Self {
        let weights = CurrentLimitingWeights::default();
        let k = joint.drive_gain;
        let torque = [limits.current[0] * k, limits.current[1] * k];
        let barrier = |lambda: f64, [lower, upper]: [f64; 2]| Barrier {
            lambda,
            lower: lower.min(upper),
            upper: lower.max(upper),
        };
        let barriers = with_barriers.then(|| {
            [
                barrier(weights.lambda[0], limits.position),
                barrier(weights.lambda[1], limits.velocity),
                barrier(weights.lambda[2], torque),
            ]
        });
        Self {
            joint,
            payload,
            weights,
            dt,
            barriers,
        }
    }

    /// `ẋ` of Eq 3.13 with the smoothed friction.
    pub fn xdot(&self, x: &Vector2<f64>, u: f64) -> Vector2<f64> {
        self.xdot_and_jacobian(x, u).0
    }

    /// `ẋ` and `∂ẋ/∂x` (sharing the sine, cosine and tanh).
    fn xdot_and_jacobian(&self, x: &Vector2<f64>, u: f64) -> (Vector2<f64>, Matrix2<f64>) {
        let (q, v) = (x[0], x[1]);
        let (fv, fs, off) = self.joint.friction();
        let inertia = self.joint.inertia(&self.payload);
        let mu = self.weights.friction_sharpness;
        let tanh = (mu * v).tanh();
        let (sin, cos) = q.sin_cos();
        let m_x = self.joint.m_x + self.payload.l_x;
        let m_y = self.joint.m_y + self.payload.l_y;
        let gravity = G * (m_y * sin + m_x * cos);
        let a = (self.joint.drive_gain * u - fv * v - fs * tanh - off - gravity) / inertia;
        let dgrav = G * (m_y * cos - m_x * sin);
        let jacobian = Matrix2::new(
            0.0,
            1.0,
            -dgrav / inertia,
            -(fv + fs * mu * (1.0 - tanh * tanh)) / inertia,
        );
        (Vector2::new(v, a), jacobian)
    }

    /// One RK4 step: `x_{k+1}`.
    pub fn step(&self, x: &Vector2<f64>, u: f64) -> Vector2<f64> {
        let h = self.dt;
        let k1 = self.xdot(x, u);
        let k2 = self.xdot(&(x + k1 * (0.5 * h)), u);
        let k3 = self.xdot(&(x + k2 * (0.5 * h)), u);
        let k4 = self.xdot(&(x + k3 * h), u);
        x + (k1 + k2 * 2.0 + k3 * 2.0 + k4) * (h / 6.0)
    }

    /// The step and its Jacobians `∂x_{k+1}/∂x`, `∂x_{k+1}/∂u`.
    pub fn step_diff(
        &self,
        x: &Vector2<f64>,
        u: f64,
    ) -> (Vector2<f64>, Matrix2<f64>, Vector2<f64>) {
        let h = self.dt;
        let b = Vector2::new(
            0.0,
            self.joint.drive_gain / self.joint.inertia(&self.payload),
        );
        let id = Matrix2::identity();
        let (k1, a1) = self.xdot_and_jacobian(x, u);
        let (k2, a2) = self.xdot_and_jacobian(&(x + k1 * (0.5 * h)), u);
        let (k3, a3) = self.xdot_and_jacobian(&(x + k2 * (0.5 * h)), u);
        let (k4, a4) = self.xdot_and_jacobian(&(x + k3 * h), u);
        let d1x = a1;
        let d2x = a2 * (id + d1x * (0.5 * h));
        let d3x = a3 * (id + d2x * (0.5 * h));
        let d4x = a4 * (id + d3x * h);
        let d1u = b;
        let d2u = a2 * d1u * (0.5 * h) + b;
        let d3u = a3 * d2u * (0.5 * h) + b;
        let d4u = a4 * d3u * h + b;
        let next = x + (k1 + k2 * 2.0 + k3 * 2.0 + k4) * (h / 6.0);
        let fx = id + (d1x + d2x * 2.0 + d3x * 2.0 + d4x) * (h / 6.0);
        let fu = (d1u + d2u * 2.0 + d3u * 2.0 + d4u) * (h / 6.0);
        (next, fx, fu)
    }

    /// The state part of the cost at `x` against the reference `xr`, with gradient and
    /// (diagonal) Hessian.
    fn state_cost(&self, x: &Vector2<f64>, xr: &Vector2<f64>) -> (f64, Vector2<f64>, Vector2<f64>) {
        let w = &self.weights;
        let e = x - xr;
        let mut cost = w.q[0] * e[0] * e[0] + w.q[1] * e[1] * e[1];
        let mut grad = Vector2::new(2.0 * w.q[0] * e[0], 2.0 * w.q[1] * e[1]);
        let mut hess = Vector2::new(2.0 * w.q[0], 2.0 * w.q[1]);
        if let Some(b) = &self.barriers {
            for i in 0..2 {
                let (c, d, dd) = b[i].squared_cost(w.w[i], x[i]);
                cost += c;
                grad[i] += d;
                hess[i] += dd;
            }
        }
        (cost, grad, hess)
    }

    /// The control part: `R u² + P C_s(R K_m u)²` with its derivatives in `u`.
    fn control_cost(&self, u: f64) -> (f64, f64, f64) {
        let w = &self.weights;
        let (mut c, mut d, mut dd) = (w.r * u * u, 2.0 * w.r * u, 2.0 * w.r);
        if let Some(b) = &self.barriers {
            let k = self.joint.drive_gain;
            let (bc, bd, bdd) = b[2].squared_cost(w.p, k * u);
            c += bc;
            d += bd * k;
            dd += bdd * k * k;
        }
        (c, d, dd)
    }

    /// Running cost and next state.
    pub fn running(&self, x: &Vector2<f64>, u: f64, xr: &Vector2<f64>) -> (f64, Vector2<f64>) {
        (
            self.state_cost(x, xr).0 + self.control_cost(u).0,
            self.step(x, u),
        )
    }

    /// Running cost's and dynamics' derivatives.
    pub fn running_diff(&self, x: &Vector2<f64>, u: f64, xr: &Vector2<f64>) -> NodeDerivatives {
        let (_, lx, hx) = self.state_cost(x, xr);
        let (_, lu, luu) = self.control_cost(u);
        let (_, fx, fu) = self.step_diff(x, u);
        NodeDerivatives {
            fx,
            fu,
            lx,
            lu,
            lxx: Matrix2::from_diagonal(&hx),
            luu,
        }
    }

    /// Terminal cost (the state terms).
    pub fn terminal(&self, x: &Vector2<f64>, xr: &Vector2<f64>) -> f64 {
        self.state_cost(x, xr).0
    }

    /// Terminal gradient and Hessian.
    pub fn terminal_diff(
        &self,
        x: &Vector2<f64>,
        xr: &Vector2<f64>,
    ) -> (Vector2<f64>, Matrix2<f64>) {
        let (_, g, h) = self.state_cost(x, xr);
        (g, Matrix2::from_diagonal(&h))
    }
}
