//! DCM PI controller → desired ZMP (seed 000 Eq 2.29–2.30, after Caron et al.; seed 002 §4.7):
//!
//! `p* = p_ref − (1 + K_P/ω)(ξ_ref − ξ) + (K_Z/ω)(p_ref − p) − (K_I/ω) I`,
//! `İ = (ξ_ref − ξ) − I/T_I`,
//!
//! with `ξ = c + ċ/ω` (seed 000 Eq 2.23–2.27) and `I` a leaky integral of the DCM error
//! (time constant `T_I`, as lipm_walking_controller's DCM integrator, anchors §4.4; seed 002
//! §4.7 gives the equivalent decay rate γ = 1/T_I = 0.2 s⁻¹). `p*` is projected onto the
//! support polygon; while it is clamped the integral is frozen (anti-windup) and `|I|` is
//! bounded by `integral_limit` per axis.

use corps_model::support::ConvexPolygon;
use nalgebra::Vector2;

/// Gains and integrator settings of [`DcmController`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DcmGains {
    /// `K_P` [s⁻¹]. Default 8 (seed 000 Table 4.3, IK 20 cm walk and TSID-position; seed 002
    /// §4.7 reference script). Stairs use 25 (IK).
    pub kp: f64,
    /// `K_I` [s⁻²]. Default 1 (seed 000 Table 4.3).
    pub ki: f64,
    /// `K_Z` [s⁻¹ · s⁻¹·s = 1]: weight of the ZMP error term. Default 1 (seed 000 Table 4.3).
    pub kz: f64,
    /// Integrator leak time constant `T_I` [s]; `f64::INFINITY` for a pure integrator.
    /// Default 5 s (seed 002 §4.7: decay factor γ = 0.2 in the reference implementation;
    /// lipm_walking_controller uses 10–15 s on HRP-4/HRP-2Kai, anchors §4.4).
    pub integral_time_constant: f64,
    /// Bound on each component of `I` [m·s]. Default 0.1 m·s, i.e. at most
    /// `K_I/ω · 0.1 ≈ 3 cm` of ZMP shift at ω = 3.35 s⁻¹ (our choice: the order of a
    /// model-mass bias, not of a push, which the proportional term handles).
    pub integral_limit: f64,
}

impl Default for DcmGains {
    fn default() -> Self {
        Self {
            kp: 8.0,
            ki: 1.0,
            kz: 1.0,
            integral_time_constant: 5.0,
            integral_limit: 0.1,
        }
    }
}

/// Output of one [`DcmController::update`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DcmOutput {
    /// Desired ZMP, inside the support polygon.
    pub zmp: Vector2<f64>,
    /// The same before the projection onto the polygon.
    pub zmp_unclamped: Vector2<f64>,
    /// DCM error `ξ_ref − ξ`.
    pub dcm_error: Vector2<f64>,
    /// Whether the polygon clamp was active.
    pub clamped: bool,
}

/// DCM PI controller with a leaky, clamped, conditionally-frozen integrator.
#[derive(Clone, Debug)]
pub struct DcmController {
    pub gains: DcmGains,
    integral: Vector2<f64>,
}

impl DcmController {
    pub fn new(gains: DcmGains) -> Self {
        Self {
            gains,
            integral: Vector2::zeros(),
        }
    }

    /// Integral of the DCM error `I` [m·s].
    pub fn integral(&self) -> Vector2<f64> {
        self.integral
    }

    /// Zero the integral (seed 002 §4.7: reset when `K_I` is engaged).
    pub fn reset(&mut self) {
        self.integral = Vector2::zeros();
    }

