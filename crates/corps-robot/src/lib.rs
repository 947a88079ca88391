//! A robot as corps knows it: the model built from its URDF/SRDF plus everything robot-specific
//! that controllers, estimators, simulators and metrics need — feet (sole frames and
//! rectangles), hands, force/torque sensors and the IMU, the reference posture, limits the URDF
//! lacks, gains files and fall criteria — read from one description file beside the URDF
//! ([`description`]). Libraries take a [`Robot`]; none holds a robot's constant.
//!
//! TALOS (also with its flexible hip), iCub (also with a battery pack) and simple_humanoid are built in ([`files::BUILT_IN`]); another robot is a
//! description file, which [`init::draft`] starts from its URDF.
//!
//! ```
//! let talos = corps_robot::Robot::built_in("talos").unwrap().unwrap();
//! assert_eq!(talos.feet.len(), 2);
//! assert!((talos.model.total_mass() - 90.27).abs() < 0.01);
//! assert!((talos.feet[0].ankle_height - 0.107).abs() < 1e-12);
//! ```

pub mod description;
pub mod fall;
pub mod files;
pub mod init;
mod passive;
mod robot;
pub mod toml_text;

pub use description::{Description, DrivesSpec, FootContact, PassiveJointSpec, SoleSpec};
pub use fall::{Criteria, CriteriaError};
pub use passive::{PassiveJoint, PlantVariant};
pub use robot::{Foot, GainsText, Hand, Robot, RobotError, SOLE_BOX_THICKNESS};
