//! The library behind the `corps` command: the default robots, simulation scenarios
//! (`corps sim`) and closed-loop controller runs (`corps run`). Tests drive the same code the
//! command runs.

pub mod interrupt;
pub mod output;
pub mod progress;
pub mod run;
pub mod sim_cmd;
pub mod stdout;
