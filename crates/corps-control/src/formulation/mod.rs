//! Formulations: stack tasks and contacts into one QP per tick: inverse dynamics on [q̈; f]
//! (TSID's), on [τ; f] (seed 001's), hierarchical velocity IK (seed 000's controller A), and
//! the inverse dynamics under an energy tank (seed 000 ch. 5).

mod inverse_dynamics;
mod inverse_kinematics;
mod passive;
mod qp_terms;
mod torque_force;

pub use inverse_dynamics::{IdOutput, InverseDynamics, HESSIAN_REGULARIZATION};
pub use inverse_kinematics::{IkGains, IkOutput, InverseKinematics, StackFrames};
pub use passive::{LeftInverse, PassiveInverseDynamics, PassiveSignals, CONTACT_WEIGHT};
pub use torque_force::{TorqueForce, TorqueForceOutput};
