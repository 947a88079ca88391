//! Joint-limit avoidance by re-parametrising the feasible joint space (seed 001 §2.9, ch. 3):
//! `s(ξ) = δ tanh(ξ) + s₀` maps every `ξ ∈ ℝⁿ` inside `S = {s_min < s < s_max}` (Eq 3.6–3.9),
//! `s₀ = (s_max + s_min)/2`, `δ = (s_max − s_min)/2`; `J(ξ) = diag(δ sech²ξ)` (3.14),
//! `J̇ = diag(−2 δ tanh ξ sech²ξ ξ̇)`. Feedback on `ξ̃ = ξ − ξ_d` instead of `s̃ = s − s_d`
//! keeps `s` inside `S` (Lemma 3). The laws, for a fixed-base model
//! `M s̈ + C ṡ + G = τ` (3.1):
//! - classical (3.3): `τ = M s̈_d + C ṡ_d + G − K_P s̃ − K_D s̃̇`;
//! - re-parametrised (3.19): `τ = M J ξ̈_d + (M J̇ + C J) ξ̇_d + G − J⁻¹K_P ξ̃ − J⁻¹K_D ξ̃̇`;
//! - set point (3.20): `τ = G − J⁻¹K_P ξ̃ − J⁻¹K_D J⁻¹ ṡ`;
//! - set point with `K_P = J K'_P`, `K_D = J K'_D J` (3.23): `τ = G − K'_P ξ̃ − K'_D ṡ`;
//! - recommended (3.26): (3.3) with `−K_P ξ̃` in place of `−K_P s̃`;
//!
//! and, for a whole-body controller, the postural acceleration (3.27)
//! `s̈* = s̈_d − J⁻¹K_p ξ̃ − J⁻¹K_d J⁻¹ s̃̇`. `ξ` is clamped at `±ξ_max` (the thesis: 100 on
//! the leg, atanh(0.99) whole-body), so that a state on or past a limit gives a finite, large
//! restoring term. `sech²` is computed as `4/(eᶠ + e⁻ᶠ)²`, which stays positive where
//! `1 − tanh²` rounds to zero.

use crate::error::{ControlError, Result};
use corps_model::{coriolis_matrix, crba, generalized_gravity, Data, Model};
use nalgebra::DVector;

/// The map `s = δ tanh(ξ) + s₀` of a box of joint limits.
#[derive(Clone, Debug, PartialEq)]
pub struct TanhJointMap {
    s0: DVector<f64>,
    delta: DVector<f64>,
    xi_max: f64,
}

fn sech2(x: f64) -> f64 {
    let e = (-x.abs()).exp();
    4.0 * e * e / ((1.0 + e * e) * (1.0 + e * e))
}

impl TanhJointMap {
    /// The map of `lower < s < upper`, `ξ` clamped at `±xi_max`. Every `upper` must exceed
    /// its `lower` (Assumption 2).
    pub fn new(lower: &[f64], upper: &[f64], xi_max: f64) -> Result<Self> {
        if lower.len() != upper.len() {
            return Err(config(
                "limits",
                format!("{} lower, {} upper", lower.len(), upper.len()),
            ));
        }
        if let Some(i) = (0..lower.len())
            .find(|&i| !(lower[i].is_finite() && upper[i].is_finite() && upper[i] > lower[i]))
        {
            return Err(config(
                "limits",
                format!("joint {i}: [{}, {}] is not an interval", lower[i], upper[i]),
            ));
        }
        if !(xi_max > 0.0 && xi_max.is_finite()) {
            return Err(config("xi_max", format!("{xi_max} must be positive")));
        }
        let n = lower.len();
        Ok(Self {
            s0: DVector::from_fn(n, |i, _| 0.5 * (upper[i] + lower[i])),
            delta: DVector::from_fn(n, |i, _| 0.5 * (upper[i] - lower[i])),
            xi_max,
        })
    }

    pub fn len(&self) -> usize {
        self.s0.len()
    }

    pub fn is_empty(&self) -> bool {
        self.s0.is_empty()
    }

    /// `ξ_i = atanh((s_i − s₀_i)/δ_i)` clamped at `±ξ_max` (a state on or past a limit gives
    /// the clamp).
    pub fn xi(&self, i: usize, s: f64) -> f64 {
        let r = (s - self.s0[i]) / self.delta[i];
        if r >= 1.0 {
            self.xi_max
        } else if r <= -1.0 {
            -self.xi_max
        } else {
            r.atanh().clamp(-self.xi_max, self.xi_max)
        }
    }

