//! # corps-control
//!
//! Whole-body controllers. A [`RobotState`] computes the model terms once per tick; tasks
//! ([`tasks`]) turn them into affine rows on the joint accelerations; contacts ([`contacts`])
//! add force variables and constraints; a formulation ([`formulation`]) stacks them into one
//! QP solved by `corps-qp`. The inverse-dynamics formulation reproduces TSID's
//! (`tests/tsid_crosscheck.rs` rebuilds 25 of TSID's TALOS QPs and matches its solutions).
//!
//! In closed loop with the corps simulator (`tests/closed_loop.rs`), the torque-mode
//! controller needs a stiff contact (4·10⁸ N/m³, 10× the simulator's default) and 0.25 ms
//! physics steps: with the default compliant contact the QP's rigid-contact torques rock the
//! light feet on their contact springs (a ≈100 Hz foot mode) and the loop diverges within
//! 0.3–1 s; at 10× stiffness and 0.5 ms it still rings. An implicit (constraint-based) contact
//! in the simulator would remove this restriction.

pub mod contacts;
mod error;
pub mod fallback;
pub mod formulation;
mod robot_state;
pub mod stabilizer;
pub mod tasks;
pub mod trajectories;

pub use error::{ControlError, Result};
pub use fallback::{safe_torques, FallbackReason};
pub use robot_state::RobotState;
