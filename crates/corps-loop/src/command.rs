//! What a controller sends a plant for one control period.

use nalgebra::DVector;

/// A command for one control period, over the actuated joints (every dof but the free-flyer's).
#[derive(Clone, Debug, PartialEq)]
pub enum Command {
    /// Joint torques (size na).
    Torque(DVector<f64>),
    /// Joint position targets as a full configuration (size nq; the base part is ignored) and
    /// joint velocity targets (size na).
    Position {
        q_ref: DVector<f64>,
        v_ref: DVector<f64>,
    },
    /// Joint velocity targets (size na).
    Velocity(DVector<f64>),
}
