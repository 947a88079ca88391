//! What can stop a scenario from running: one message per problem, naming the key or the
//! part that failed, with the context it arose in.

use thiserror::Error;

/// An error of a scenario run.
#[derive(Debug, Error)]
pub enum ScenarioError {
    /// Bad input: the message names the key and what is wrong with it.
    #[error("{0}")]
    Invalid(String),
    /// `error`, arising while doing `context`. Its message holds the whole chain, so `error`
    /// is not also reported as a source (a printer of sources would repeat it).
    #[error("{context}: {error}")]
    Context {
        context: String,
        error: Box<ScenarioError>,
    },
    /// The run was interrupted before its controller took over (`t` = 0 s of control).
    #[error("interrupted at t = {t:.3} s")]
    Interrupted { t: f64 },
    /// A campaign's rollout executor failed (not a rollout: those are penalised).
    #[error("running rollouts: {0}")]
    Rollouts(String),
    /// Writing the run's outputs failed.
    #[error("{0}")]
    Output(String),
    #[error(transparent)]
    Io(#[from] std::io::Error),
    #[error(transparent)]
    Model(#[from] corps_model::ModelError),
    #[error(transparent)]
    Robot(#[from] corps_robot::RobotError),
    #[error(transparent)]
    Sim(#[from] corps_sim::SimError),
    #[error(transparent)]
    Control(#[from] corps_control::ControlError),
    #[error(transparent)]
    Estimation(#[from] corps_estimation::EstimationError),
    #[error(transparent)]
    Walk(#[from] corps_walk::WalkError),
    #[error(transparent)]
    Toml(#[from] toml::ser::Error),
    #[error(transparent)]
    Plant(#[from] corps_loop::PlantError),
    #[error(transparent)]
    Loop(#[from] corps_loop::LoopError),
    #[error(transparent)]
    Criteria(#[from] corps_robot::CriteriaError),
}

impl ScenarioError {
    /// Whether this error, or one it wraps, is an interruption.
    pub fn interrupted_at(&self) -> Option<f64> {
        match self {
            ScenarioError::Interrupted { t } => Some(*t),
            ScenarioError::Context { error, .. } => error.interrupted_at(),
            _ => None,
        }
    }
}

/// Result of a scenario run.
pub type Result<T, E = ScenarioError> = std::result::Result<T, E>;

/// Adds the context an error arose in.
pub trait Context<T> {
    fn context(self, context: impl std::fmt::Display) -> Result<T>;
    fn with_context<D: std::fmt::Display>(self, context: impl FnOnce() -> D) -> Result<T>;
}

impl<T, E: Into<ScenarioError>> Context<T> for std::result::Result<T, E> {
    fn context(self, context: impl std::fmt::Display) -> Result<T> {
        self.map_err(|e| ScenarioError::Context {
            context: context.to_string(),
            error: Box::new(e.into()),
        })
    }
    fn with_context<D: std::fmt::Display>(self, context: impl FnOnce() -> D) -> Result<T> {
        self.map_err(|e| ScenarioError::Context {
            context: context().to_string(),
            error: Box::new(e.into()),
        })
    }
}

impl<T> Context<T> for Option<T> {
    fn context(self, context: impl std::fmt::Display) -> Result<T> {
        self.ok_or_else(|| ScenarioError::Invalid(context.to_string()))
    }
    fn with_context<D: std::fmt::Display>(self, context: impl FnOnce() -> D) -> Result<T> {
        self.ok_or_else(|| ScenarioError::Invalid(context().to_string()))
    }
}

/// A [`ScenarioError::Invalid`] from a format string.
macro_rules! invalid {
    ($($arg:tt)*) => { $crate::error::ScenarioError::Invalid(format!($($arg)*)) };
}
/// Returns a [`ScenarioError::Invalid`] from a format string.
macro_rules! bail {
    ($($arg:tt)*) => { return Err($crate::error::invalid!($($arg)*).into()) };
}
pub(crate) use {bail, invalid};
