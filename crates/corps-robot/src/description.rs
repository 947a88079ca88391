//! The robot description file's schema: what corps needs to know about a robot beyond its
//! URDF/SRDF. Unknown keys are errors; paths are relative to the description file.
//!
//! ```toml
//! name = "talos"
//! urdf = "robots/talos_reduced_box.urdf"
//! srdf = "srdf/talos.srdf"
//! posture = "half_sitting"          # an SRDF group_state: the reference posture
//! base = "base_link"                # the waist frame (orientation task, pushes)
//!
//! [[feet]]
//! label = "left"
//! frame = "leg_left_sole_fix_joint" # origin on the sole surface, z = contact normal
//! sole = { front = 0.1, back = 0.1, left = 0.065, right = 0.065 }
//! force_torque = "left_ankle"
//!
//! [[sensors.force_torque]]
//! name = "left_ankle"
//! frame = "leg_left_sole_fix_joint"
//!
//! [gains]                            # controller kind -> gains file
//! tsid_torque = "../../config/talos/tsid_torque.toml"
//! ```

use crate::fall::Criteria;
use serde::Deserialize;
use std::collections::BTreeMap;
use std::path::PathBuf;

/// A robot description (`robots/<robot>/<robot>.toml`).
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Description {
    /// Short name (`talos`), used in messages and output.
    pub name: String,
    /// The URDF, relative to this file. Its collision primitives are the simulator's contact
    /// geometry (meshes are not used).
    pub urdf: PathBuf,
    /// The SRDF with the reference posture, relative to this file.
    pub srdf: Option<PathBuf>,
    /// The reference posture: a `group_state` of the SRDF.
    pub posture: String,
    /// The waist (base) frame: the orientation task's frame and where pushes usually land.
    pub base: String,
    /// Turn the posture's base so that the soles' mean normal points up (for an SRDF posture
    /// whose feet are not flat on the ground). Default false: the posture as the SRDF gives it.
    #[serde(default)]
    pub level_posture: bool,
    /// Extra frames the URDF lacks (a sole frame, a hand's tool point).
    #[serde(default)]
    pub frames: Vec<FrameSpec>,
    /// Smallest principal moment of inertia of a body (kg·m²): a body whose URDF inertia is
    /// smaller (some URDFs give zero) gets its principal moments raised to it, so that the
    /// dynamics stay regular. Absent: the URDF's inertias as they are.
    pub inertia_floor: Option<f64>,
    /// Joints made rigid at their position in the reference posture (the model has no dof
    /// for them; their bodies merge into their parents'): joints a controller leaves to stiff
    /// position servos.
    #[serde(default)]
    pub locked_joints: Vec<String>,
    /// Rigid bodies the URDF lacks, fixed to a link (a battery pack on the back): each is
    /// merged into the inertia of the body that carries its link.
    #[serde(default)]
    pub added_bodies: Vec<AddedBodySpec>,
    /// Links whose URDF collision shapes the simulator ignores (a placeholder shape, a body
    /// that must not touch the ground).
    #[serde(default)]
    pub ignore_collisions: Vec<String>,
    /// The feet, in the order the controllers and logs use (left first).
    pub feet: Vec<FootSpec>,
    /// The hands (end effectors for manipulation and teleoperation).
    #[serde(default)]
    pub hands: Vec<HandSpec>,
    #[serde(default)]
    pub sensors: SensorsSpec,
    /// Gains files by name (a controller kind, or another set a scenario can name), relative
    /// to this file.
    #[serde(default)]
    pub gains: BTreeMap<String, PathBuf>,
    /// Joint limits replacing or completing the URDF's.
    #[serde(default)]
    pub limits: LimitsSpec,
    /// When a run of this robot counts as fallen or diverged (absent keys: corps' defaults).
    #[serde(default)]
    pub fall: Criteria,
    /// The joint drives a scenario simulates with `[actuation] drives = true` (absent: ideal
    /// torques only).
    pub drives: Option<DrivesSpec>,
    /// Elastic joints the robot has but its encoders and its controllers' model do not: the
    /// simulator's model gets them ([`crate::PlantVariant`]), every controller and estimator
    /// keeps the rigid one.
    #[serde(default)]
    pub passive_joints: Vec<PassiveJointSpec>,
}

/// A passive spring-damper joint inserted into the URDF's tree for the simulator only:
/// `τ = −k θ − d θ̇` (seed 000 Eq 6.4), TALOS' flexible hip of seed 000 App. 4.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct PassiveJointSpec {
    /// Its name (no joint of the URDF has it).
    pub name: String,
    /// The URDF joint it is inserted before: the passive joint takes that joint's parent link
    /// and origin, and the joint then hangs from the passive joint's (massless) link.
    pub before: String,
    /// Rotation axis in the joint frame (the frame of `before`'s origin).
    pub axis: [f64; 3],
    /// `k`, N·m/rad, > 0.
    pub stiffness: f64,
    /// `d`, N·m·s/rad, ≥ 0.
    pub damping: f64,
    /// The actuated joint of the rigid model that turns about the same axis (while the joints
    /// between them are at zero), whose command a controller offsets to compensate the
    /// deflection (seed 000 Eq 6.3); one passive joint each.
    pub compensated_by: Option<String>,
}

