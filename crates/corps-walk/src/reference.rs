//! The walking reference that every pattern generator of this crate produces, one sample per
//! control tick, for the whole-body controller (seed 002 §4.4 "Output": CoM with Ċ and C̈,
//! waist orientation, feet, ZMP, DCM, contact phase).

use crate::pose::{waist_yaw, FootPose, FootVelocity};
use nalgebra::{Vector2, Vector3};

pub use corps_model::support::ContactPhase;

/// One sample of a walking reference.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct WalkingReference {
    /// Time (s) since the generator started.
    pub time: f64,
    /// CoM position (world).
    pub com: Vector3<f64>,
    /// CoM velocity.
    pub com_vel: Vector3<f64>,
    /// CoM acceleration.
    pub com_acc: Vector3<f64>,
    /// ZMP (x, y, and the ground height z under it).
    pub zmp: Vector3<f64>,
    /// DCM `ξ = c + ċ/ω` (seed 000 eq. 2.27; its z is the CoM height).
    pub dcm: Vector3<f64>,
    /// Left foot pose.
    pub left_foot: FootPose,
    /// Right foot pose.
    pub right_foot: FootPose,
    /// Left foot velocity.
    pub left_foot_vel: FootVelocity,
    /// Right foot velocity.
    pub right_foot_vel: FootVelocity,
    /// Contact phase.
    pub phase: ContactPhase,
    /// Waist yaw: circular mean of the feet yaws (seed 002 §4.13).
    pub waist_yaw: f64,
}

impl WalkingReference {
    /// Fills the derived fields (DCM and waist yaw) from the others; `omega` is the LIPM's
    /// natural frequency.
    pub fn complete(&mut self, omega: f64) {
        let xy = Vector2::new(self.com.x, self.com.y)
            + Vector2::new(self.com_vel.x, self.com_vel.y) / omega;
        self.dcm = Vector3::new(xy.x, xy.y, self.com.z);
        self.waist_yaw = waist_yaw(self.left_foot.yaw, self.right_foot.yaw);
    }
}
