//! Typed errors of the OCP solver.

use thiserror::Error;

#[derive(Debug, Error, Clone, PartialEq)]
pub enum OcpError {
    /// A problem whose sizes do not fit (state, control, horizon).
    #[error("invalid problem: {0}")]
    Invalid(String),
    /// A cost, a dynamics value or a derivative is NaN or infinite.
    #[error("non-finite {what} at node {node}")]
    NonFinite { what: &'static str, node: usize },
}
