//! corps scenarios as a library. A scenario file (TOML) names a robot description, a
//! terrain, the simulator's settings, sensor noise and pushes, and for a closed-loop run a
//! controller, its gains and a motion. This crate reads it ([`scenario`]), builds the world
//! ([`setup`]), simulates it open-loop ([`simulation`], `corps sim`), the controllers of seed 000 chapter 4 ([`controller`], [`gains`]), the
//! estimator ([`estimation`]) and the references ([`motion`], [`walk`], [`velocity_walk`],
//! [`dynamic_filter`]; a velocity walk steered live by [`teleop`]),
//! closes the loop through [`corps_loop`] and returns the [`metrics`], the verdict and the
//! time series in memory ([`run`]). Writing files and printing belong to the caller.
//!
//! ```no_run
//! use corps_scenario::{run::{RunOptions, ScenarioRun}, scenario::Scenario};
//! let text = std::fs::read_to_string("scenarios/control/tsid_torque_push_front.toml")?;
//! let scenario = Scenario::parse(&text)?;
//! let run = ScenarioRun::new(&scenario, "push", "scenarios/control".as_ref(), RunOptions::default())?;
//! let result = run.run(&mut [])?;
//! println!("{}", result.metrics.verdict);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

pub mod conav;
pub mod controller;
pub mod default_robot;
pub mod drilling;
pub mod drives;
pub mod dynamic_filter;
pub mod error;
pub mod estimation;
pub mod foot;
pub mod footsteps;
pub mod gains;
mod gait;
pub mod identify;
pub mod learning;
pub mod metrics;
pub mod mocap;
pub mod motion;
pub mod numbers;
pub mod overrides;
pub mod pid_gains;
pub mod press;
pub mod pushes;
pub mod run;
pub mod scenario;
pub mod sensor_profile;
pub mod series;
pub mod setup;
pub mod simulation;
pub mod targets;
pub mod teleop;
pub mod velocity_walk;
pub mod walk;

pub use error::{Result, ScenarioError};
