//! The closed loop of corps, whatever the robot: a [`Plant`] (a simulator, another physics
//! engine, a real robot) takes a [`Command`] per control period and gives sensor readings; an
//! [`Estimator`](corps_estimation::Estimator) turns them into the state a [`Controller`]
//! reads with its references; [`Observer`]s (metrics, logs, the [`verdict`]) see every tick.
//! [`ClosedLoop::run`] ties them together and returns how the run ended.
//!
//! The verdict's criteria come from the robot description and the scenario, never from a
//! robot's constants:
//!
//! ```
//! use corps_loop::verdict::{Criteria, TickSample, Verdict, VerdictObserver};
//! // A 90 kg robot whose CoM starts 0.88 m above its soles.
//! let mut watch = VerdictObserver::new(Criteria::default(), 90.0 * 9.81, 0.88).unwrap();
//! let sample = TickSample { t: 0.0, com_height: 0.88, base_speed: 0.0, total_contact_force: 883.0,
//!                           other_contact_force: 0.0, state_finite: true, safe_command: false };
//! assert!(watch.observe(&sample).is_none());
//! assert_eq!(watch.finish(1.0).verdict, Verdict::Completed);
//! ```

mod closed_loop;
mod command;
mod controller;
mod observer;
mod plant;
pub mod verdict;

pub use closed_loop::{ClosedLoop, Feed, LoopEnd, LoopError, LoopOutcome, LoopSettings};
pub use command::Command;
pub use controller::{Controller, ReferenceSource};
pub use observer::{Flow, Observer, Tick};
pub use plant::{ContactForce, Plant, PlantError, Sensed, Truth};
