//! Error type of the crate.

use corps_qp::QpError;

/// Errors of the walking pattern generators.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum WalkError {
    /// A parameter is out of its valid range (the message names it and the range).
    #[error("invalid parameter: {0}")]
    InvalidParameter(&'static str),
    /// The discrete algebraic Riccati equation did not converge.
    #[error("Riccati equation did not converge after {0} doubling steps")]
    RiccatiNotConverged(usize),
    /// The MPC QP failed (infeasible constraints or solver limit).
    #[error("MPC QP failed: {0}")]
    Qp(#[from] QpError),
    /// A preview window is shorter than the controller's horizon.
    #[error("preview window has {got} samples, the controller needs {need}")]
    PreviewTooShort {
        /// Samples given.
        got: usize,
        /// Samples needed.
        need: usize,
    },
}
