//! What watches a closed-loop run tick by tick, whatever the robot, plant or controller: the
//! [`verdict`] that ends every run (completed, fell, diverged, controller failed), decided
//! from criteria that come from the robot description and the scenario, never from a robot's
//! constants.
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

pub mod verdict;
