//! The energy tank `E_tank = ½ s²` (seed 000 Eq 5.2) and its valves (Eq 5.20–5.23):
//! - γ = P_low / B_σ when B_σ < P_low ≤ 0, else 1: limits the power drawn for the tasks;
//! - β = 0 when the tank is empty (E ≤ E_min) and would drain (γB_σ − B_φ < 0), else 1;
//! - α = 1 when the tank is full (E ≥ E_max) and would fill (βγB_σ − B_φ > 0), else 0;
//!
//! and `Ė_tank = (1 − α)(βγ B_σ − β_φ B_φ)` (Eq 5.22 with one more valve, β_φ). Eq 5.22 leaves
//! the uncontrollable power B_φ (gravity and Coriolis along the motion, the contacts' power)
//! ungated, so an empty tank keeps paying it and its energy goes below zero (measured: a 5 cm
//! CoM step on TALOS with a 3 J tank reached −0.011 J within 1 s), where `H = S + E_tank ≥ 0`
//! no longer holds. corps closes the drain below E_min: β_φ falls from 1 at E_min to 0 at
//! E = 0 while B_φ > 0, and the QP's power row `Ḣ ≤ −q̇_jᵀτ` then refuses the command that
//! would inject what the tank cannot pay. Above E_min β_φ = 1 and the tank is Eq 5.22's. A
//! step of Euler's integration still overshoots zero where B_φ is large (a fall, a hard
//! push), so the passive formulation also bounds one step's drain by what the tank holds,
//! `Ė_tank ≥ −E_tank / dt`, and one step's filling by the room left, `Ė_tank ≤ (E_max −
//! E_tank) / dt`.
//!
//! The thesis smooths β and α "as Kronander and Billard" without giving the function; here each condition is a cubic smooth step
//! `3x² − 2x³` ([`smooth_step`]) over a band on the safe side of its threshold: β falls from
//! 1 at `E_min + energy_width` to 0 at `E_min` while the drain power goes from 0 to
//! `−power_width`; α rises from 0 at `E_max − energy_width` to 1 at `E_max` while the fill
//! power goes from 0 to `power_width`. So β = 0 only where Eq 5.21 says 0, and α ≠ 0 only
//! where the fill power is positive, which the passivity proof (Eq 5.25–5.27) needs. γ is
//! continuous as printed.

use crate::error::{ControlError, Result};

/// Tank design parameters (seed 000 L6396–L6401) and the valves' smoothing bands.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TankParams {
    /// E_max (J). Default 5.
    pub e_max: f64,
    /// E_min (J). Default 0.1.
    pub e_min: f64,
    /// P_low (W), ≤ 0. Default −0.5.
    pub p_low: f64,
    /// Width of the energy band of β and α (J). Default 0.1.
    pub energy_width: f64,
    /// Width of the power band of β and α (W). Default 0.1.
    pub power_width: f64,
}

impl Default for TankParams {
    fn default() -> Self {
        Self {
            e_max: 5.0,
            e_min: 0.1,
            p_low: -0.5,
            energy_width: 0.1,
            power_width: 0.1,
        }
    }
}

impl TankParams {
    /// 0 < E_min < E_max, P_low ≤ 0, bands > 0 and narrower than [E_min, E_max], all finite.
    pub fn check(&self) -> Result<()> {
        let bad = |reason: String| {
            Err(ControlError::Config {
                name: "energy tank".into(),
                reason,
            })
        };
        let all = [
            self.e_max,
            self.e_min,
            self.p_low,
            self.energy_width,
            self.power_width,
        ];
        if all.iter().any(|x| !x.is_finite()) {
            return bad(format!("parameters must be finite, got {self:?}"));
        }
        if !(self.e_min > 0.0 && self.e_min < self.e_max) {
            return bad(format!(
                "needs 0 < E_min < E_max, got E_min = {} J, E_max = {} J",
                self.e_min, self.e_max
            ));
        }
        if self.p_low > 0.0 {
            return bad(format!(
                "P_low is the most power the tasks may draw, ≤ 0 W, got {} W",
                self.p_low
            ));
        }
        if !(self.energy_width > 0.0 && self.power_width > 0.0) {
            return bad("the valves' smoothing widths must be > 0".into());
        }
        if 2.0 * self.energy_width > self.e_max - self.e_min {
            return bad(format!(
                "the energy band {} J is more than half of [E_min, E_max]",
                self.energy_width
            ));
        }
        Ok(())
    }
}