/// Flexible joint drives with a current-controlled motor (seed 000 Eq 2.33–2.34), the same
/// parameters on every actuated joint except those listed `ideal`.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct DrivesSpec {
    /// Motor inertia through the gear ratio, kg·m².
    pub motor_inertia: f64,
    /// Drive stiffness, N·m/rad, and damping, N·m·s/rad.
    pub stiffness: f64,
    pub damping: f64,
    /// Motor and joint friction together: viscous (N·m·s/rad), dry (N·m), and the velocity
    /// of the dry friction's tanh (rad/s).
    pub viscous_friction: f64,
    pub dry_friction: f64,
    pub friction_velocity: f64,
    /// `R K_m`, N·m/A.
    pub drive_gain: f64,
    /// Motor current limit, A (absent: each joint's effort limit over `drive_gain`).
    pub current_limit: Option<f64>,
    /// Torque-loop bandwidth, Hz, and command delay, control periods.
    pub bandwidth_hz: f64,
    pub delay_periods: usize,
    /// Joints kept on ideal torques.
    #[serde(default)]
    pub ideal: Vec<String>,
}

/// A frame added to the model, rigidly attached to an existing frame.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct FrameSpec {
    pub name: String,
    /// The frame it is attached to.
    pub parent: String,
    /// Position in the parent frame (m).
    #[serde(default)]
    pub translation: [f64; 3],
    /// Orientation in the parent frame, roll-pitch-yaw (rad), as URDF's `rpy`.
    #[serde(default)]
    pub rpy: [f64; 3],
}

/// A rigid body fixed to a link: its mass, its centre of mass and its inertia about that
/// centre, both in the link's frame.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct AddedBodySpec {
    pub name: String,
    /// The link (a frame of the model) it is fixed to.
    pub link: String,
    /// kg, > 0.
    pub mass: f64,
    /// Centre of mass in the link frame (m).
    pub com: [f64; 3],
    /// Inertia about the centre of mass, link axes: [ixx, iyy, izz, ixy, ixz, iyz] (kg·m²),
    /// positive definite.
    pub inertia: [f64; 6],
}

/// A foot: its sole frame, sole rectangle and sensors.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct FootSpec {
    /// `left` or `right` for a biped (names columns and plots).
    pub label: String,
    /// The sole frame: origin on the sole surface, z the contact normal, x forward.
    pub frame: String,
    /// The contact rectangle in the sole frame: the controllers' contact points.
    pub sole: SoleSpec,
    /// The force/torque sensor that measures this foot's contact wrench (a name of
    /// `[[sensors.force_torque]]`).
    pub force_torque: Option<String>,
    /// Ankle pitch and roll joints (gait measures); absent: the joint that moves the sole and
    /// the one before it.
    pub ankle: Option<[String; 2]>,
    /// Where the simulator's contact comes from: `urdf` (the foot body's collision
    /// primitives, the default) or `sole_box` (a thin box on the sole rectangle, for URDFs
    /// whose feet have only meshes).
    #[serde(default)]
    pub contact: FootContact,
}

/// The sole rectangle: distances from the sole frame's origin to its four edges (m).
#[derive(Clone, Copy, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct SoleSpec {
    pub front: f64,
    pub back: f64,
    pub left: f64,
    pub right: f64,
}

/// The simulator's contact geometry of a foot.
#[derive(Clone, Copy, Debug, Default, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum FootContact {
    #[default]
    Urdf,
    SoleBox,
}

/// A hand.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct HandSpec {
    pub label: String,
    pub frame: String,
    /// Its force/torque sensor, a name of `[[sensors.force_torque]]`.
    pub force_torque: Option<String>,
}

/// `[sensors]`: force/torque sensors and the IMU.
#[derive(Clone, Debug, Default, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct SensorsSpec {
    #[serde(default)]
    pub force_torque: Vec<ForceTorqueSpec>,
    /// The IMU's frame; absent: the root body.
    pub imu: Option<String>,
}

/// A six-axis force/torque sensor, measuring in `frame`.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct ForceTorqueSpec {
    pub name: String,
    pub frame: String,
}

/// `[limits]`: per-joint values replacing the URDF's (N·m or N; rad/s or m/s).
#[derive(Clone, Debug, Default, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct LimitsSpec {
    #[serde(default)]
    pub effort: BTreeMap<String, f64>,
    #[serde(default)]
    pub velocity: BTreeMap<String, f64>,
}
