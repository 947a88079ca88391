//! The library behind the `corps` command: the default robots, simulation scenarios
//! (`corps sim`) and closed-loop controller runs (`corps run`). Tests drive the same code the
//! command runs.

pub mod default_robot;
pub mod foot;
pub mod interrupt;
pub mod numbers;
pub mod output;
pub mod progress;
pub mod run;
pub mod sim_cmd;
pub mod stdout;
