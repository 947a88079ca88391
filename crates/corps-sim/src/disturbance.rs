//! External pushes: a constant wrench on a named body for a time window.

use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

/// A push: `force` (N, world axes) applied at the origin of frame `frame`, and `torque` (N·m,
/// world axes), from `start` for `duration` seconds.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Push {
    pub frame: String,
    pub start: f64,
    pub duration: f64,
    pub force: [f64; 3],
    #[serde(default)]
    pub torque: [f64; 3],
}

impl Push {
    /// Whether the push acts at time t.
    pub fn active(&self, t: f64) -> bool {
        t >= self.start && t < self.start + self.duration
    }

    pub fn force(&self) -> Vector3<f64> {
        Vector3::from(self.force)
    }

    pub fn torque(&self) -> Vector3<f64> {
        Vector3::from(self.torque)
    }
}
