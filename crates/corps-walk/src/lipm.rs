//! Linear inverted pendulum (cart-table) model.
//!
//! With the CoM at constant height `z_c` above the ground and no angular momentum about it,
//! each horizontal axis obeys (seed 002 §4.1 eq. 3 and eq. 22; seed 000 §3.3 eq. 2.20–2.22;
//! Kajita et al. 2003):
//!
//! ```text
//! p = c − c̈ / ω²,     c̈ = ω² (c − p),     ω = √(g / z_c)
//! ```
//!
//! The discrete *jerk-input* model (seed 002 §4.4 eq. 5, Kajita 2003 eq. 7) holds the CoM jerk
//! constant over a period `T`; its state is `x = [c, ċ, c̈]` and its output is the ZMP
//! `p = [1, 0, −1/ω²] x`.

use crate::WalkError;
use nalgebra::{Matrix3, RowVector3, Vector3};

/// Standard gravity used by default (seed 002 §2: `g = 9.81`, ω = 3.345 rad/s at
/// `z_c = 0.876681`).
pub const GRAVITY: f64 = corps_model::STANDARD_GRAVITY;

/// A linear inverted pendulum: CoM height above the ground and gravity.
#[derive(Debug, Clone, Copy, PartialEq, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Lipm {
    /// CoM height `z_c` above the ground plane (m), > 0.
    pub com_height: f64,
    /// Gravity `g` (m/s²), > 0.
    pub gravity: f64,
}

impl Lipm {
    /// A pendulum of height `com_height` under `gravity`; both must be finite and positive.
    pub fn new(com_height: f64, gravity: f64) -> Result<Self, WalkError> {
        if !(com_height.is_finite() && com_height > 0.0) {
            return Err(WalkError::InvalidParameter(
                "com_height must be finite and > 0",
            ));
        }
        if !(gravity.is_finite() && gravity > 0.0) {
            return Err(WalkError::InvalidParameter(
                "gravity must be finite and > 0",
            ));
        }
        Ok(Self {
            com_height,
            gravity,
        })
    }

    /// Natural frequency `ω = √(g / z_c)` (rad/s).
    pub fn omega(&self) -> f64 {
        (self.gravity / self.com_height).sqrt()
    }

    /// ZMP `p = c − c̈/ω²` of one axis (seed 002 eq. 3).
    pub fn zmp(&self, c: f64, c_ddot: f64) -> f64 {
        c - c_ddot * self.com_height / self.gravity
    }

    /// CoM acceleration `c̈ = ω² (c − p)` for a given ZMP (seed 002 eq. 22).
    pub fn com_acceleration(&self, c: f64, p: f64) -> f64 {
        self.gravity / self.com_height * (c - p)
    }

    /// Closed-form solution of `c̈ = ω² (c − p)` with the ZMP held at `p` for a time `t`:
    /// `c(t) = p + (c₀ − p) cosh ωt + (ċ₀/ω) sinh ωt`. Returns `(c, ċ)`.
    pub fn free_response(&self, c0: f64, v0: f64, p: f64, t: f64) -> (f64, f64) {
        let w = self.omega();
        let (ch, sh) = ((w * t).cosh(), (w * t).sinh());
        let c = p + (c0 - p) * ch + v0 / w * sh;
        let v = (c0 - p) * w * sh + v0 * ch;
        (c, v)
    }
}

/// Discrete cart-table model with piecewise-constant jerk (Kajita 2003 eq. 7):
///
/// ```text
/// x_{k+1} = A x_k + b u_k,  A = [1 T T²/2; 0 1 T; 0 0 1],  b = [T³/6; T²/2; T]
/// p_k     = c x_k,          c = [1, 0, −z_c/g]
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct JerkModel {
    /// Sampling period `T` (s).
    pub period: f64,
    /// State matrix `A`.
    pub a: Matrix3<f64>,
    /// Input vector `b`.
    pub b: Vector3<f64>,
    /// ZMP output row `c`.
    pub c: RowVector3<f64>,
}

impl JerkModel {
    /// The model of `lipm` sampled at `period` (finite, > 0).
    pub fn new(lipm: &Lipm, period: f64) -> Result<Self, WalkError> {
        if !(period.is_finite() && period > 0.0) {
            return Err(WalkError::InvalidParameter("period must be finite and > 0"));
        }
        let (a, b) = jerk_integrator(period);
        Ok(Self {
            period,
            a,
            b,
            c: RowVector3::new(1.0, 0.0, -lipm.com_height / lipm.gravity),
        })
    }

