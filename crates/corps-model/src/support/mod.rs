//! Support geometry shared by planners, stabilizers and metrics: which feet touch the ground
//! and the convex polygons their soles span.

mod phase;
mod polygon;

pub use phase::ContactPhase;
pub use polygon::{ConvexPolygon, MAX_VERTICES};