    /// `ξ_d` of a reference, which must lie strictly inside the limits (Assumption 2).
    pub fn xi_of_reference(&self, i: usize, s_d: f64) -> Result<f64> {
        let r = (s_d - self.s0[i]) / self.delta[i];
        if r.is_nan() || r.abs() >= 1.0 {
            return Err(config(
                "reference",
                format!(
                    "joint {i}: {s_d} is not inside its limits [{}, {}]",
                    self.s0[i] - self.delta[i],
                    self.s0[i] + self.delta[i]
                ),
            ));
        }
        Ok(r.atanh().clamp(-self.xi_max, self.xi_max))
    }

    /// `s(ξ)`.
    pub fn s(&self, i: usize, xi: f64) -> f64 {
        self.delta[i] * xi.tanh() + self.s0[i]
    }

    /// `J_ii(ξ) = δ_i sech²ξ`.
    pub fn jacobian(&self, i: usize, xi: f64) -> f64 {
        self.delta[i] * sech2(xi)
    }

    /// `J̇_ii(ξ, ξ̇) = −2 δ_i tanh ξ sech²ξ ξ̇`.
    pub fn jacobian_rate(&self, i: usize, xi: f64, xi_dot: f64) -> f64 {
        -2.0 * self.delta[i] * xi.tanh() * sech2(xi) * xi_dot
    }
}

fn config(name: &str, reason: String) -> ControlError {
    ControlError::Config {
        name: format!("joint-limit avoidance {name}"),
        reason,
    }
}

/// Which law computes the torque.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum JointLimitLaw {
    /// Eq 3.3, the classical passivity-based law (no limit awareness).
    Classical,
    /// Eq 3.19, the re-parametrised law with its proof (Lemma 3).
    Reparametrized,
    /// Eq 3.20, its set-point form.
    SetPoint,
    /// Eq 3.23, the set point with the gains `K_P = J K'_P`, `K_D = J K'_D J`.
    SetPointScaledGains,
    /// Eq 3.26, the classical law with `−K_P ξ̃` for `−K_P s̃` (the thesis's recommendation).
    Recommended,
}

/// A joint-space torque controller for a fixed-base model whose every velocity is a joint of
/// the map.
#[derive(Clone, Debug)]
pub struct JointLimitController {
    pub map: TanhJointMap,
    pub law: JointLimitLaw,
    pub kp: DVector<f64>,
    pub kd: DVector<f64>,
    data: Data,
    a: DVector<f64>,
    v_ref: DVector<f64>,
}

/// A reference `(s_d, ṡ_d, s̈_d)`.
pub struct JointReference<'a> {
    pub s: &'a [f64],
    pub v: &'a [f64],
    pub a: &'a [f64],
}

impl JointLimitController {
    pub fn new(
        model: &Model,
        map: TanhJointMap,
        law: JointLimitLaw,
        kp: DVector<f64>,
        kd: DVector<f64>,
    ) -> Result<Self> {
        let n = model.nv;
        if model.nq != n || map.len() != n || kp.len() != n || kd.len() != n {
            return Err(config(
                "sizes",
                format!(
                    "a fixed-base model of {n} one-dof joints needs {n} limits and gains \
                     (got {}, {}, {})",
                    map.len(),
                    kp.len(),
                    kd.len()
                ),
            ));
        }
        Ok(Self {
            map,
            law,
            kp,
            kd,
            data: Data::new(model),
            a: DVector::zeros(n),
            v_ref: DVector::zeros(n),
        })
    }