/// `3x² − 2x³` of `x = (value − start) / width` clamped to [0, 1]: 0 at or below `start`,
/// 1 at or above `start + width`, C¹ in between.
pub fn smooth_step(value: f64, start: f64, width: f64) -> f64 {
    let x = ((value - start) / width).clamp(0.0, 1.0);
    x * x * (3.0 - 2.0 * x)
}

/// The valves' values at one tick.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Valves {
    pub alpha: f64,
    pub beta: f64,
    pub gamma: f64,
    /// The uncontrollable drain's valve (1 above E_min; see the module).
    pub beta_phi: f64,
}

impl Valves {
    /// βγ: the scale of every reference (Eq 5.24).
    pub fn scale(&self) -> f64 {
        self.beta * self.gamma
    }
}

/// The tank: its energy, integrated from Eq 5.22.
#[derive(Clone, Debug, PartialEq)]
pub struct EnergyTank {
    pub params: TankParams,
    energy: f64,
}

impl EnergyTank {
    /// A tank holding `energy` J (the thesis starts at 3 J or at E_max = 5 J).
    pub fn new(params: TankParams, energy: f64) -> Result<Self> {
        params.check()?;
        if !(energy >= 0.0 && energy.is_finite()) {
            return Err(ControlError::Config {
                name: "energy tank".into(),
                reason: format!("initial energy must be finite and ≥ 0 J, got {energy} J"),
            });
        }
        Ok(Self { params, energy })
    }

    /// E_tank (J).
    pub fn energy(&self) -> f64 {
        self.energy
    }

    /// The valves for controllable power `b_sigma` and uncontrollable power `b_phi` (W) at
    /// the tank's energy (Eq 5.20–5.23, smoothed as the module says).
    pub fn valves(&self, b_sigma: f64, b_phi: f64) -> Valves {
        let p = &self.params;
        let gamma = if b_sigma < p.p_low {
            (p.p_low / b_sigma).clamp(0.0, 1.0)
        } else {
            1.0
        };
        let beta = self.beta_at(self.energy, gamma, b_sigma, b_phi);
        let below_min = 1.0 - smooth_step(self.energy, 0.0, p.e_min);
        let beta_phi = 1.0 - below_min * smooth_step(b_phi, 0.0, p.power_width);
        let full = smooth_step(self.energy, p.e_max - p.energy_width, p.energy_width);
        let filling = smooth_step(
            beta * gamma * b_sigma - beta_phi * b_phi,
            0.0,
            p.power_width,
        );
        Valves {
            alpha: full * filling,
            beta,
            gamma,
            beta_phi,
        }
    }

    /// β (Eq 5.21, smoothed) were the tank at `energy`: closed at E_min while the tasks
    /// would drain it (γB_σ − B_φ < 0), open from E_min + `energy_width` or while they fill.
    pub fn beta_at(&self, energy: f64, gamma: f64, b_sigma: f64, b_phi: f64) -> f64 {
        let p = &self.params;
        let empty = 1.0 - smooth_step(energy, p.e_min, p.energy_width);
        let draining = 1.0 - smooth_step(gamma * b_sigma - b_phi, -p.power_width, p.power_width);
        1.0 - empty * draining
    }

    /// Ė_tank = (1 − α)(βγ B_σ − β_φ B_φ) (Eq 5.22).
    pub fn rate(valves: &Valves, b_sigma: f64, b_phi: f64) -> f64 {
        (1.0 - valves.alpha) * (valves.scale() * b_sigma - valves.beta_phi * b_phi)
    }

