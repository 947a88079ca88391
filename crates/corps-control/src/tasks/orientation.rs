//! Frame orientation task with seed 001's feedback law on SO(3) (§2.3, Eq 2.23–2.26, after
//! Olfati-Saber 2001 §5.11.6), in the frame's LOCAL coordinates: with R the frame's rotation
//! (world from frame), ^Bω = Rᵀω its body angular velocity, R_d, ω_d, ω̇_d the reference
//! (world), e = skew(R_dᵀR)^∨, ω̃ = ^Bω − R_dᵀω_d,
//!
//! `λ̇ = K0 skew(R_dᵀR [^Bω]× − [R_dᵀω_d]× R_dᵀR)^∨` (2.25),
//! `^Bω̇* = −K0 K1 e − K1 ω̃ − λ̇ + R_dᵀω̇_d` (2.26b with the exact feed-forward),
//!
//! so that x = ω̃ + K0 e obeys ẋ = −K1 x and `V = 2 K0 K1 δ + ½|x|²`, δ = ½ tr(1 − R R_dᵀ),
//! decreases as `−K1|ω̃|² − K0² K1|e|²` (the digest's consistent form of 2.27–2.28). The rows
//! are `J_ω q̈ = ^Bω̇* − J̇_ω v` with J_ω the LOCAL Jacobian's angular rows (the body angular
//! acceleration is Rᵀω̇).

use super::{Se3Reference, TaskRows};
use crate::robot_state::RobotState;
use corps_model::{Model, Result};
use nalgebra::{Matrix3, Matrix6xX, Vector3};

/// `(skew(A))^∨ = ½ (A − Aᵀ)^∨`.
fn skew_vee(a: &Matrix3<f64>) -> Vector3<f64> {
    0.5 * Vector3::new(
        a[(2, 1)] - a[(1, 2)],
        a[(0, 2)] - a[(2, 0)],
        a[(1, 0)] - a[(0, 1)],
    )
}

fn hat(w: &Vector3<f64>) -> Matrix3<f64> {
    Matrix3::new(0.0, -w.z, w.y, w.z, 0.0, -w.x, -w.y, w.x, 0.0)
}

/// The distance δ(R, R_d) = ½ tr(1 − R R_dᵀ) ∈ [0, 2] (Eq 2.16; 1 − cos θ).
pub fn so3_distance(r: &Matrix3<f64>, r_d: &Matrix3<f64>) -> f64 {
    0.5 * (3.0 - (r * r_d.transpose()).trace())
}

/// The body angular acceleration ^Bω̇* of the SO(3) law (module docs) for the frame at `r`
/// with body angular velocity `w_body`, towards `r_d` moving at world `w_d` with world
/// acceleration `dw_d`, gains K0 = `k0`, K1 = `k1`.
pub fn so3_acceleration(
    r: &Matrix3<f64>,
    w_body: &Vector3<f64>,
    r_d: &Matrix3<f64>,
    w_d: &Vector3<f64>,
    dw_d: &Vector3<f64>,
    k0: f64,
    k1: f64,
) -> Vector3<f64> {
    let rel = r_d.transpose() * r;
    let e = skew_vee(&rel);
    let w_d_body = r_d.transpose() * w_d;
    let lambda_dot = k0 * skew_vee(&(rel * hat(w_body) - hat(&w_d_body) * rel));
    -k0 * k1 * e - k1 * (w_body - w_d_body) - lambda_dot + r_d.transpose() * dw_d
}

/// An orientation task on one frame under the SO(3) law (module docs). The reference's
/// translation is ignored.
#[derive(Clone, Debug)]
pub struct OrientationTask {
    pub frame: usize,
    /// K0 (1/s).
    pub k0: f64,
    /// K1 (1/s).
    pub k1: f64,
    pub reference: Se3Reference,
    jac: Matrix6xX<f64>,
    rows: TaskRows,
}

impl OrientationTask {
    pub fn new(nv: usize, frame: usize, k0: f64, k1: f64, reference: Se3Reference) -> Self {
        Self {
            frame,
            k0,
            k1,
            reference,
            jac: Matrix6xX::zeros(nv),
            rows: TaskRows::new(3, nv),
        }
    }

    /// The distance δ of the frame at state `s` to the reference.
    pub fn distance(&self, model: &Model, s: &RobotState) -> Result<f64> {
        let r = s.frame_placement(model, self.frame)?.rotation;
        Ok(so3_distance(&r, &self.reference.placement.rotation))
    }

