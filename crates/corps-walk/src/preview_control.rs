//! Kajita 2003 ZMP preview control (Kajita et al., "Biped walking pattern generation by using
//! preview control of zero-moment point", ICRA 2003), per horizontal axis, on the jerk-input
//! cart-table model of [`crate::lipm::JerkModel`].
//!
//! **With integral action** (Kajita 2003 eq. 10–13, after Katayama et al. 1985): the optimal
//! control of the augmented system `[e; Δx]`, `Ã = [1 cA; 0 A]`, `b̃ = [cb; b]`, with cost
//! `Σ Q e² + R Δu²`, written in absolute form:
//!
//! ```text
//! u_k = −G_i Σ_{i≤k} (c x_i − p_ref,i) − G_x x_k − Σ_{j=1..N} G_d(j) p_ref,k+j
//! [G_i G_x] = (R + b̃ᵀP̃b̃)⁻¹ b̃ᵀP̃Ã,  G_d(1) = −G_i,
//! G_d(l) = −(R + b̃ᵀP̃b̃)⁻¹ b̃ᵀ (Ãcᵀ)^{l−1} P̃ e₁,   Ãc = Ã − b̃ [G_i G_x]
//! ```
//!
//! **Without integrator** (Kajita's earlier form): `u_k = −K x_k + Σ_{j=1..N} f_j p_ref,k+j`,
//! `K = (R + bᵀPb)⁻¹ bᵀPA`, `f_j = (R + bᵀPb)⁻¹ bᵀ (A_cᵀ)^{j−1} cᵀ Q`. It is stored in the same
//! form with `G_i = 0`, `G_x = K`, `G_d(j) = −f_j`.
//!
//! The Riccati equations are solved by [`crate::riccati::solve_dare`]. Gains reproduce
//! jrl-walkgen's `TestRiccatiEquation` references (anchors §4.3; see the tests).

use crate::lipm::{JerkModel, Lipm};
use crate::riccati::solve_dare;
use crate::WalkError;
use nalgebra::{DMatrix, RowVector3, Vector3};

/// Parameters of a preview controller.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PreviewParams {
    /// Control period `T` (s).
    pub period: f64,
    /// The pendulum.
    pub lipm: Lipm,
    /// ZMP error weight `Q`.
    pub q: f64,
    /// Jerk (increment) weight `R`.
    pub r: f64,
    /// Number of preview samples `N` (preview time `N T`).
    pub horizon: usize,
}

impl PreviewParams {
    /// Kajita 2003 / jrl-walkgen test values: `T = 5 ms`, `z_c = 0.814`, `g = 9.8`, `Q = 1`,
    /// `R = 1e-6`, `N = 320` (1.6 s) (anchors §1.4, §4.3).
    pub fn kajita2003() -> Self {
        Self {
            period: 0.005,
            lipm: Lipm {
                com_height: 0.814,
                gravity: 9.8,
            },
            q: 1.0,
            r: 1e-6,
            horizon: 320,
        }
    }
}

/// Preview-control gains.
#[derive(Debug, Clone, PartialEq)]
pub struct PreviewController {
    /// The discrete model.
    pub model: JerkModel,
    /// Integral gain `G_i` (0 for the variant without integrator).
    pub gi: f64,
    /// State gain `G_x` (or `K`).
    pub gx: RowVector3<f64>,
    /// Preview gains `G_d(1..=N)` (`gd[j − 1] = G_d(j)`; `−f_j` without integrator).
    pub gd: Vec<f64>,
}

/// State of one axis under preview control.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct PreviewAxis {
    /// `[c, ċ, c̈]`.
    pub x: Vector3<f64>,
    /// `Σ (c x_i − p_ref,i)` (integral action).
    pub error_sum: f64,
}

impl PreviewAxis {
    /// An axis at rest at position `c`.
    pub fn at_rest(c: f64) -> Self {
        Self {
            x: Vector3::new(c, 0.0, 0.0),
            error_sum: 0.0,
        }
    }
}

