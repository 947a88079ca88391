//! Retargeting an operator's poses onto a robot (seed 001 §6.1.1), from a mapping file:
//!
//! - **Joints** by delta retargeting, Eq 6.1–6.2: `s_iR = s_0R + (s_iH − s_0H)`, from both rest
//!   poses (the robot's reference posture, the operator's rest frame), clipped to the robot's
//!   joint limits (each clipping counted). A group maps human joints (one or several, whose
//!   angles add: a torso DOF is the sum of the spine rotations) onto a chain of robot joints:
//!   the rotation each human joint made since its rest, seen in the operator's body frame at
//!   rest (x forward, y left, z up), is split into angles about the chain's axes at the
//!   robot's rest posture in the robot's world ([`axes::solve_chain`], warm-started from the
//!   previous pose); the axes, and so the signs, come from the robot's model, not the file.
//! - **Waist height**, Eq 6.3–6.5: `z_R = z_0R + (z_0R / z_0H)(z_H − z_0H)`, heights above the
//!   floor (the operator's lowest joint at rest; the robot's soles).
//!
//! ```toml
//! robot = "../../robots/icub_description/icub_teleop.toml"  # a built-in name, or a file
//! [skeleton]
//! length_unit = 0.01          # metres per file unit
//! up = "y"                    # the file's vertical axis
//! waist = "Hips"
//! feet = ["Foot_L", "Foot_R"] # left, right
//! hips = ["UpperLeg_L", "UpperLeg_R"]  # left, right: the operator's left at rest
//! [[groups]]
//! human = ["Spine", "Chest"]
//! robot = ["torso_pitch", "torso_roll", "torso_yaw"]
//! ```

pub mod axes;

use crate::error::{MocapError, Result};
use crate::skeleton::{Pose, Skeleton, Units};
use corps_robot::Robot;
use nalgebra::{Matrix3, Rotation3, Vector3};
use serde::Deserialize;
use std::path::{Path, PathBuf};

/// The `[skeleton]` section: how to read the operator's file and find the landmarks.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SkeletonSpec {
    #[serde(default = "default_length_unit")]
    pub length_unit: f64,
    #[serde(default = "default_up")]
    pub up: String,
    pub waist: String,
    pub feet: [String; 2],
    pub hips: [String; 2],
    /// The frame of a clip taken as the operator's rest pose.
    #[serde(default)]
    pub rest_frame: usize,
}

fn default_length_unit() -> f64 {
    0.01
}
fn default_up() -> String {
    "y".into()
}

/// A group: human joints onto a chain of robot joints.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GroupSpec {
    pub human: Vec<String>,
    pub robot: Vec<String>,
}

/// Footstep ranges of Eq 6.6–6.7 (m): the operator's and the robot's.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StepsSpec {
    pub human_length: [f64; 2],
    pub robot_length: [f64; 2],
    pub human_height: [f64; 2],
    pub robot_height: [f64; 2],
    /// Step detection: a foot lifted more than `lift` above the ground and moved more
    /// than `travel` from where it stood is stepping; back within `land` of the ground,
    /// the step ends.
    pub lift: f64,
    pub travel: f64,
    pub land: f64,
}

/// A mapping file.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MappingSpec {
    pub robot: String,
    /// The robot's frame whose orientation the neck task holds (Table 6.1's R_neck).
    pub neck_frame: Option<String>,
    /// Damping of the chain solve per pose (rad⁻¹ weight on the change from the previous
    /// pose, [`axes::solve_chain`]; 0: exact): for chains with a singularity in reach.
    #[serde(default)]
    pub chain_damping: f64,
    pub skeleton: SkeletonSpec,
    pub groups: Vec<GroupSpec>,
    pub steps: StepsSpec,
}

/// A mapping file read: its spec and where relative paths start.
#[derive(Clone, Debug)]
pub struct Mapping {
    pub spec: MappingSpec,
    pub file: String,
    pub dir: PathBuf,
}

impl Mapping {
    /// Reads the mapping file at `path`.
    pub fn read(path: &Path) -> Result<Mapping> {
        let file = path.display().to_string();
        let text = std::fs::read_to_string(path).map_err(|e| MocapError::Io {
            file: file.clone(),
            message: e.to_string(),
        })?;
        let spec: MappingSpec = toml::from_str(&text).map_err(|e| MocapError::Mapping {
            file: file.clone(),
            message: e.message().to_string(),
        })?;
        let m = Mapping {
            spec,
            file,
            dir: path.parent().unwrap_or(Path::new("")).to_path_buf(),
        };
        m.check()?;
        Ok(m)
    }

