//! Collision geometry read from the URDF, kept for the simulator.

use crate::spatial::Se3;
use nalgebra::Vector3;

/// A collision primitive.
#[derive(Clone, Debug, PartialEq)]
pub enum Shape {
    /// Box with full side lengths.
    Box { size: Vector3<f64> },
    /// Cylinder along its local z axis.
    Cylinder { radius: f64, length: f64 },
    /// Sphere.
    Sphere { radius: f64 },
    /// A mesh file reference (not loaded).
    Mesh {
        filename: String,
        scale: Vector3<f64>,
    },
}

/// One collision shape of a link, placed in the frame of the joint that moves it.
#[derive(Clone, Debug, PartialEq)]
pub struct CollisionGeometry {
    /// Link the shape belongs to.
    pub link: String,
    /// Joint that moves it (None = the world, for a fixed-base root link).
    pub parent_joint: Option<usize>,
    /// Placement of the shape in the parent joint's frame.
    pub placement: Se3,
    /// The shape.
    pub shape: Shape,
}
