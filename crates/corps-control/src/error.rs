//! Typed errors of the controllers.

use thiserror::Error;

#[derive(Debug, Error, Clone, PartialEq)]
pub enum ControlError {
    #[error(transparent)]
    Model(#[from] corps_model::ModelError),
    #[error("QP failed: {0}")]
    Qp(corps_qp::QpError),
    #[error("hierarchical QP failed: {0}")]
    Hqp(corps_qp::HqpError),
    #[error("non-finite {0}")]
    NonFinite(&'static str),
    #[error("invalid configuration {name}: {reason}")]
    Config { name: String, reason: String },
}

pub type Result<T> = std::result::Result<T, ControlError>;