    fn error<T>(&self, message: impl Into<String>) -> Result<T> {
        Err(MocapError::Mapping {
            file: self.file.clone(),
            message: message.into(),
        })
    }

    fn check(&self) -> Result<()> {
        let s = &self.spec;
        if !(s.skeleton.length_unit.is_finite() && s.skeleton.length_unit > 0.0) {
            return self.error("skeleton.length_unit: must be > 0");
        }
        if !(s.chain_damping.is_finite() && s.chain_damping >= 0.0) {
            return self.error("chain_damping: must be ≥ 0");
        }
        if !matches!(s.skeleton.up.as_str(), "y" | "z") {
            return self.error(format!("skeleton.up: '{}' is not y or z", s.skeleton.up));
        }
        for (k, g) in s.groups.iter().enumerate() {
            if g.human.is_empty() || g.robot.is_empty() || g.robot.len() > 3 {
                return self.error(format!(
                    "groups[{k}]: one or more human joints onto 1 to 3 robot joints"
                ));
            }
        }
        let st = &s.steps;
        for (name, r) in [
            ("human_length", st.human_length),
            ("robot_length", st.robot_length),
            ("human_height", st.human_height),
            ("robot_height", st.robot_height),
        ] {
            if !(r[0].is_finite() && r[1].is_finite() && r[0] >= 0.0 && r[1] > r[0]) {
                return self.error(format!("steps.{name}: [min, max] with 0 ≤ min < max"));
            }
        }
        for (name, v) in [("lift", st.lift), ("travel", st.travel), ("land", st.land)] {
            if !(v.is_finite() && v > 0.0) {
                return self.error(format!("steps.{name}: must be > 0"));
            }
        }
        if st.land >= st.lift {
            return self.error("steps.land: must be below steps.lift");
        }
        Ok(())
    }

    /// The robot the file names (relative paths from the file's directory).
    pub fn robot(&self) -> Result<Robot> {
        Robot::resolve(&self.spec.robot, &self.dir).map_err(|e| MocapError::Mapping {
            file: self.file.clone(),
            message: format!("robot: {e}"),
        })
    }

    /// The operator's rest pose: frame `skeleton.rest_frame` of `clip`.
    pub fn rest_pose(&self, skeleton: &Skeleton, clip: &crate::bvh::Bvh) -> Result<Pose> {
        let k = self.spec.skeleton.rest_frame;
        if k >= clip.frames() {
            return self.error(format!(
                "skeleton.rest_frame {k}: the clip has {} frames",
                clip.frames()
            ));
        }
        Ok(skeleton.pose(clip.frame(k), k as f64 * clip.frame_time))
    }

    /// How to read the operator's files.
    pub fn units(&self) -> Units {
        Units {
            length: self.spec.skeleton.length_unit,
            up: if self.spec.skeleton.up == "z" { 2 } else { 1 },
        }
    }
}

/// One group resolved: human joint indices, robot joints (q index, rest value, limits) and
/// the chain's axes in the robot's world at rest.
struct Group {
    human: Vec<usize>,
    axes: Vec<Vector3<f64>>,
}

/// A mapped robot joint.
#[derive(Clone, Debug, PartialEq)]
pub struct MappedJoint {
    pub name: String,
    /// Its index in the robot's q.
    pub q_index: usize,
    /// Its angle at the robot's rest posture (rad).
    pub rest: f64,
    pub lower: f64,
    pub upper: f64,
}

/// Retargets poses of one operator onto one robot.
pub struct Retargeter {
    groups: Vec<Group>,
    /// Every mapped robot joint, in the groups' order.
    pub joints: Vec<MappedJoint>,
    /// The operator's joints' world and local rotations at rest.
    rest_world: Vec<Rotation3<f64>>,
    rest_local: Vec<Rotation3<f64>>,
    /// The operator's body frame at rest (columns: forward, left, up in the world).
    body: Matrix3<f64>,
    /// The operator's floor height (m, world).
    floor: f64,
    waist: usize,
    /// The operator's feet (left, right).
    feet: [usize; 2],
    /// Eq 6.3–6.5: the operator's and the robot's waist heights at rest (m).
    pub waist_rest_human: f64,
    pub waist_rest_robot: f64,
    /// Clippings to the joint limits, per mapped joint.
    pub clipped: Vec<usize>,
    /// Each (group, human joint)'s angles at the last pose: the next pose's start.
    warm: Vec<[f64; 3]>,
    damping: f64,
}

