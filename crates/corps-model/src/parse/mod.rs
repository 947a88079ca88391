//! Model loading: URDF (kinematics, inertias, limits, collision shapes) and SRDF (reference
//! configurations).

mod srdf;
mod urdf;
mod xml;

pub use srdf::{load_reference_configurations, load_reference_configurations_str};
pub use urdf::{
    build_model_from_urdf_file, build_model_from_urdf_str, build_model_from_urdf_str_locked,
    RootJoint,
};