    pub fn compute(&mut self, model: &Model, s: &RobotState) -> Result<&TaskRows> {
        let r = s.frame_placement(model, self.frame)?.rotation;
        let w_body = s.frame_velocity_local(model, self.frame)?.angular;
        let drift = s.frame_drift_local(model, self.frame)?.angular;
        let reference = &self.reference;
        let acc = so3_acceleration(
            &r,
            &w_body,
            &reference.placement.rotation,
            &reference.velocity.angular,
            &reference.acceleration.angular,
            self.k0,
            self.k1,
        );
        s.frame_jacobian_local(model, self.frame, &mut self.jac)?;
        for k in 0..3 {
            self.rows.b[k] = acc[k] - drift[k];
            for c in 0..self.jac.ncols() {
                self.rows.a[(k, c)] = self.jac[(3 + k, c)];
            }
        }
        Ok(&self.rows)
    }
}

impl super::Task for OrientationTask {
    fn level(&self) -> super::TaskLevel {
        super::TaskLevel::Acceleration
    }
    fn dim(&self) -> usize {
        3
    }
    fn compute(&mut self, model: &Model, s: &RobotState) -> crate::error::Result<&TaskRows> {
        Ok(OrientationTask::compute(self, model, s)?)
    }
    fn last_rows(&self) -> Option<&TaskRows> {
        Some(&self.rows)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Rotation3;

    fn exp(w: &Vector3<f64>) -> Matrix3<f64> {
        *Rotation3::from_scaled_axis(*w).matrix()
    }

    /// A rigid body driven by ω̇ = R ^Bω̇* (world) from a large error, the reference turning
    /// at a constant rate: x = ω̃ + K0 e decays as e^{−K1 t} and V never increases.
    #[test]
    fn the_law_decays_x_at_rate_k1_and_v_decreases() {
        let (k0, k1, dt) = (2.0, 3.0, 1e-5);
        let mut r = exp(&Vector3::new(1.2, -0.8, 0.5));
        let mut w = Vector3::new(0.3, -0.2, 0.4); // world
        let w_d = Vector3::new(0.0, 0.0, 0.5);
        let mut r_d = Matrix3::identity();
        let x_of = |r: &Matrix3<f64>, w: &Vector3<f64>, r_d: &Matrix3<f64>| {
            let e = skew_vee(&(r_d.transpose() * r));
            r.transpose() * w - r_d.transpose() * w_d + k0 * e
        };
        let v_of = |r: &Matrix3<f64>, w: &Vector3<f64>, r_d: &Matrix3<f64>| {
            2.0 * k0 * k1 * so3_distance(r, r_d) + 0.5 * x_of(r, w, r_d).norm_squared()
        };
        let x0 = x_of(&r, &w, &r_d).norm();
        let mut v_prev = v_of(&r, &w, &r_d);
        let steps = 100_000; // 1 s
        for _ in 0..steps {
            let wb = r.transpose() * w;
            let acc_body = so3_acceleration(&r, &wb, &r_d, &w_d, &Vector3::zeros(), k0, k1);
            // Semi-implicit step of Ṙ = [ω]× R, ω̇ = R ^Bω̇*.
            w += r * acc_body * dt;
            r = exp(&(w * dt)) * r;
            r_d = exp(&(w_d * dt)) * r_d;
            let v = v_of(&r, &w, &r_d);
            assert!(v <= v_prev + 1e-9, "V rose from {v_prev} to {v}");
            v_prev = v;
        }
        let x1 = x_of(&r, &w, &r_d).norm();
        let expected = x0 * (-k1 * 1.0_f64).exp();
        assert!(
            (x1 - expected).abs() < 1e-3 * x0,
            "|x| after 1 s: {x1}, e^(-K1 t)|x0| = {expected}"
        );
    }

    #[test]
    fn distance_is_one_minus_cos_of_the_angle() {
        let r = exp(&Vector3::new(0.0, 0.7, 0.0));
        assert!((so3_distance(&r, &Matrix3::identity()) - (1.0 - 0.7_f64.cos())).abs() < 1e-14);
        let flip = exp(&Vector3::new(std::f64::consts::PI, 0.0, 0.0));
        assert!((so3_distance(&flip, &Matrix3::identity()) - 2.0).abs() < 1e-14);
    }
}