fn check(p: &PreviewParams) -> Result<JerkModel, WalkError> {
    let lipm = Lipm::new(p.lipm.com_height, p.lipm.gravity)?;
    if !(p.q.is_finite() && p.q > 0.0 && p.r.is_finite() && p.r > 0.0) {
        return Err(WalkError::InvalidParameter(
            "preview weights Q and R must be > 0",
        ));
    }
    if p.horizon == 0 {
        return Err(WalkError::InvalidParameter(
            "preview horizon must be ≥ 1 sample",
        ));
    }
    JerkModel::new(&lipm, p.period)
}

impl PreviewController {
    /// Kajita 2003 preview control with integral action (augmented 4-state system).
    pub fn with_integral(p: &PreviewParams) -> Result<Self, WalkError> {
        let m = check(p)?;
        let ca = m.c * m.a;
        let cb = (m.c * m.b)[0];
        let mut at = DMatrix::<f64>::zeros(4, 4);
        at[(0, 0)] = 1.0;
        for j in 0..3 {
            at[(0, j + 1)] = ca[j];
            for i in 0..3 {
                at[(i + 1, j + 1)] = m.a[(i, j)];
            }
        }
        let bt = DMatrix::from_column_slice(4, 1, &[cb, m.b[0], m.b[1], m.b[2]]);
        let mut qt = DMatrix::<f64>::zeros(4, 4);
        qt[(0, 0)] = p.q;
        let rt = DMatrix::from_element(1, 1, p.r);
        let pt = solve_dare(&at, &bt, &qt, &rt)?;
        let s = p.r + (bt.transpose() * &pt * &bt)[0];
        let k = bt.transpose() * &pt * &at / s; // 1×4
        let ac = &at - &bt * &k;
        let mut x = -pt.column(0).clone_owned(); // X(0) = −P̃ e₁
        let mut gd = Vec::with_capacity(p.horizon);
        for _ in 0..p.horizon {
            gd.push((bt.transpose() * &x)[0] / s);
            x = ac.transpose() * x;
        }
        Ok(Self {
            model: m,
            gi: k[0],
            gx: RowVector3::new(k[1], k[2], k[3]),
            gd,
        })
    }

    /// Preview control without integrator (3-state).
    pub fn without_integrator(p: &PreviewParams) -> Result<Self, WalkError> {
        let m = check(p)?;
        let a = DMatrix::from_fn(3, 3, |i, j| m.a[(i, j)]);
        let b = DMatrix::from_column_slice(3, 1, m.b.as_slice());
        let c = DMatrix::from_row_slice(1, 3, m.c.as_slice());
        let q = c.transpose() * &c * p.q;
        let pm = solve_dare(&a, &b, &q, &DMatrix::from_element(1, 1, p.r))?;
        let s = p.r + (b.transpose() * &pm * &b)[0];
        let k = b.transpose() * &pm * &a / s;
        let ac = &a - &b * &k;
        let mut x = c.transpose() * p.q;
        let mut gd = Vec::with_capacity(p.horizon);
        for _ in 0..p.horizon {
            gd.push(-(b.transpose() * &x)[0] / s);
            x = ac.transpose() * x;
        }
        Ok(Self {
            model: m,
            gi: 0.0,
            gx: RowVector3::new(k[0], k[1], k[2]),
            gd,
        })
    }

    /// Number of preview samples `N`.
    pub fn horizon(&self) -> usize {
        self.gd.len()
    }