    /// `A x + b u`: the state one period later under jerk `u`.
    pub fn step(&self, x: &Vector3<f64>, jerk: f64) -> Vector3<f64> {
        self.a * x + self.b * jerk
    }

    /// ZMP `c x` of a state.
    pub fn zmp(&self, x: &Vector3<f64>) -> f64 {
        (self.c * x)[0]
    }
}

/// Exact integration of a triple integrator under constant jerk for a time `t`:
/// `A(t) = [1 t t²/2; 0 1 t; 0 0 1]`, `b(t) = [t³/6; t²/2; t]`.
pub fn jerk_integrator(t: f64) -> (Matrix3<f64>, Vector3<f64>) {
    let a = Matrix3::new(1.0, t, t * t / 2.0, 0.0, 1.0, t, 0.0, 0.0, 1.0);
    let b = Vector3::new(t * t * t / 6.0, t * t / 2.0, t);
    (a, b)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn omega_matches_seed_002() {
        // seed 002 §2: ω = 3.345 rad/s with g = 9.81, c_z = 0.876681 (3 decimals printed).
        let l = Lipm::new(crate::test_fixtures::TALOS_COM_HEIGHT, GRAVITY).unwrap();
        assert!((l.omega() - 3.345).abs() < 5e-4, "{}", l.omega());
        assert!(Lipm::new(0.0, 9.81).is_err());
        assert!(Lipm::new(0.8, f64::NAN).is_err());
    }

    #[test]
    fn discrete_model_equals_cubic_polynomial() {
        // Constant jerk j for k periods: c(t) = c0 + v0 t + a0 t²/2 + j t³/6, exactly.
        let l = Lipm::new(0.8, 9.81).unwrap();
        let m = JerkModel::new(&l, 0.005).unwrap();
        let (c0, v0, a0, j) = (0.1, -0.3, 0.7, 2.5);
        let mut x = Vector3::new(c0, v0, a0);
        for _ in 0..400 {
            x = m.step(&x, j);
        }
        let t = 400.0 * 0.005;
        let c = c0 + v0 * t + a0 * t * t / 2.0 + j * t.powi(3) / 6.0;
        let v = v0 + a0 * t + j * t * t / 2.0;
        let a = a0 + j * t;
        corps_testkit::assert_close("state", x.as_slice(), &[c, v, a], 1e-12);
    }

    #[test]
    fn zmp_feedback_converges_to_closed_form_pendulum() {
        // Drive the jerk model so that its ZMP stays at p (jerk = ω² ċ, the time derivative of
        // c̈ = ω²(c − p)); as T → 0 it must converge to the cosh/sinh solution. We check the
        // error shrinks at least linearly with T (a factor ≥ 10 per decade, minus rounding).
        let l = Lipm::new(0.814, 9.8).unwrap();
        let w2 = l.omega().powi(2);
        let p = 0.05;
        let (c0, v0) = (0.0, 0.1);
        let (c_ref, _) = l.free_response(c0, v0, p, 1.0);
        let err = |dt: f64| {
            let m = JerkModel::new(&l, dt).unwrap();
            let mut x = Vector3::new(c0, v0, w2 * (c0 - p));
            for _ in 0..(1.0 / dt).round() as usize {
                x = m.step(&x, w2 * x[1]);
            }
            (x[0] - c_ref).abs()
        };
        let (e1, e2, e3) = (err(1e-2), err(1e-3), err(1e-4));
        assert!(
            e2 < e1 / 9.0 && e3 < e2 / 9.0,
            "errors {e1:e} {e2:e} {e3:e}"
        );
    }

    #[test]
    fn free_response_satisfies_the_ode() {
        // Central second difference of c(t) equals ω²(c − p).
        let l = Lipm::new(0.876681, 9.81).unwrap();
        let (c0, v0, p) = (0.02, -0.05, 0.01);
        let h = 1e-4;
        for &t in &[0.0, 0.3, 0.9] {
            let cm = l.free_response(c0, v0, p, t - h).0;
            let c = l.free_response(c0, v0, p, t).0;
            let cp = l.free_response(c0, v0, p, t + h).0;
            let acc = (cp - 2.0 * c + cm) / (h * h);
            assert!((acc - l.com_acceleration(c, p)).abs() < 1e-5);
            assert!((l.zmp(c, acc) - p).abs() < 1e-6);
        }
    }
}