impl Retargeter {
    /// The retargeting of `mapping` from `skeleton` (whose rest pose is `rest`) onto `robot`.
    pub fn new(
        mapping: &Mapping,
        robot: &Robot,
        skeleton: &Skeleton,
        rest: &Pose,
    ) -> Result<Retargeter> {
        let s = &mapping.spec.skeleton;
        let human = |name: &str, what: &str| {
            skeleton.joint(name).ok_or_else(|| MocapError::Mapping {
                file: mapping.file.clone(),
                message: format!("{what}: the skeleton has no joint '{name}'"),
            })
        };
        let waist = human(&s.waist, "skeleton.waist")?;
        let hips = [
            human(&s.hips[0], "skeleton.hips")?,
            human(&s.hips[1], "skeleton.hips")?,
        ];
        let feet = [
            human(&s.feet[0], "skeleton.feet")?,
            human(&s.feet[1], "skeleton.feet")?,
        ];
        let body = body_frame(rest, hips);
        let floor = rest
            .world
            .iter()
            .map(|w| w.translation.vector.z)
            .fold(f64::INFINITY, f64::min);

        let model = &robot.model;
        let mut data = corps_model::Data::new(model);
        corps_model::forward_kinematics_placements(model, &mut data, robot.posture.as_slice())
            .map_err(|e| MocapError::Mapping {
                file: mapping.file.clone(),
                message: format!("the robot's rest posture: {e}"),
            })?;
        corps_model::update_frame_placements(model, &mut data);
        let mut groups = Vec::new();
        let mut joints = Vec::new();
        for (k, g) in mapping.spec.groups.iter().enumerate() {
            let human_joints = (g.human.iter())
                .map(|n| human(n, &format!("groups[{k}].human")))
                .collect::<Result<Vec<_>>>()?;
            let mut ids = Vec::new();
            for name in &g.robot {
                let id = model.joint_id(name).map_err(|_| MocapError::Mapping {
                    file: mapping.file.clone(),
                    message: format!("groups[{k}].robot: {} has no joint '{name}'", robot.name),
                })?;
                if joints.iter().any(|j: &MappedJoint| j.name == *name) {
                    return mapping.error(format!("groups[{k}].robot: '{name}' is mapped twice"));
                }
                ids.push(id);
            }
            // The chain from the root outwards: each joint an ancestor of the next.
            ids.sort_by_key(|&id| depth(model, id));
            for w in ids.windows(2) {
                if !is_ancestor(model, w[0], w[1]) {
                    return mapping.error(format!(
                        "groups[{k}].robot: {} and {} are not on one chain",
                        model.joints[w[0]].name, model.joints[w[1]].name
                    ));
                }
            }
            let mut axes = Vec::new();
            for &id in &ids {
                let j = &model.joints[id];
                let axis = match &j.kind {
                    corps_model::JointKind::Revolute { axis } => *axis,
                    _ => {
                        return mapping.error(format!(
                            "groups[{k}].robot: '{}' is not a bounded revolute joint (continuous and prismatic joints are not retargeted)",
                            j.name
                        ))
                    }
                };
                axes.push(data.o_m_i[id].rotation * axis);
                joints.push(MappedJoint {
                    name: j.name.clone(),
                    q_index: j.idx_q,
                    rest: robot.posture[j.idx_q],
                    lower: model.lower_position_limit[j.idx_q],
                    upper: model.upper_position_limit[j.idx_q],
                });
            }
            groups.push(Group {
                human: human_joints,
                axes,
            });
        }
        let sole_z = robot
            .feet
            .iter()
            .map(|f| data.o_m_f[f.frame].translation.z)
            .fold(f64::INFINITY, f64::min);
        let base_z = data.o_m_f[robot.base].translation.z;
        let waist_rest_robot = base_z - sole_z;
        let waist_rest_human = rest.world[waist].translation.vector.z - floor;
        if !(waist_rest_human > 0.0 && waist_rest_robot > 0.0) {
            return mapping.error(format!(
                "waist heights at rest: operator {waist_rest_human:.3} m, robot {waist_rest_robot:.3} m (both must be > 0)"
            ));
        }
        let n = joints.len();
        let warm = groups.iter().map(|g| g.human.len()).sum();
        Ok(Retargeter {
            groups,
            joints,
            rest_world: rest
                .world
                .iter()
                .map(|w| w.rotation.to_rotation_matrix())
                .collect(),
            rest_local: rest.local.iter().map(|r| r.to_rotation_matrix()).collect(),
            body,
            floor,
            waist,
            feet,
            waist_rest_human,
            waist_rest_robot,
            clipped: vec![0; n],
            warm: vec![[0.0; 3]; warm],
            damping: mapping.spec.chain_damping,
        })
    }