    /// One control step of an axis: accumulates the ZMP error `c x_k − p_ref,k`, computes the
    /// jerk `u_k` and advances the state to `x_{k+1}`. `zmp_ref[j]` is `p_ref,k+j`,
    /// `j = 0..=N` (at least `N + 1` samples). Returns `u_k`. Never allocates.
    pub fn step(&self, axis: &mut PreviewAxis, zmp_ref: &[f64]) -> Result<f64, WalkError> {
        let n = self.gd.len();
        if zmp_ref.len() < n + 1 {
            return Err(WalkError::PreviewTooShort {
                got: zmp_ref.len(),
                need: n + 1,
            });
        }
        axis.error_sum += self.model.zmp(&axis.x) - zmp_ref[0];
        // Σ_j G_d(j) p_ref,k+j: 1600 terms at 1 ms, in independent partial sums.
        let preview = corps_qp::dot(&self.gd, &zmp_ref[1..=n]);
        let u = -self.gi * axis.error_sum - (self.gx * axis.x)[0] - preview;
        axis.x = self.model.step(&axis.x, u);
        Ok(u)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::riccati::dare_residual;

    /// |value − printed| ≤ half a unit of the last printed digit.
    fn printed(value: f64, printed: &str) {
        let digits = printed.split('.').nth(1).map_or(0, str::len);
        let half_ulp = 0.5 * 10f64.powi(-(digits as i32));
        let p: f64 = printed.parse().unwrap();
        assert!(
            (value - p).abs() <= half_ulp,
            "{value} vs printed {printed}"
        );
    }

    #[test]
    fn reproduces_jrl_walkgen_gains_with_integral_action() {
        // anchors §4.3 item 1 (jrl-walkgen TestRiccatiEquationWeightsWithInitialPose)
        let c = PreviewController::with_integral(&PreviewParams::kajita2003()).unwrap();
        printed(c.gi, "618.556");
        printed(c.gx[0], "72738.07");
        printed(c.gx[1], "21565.614");
        printed(c.gx[2], "177.089");
        let expected = [
            "618.556", "777.45", "952.24", "1082.22", "1155.16", "1181.2", "1176.71", "1156.25",
        ];
        for (j, e) in expected.iter().enumerate() {
            printed(-c.gd[j], e);
        }
        assert_eq!(c.horizon(), 320);
        printed(-c.gd[319], "5.04108");
        // G_d(1) = −G_i exactly by construction of the recurrence
        assert!((c.gd[0] + c.gi).abs() < 1e-9 * c.gi);
    }

    #[test]
    fn reproduces_jrl_walkgen_gains_without_integrator() {
        // anchors §4.3 item 2: T = 0.01, R = 1e-5, N = 160
        let p = PreviewParams {
            period: 0.01,
            r: 1e-5,
            horizon: 160,
            ..PreviewParams::kajita2003()
        };
        let c = PreviewController::without_integrator(&p).unwrap();
        printed(c.gx[0], "268.484");
        printed(c.gx[1], "165.550");
        printed(c.gx[2], "28.740");
        let f = [
            "-59.8616", "-42.0874", "-28.4901", "-18.1176", "-10.2337", "-4.26928", "0.21549",
            "3.56057",
        ];
        for (j, e) in f.iter().enumerate() {
            printed(-c.gd[j], e);
        }
        printed(-c.gd[159], "0.0818453");
        let sum: f64 = c.gd.iter().map(|g| -g).sum();
        assert!((sum - 266.16).abs() < 0.005, "Σf = {sum}"); // printed "≈ 266.16"
    }

    #[test]
    fn riccati_solution_is_a_fixed_point() {
        let p = PreviewParams::kajita2003();
        let m = JerkModel::new(&p.lipm, p.period).unwrap();
        let a = DMatrix::from_fn(3, 3, |i, j| m.a[(i, j)]);
        let b = DMatrix::from_column_slice(3, 1, m.b.as_slice());
        let c = DMatrix::from_row_slice(1, 3, m.c.as_slice());
        let q = c.transpose() * &c;
        let r = DMatrix::from_element(1, 1, p.r);
        let pm = solve_dare(&a, &b, &q, &r).unwrap();
        assert!(dare_residual(&a, &b, &q, &r, &pm) < 1e-10);
    }

    #[test]
    fn rejects_bad_parameters_and_short_previews() {
        let mut p = PreviewParams::kajita2003();
        p.r = 0.0;
        assert!(PreviewController::with_integral(&p).is_err());
        let c = PreviewController::with_integral(&PreviewParams {
            horizon: 10,
            ..PreviewParams::kajita2003()
        })
        .unwrap();
        let mut ax = PreviewAxis::at_rest(0.0);
        assert!(matches!(
            c.step(&mut ax, &[0.0; 5]),
            Err(WalkError::PreviewTooShort { got: 5, need: 11 })
        ));
    }
}
