//! When a run counts as failed: the fall and divergence criteria of a robot (its
//! description's `[fall]`, replaced by a scenario's `[verdict]`).

use serde::{Deserialize, Serialize};

/// When a run counts as failed. Defaults: issue "honest runs" (contact force 50× the body
/// weight, base speed 10 m/s); the fall and controller limits are this module's choice.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Criteria {
    /// Fell: the CoM height above the support below this fraction of its initial value.
    pub min_com_height_fraction: f64,
    /// Fell: bodies other than the allowed contacts carry more than this fraction of the
    /// body weight.
    pub other_contact_weight_fraction: f64,
    /// Diverged: the total contact force above this many body weights.
    pub max_contact_force_weights: f64,
    /// Diverged: the base faster than this (m/s).
    pub max_base_speed: f64,
    /// Controller failed: the safe command held this long without a break (s).
    pub max_safe_command_time: f64,
}

impl Default for Criteria {
    fn default() -> Self {
        Self {
            min_com_height_fraction: 0.5,
            other_contact_weight_fraction: 0.1,
            max_contact_force_weights: 50.0,
            max_base_speed: 10.0,
            max_safe_command_time: 0.1,
        }
    }
}

/// A criterion that cannot judge anything.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum CriteriaError {
    #[error("{key}: must be {what}, got {value}")]
    OutOfRange {
        key: &'static str,
        what: &'static str,
        value: f64,
    },
}

impl Criteria {
    /// Checks every value; the error names the key.
    pub fn check(&self) -> Result<(), CriteriaError> {
        let checks: [(&'static str, f64, &'static str, bool); 5] = [
            (
                "min_com_height_fraction",
                self.min_com_height_fraction,
                "in [0, 1)",
                (0.0..1.0).contains(&self.min_com_height_fraction),
            ),
            (
                "other_contact_weight_fraction",
                self.other_contact_weight_fraction,
                "a finite number > 0",
                self.other_contact_weight_fraction > 0.0
                    && self.other_contact_weight_fraction.is_finite(),
            ),
            (
                "max_contact_force_weights",
                self.max_contact_force_weights,
                "a finite number > 1",
                self.max_contact_force_weights > 1.0 && self.max_contact_force_weights.is_finite(),
            ),
            (
                "max_base_speed",
                self.max_base_speed,
                "a finite speed > 0 m/s",
                self.max_base_speed > 0.0 && self.max_base_speed.is_finite(),
            ),
            (
                "max_safe_command_time",
                self.max_safe_command_time,
                "a finite time ≥ 0 s",
                self.max_safe_command_time >= 0.0 && self.max_safe_command_time.is_finite(),
            ),
        ];
        for (key, value, what, ok) in checks {
            if !ok {
                return Err(CriteriaError::OutOfRange { key, what, value });
            }
        }
        Ok(())
    }
}