    /// The operator's body frame at rest (columns forward, left, up, in the world).
    pub fn body(&self) -> &Matrix3<f64> {
        &self.body
    }

    /// The operator's floor height (m, world).
    pub fn floor(&self) -> f64 {
        self.floor
    }

    /// Eq 6.1–6.2 for every mapped joint: `operator[k]` the unclipped `s_0R + Δs_H`,
    /// `robot[k]` the same clipped to the joint's limits (clippings counted).
    pub fn joints_into(&mut self, pose: &Pose, operator: &mut [f64], robot: &mut [f64]) {
        let mut k = 0;
        let mut w = 0;
        for g in &self.groups {
            let n = g.axes.len();
            let mut delta = [0.0; 3];
            for &h in &g.human {
                let rest = &self.rest_world[h];
                // D_w = W₀ (L₀⁻¹ Lᵢ) W₀ᵀ: the joint's motion since rest, in the world at rest,
                // then in the operator's body coordinates.
                let d_local = self.rest_local[h].inverse() * pose.local[h].to_rotation_matrix();
                let d_world = rest * d_local * rest.inverse();
                let b = Rotation3::from_matrix_unchecked(self.body);
                let d_body = b.inverse() * d_world * b;
                let warm = &mut self.warm[w];
                axes::solve_chain(&g.axes, &d_body, &mut warm[..n], self.damping);
                for (d, s) in delta.iter_mut().zip(&warm[..n]) {
                    *d += s;
                }
                w += 1;
            }
            for d in delta.iter().take(n) {
                let j = &self.joints[k];
                let s = j.rest + d;
                operator[k] = s;
                let c = s.clamp(j.lower, j.upper);
                if c != s {
                    self.clipped[k] += 1;
                }
                robot[k] = c;
                k += 1;
            }
        }
    }

    /// Eq 6.3–6.5: the robot's waist height for the operator's `pose` (m above the soles).
    pub fn waist_height(&self, pose: &Pose) -> f64 {
        let z = pose.world[self.waist].translation.vector.z - self.floor;
        self.waist_rest_robot
            + self.waist_rest_robot / self.waist_rest_human * (z - self.waist_rest_human)
    }

    /// The operator's feet in `pose`, in body coordinates at rest (z above the floor).
    pub fn feet(&self, pose: &Pose) -> [Vector3<f64>; 2] {
        self.feet
            .map(|k| self.in_body(&pose.world[k].translation.vector))
    }

    /// A point of the world in the operator's body coordinates at rest (x forward, y left,
    /// z up, from the floor below the world's origin).
    pub fn in_body(&self, p: &Vector3<f64>) -> Vector3<f64> {
        let v = self.body.transpose() * p;
        Vector3::new(v.x, v.y, p.z - self.floor)
    }
}

/// The operator's body frame at rest: up the world's z, left from the right hip to the left
/// (horizontal), forward = left × up.
fn body_frame(rest: &Pose, hips: [usize; 2]) -> Matrix3<f64> {
    let up = Vector3::z();
    let mut left = rest.world[hips[0]].translation.vector - rest.world[hips[1]].translation.vector;
    left.z = 0.0;
    let left = left.try_normalize(1e-9).unwrap_or_else(Vector3::y);
    let forward = left.cross(&up);
    Matrix3::from_columns(&[forward, left, up])
}

fn depth(model: &corps_model::Model, mut id: usize) -> usize {
    let mut d = 0;
    while let Some(p) = model.joints[id].parent {
        id = p;
        d += 1;
    }
    d
}

fn is_ancestor(model: &corps_model::Model, a: usize, mut b: usize) -> bool {
    while let Some(p) = model.joints[b].parent {
        if p == a {
            return true;
        }
        b = p;
    }
    false
}
