//! Divergent component of motion (DCM) / capture point of the LIPM.
//!
//! Seed 000 §3.3 (eq. 2.23–2.28), after Englsberger et al. 2015:
//!
//! ```text
//! ξ = c + ċ/ω,     ċ = ω (ξ − c),     ξ̇ = ω (ξ − p)
//! ```
//!
//! With the ZMP held at `p`, `ξ(t) − p = (ξ₀ − p) e^{ωt}`: the DCM diverges from the ZMP,
//! and the CoM converges to the DCM. For the LIPM the instantaneous capture point (the ZMP
//! location at which the pendulum comes to rest above it) equals the DCM.

use nalgebra::Vector2;

/// DCM `ξ = c + ċ/ω` (per axis).
pub fn dcm(c: f64, c_dot: f64, omega: f64) -> f64 {
    c + c_dot / omega
}

/// DCM of a horizontal CoM position / velocity pair.
pub fn dcm2(c: &Vector2<f64>, c_dot: &Vector2<f64>, omega: f64) -> Vector2<f64> {
    c + c_dot / omega
}

/// Instantaneous capture point: the ZMP that brings the LIPM to rest over it. Equal to the
/// DCM for the LIPM (Englsberger 2015; Pratt et al. 2006).
pub fn capture_point(c: &Vector2<f64>, c_dot: &Vector2<f64>, omega: f64) -> Vector2<f64> {
    dcm2(c, c_dot, omega)
}

/// DCM dynamics `ξ̇ = ω (ξ − p)`.
pub fn dcm_derivative(xi: f64, zmp: f64, omega: f64) -> f64 {
    omega * (xi - zmp)
}

/// CoM velocity from the DCM, `ċ = ω (ξ − c)`.
pub fn com_velocity(c: f64, xi: f64, omega: f64) -> f64 {
    omega * (xi - c)
}

/// DCM after a time `t` with the ZMP held at `p`: `p + (ξ₀ − p) e^{ωt}`.
pub fn dcm_at(xi0: f64, zmp: f64, omega: f64, t: f64) -> f64 {
    zmp + (xi0 - zmp) * (omega * t).exp()
}

/// ZMP that makes the DCM reach `xi_end` after time `t` from `xi0` (inverse of [`dcm_at`]):
/// `p = (ξ_end − ξ₀ e^{ωt}) / (1 − e^{ωt})`; `t` must be > 0.
pub fn zmp_for_dcm_transfer(xi0: f64, xi_end: f64, omega: f64, t: f64) -> f64 {
    let e = (omega * t).exp();
    (xi_end - xi0 * e) / (1.0 - e)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lipm::Lipm;

    #[test]
    fn dcm_diverges_exponentially_from_fixed_zmp() {
        let l = Lipm::new(0.876681, 9.81).unwrap();
        let w = l.omega();
        let (c0, v0, p) = (0.03, 0.12, -0.01);
        let xi0 = dcm(c0, v0, w);
        for &t in &[0.1, 0.5, 1.2] {
            let (c, v) = l.free_response(c0, v0, p, t);
            let xi = dcm(c, v, w);
            let expected = (xi0 - p) * (w * t).exp();
            assert!(((xi - p) - expected).abs() < 1e-12 * expected.abs().max(1.0));
            // ċ = ω(ξ − c) holds along the trajectory
            assert!((com_velocity(c, xi, w) - v).abs() < 1e-12);
            assert!((dcm_at(xi0, p, w, t) - xi).abs() < 1e-12 * xi.abs().max(1.0));
        }
    }

    #[test]
    fn dcm_derivative_matches_finite_difference() {
        let l = Lipm::new(0.8, 9.81).unwrap();
        let w = l.omega();
        let (c0, v0, p) = (0.0, 0.2, 0.05);
        let h = 1e-6;
        let t = 0.4;
        let xi = |t: f64| {
            let (c, v) = l.free_response(c0, v0, p, t);
            dcm(c, v, w)
        };
        let fd = (xi(t + h) - xi(t - h)) / (2.0 * h);
        assert!((fd - dcm_derivative(xi(t), p, w)).abs() < 1e-7);
    }

    #[test]
    fn capture_point_stops_the_pendulum() {
        // Putting the ZMP on the capture point: the pendulum's DCM stays constant, the CoM
        // converges to it and the velocity to zero (as e^{−ωt}).
        let l = Lipm::new(0.8, 9.81).unwrap();
        let w = l.omega();
        let c = Vector2::new(0.0, 0.01);
        let v = Vector2::new(0.3, -0.1);
        let cp = capture_point(&c, &v, w);
        for k in 0..2 {
            let (c5, v5) = l.free_response(c[k], v[k], cp[k], 5.0);
            assert!((c5 - cp[k]).abs() < 1e-8 && v5.abs() < 1e-8);
        }
        let p = zmp_for_dcm_transfer(0.1, 0.3, w, 0.8);
        assert!((dcm_at(0.1, p, w, 0.8) - 0.3).abs() < 1e-12);
    }
}