    /// One tick: `omega` = ω [s⁻¹], `dcm_ref`/`dcm` = ξ_ref/ξ, `zmp_ref` = p_ref,
    /// `zmp` = measured p, `dt` [s]. The integral is updated after use (explicit Euler).
    #[allow(clippy::too_many_arguments)]
    pub fn update(
        &mut self,
        omega: f64,
        dcm_ref: &Vector2<f64>,
        dcm: &Vector2<f64>,
        zmp_ref: &Vector2<f64>,
        zmp: &Vector2<f64>,
        support: &ConvexPolygon,
        dt: f64,
    ) -> DcmOutput {
        let g = &self.gains;
        let e = dcm_ref - dcm;
        let p = zmp_ref - e * (1.0 + g.kp / omega) + (zmp_ref - zmp) * (g.kz / omega)
            - self.integral * (g.ki / omega);
        let pc = support.closest_point(&p);
        let clamped = (pc - p).norm() > 1e-12;
        if !clamped {
            let leak = if g.integral_time_constant.is_finite() {
                1.0 / g.integral_time_constant
            } else {
                0.0
            };
            for k in 0..2 {
                let i = self.integral[k] + (e[k] - leak * self.integral[k]) * dt;
                self.integral[k] = i.clamp(-g.integral_limit, g.integral_limit);
            }
        }
        DcmOutput {
            zmp: pc,
            zmp_unclamped: p,
            dcm_error: e,
            clamped,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square() -> ConvexPolygon {
        ConvexPolygon::hull(&[
            Vector2::new(-0.1, -0.15),
            Vector2::new(0.1, -0.15),
            Vector2::new(0.1, 0.15),
            Vector2::new(-0.1, 0.15),
        ])
    }

    /// Eq 2.30 is the ZMP that realizes Eq 2.29 on the LIPM: with `ξ̇ = ω(ξ − p*)` the DCM
    /// error obeys `ė = −K_P e − K_I I` when `p = p_ref` (K_Z term zero) and `ξ̇_ref =
    /// ω(ξ_ref − p_ref)` (seed 002 §4.7, checked algebra).
    #[test]
    fn desired_zmp_realizes_the_dcm_pi_law() {
        let omega = (9.81f64 / 0.876681).sqrt();
        let mut c = DcmController::new(DcmGains {
            integral_time_constant: f64::INFINITY,
            ..Default::default()
        });
        let (xi_ref, p_ref) = (Vector2::new(0.01, 0.0), Vector2::new(0.0, 0.0));
        let xi = Vector2::new(0.005, -0.004);
        // Seed a known integral.
        c.integral = Vector2::new(0.002, 0.001);
        let i0 = c.integral;
        let out = c.update(omega, &xi_ref, &xi, &p_ref, &p_ref, &square(), 1e-3);
        assert!(!out.clamped);
        let xi_dot = (xi - out.zmp) * omega;
        let xi_ref_dot = (xi_ref - p_ref) * omega;
        let e = xi_ref - xi;
        let e_dot = xi_ref_dot - xi_dot;
        let law = -e * c.gains.kp - i0 * c.gains.ki;
        assert!((e_dot - law).norm() < 1e-12, "{e_dot} vs {law}");
        assert!((c.integral - (i0 + e * 1e-3)).norm() < 1e-15);
    }

    #[test]
    fn clamp_to_polygon_freezes_the_integral() {
        let omega = 3.345;
        let mut c = DcmController::new(DcmGains::default());
        // DCM 10 cm behind its reference: p* far outside the 10 cm half-length polygon.
        let out = c.update(
            omega,
            &Vector2::new(0.1, 0.0),
            &Vector2::zeros(),
            &Vector2::zeros(),
            &Vector2::zeros(),
            &square(),
            1e-3,
        );
        assert!(out.clamped);
        assert!((out.zmp - Vector2::new(-0.1, 0.0)).norm() < 1e-12);
        assert_eq!(c.integral(), Vector2::zeros());
    }

    #[test]
    fn integral_leaks_and_saturates() {
        let mut c = DcmController::new(DcmGains {
            ki: 0.0, // keep p* inside: only the integrator is under test
            kp: 0.0,
            ..Default::default()
        });
        let big = ConvexPolygon::hull(&[
            Vector2::new(-1.0, -1.0),
            Vector2::new(1.0, -1.0),
            Vector2::new(1.0, 1.0),
            Vector2::new(-1.0, 1.0),
        ]);
        let e = Vector2::new(0.004, -0.3);
        for _ in 0..200_000 {
            c.update(
                3.345,
                &e,
                &Vector2::zeros(),
                &Vector2::zeros(),
                &Vector2::zeros(),
                &big,
                1e-3,
            );
        }
        // x: leaky steady state e·T_I = 0.02; y: saturated at the limit.
        assert!(
            (c.integral().x - 0.004 * 5.0).abs() < 1e-6,
            "{}",
            c.integral().x
        );
        assert_eq!(c.integral().y, -0.1);
    }
}
