//! The `corps` command's own code: argument handling, the files a run writes (CSV log,
//! metrics, plots), progress and printing around the libraries (`corps-scenario` runs the
//! scenarios, `corps-loop` closes the loop). Tests drive the same code the command runs.

pub mod actuator_cmd;
pub mod drill_cmd;
pub mod interrupt;
pub mod learn;
pub mod mocap_cmd;
pub mod output;
pub mod progress;
pub mod run;
pub mod sim_cmd;
pub mod stdout;
pub mod teleop;
