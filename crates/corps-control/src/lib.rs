//! # corps-control
//!
//! Whole-body controllers. A [`RobotState`] computes the model terms once per tick; tasks
//! ([`tasks`]) turn them into affine rows on the joint accelerations; contacts ([`contacts`])
//! add force variables and constraints; a formulation ([`formulation`]) stacks them into one
//! QP solved by `corps-qp`. The inverse-dynamics formulation reproduces TSID's
//! (`tests/tsid_crosscheck.rs` rebuilds 25 of TSID's TALOS QPs and matches its solutions).

pub mod contacts;
mod error;
pub mod formulation;
mod robot_state;
pub mod tasks;

pub use error::{ControlError, Result};
pub use robot_state::RobotState;
