//! # corps-sim
//!
//! The simulator embedded in corps: pure Rust, nothing to install. A floating-base robot
//! (any [`corps_model::Model`]) moves under joint commands, gravity, compliant contact with a
//! terrain of planes and boxes, and pushes; sensors read it with seeded noise.
//!
//! - dynamics: ABA with the contact and push wrenches as external forces (RK4, semi-implicit
//!   Euler), or CRBA with them linearized (implicit Euler);
//! - integration on the configuration manifold: RK4 (default), semi-implicit Euler, or
//!   linearly implicit Euler in the contact springs and servos (one sparse factorization per
//!   step, stable at 1 ms on the stiff contact a torque controller needs); 1 ms control
//!   period, physics substeps a setting;
//! - contact: spring–damper normal force and an anchored tangential spring on the Coulomb cone
//!   (stiction without creep), on points sampled over the robot's box/cylinder/sphere shapes;
//! - actuation: torques, positions through a joint PD servo, or velocities, clamped at the
//!   URDF effort limits; torques optionally through flexible drives with a current-controlled
//!   motor ([`drive`]);
//! - the loop's plant: [`SimulatedRobot`] (the simulator and its sensors as a
//!   [`corps_loop::Plant`], optionally preparing each next step on a second thread).
//!
//! ```
//! use corps_sim::*;
//! use corps_model::{build_model_from_urdf_str, RootJoint, neutral};
//! use std::sync::Arc;
//! let urdf = r#"<robot name="box"><link name="b"><inertial><mass value="1"/>
//!   <inertia ixx="0.01" iyy="0.01" izz="0.01"/></inertial>
//!   <collision><geometry><box size="0.1 0.1 0.1"/></geometry></collision></link></robot>"#;
//! let model = Arc::new(build_model_from_urdf_str(urdf, RootJoint::FreeFlyer).unwrap());
//! let mut q = neutral(&model);
//! q[2] = 0.2; // 15 cm above the ground
//! let gains = ServoGains { kp: Default::default(), kd: Default::default(), integral: None };
//! let terrain = Terrain::preset(TerrainPreset::Flat, 0.8);
//! let mut sim = Simulator::new(model, terrain, SimSettings::default(), q.as_slice(), gains).unwrap();
//! for _ in 0..1000 {
//!     sim.step(&Command::Torque(Default::default())).unwrap();
//! }
//! assert!((sim.q()[2] - 0.05).abs() < 1e-3); // resting on its face
//! ```

mod actuation;
mod contact;
mod contact_pass;
mod contact_points;
mod disturbance;
pub mod drive;
mod error;
mod external;
mod hidden_joints;
mod overlap;
mod placement;
mod plant;
mod sensors;
mod simulator;
mod terrain;

pub use actuation::{first_actuated, Actuators, Command, IntegralTerm, JointStops, ServoGains};
pub use contact::{point_force, Anchor, ContactParams, PointForce, PointLinearization};
pub use contact_points::{sample_contact_points, ContactPoint, ShapeBound};
pub use disturbance::{PlacedPush, Push};
pub use drive::{DriveState, Drives, FlexibleDrive};
pub use error::{Result, SimError};
pub use external::{ExternalPlant, PlantState, StatePlant};
pub use hidden_joints::{HiddenJoints, WithHiddenJoints};
pub use overlap::Overlap;
pub use placement::place_on_ground;
pub use plant::{touching_points, SimulatedRobot};
pub use sensors::{
    ForceTorqueModel, ImuReading, Noise, Readings, SensorInput, SensorLayout, SensorNoise, Sensors,
};
pub use simulator::{ContactState, Integrator, SimSettings, Simulator};
pub use terrain::{Penetration, Surface, Terrain, TerrainPreset};
