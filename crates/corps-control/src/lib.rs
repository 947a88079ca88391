//! # corps-control
//!
//! Whole-body controllers. A [`RobotState`] computes the model terms once per tick; tasks
//! ([`Task`], [`tasks`]) turn them into affine rows on the joint accelerations or velocities
//! and sit, named, weighted and prioritized, in a [`TaskStack`]; contacts ([`contacts`])
//! add force variables and constraints; a formulation ([`formulation`]) stacks them into one
//! QP solved by `corps-qp`. The inverse-dynamics formulation reproduces TSID's
//! (`tests/tsid_crosscheck.rs` rebuilds 25 of TSID's TALOS QPs and matches its solutions).
//!
//! In closed loop with the corps simulator (`tests/closed_loop.rs`), the torque-mode
//! controller needs a stiff contact (4·10⁸ N/m³, 10× the simulator's default): with the
//! default compliant contact the QP's rigid-contact torques rock the light feet on their
//! contact springs (a ≈100 Hz foot mode) and the loop diverges within 0.3–1 s. Explicit RK4
//! needs 0.25 ms steps on that contact (at 0.5 ms it still rings); the simulator's linearly
//! implicit Euler (`Integrator::ImplicitEuler`) takes it in one 1 ms step, and the scenarios
//! in `scenarios/` run that way.

pub mod contacts;
mod error;
pub mod fallback;
pub mod flexibility;
pub mod formulation;
pub mod joint_limits;
pub mod passivity;
pub mod posture_consistency;
mod robot_state;
pub mod stabilizer;
mod stack;
pub mod tasks;
pub mod trajectories;

pub use error::{ControlError, Result};
pub use fallback::{safe_torques, FallbackReason};
pub use robot_state::RobotState;
pub use stack::{TaskEntry, TaskStack};
pub use tasks::{Task, TaskLevel};
