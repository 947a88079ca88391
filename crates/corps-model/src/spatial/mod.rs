//! Spatial algebra (Featherstone, RBDA ch. 2), with Pinocchio's conventions: spatial vectors are
//! [linear; angular], transforms `aMb` map b coordinates to a.

mod force;
mod inertia;
pub mod kernels;
mod motion;
pub mod rotation;
mod se3;
mod se3_lie;

pub use force::Force;
pub use inertia::{Inertia, OriginInertia};
pub use motion::Motion;
pub use se3::Se3;
pub use se3_lie::{exp6, log6};

use nalgebra::{Matrix3, Vector3};

/// The skew-symmetric matrix `[a]×` with `[a]× b = a × b`.
#[inline]
pub fn skew(a: &Vector3<f64>) -> Matrix3<f64> {
    Matrix3::new(0.0, -a.z, a.y, a.z, 0.0, -a.x, -a.y, a.x, 0.0)
}
