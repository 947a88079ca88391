//! What a robot's sensors give at one instant: the input of every [`crate::Estimator`]. A
//! simulator fills it from its state (with noise); a real robot from its drivers.

use nalgebra::DVector;
use serde::Serialize;

/// An IMU reading: orientation of the IMU frame in the world (quaternion x, y, z, w), angular
/// velocity and proper linear acceleration (specific force), both in the IMU frame.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct ImuReading {
    pub orientation: [f64; 4],
    pub angular_velocity: [f64; 3],
    pub linear_acceleration: [f64; 3],
}

/// All readings at one instant.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Readings {
    pub time: f64,
    /// Joint positions (angles; continuous joints unwrapped to an angle), size na.
    pub joint_positions: DVector<f64>,
    pub joint_velocities: DVector<f64>,
    /// Applied (clamped) joint torques.
    pub joint_torques: DVector<f64>,
    /// Wrench measured by each F/T sensor, in its frame, moment about its origin:
    /// [fx, fy, fz, tx, ty, tz]. It is the contact wrench on the sensor's body.
    pub force_torque: Vec<[f64; 6]>,
    pub imu: ImuReading,
    /// Base position and orientation (x, y, z, qx, qy, qz, qw); zeros for a fixed base.
    pub base_pose: [f64; 7],
    /// Base twist in the base frame [linear; angular].
    pub base_twist: [f64; 6],
    /// Contact wrench on each joint's body, world frame, moment about the world origin.
    pub contact_wrenches: Vec<[f64; 6]>,
}

impl Readings {
    /// Copies `other` into `self` without allocating (same sizes).
    pub fn copy_from(&mut self, other: &Readings) {
        self.time = other.time;
        self.joint_positions.copy_from(&other.joint_positions);
        self.joint_velocities.copy_from(&other.joint_velocities);
        self.joint_torques.copy_from(&other.joint_torques);
        self.force_torque.copy_from_slice(&other.force_torque);
        self.imu = other.imu;
        self.base_pose = other.base_pose;
        self.base_twist = other.base_twist;
        self.contact_wrenches
            .copy_from_slice(&other.contact_wrenches);
    }
}
