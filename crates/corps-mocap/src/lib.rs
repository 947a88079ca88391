//! Motion capture of a person for teleoperation (seed 001 ch. 6): a human skeleton's poses
//! from a BVH file ([`bvh`]) or a live stream ([`stream`]) behind one source trait
//! ([`source::MocapSource`]), and their retargeting onto a robot ([`retarget`]): joint
//! angles by delta retargeting (Eq 6.1–6.2) through a mapping file, waist height scaled by
//! the rest poses' ratio (Eq 6.3–6.5), and the operator's steps detected, counted and
//! normalised into the robot's range (Eq 6.6–6.7, [`steps`]).
//!
//! Frames: the skeleton's poses are turned into corps' world (z up, metres) once, in
//! [`skeleton`]; everything after works in the operator's body frame at rest (x forward,
//! y to the left, z up), which the robot's base frame at rest is taken to face the same way as.

pub mod bvh;
pub mod error;
pub mod replay;
pub mod retarget;
pub mod skeleton;
pub mod source;
pub mod steps;
pub mod stream;

pub use error::{MocapError, Result};
