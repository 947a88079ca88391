//! # corps-model
//!
//! Robot models and rigid-body dynamics for corps, with Pinocchio's conventions so that every
//! state vector exchanges with it unchanged:
//!
//! - joints in depth-first order from the root link (children in joint-name order, as
//!   Pinocchio's URDF parser walks them);
//! - a free-flyer root has q = [position; quaternion (x, y, z, w)] and v = [linear; angular]
//!   in the base's local frame; a continuous joint has q = (cos θ, sin θ), v = θ̇;
//! - spatial vectors are [linear; angular].
//!
//! The [`Model`] is immutable once loaded; every algorithm is a free function writing into a
//! [`Data`] workspace, and none allocates on the heap once the `Data` exists.
//!
//! ```
//! use corps_model::{build_model_from_urdf_str, Data, RootJoint, rnea, neutral};
//! let urdf = r#"<robot name="pendulum">
//!   <link name="base"/>
//!   <link name="arm"><inertial><origin xyz="0 0 -0.5"/><mass value="2"/>
//!     <inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial></link>
//!   <joint name="hinge" type="revolute"><parent link="base"/><child link="arm"/>
//!     <axis xyz="0 1 0"/><limit lower="-3" upper="3" effort="50" velocity="5"/></joint>
//! </robot>"#;
//! let model = build_model_from_urdf_str(urdf, RootJoint::Fixed).unwrap();
//! let mut data = Data::new(&model);
//! let q = neutral(&model);
//! let tau = rnea(&model, &mut data, q.as_slice(), &[0.0], &[0.0]).unwrap();
//! assert!(tau[0].abs() < 1e-12); // hanging straight down: no gravity torque
//! ```

pub mod algorithms;
pub mod configuration;
mod data;
mod error;
mod frame;
mod geometry;
mod joint;
pub mod min_jerk;
mod model;
pub mod parse;
pub mod spatial;
pub mod support;

pub use algorithms::aba::{aba, aba_with_external_forces};
pub use algorithms::all_terms::compute_all_terms;
pub use algorithms::centroidal::{
    center_of_mass, centroidal_momentum_drift, com_and_momentum_drifts, com_at_placements,
    compute_centroidal_map, compute_centroidal_momentum, jacobian_center_of_mass,
};
pub use algorithms::cholesky::{
    compute_minverse_factorized, factorize_branch_sparse, factorize_mass_matrix,
    forward_dynamics_crba, solve_mass_matrix,
};
pub use algorithms::coriolis::coriolis_matrix;
pub use algorithms::crba::{crba, crba_at_jacobians};
pub use algorithms::energy::{kinetic_energy, potential_energy};
pub use algorithms::jacobians::{
    compute_frame_jacobian, compute_joint_jacobians, frame_acceleration,
    frame_classical_acceleration, frame_jacobian, frame_placement, frame_velocity,
    update_frame_placements, world_motions_from_jacobians, ReferenceFrame,
};
pub use algorithms::kinematics::{forward_kinematics, forward_kinematics_placements};
pub use algorithms::minverse::compute_minverse;
pub use algorithms::operational_space::frame_operational_space_inertia;
pub use algorithms::rnea::{
    generalized_gravity, nonlinear_effects, nonlinear_effects_at_placements, rnea,
};
pub use configuration::{
    difference, difference_to, integrate, integrate_to, interpolate, neutral, normalize,
    random_configuration,
};
pub use data::Data;
pub use error::{ModelError, Result};
pub use frame::{Frame, FrameKind};
pub use geometry::{CollisionGeometry, Shape};
pub use joint::{Joint, JointKind};
pub use model::{check_vector, Model, STANDARD_GRAVITY};
pub use parse::{
    build_model_from_urdf_file, build_model_from_urdf_str, build_model_from_urdf_str_locked,
    load_reference_configurations, RootJoint,
};
