//! Tasks: each maps the robot state to affine rows `A q̈ = b` over the joint accelerations
//! (TSID's task-space acceleration form), with per-axis PD gains, a mask and a reference.
//! The [`velocity`] tasks give rows `A v = b` over the joint velocities, for inverse
//! kinematics. Every task implements [`Task`], so that formulations take any task of their
//! level, named, in a [`crate::TaskStack`].

mod angular_momentum;
mod com;
mod contact_force;
mod joint_bounds;
mod orientation;
mod posture;
mod se3;
pub mod velocity;

pub use angular_momentum::AngularMomentumTask;
pub use com::ComTask;
pub use contact_force::ContactForceTask;
pub use joint_bounds::JointBoundsTask;
pub use orientation::{so3_acceleration, so3_distance, OrientationTask};
pub use posture::PostureTask;
pub use se3::{se3_error, Se3Reference, Se3Task};

use crate::error::Result;
use crate::robot_state::RobotState;
use corps_model::Model;
use nalgebra::{DMatrix, DVector};
use std::any::Any;

/// Which derivative of the configuration a task's rows constrain.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TaskLevel {
    /// Rows in the joint accelerations q̈ (inverse dynamics).
    Acceleration,
    /// Rows in the joint velocities v (inverse kinematics).
    Velocity,
}

/// A task: the robot state → affine rows `A x = b` in x = q̈ or x = v (size nv), as TSID's
/// tasks. A formulation weighs the rows (`w‖A x − b‖²`) or makes them equalities, by the
/// task's priority in the stack. Implement it for a new task; any formulation of its level
/// then takes it.
pub trait Task: Any + Send {
    /// The derivative the rows constrain.
    fn level(&self) -> TaskLevel;
    /// Number of rows.
    fn dim(&self) -> usize;
    /// The rows at state `s` (whose `RobotState::update` has run); allocation-free.
    fn compute(&mut self, model: &Model, s: &RobotState) -> Result<&TaskRows>;
    /// The task's error terms from the last `compute`, for formulations that account for a
    /// task's energy (the energy tank); `None` for a task that has no PD law on an error.
    fn error_terms(&self) -> Option<&TaskErrorTerms> {
        None
    }
    /// The rows of the last `compute`, if the task keeps them (a formulation that computed
    /// the tasks once this tick reads them instead of computing them again).
    fn last_rows(&self) -> Option<&TaskRows> {
        None
    }
}

/// A task's PD law split into its parts (seed 000 Eq 5.7–5.8): rows `J q̈ = b` with
/// `b = Ẍ* − J̇v − K_P E − K_D Ė`, error `E = X − X*`, `Ė = J v − Ẋ*`, one entry per row
/// (a masked-out row has every entry zero). The tank's stacked energy reads these.
#[derive(Clone, Debug, PartialEq)]
pub struct TaskErrorTerms {
    /// E = X − X*.
    pub e: DVector<f64>,
    /// Ė = Ẋ − Ẋ*.
    pub e_dot: DVector<f64>,
    /// Diagonal of K_P.
    pub kp: DVector<f64>,
    /// Diagonal of K_D.
    pub kd: DVector<f64>,
    /// Ẋ*.
    pub ref_vel: DVector<f64>,
    /// Ẍ* − J̇v.
    pub ref_acc_minus_drift: DVector<f64>,
}

impl TaskErrorTerms {
    /// Zero terms for a task of `rows` rows.
    pub fn new(rows: usize) -> Self {
        let z = || DVector::zeros(rows);
        Self {
            e: z(),
            e_dot: z(),
            kp: z(),
            kd: z(),
            ref_vel: z(),
            ref_acc_minus_drift: z(),
        }
    }

    pub fn rows(&self) -> usize {
        self.e.len()
    }

    /// Row `k`: (E, Ė, K_P, K_D, Ẋ*, Ẍ* − J̇v).
    pub fn set(&mut self, k: usize, [e, e_dot, kp, kd, ref_vel, acc]: [f64; 6]) {
        self.e[k] = e;
        self.e_dot[k] = e_dot;
        self.kp[k] = kp;
        self.kd[k] = kd;
        self.ref_vel[k] = ref_vel;
        self.ref_acc_minus_drift[k] = acc;
    }
}

/// The rows a task contributes: `a x ≈ b` (or `=` at priority 0).
#[derive(Clone, Debug)]
pub struct TaskRows {
    pub a: DMatrix<f64>,
    pub b: DVector<f64>,
    /// `Some(c)` when `a` is the identity on columns `c..c + rows` and zero elsewhere (a
    /// joint-space task): formulations then add the rows without a product.
    pub selection: Option<usize>,
}

impl TaskRows {
    pub fn new(rows: usize, nv: usize) -> Self {
        Self {
            a: DMatrix::zeros(rows, nv),
            b: DVector::zeros(rows),
            selection: None,
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
