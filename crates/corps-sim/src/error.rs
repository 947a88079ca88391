//! Typed errors of the simulator.

use thiserror::Error;

/// What can go wrong building or stepping a simulation.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum SimError {
    /// An error from the model (bad state vector, unknown frame, ...).
    #[error(transparent)]
    Model(#[from] corps_model::ModelError),
    /// A setting is out of range.
    #[error("invalid setting {name}: {reason}")]
    Setting { name: String, reason: String },
    /// A command has the wrong size or holds NaN.
    #[error("command {what}: {reason}")]
    Command { what: &'static str, reason: String },
    /// The state blew up (NaN or huge velocity): the step size is too large for the contact
    /// stiffness, or the controller drove the robot unstable.
    #[error("simulation diverged at t = {t:.4} s ({reason})")]
    Diverged { t: f64, reason: String },
}

/// Result alias of the simulator.
pub type Result<T> = std::result::Result<T, SimError>;
