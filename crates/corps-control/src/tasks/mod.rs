//! Tasks: each maps the robot state to affine rows `A q̈ = b` over the joint accelerations
//! (TSID's task-space acceleration form), with per-axis PD gains, a mask and a reference.
//! The [`velocity`] tasks give rows `A v = b` over the joint velocities, for inverse
//! kinematics.

mod angular_momentum;
mod com;
mod contact_force;
mod joint_bounds;
mod posture;
mod se3;
pub mod velocity;

pub use angular_momentum::AngularMomentumTask;
pub use com::ComTask;
pub use contact_force::ContactForceTask;
pub use joint_bounds::JointBoundsTask;
pub use posture::PostureTask;
pub use se3::{se3_error, Se3Reference, Se3Task};

use nalgebra::{DMatrix, DVector};

/// The rows a task contributes: `a q̈ ≈ b` (or `=` at priority 0).
#[derive(Clone, Debug)]
pub struct TaskRows {
    pub a: DMatrix<f64>,
    pub b: DVector<f64>,
}

impl TaskRows {
    pub fn new(rows: usize, nv: usize) -> Self {
        Self {
            a: DMatrix::zeros(rows, nv),
            b: DVector::zeros(rows),
        }
    }
    pub fn rows(&self) -> usize {
        self.b.len()
    }
}

/// A position reference with its first two derivatives.
#[derive(Clone, Debug, PartialEq)]
pub struct Reference {
    pub pos: DVector<f64>,
    pub vel: DVector<f64>,
    pub acc: DVector<f64>,
}

impl Reference {
    pub fn constant(pos: DVector<f64>) -> Self {
        let n = pos.len();
        Self {
            pos,
            vel: DVector::zeros(n),
            acc: DVector::zeros(n),
        }
    }
}
