//! External pushes: a constant wrench on a named body for a time window.

use corps_model::spatial::{Force, Se3};
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

/// A push with the joint whose body it acts on and its frame's placement in that joint's frame
/// (the frame resolved once, by [`crate::Simulator::add_push`]).
pub type PlacedPush = (Push, usize, Se3);

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

    /// The push as a world wrench about the world origin, on a body placed at `o_m_joint`
    /// with the pushed frame at `placement` in it.
    pub fn world_wrench(&self, o_m_joint: &Se3, placement: &Se3) -> Force {
        let p = o_m_joint.act_point(&placement.translation);
        let f = self.force();
        Force::new(f, p.cross(&f) + self.torque())
    }
}
