//! Typed errors of the optimizer's set-up.

use thiserror::Error;

#[derive(Debug, Error, Clone, PartialEq)]
pub enum LearnError {
    #[error("invalid {name}: {reason}")]
    Setting { name: &'static str, reason: String },
}