    /// The torque at state `(s, ṡ)` for `reference`, written to `tau`.
    pub fn torque(
        &mut self,
        model: &Model,
        s: &[f64],
        s_dot: &[f64],
        reference: &JointReference,
        tau: &mut [f64],
    ) -> Result<()> {
        let n = self.map.len();
        let g = generalized_gravity(model, &mut self.data, s)?.clone_owned();
        let m = crba(model, &mut self.data, s)?.clone_owned();
        let c = coriolis_matrix(model, &mut self.data, s, s_dot)?.clone_owned();
        let map = &self.map;
        match self.law {
            JointLimitLaw::Classical | JointLimitLaw::Recommended => {
                // M s̈_d + C ṡ_d + G − K_P e − K_D s̃̇, e = s̃ or ξ̃.
                for i in 0..n {
                    self.a[i] = reference.a[i];
                    self.v_ref[i] = reference.v[i];
                }
                let ff = &m * &self.a + &c * &self.v_ref;
                for i in 0..n {
                    let e = match self.law {
                        JointLimitLaw::Classical => s[i] - reference.s[i],
                        _ => map.xi(i, s[i]) - map.xi_of_reference(i, reference.s[i])?,
                    };
                    tau[i] =
                        ff[i] + g[i] - self.kp[i] * e - self.kd[i] * (s_dot[i] - reference.v[i]);
                }
            }
            JointLimitLaw::Reparametrized => {
                // ξ_d, ξ̇_d = J(ξ_d)⁻¹ṡ_d, ξ̈_d = J(ξ_d)⁻¹(s̈_d − J̇(ξ_d, ξ̇_d) ξ̇_d).
                let mut xi_tilde = DVector::zeros(n);
                let mut xi_tilde_dot = DVector::zeros(n);
                let mut jac = DVector::zeros(n);
                for i in 0..n {
                    let xi_d = map.xi_of_reference(i, reference.s[i])?;
                    let jd = map.jacobian(i, xi_d);
                    let xi_d_dot = reference.v[i] / jd;
                    let xi_d_ddot =
                        (reference.a[i] - map.jacobian_rate(i, xi_d, xi_d_dot) * xi_d_dot) / jd;
                    let xi = map.xi(i, s[i]);
                    let j = map.jacobian(i, xi);
                    let xi_dot = s_dot[i] / j;
                    jac[i] = j;
                    xi_tilde[i] = xi - xi_d;
                    xi_tilde_dot[i] = xi_dot - xi_d_dot;
                    // M J ξ̈_d + M J̇ ξ̇_d = M a with a = J ξ̈_d + J̇ ξ̇_d; C J ξ̇_d = C w.
                    self.a[i] = j * xi_d_ddot + map.jacobian_rate(i, xi, xi_dot) * xi_d_dot;
                    self.v_ref[i] = j * xi_d_dot;
                }
                let ff = &m * &self.a + &c * &self.v_ref;
                for i in 0..n {
                    tau[i] = ff[i] + g[i]
                        - (self.kp[i] * xi_tilde[i] + self.kd[i] * xi_tilde_dot[i]) / jac[i];
                }
            }
            JointLimitLaw::SetPoint | JointLimitLaw::SetPointScaledGains => {
                for i in 0..n {
                    let xi = map.xi(i, s[i]);
                    let e = xi - map.xi_of_reference(i, reference.s[i])?;
                    let j = map.jacobian(i, xi);
                    tau[i] = g[i]
                        - match self.law {
                            JointLimitLaw::SetPoint => {
                                (self.kp[i] * e + self.kd[i] * s_dot[i] / j) / j
                            }
                            _ => self.kp[i] * e + self.kd[i] * s_dot[i],
                        };
                }
            }
        }
        if tau.iter().any(|t| !t.is_finite()) {
            return Err(ControlError::NonFinite("joint-limit torque"));
        }
        Ok(())
    }
}

/// The whole-body postural acceleration of Eq 3.27 for joint `i`:
/// `s̈* = s̈_d − J⁻¹K_p ξ̃ − J⁻¹K_d J⁻¹ s̃̇`.
pub fn postural_acceleration(
    map: &TanhJointMap,
    i: usize,
    s: f64,
    s_dot: f64,
    reference: (f64, f64, f64),
    kp: f64,
    kd: f64,
) -> Result<f64> {
    let (s_d, v_d, a_d) = reference;
    let xi = map.xi(i, s);
    let j = map.jacobian(i, xi);
    let e = xi - map.xi_of_reference(i, s_d)?;
    Ok(a_d - kp * e / j - kd * (s_dot - v_d) / (j * j))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_map_and_its_derivatives() {
        let m = TanhJointMap::new(&[-0.5, -1.7], &[1.5, 0.0], 100.0).unwrap();
        for (i, s) in [(0, 0.3), (0, 1.49), (1, -1.6), (1, -0.01)] {
            let xi = m.xi(i, s);
            assert!((m.s(i, xi) - s).abs() < 1e-12);
            let h = 1e-6;
            let fd = (m.s(i, xi + h) - m.s(i, xi - h)) / (2.0 * h);
            assert!((fd - m.jacobian(i, xi)).abs() < 1e-8 * (1.0 + fd.abs()));
            let xi_dot = 0.7;
            let fd = (m.jacobian(i, xi + h * xi_dot) - m.jacobian(i, xi - h * xi_dot)) / (2.0 * h);
            assert!((fd - m.jacobian_rate(i, xi, xi_dot)).abs() < 1e-7 * (1.0 + fd.abs()));
        }
        // On and past a limit: the clamp, a positive (tiny) Jacobian.
        assert_eq!(m.xi(0, 1.5), 100.0);
        assert_eq!(m.xi(0, 7.0), 100.0);
        assert_eq!(m.xi(1, -3.0), -100.0);
        assert!(m.jacobian(0, 100.0) > 0.0);
        assert!(m.xi_of_reference(1, 0.0).is_err());
        assert!(m.xi_of_reference(1, f64::NAN).is_err());
        assert!(TanhJointMap::new(&[0.0], &[0.0], 1.0).is_err());
        assert!(TanhJointMap::new(&[0.0], &[1.0], 0.0).is_err());
    }
}
