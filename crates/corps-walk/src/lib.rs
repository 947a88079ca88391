//! # corps-walk — walking pattern generation
//!
//! LIPM / DCM models, Kajita preview control, a velocity-driven MPC with automatic footstep
//! placement, the dynamic filter, swing-foot trajectories and footstep plans.
#![warn(missing_docs)]

pub mod dcm;
mod error;
pub mod footsteps;
pub mod lipm;
pub mod mpc;
pub mod pose;
pub mod preview_control;
pub mod preview_walk;
pub mod reference;
pub mod riccati;
pub mod support_polygon;
pub mod swing_foot;

pub use error::WalkError;
pub use footsteps::{Footstep, FootstepPlan, PlanSample, StepTiming};
pub use lipm::{JerkModel, Lipm};
pub use pose::{waist_yaw, Foot, FootPose, FootVelocity};
pub use reference::{ContactPhase, WalkingReference};
pub use support_polygon::{ConvexPolygon, FootGeometry};
pub use swing_foot::{Quintic, SwingTrajectory};
