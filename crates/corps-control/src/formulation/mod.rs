//! Formulations: stack tasks and contacts into one QP per tick.

mod inverse_dynamics;

pub use inverse_dynamics::{IdOutput, InverseDynamics};
