//! Typed errors of the actuator models, identification and iLQR.

use thiserror::Error;

#[derive(Debug, Error, Clone, PartialEq)]
pub enum ActuatorError {
    /// An actuator description that cannot be read or holds an impossible value.
    #[error("actuator description: {0}")]
    Description(String),
    /// Recorded data that cannot be used (format, NaN, time order, too few samples).
    #[error("identification data: {0}")]
    Data(String),
    /// A regressor that does not determine every parameter.
    #[error("the regressor is rank-deficient (condition number {cond:.2e}): {cause}")]
    RankDeficient { cond: f64, cause: String },
    /// An optimal-control problem that cannot be solved as posed.
    #[error("iLQR: {0}")]
    Ilqr(String),
}