    /// Integrates Ė_tank over `dt` (explicit Euler, as the thesis: the energy serves only
    /// the full and empty tests).
    pub fn integrate(&mut self, rate: f64, dt: f64) {
        self.energy += rate * dt;
    }

    /// Adds `energy` J to the tank at once (negative: takes it out), kept within
    /// [0, E_max] (what would pass E_max is let go, as α does). Returns what it could not
    /// pay: the part of a withdrawal beyond its energy (J, ≥ 0).
    pub fn transfer(&mut self, energy: f64) -> f64 {
        let target = self.energy + energy;
        self.energy = target.clamp(0.0, self.params.e_max);
        (-target).max(0.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tank(e: f64) -> EnergyTank {
        EnergyTank::new(TankParams::default(), e).expect("valid tank")
    }

    #[test]
    fn valves_follow_eq_5_21_to_5_23_outside_their_bands() {
        // Half full, drawing −2 W against P_low = −0.5 W: γ = 0.25, β = 1, α = 0.
        let v = tank(2.5).valves(-2.0, 0.0);
        assert_eq!((v.alpha, v.beta, v.gamma), (0.0, 1.0, 0.25));
        // Empty and draining: β = 0.
        let v = tank(0.05).valves(-0.4, 0.3);
        assert_eq!(v.beta, 0.0);
        // Empty but filling: β = 1.
        assert_eq!(tank(0.05).valves(0.4, 0.0).beta, 1.0);
        // At E = 0 a positive B_φ no longer drains: β_φ = 0; above E_min β_φ = 1.
        assert_eq!(tank(0.0).valves(0.0, 0.5).beta_phi, 0.0);
        assert_eq!(tank(0.2).valves(0.0, 0.5).beta_phi, 1.0);
        assert_eq!(EnergyTank::rate(&tank(0.0).valves(0.0, 0.5), 0.0, 0.5), 0.0);
        // Full and filling: α = 1; full but draining: α = 0.
        assert_eq!(tank(5.0).valves(1.0, 0.0).alpha, 1.0);
        assert_eq!(tank(5.0).valves(-0.3, 0.0).alpha, 0.0);
    }

    #[test]
    fn alpha_is_non_zero_only_when_the_tank_would_fill() {
        for e in [4.85, 4.95, 5.0, 5.2] {
            for b_sigma in [-3.0, -0.4, -0.01, 0.0, 0.05, 2.0] {
                for b_phi in [-1.0, 0.0, 0.03, 1.0] {
                    let t = tank(e);
                    let v = t.valves(b_sigma, b_phi);
                    let fill = v.scale() * b_sigma - v.beta_phi * b_phi;
                    assert!(v.alpha == 0.0 || fill > 0.0, "e {e} σ {b_sigma} φ {b_phi}");
                    assert!((0.0..=1.0).contains(&v.alpha));
                    assert!((0.0..=1.0).contains(&v.beta));
                    assert!((0.0..=1.0).contains(&v.gamma));
                    // Eq 5.25: Ḣ − (−vᵀNᵀτ) = −α (βγB_σ − B_φ) ≤ 0.
                    assert!(-v.alpha * fill <= 0.0);
                }
            }
        }
    }

    #[test]
    fn bad_parameters_are_refused() {
        let p = TankParams::default();
        for bad in [
            TankParams { e_min: 5.0, ..p },
            TankParams { e_min: 6.0, ..p },
            TankParams { p_low: 0.1, ..p },
            TankParams {
                e_max: f64::NAN,
                ..p
            },
            TankParams {
                power_width: 0.0,
                ..p
            },
        ] {
            assert!(EnergyTank::new(bad, 1.0).is_err(), "{bad:?}");
        }
        assert!(EnergyTank::new(p, -0.1).is_err());
        assert!(EnergyTank::new(p, f64::INFINITY).is_err());
    }
}
