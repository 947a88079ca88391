//! # corps-walk — walking pattern generation
//!
//! LIPM / DCM models, Kajita preview control, a velocity-driven MPC with automatic footstep
//! placement, the dynamic filter, swing-foot trajectories and footstep plans. Both generators
//! produce the same [`WalkingReference`] sample (CoM pos/vel/acc, ZMP, DCM, feet poses and
//! velocities, contact phase, waist yaw), so the whole-body controller can consume either.
//!
//! | module | content | source |
//! |---|---|---|
//! | [`lipm`], [`dcm`] | cart-table / LIPM, jerk-input model, DCM | seed 002 §4.1, Kajita 2003, Englsberger 2015 |
//! | [`support_polygon`] | soles, hulls, signed distance, half-spaces | seed 002 §4.2 |
//! | [`footsteps`] | timed footstep plans, ZMP reference, phase, footholds on tilted ground | seed 000 §4 (20/60 cm, stairs, platforms) |
//! | [`swing_foot`] | quintic swing with apex | seed 002 §4.4 (5 cm) |
//! | [`preview_control`], [`riccati`] | Kajita 2003 preview control, DARE | anchors §4.3 golden gains |
//! | [`preview_walk`] | preview control over a footstep plan | Kajita 2003 |
//! | [`mpc`] | velocity MPC with automatic footsteps | Herdt 2010, seed 002 §4.4 |
//! | [`dynamic_filter`] | multibody-ZMP CoM correction | seed 002 §4.5 |
//!
//! ## Example: preview-control walk over a footstep plan
//!
//! ```
//! use corps_walk::preview_control::PreviewParams;
//! use corps_walk::preview_walk::PreviewWalk;
//! use corps_walk::{Foot, FootstepPlan, StepTiming};
//!
//! // seed 000 S5: six 20 cm steps plus a closing step, SS 0.9 s / DS 0.115 s
//! let plan = FootstepPlan::straight(6, 0.2, 0.162, Foot::Left, StepTiming::seed000_nominal())?;
//! // TALOS' CoM height on jrl-walkgen (seed 002 §4.4), Kajita's weights and 1.6 s preview
//! let mut params = PreviewParams::kajita2003();
//! params.lipm = corps_walk::lipm::Lipm::new(0.876681, 9.81)?;
//! let mut walk = PreviewWalk::new(plan, params)?;
//! while !walk.finished() {
//!     let r = walk.step()?; // one 5 ms sample: r.com, r.zmp, r.left_foot, r.phase, …
//!     assert!((r.zmp.xy() - walk.plan().sample(walk.plan_time(r.time)).zmp.xy()).norm() < 0.1);
//! }
//! # Ok::<(), corps_walk::WalkError>(())
//! ```
//!
//! ## Example: the velocity-driven MPC loop
//!
//! ```
//! use corps_walk::mpc::{MpcParams, VelocityCommand, WalkingMpc};
//!
//! // TALOS' settings (seed 002 §4.4), from its configuration file
//! let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../../config/talos/walk_mpc.toml")).unwrap();
//! let params: MpcParams = toml::from_str(&text).unwrap();
//! let mut mpc = WalkingMpc::new(params, 0.0, 0.0, 0.0)?;
//! for tick in 0..400 {
//!     // the command may change at any tick (teleop, planner)
//!     let cmd = VelocityCommand::new(0.1, 0.0, if tick > 200 { 0.05 } else { 0.0 });
//!     let r = mpc.tick(cmd)?; // re-plan, apply the first jerk, advance 5 ms
//!     let _ = (r.com, r.phase.code(), mpc.planned_footsteps(), mpc.horizon());
//! }
//! # Ok::<(), corps_walk::WalkError>(())
//! ```
#![warn(missing_docs)]

pub mod dcm;
pub mod dynamic_filter;
mod error;
pub mod footsteps;
pub mod lipm;
mod min_jerk;
pub mod mpc;
pub mod pose;
pub mod preview_control;
pub mod preview_walk;
pub mod reference;
pub mod riccati;
pub mod support_polygon;
pub mod swing_foot;

pub use error::WalkError;
pub use footsteps::{Footstep, FootstepPlan, Ground, PlanSample, StepTiming};
pub use lipm::{JerkModel, Lipm};
pub use pose::{waist_yaw, Foot, FootPose, FootVelocity};
pub use reference::{ContactPhase, WalkingReference};
pub use support_polygon::{ConvexPolygon, FootGeometry};
pub use swing_foot::{Quintic, SwingTrajectory};

/// TALOS' walking settings for the crate's unit tests (shared with the integration tests,
/// which name the crate `corps_walk`).
#[cfg(test)]
extern crate self as corps_walk;
#[cfg(test)]
#[path = "../tests/common/talos.rs"]
mod test_fixtures;
