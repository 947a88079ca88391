//! Formulations: stack tasks and contacts into one QP per tick.

mod inverse_dynamics;
mod inverse_kinematics;

pub use inverse_dynamics::{IdOutput, InverseDynamics};
pub use inverse_kinematics::{IkGains, IkOutput, InverseKinematics, StackFrames};
