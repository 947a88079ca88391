//! Small optimal control problems solved by shooting: a discrete-time model
//! `x_{k+1} = f(x_k, u_k)` with running costs `l(x_k, u_k)` and a terminal cost `l_N(x_N)`
//! ([`ActionModel`]), and the DDP solver that minimises their sum from a fixed `x_0`
//! ([`Ddp`]: Gauss–Newton backward passes with a regularised `Q_uu` and a backtracking
//! forward pass, the scheme of Crocoddyl's `SolverDDP`, Mastalli et al. ICRA 2020).
//!
//! [`human_walk`] is the optimal-control model of a person walking to a goal that seed 000
//! §3.17 uses to predict the person's path (Maroger et al., IROS 2020 and RA-L 2021);
//! [`prediction`] predicts the rest of a walk from its last samples with it, and
//! [`recorded_walks`] reads the recorded walks of that work's data set.

mod ddp;
mod error;
pub mod human_walk;
pub mod prediction;
pub mod recorded_walks;

pub use ddp::{
    ActionDerivatives, ActionModel, Ddp, DdpOutcome, DdpSettings, DdpSolution, DdpWorkspace,
    TerminalCost,
};
pub use error::OcpError;
