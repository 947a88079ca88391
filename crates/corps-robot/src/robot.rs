//! A loaded robot: the one shared model plus what its description says, checked against the
//! model (every frame and joint it names exists, soles have an area, feet can touch the
//! ground) and resolved to indices.

use crate::description::{Description, FootContact, SoleSpec};
use crate::fall::Criteria;
use crate::files::{FileSource, BUILT_IN};
use crate::passive::{PassiveJoint, PlantVariant};
use corps_model::spatial::rotation::rpy_to_matrix;
use corps_model::spatial::{Inertia, Se3};
use corps_model::{
    build_model_from_urdf_str, build_model_from_urdf_str_locked, forward_kinematics_placements,
    CollisionGeometry, Data, Frame, FrameKind, Model, RootJoint, Shape,
};
use nalgebra::{DVector, Vector3};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// Thickness of the contact box a `sole_box` foot gets (m).
pub const SOLE_BOX_THICKNESS: f64 = 0.01;

/// A description that cannot be used.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum RobotError {
    /// The file, then `key: message` (or `line N: key: message`).
    #[error("{file}: {message}")]
    Invalid { file: String, message: String },
    #[error(
        "robot '{name}' is neither a built-in robot ({built_in}) nor a description file (.toml)"
    )]
    Unknown { name: String, built_in: String },
}

/// A foot, resolved.
#[derive(Clone, Debug, PartialEq)]
pub struct Foot {
    pub label: String,
    /// The sole frame's index and name.
    pub frame: usize,
    pub frame_name: String,
    /// The joint that moves the sole.
    pub joint: usize,
    pub sole: SoleSpec,
    /// The sole rectangle's corners in the sole frame: front-left, front-right, back-left,
    /// back-right (the order of the controllers' contact points).
    pub corners: [Vector3<f64>; 4],
    /// Ankle pitch and roll joint indices.
    pub ankle: [usize; 2],
    /// Height of the sole joint's origin above the sole (m).
    pub ankle_height: f64,
    /// Index of its force/torque sensor in [`Robot::force_torque`].
    pub force_torque: Option<usize>,
}

/// A hand, resolved.
#[derive(Clone, Debug, PartialEq)]
pub struct Hand {
    pub label: String,
    pub frame: usize,
    pub force_torque: Option<usize>,
}

/// A gains file's text and how to name it in messages.
#[derive(Clone, Debug, PartialEq)]
pub struct GainsText {
    pub text: String,
    pub shown: String,
}

/// A robot as corps runs it.
#[derive(Clone, Debug)]
pub struct Robot {
    pub name: String,
    /// Where the description came from (a path, or `built-in robots/…`).
    pub shown: String,
    /// The one model every part of a run shares.
    pub model: Arc<Model>,
    /// The reference posture's name and configuration.
    pub posture_name: String,
    pub posture: DVector<f64>,
    /// The waist (base) frame.
    pub base: usize,
    pub feet: Vec<Foot>,
    pub hands: Vec<Hand>,
    /// Force/torque sensors: (name, frame name).
    pub force_torque: Vec<(String, String)>,
    /// The IMU's frame name (None: the root body).
    pub imu: Option<String>,
    /// Gains files by name.
    pub gains: BTreeMap<String, GainsText>,
    pub fall: Criteria,
    /// The joint drives of the description, if it gives them.
    pub drives: Option<crate::description::DrivesSpec>,
    /// The simulator's model when the robot has passive joints its controllers do not model
    /// (None: the simulator runs [`Robot::model`] too).
    pub plant: Option<Arc<PlantVariant>>,
}

impl Robot {
    /// A built-in robot by name, or the description file at `spec` (relative paths from
    /// `base_dir`).
    pub fn resolve(spec: &str, base_dir: &Path) -> Result<Robot, RobotError> {
        if let Some(robot) = Self::built_in(spec) {
            return robot;
        }
        let path = Path::new(spec);
        if path.extension().is_none() {
            return Err(RobotError::Unknown {
                name: spec.to_string(),
                built_in: BUILT_IN.map(|(n, _)| n).join(", "),
            });
        }
        Self::from_file(&base_dir.join(path))
    }

    /// A built-in robot (`talos`, `icub`, `simple_humanoid`); None for another name.
    pub fn built_in(name: &str) -> Option<Result<Robot, RobotError>> {
        let (_, path) = BUILT_IN.iter().find(|(n, _)| *n == name)?;
        Some(Self::read(Path::new(path), FileSource::BuiltIn))
    }

    /// The description file at `path`.
    pub fn from_file(path: &Path) -> Result<Robot, RobotError> {
        Self::read(path, FileSource::Disk)
    }

    fn read(path: &Path, source: FileSource) -> Result<Robot, RobotError> {
        let shown = source.show(path);
        let invalid = |message: String| RobotError::Invalid {
            file: shown.clone(),
            message,
        };
        let text = source.read(path).map_err(&invalid)?;
        let text = extended(text, path, &source, 0).map_err(&invalid)?;
        let description: Description = crate::toml_text::parse(&text).map_err(&invalid)?;
        let dir = path.parent().unwrap_or(Path::new("")).to_path_buf();
        Loader {
            source,
            dir,
            shown: shown.clone(),
        }
        .load(description)
        .map_err(invalid)
    }

    /// The foot labelled `label`.
    pub fn foot(&self, label: &str) -> Option<&Foot> {
        self.feet.iter().find(|f| f.label == label)
    }

    /// The gains file named `name` (a controller kind or another set).
    pub fn gains(&self, name: &str) -> Result<&GainsText, String> {
        self.gains.get(name).ok_or_else(|| {
            let names: Vec<&str> = self.gains.keys().map(String::as_str).collect();
            format!(
                "robot '{}' has no gains named '{name}' (its description's [gains] has: {})",
                self.name,
                if names.is_empty() {
                    "none".to_string()
                } else {
                    names.join(", ")
                }
            )
        })
    }
}

struct Loader {
    source: FileSource,
    dir: PathBuf,
    shown: String,
}

type Checked<T> = Result<T, String>;

impl Loader {
    fn read(&self, key: &str, rel: &Path) -> Checked<(String, String)> {
        let path = self.dir.join(rel);
        let text = self.source.read(&path).map_err(|e| format!("{key}: {e}"))?;
        Ok((text, self.source.show(&path)))
    }

    fn load(&self, mut d: Description) -> Checked<Robot> {
        let passive = std::mem::take(&mut d.passive_joints);
        let (urdf, urdf_shown) = self.read("urdf", &d.urdf)?;
        let mut robot = self.load_urdf(d.clone(), &urdf, &urdf_shown)?;
        if passive.is_empty() {
            return Ok(robot);
        }
        let mut text = urdf;
        for (k, p) in passive.iter().enumerate() {
            let key = format!("passive_joints[{k}]");
            crate::passive::check_spec(p, &key)?;
            text = crate::passive::insert(&text, p, &key)?;
        }
        let plant = self.load_urdf(d, &text, &format!("{urdf_shown} (with passive joints)"))?;
        let rigid = &robot.model;
        let passive = (passive.iter().enumerate())
            .map(|(k, p)| {
                let compensated_by = (p.compensated_by.as_ref())
                    .map(|name| {
                        rigid
                            .joint_id(name)
                            .ok()
                            .filter(|&j| j > 0 && rigid.joints[j].nv() == 1)
                            .ok_or_else(|| {
                                format!(
                                    "passive_joints[{k}].compensated_by: no one-axis joint '{name}'"
                                )
                            })
                    })
                    .transpose()?;
                Ok(PassiveJoint {
                    name: p.name.clone(),
                    joint: plant.model.joint_id(&p.name).map_err(|e| e.to_string())?,
                    stiffness: p.stiffness,
                    damping: p.damping,
                    compensated_by,
                })
            })
            .collect::<Checked<Vec<_>>>()?;
        for (k, p) in passive.iter().enumerate() {
            if (p.compensated_by)
                .is_some_and(|j| passive[..k].iter().any(|o| o.compensated_by == Some(j)))
            {
                return Err(format!(
                    "passive_joints[{k}].compensated_by: '{}' compensates another passive joint already",
                    robot.model.joints[p.compensated_by.unwrap_or(0)].name
                ));
            }
        }
        robot.plant = Some(Arc::new(PlantVariant {
            model: plant.model,
            passive,
        }));
        Ok(robot)
    }

    /// The robot of description `d` (without passive joints) on the URDF text `urdf`.
    fn load_urdf(&self, d: Description, urdf: &str, urdf_shown: &str) -> Checked<Robot> {
        let mut model = build_model_from_urdf_str(urdf, RootJoint::FreeFlyer)
            .map_err(|e| format!("urdf: {urdf_shown}: {e}"))?;
        let srdf = match &d.srdf {
            Some(srdf) => Some(self.read("srdf", srdf)?),
            None => None,
        };
        if let Some((text, shown)) = &srdf {
            corps_model::parse::load_reference_configurations_str(&mut model, text)
                .map_err(|e| format!("srdf: {shown}: {e}"))?;
        }
        if !d.locked_joints.is_empty() {
            // Lock at the reference posture, then read the SRDF again for the smaller model.
            let posture = model
                .reference_configuration(&d.posture)
                .map_err(|e| format!("posture: {e}"))?;
            let locked = (d.locked_joints.iter())
                .map(|name| {
                    let j = model.joint_id(name).map(|id| &model.joints[id]).map_err(|_| {
                        format!(
                            "locked_joints: the model has no movable joint '{name}' (unknown, or fixed in the URDF)"
                        )
                    })?;
                    // A continuous joint's configuration is (cos θ, sin θ).
                    let angle = match j.nq() {
                        2 => posture[j.idx_q + 1].atan2(posture[j.idx_q]),
                        _ => posture[j.idx_q],
                    };
                    Ok((name.clone(), angle))
                })
                .collect::<Checked<Vec<_>>>()?;
            model = build_model_from_urdf_str_locked(urdf, RootJoint::FreeFlyer, &locked)
                .map_err(|e| format!("locked_joints: {e}"))?;
            if let Some((text, shown)) = &srdf {
                corps_model::parse::load_reference_configurations_str(&mut model, text)
                    .map_err(|e| format!("srdf: {shown}: {e}"))?;
            }
        }
        apply_limits(&mut model, &d)?;
        if let Some(floor) = d.inertia_floor {
            if !(floor > 0.0 && floor.is_finite()) {
                return Err(format!(
                    "inertia_floor: must be a finite number > 0, got {floor}"
                ));
            }
            raise_inertias(&mut model, floor);
        }
        for (k, b) in d.added_bodies.iter().enumerate() {
            add_body(&mut model, b)
                .map_err(|e| format!("added_bodies[{k}] ('{}'): {e}", b.name))?;
        }
        for (k, f) in d.frames.iter().enumerate() {
            add_frame(&mut model, f).map_err(|e| format!("frames[{k}]: {e}"))?;
        }
        for (k, link) in d.ignore_collisions.iter().enumerate() {
            if !model.frames.iter().any(|f| &f.name == link) {
                return Err(format!("ignore_collisions[{k}]: no link named '{link}'"));
            }
            model.collisions.retain(|c| &c.link != link);
        }
        let base = find_frame(&model, "base", &d.base)?;
        let posture = model
            .reference_configuration(&d.posture)
            .map_err(|e| format!("posture: {e}"))?
            .clone();
        let force_torque: Vec<(String, String)> = d
            .sensors
            .force_torque
            .iter()
            .map(|s| (s.name.clone(), s.frame.clone()))
            .collect();
        for (k, (name, f)) in force_torque.iter().enumerate() {
            find_frame(&model, &format!("sensors.force_torque[{k}].frame"), f)?;
            if force_torque[..k].iter().any(|(n, _)| n == name) {
                return Err(format!(
                    "sensors.force_torque[{k}].name: '{name}' is used twice"
                ));
            }
        }
        if let Some(imu) = &d.sensors.imu {
            find_frame(&model, "sensors.imu", imu)?;
        }
        let sensor = |key: String, name: &Option<String>| -> Checked<Option<usize>> {
            name.as_ref()
                .map(|n| {
                    force_torque
                        .iter()
                        .position(|(s, _)| s == n)
                        .ok_or_else(|| {
                            format!("{key}: '{n}' is not a name of [[sensors.force_torque]]")
                        })
                })
                .transpose()
        };
        if d.feet.is_empty() {
            return Err("feet: a robot description needs at least one foot".into());
        }
        let mut feet = Vec::with_capacity(d.feet.len());
        for (k, f) in d.feet.iter().enumerate() {
            let key = format!("feet[{k}]");
            let frame_id = find_frame(&model, &format!("{key}.frame"), &f.frame)?;
            let joint = model.frames[frame_id]
                .parent_joint
                .filter(|j| *j > 0)
                .ok_or_else(|| format!("{key}.frame: '{}' does not move with a leg", f.frame))?;
            check_sole(&f.sole).map_err(|e| format!("{key}.sole: {e}"))?;
            let ankle = match &f.ankle {
                Some([pitch, roll]) => {
                    let j = |n: &str| {
                        model
                            .joint_id(n)
                            .map_err(|_| format!("{key}.ankle: no joint named '{n}'"))
                    };
                    let ankle = [j(pitch)?, j(roll)?];
                    if ankle.iter().any(|a| *a == 0 || model.joints[*a].nv() != 1) {
                        return Err(format!(
                            "{key}.ankle: must name two one-axis joints of the leg"
                        ));
                    }
                    ankle
                }
                None => {
                    let parent = model.joints[joint].parent.filter(|p| *p > 0).ok_or_else(|| {
                        format!("{key}.ankle: the sole joint has no parent joint; name the ankle joints")
                    })?;
                    [parent, joint]
                }
            };
            let placement = model.frames[frame_id].placement;
            let ankle_height = -(placement.rotation.transpose() * placement.translation).z;
            let s = f.sole;
            feet.push(Foot {
                label: f.label.clone(),
                frame: frame_id,
                frame_name: f.frame.clone(),
                joint,
                sole: s,
                corners: [
                    Vector3::new(s.front, s.left, 0.0),
                    Vector3::new(s.front, -s.right, 0.0),
                    Vector3::new(-s.back, s.left, 0.0),
                    Vector3::new(-s.back, -s.right, 0.0),
                ],
                ankle,
                ankle_height,
                force_torque: sensor(format!("{key}.force_torque"), &f.force_torque)?,
            });
            if d.feet[..k].iter().any(|o| o.label == f.label) {
                return Err(format!("{key}.label: '{}' is used twice", f.label));
            }
        }
        for (k, f) in d.feet.iter().enumerate() {
            match f.contact {
                FootContact::SoleBox => add_sole_box(&mut model, &feet[k]),
                FootContact::Urdf => check_foot_collision(&model, &feet[k])
                    .map_err(|e| format!("feet[{k}].contact: {e}"))?,
            }
        }
        let mut posture = posture;
        if d.level_posture {
            level(&model, &feet, &mut posture).map_err(|e| format!("level_posture: {e}"))?;
            if let Some((_, q)) =
                (model.reference_configurations.iter_mut()).find(|(n, _)| *n == d.posture)
            {
                q.copy_from(&posture);
            }
        }
        check_feet_lowest(&model, &feet, &posture, &d.posture)?;
        let mut hands = Vec::with_capacity(d.hands.len());
        for (k, h) in d.hands.iter().enumerate() {
            hands.push(Hand {
                label: h.label.clone(),
                frame: find_frame(&model, &format!("hands[{k}].frame"), &h.frame)?,
                force_torque: sensor(format!("hands[{k}].force_torque"), &h.force_torque)?,
            });
        }
        let mut gains = BTreeMap::new();
        for (name, path) in &d.gains {
            let (text, shown) = self.read(&format!("gains.{name}"), path)?;
            gains.insert(name.clone(), GainsText { text, shown });
        }
        d.fall.check().map_err(|e| format!("fall.{e}"))?;
        if let Some(drives) = &d.drives {
            if let Some(j) = drives
                .ideal
                .iter()
                .find(|j| !model.joints.iter().any(|x| &x.name == *j))
            {
                return Err(format!("drives.ideal: the model has no joint '{j}'"));
            }
        }
        Ok(Robot {
            name: d.name,
            shown: self.shown.clone(),
            model: Arc::new(model),
            posture_name: d.posture,
            posture,
            base,
            feet,
            hands,
            force_torque,
            imu: d.sensors.imu,
            gains,
            fall: d.fall,
            drives: d.drives,
            plant: None,
        })
    }
}

/// Descriptions deeper than this in a chain of `extends` are refused (a loop, most likely).
const MAX_EXTENDS: usize = 4;

/// A description's text with its `extends = "base.toml"` resolved: the base description (in
/// the same directory) with this file's keys replacing or completing its own, tables merged
/// key by key, arrays and values replaced. Text without `extends` comes back as it is.
fn extended(text: String, path: &Path, source: &FileSource, depth: usize) -> Checked<String> {
    let Ok(mut table) = text.parse::<toml::Table>() else {
        return Ok(text); // the strict reading reports the syntax error
    };
    let Some(base) = table.remove("extends") else {
        return Ok(text);
    };
    let toml::Value::String(base) = base else {
        return Err("extends: must be the file name of a description in the same directory".into());
    };
    let rel = Path::new(&base);
    if rel.components().count() != 1 {
        return Err(format!(
            "extends: '{base}' must be a description in the same directory (its paths resolve from there)"
        ));
    }
    if depth >= MAX_EXTENDS {
        return Err(format!(
            "extends: more than {MAX_EXTENDS} descriptions deep (a loop?)"
        ));
    }
    let base_path = path.parent().unwrap_or(Path::new("")).join(rel);
    let base_text = source
        .read(&base_path)
        .map_err(|e| format!("extends: {e}"))?;
    let base_text = extended(base_text, &base_path, source, depth + 1)
        .map_err(|e| format!("extends '{base}': {e}"))?;
    let mut merged: toml::Table = base_text
        .parse()
        .map_err(|e: toml::de::Error| format!("extends '{base}': {}", e.message()))?;
    crate::toml_text::merge(&mut merged, &table);
    toml::to_string(&merged).map_err(|e| format!("extends: {e}"))
}

/// Merges the rigid body `b` into the inertia of the body that carries its link.
fn add_body(model: &mut Model, b: &crate::description::AddedBodySpec) -> Checked<()> {
    if !(b.mass > 0.0 && b.mass.is_finite()) {
        return Err(format!("mass must be a finite number > 0, got {}", b.mass));
    }
    let [xx, yy, zz, xy, xz, yz] = b.inertia;
    if !b.inertia.iter().all(|x| x.is_finite()) {
        return Err(format!("inertia must be finite, got {:?}", b.inertia));
    }
    let inertia = nalgebra::Matrix3::new(xx, xy, xz, xy, yy, yz, xz, yz, zz);
    let eig = nalgebra::SymmetricEigen::new(inertia);
    if eig.eigenvalues.min() <= 0.0 {
        return Err(format!(
            "inertia must be positive definite, its principal moments are {:?}",
            eig.eigenvalues.as_slice()
        ));
    }
    let [a, bb, c] = eig.eigenvalues.into();
    if a + bb < c || a + c < bb || bb + c < a {
        return Err("inertia breaks the triangle inequality of a rigid body's moments".into());
    }
    if !b.com.iter().all(|x| x.is_finite()) {
        return Err(format!("com must be finite, got {:?}", b.com));
    }
    let link = model
        .frames
        .iter()
        .find(|f| f.name == b.link)
        .ok_or_else(|| format!("no link named '{}'", b.link))?;
    let joint = link
        .parent_joint
        .ok_or_else(|| format!("link '{}' is fixed to the world", b.link))?;
    let body = Inertia::new(b.mass, Vector3::from(b.com), inertia).transformed(&link.placement);
    model.inertias[joint] += body;
    Ok(())
}

/// Raises every body's principal moments of inertia (about its centre of mass) to `floor`.
fn raise_inertias(model: &mut Model, floor: f64) {
    for body in model.inertias.iter_mut() {
        let eig = nalgebra::SymmetricEigen::new(body.inertia);
        if eig.eigenvalues.min() < floor {
            let raised = eig.eigenvalues.map(|x| x.max(floor));
            body.inertia = eig.eigenvectors
                * nalgebra::Matrix3::from_diagonal(&raised)
                * eig.eigenvectors.transpose();
        }
    }
}

/// Rotates the free-flyer of `q` so that the feet's mean sole normal becomes the world's z.
fn level(model: &Model, feet: &[Foot], q: &mut DVector<f64>) -> Checked<()> {
    let mut data = Data::new(model);
    forward_kinematics_placements(model, &mut data, q.as_slice()).map_err(|e| e.to_string())?;
    let mut normal = Vector3::zeros();
    for f in feet {
        let p = corps_model::frame_placement(model, &data, f.frame).map_err(|e| e.to_string())?;
        normal += p.rotation.column(2);
    }
    let Some(turn) = nalgebra::UnitQuaternion::rotation_between(&normal, &Vector3::z()) else {
        return Err("the soles face opposite ways".into());
    };
    let base = nalgebra::UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(
        q[6], q[3], q[4], q[5],
    ));
    let levelled = turn * base;
    let c = levelled.coords;
    q[3] = c.x;
    q[4] = c.y;
    q[5] = c.z;
    q[6] = c.w;
    Ok(())
}

fn find_frame(model: &Model, key: &str, name: &str) -> Checked<usize> {
    model
        .frame_id(name)
        .map_err(|_| format!("{key}: no frame named '{name}' in the model"))
}

fn apply_limits(model: &mut Model, d: &Description) -> Checked<()> {
    for (kind, table) in [
        ("effort", &d.limits.effort),
        ("velocity", &d.limits.velocity),
    ] {
        for (name, value) in table {
            let key = format!("limits.{kind}.{name}");
            let j = model
                .joint_id(name)
                .map_err(|_| format!("{key}: no joint named '{name}'"))?;
            let joint = &model.joints[j];
            if joint.nv() != 1 {
                return Err(format!("{key}: only one-axis joints take a limit"));
            }
            if !(*value > 0.0 && value.is_finite()) {
                return Err(format!("{key}: must be a finite number > 0, got {value}"));
            }
            let idx = joint.idx_v;
            match kind {
                "effort" => model.effort_limit[idx] = *value,
                _ => model.velocity_limit[idx] = *value,
            }
        }
    }
    Ok(())
}

fn add_frame(model: &mut Model, f: &crate::description::FrameSpec) -> Checked<()> {
    if model.frame_id(&f.name).is_ok() {
        return Err(format!("name: the model already has a frame '{}'", f.name));
    }
    if f.translation.iter().chain(&f.rpy).any(|x| !x.is_finite()) {
        return Err("translation and rpy must be finite".into());
    }
    let parent = model
        .frame_id(&f.parent)
        .map_err(|_| format!("parent: no frame named '{}' in the model", f.parent))?;
    let p = &model.frames[parent];
    let local = Se3::new(
        rpy_to_matrix(f.rpy[0], f.rpy[1], f.rpy[2]),
        Vector3::from(f.translation),
    );
    let frame = Frame {
        name: f.name.clone(),
        kind: FrameKind::FixedJoint,
        parent_joint: p.parent_joint,
        placement: p.placement * local,
    };
    model.frames.push(frame);
    Ok(())
}

fn check_sole(s: &SoleSpec) -> Checked<()> {
    let values = [s.front, s.back, s.left, s.right];
    if values.iter().any(|x| !x.is_finite()) {
        return Err("front, back, left and right must be finite".into());
    }
    if values.iter().any(|x| *x < 0.0) {
        return Err("front, back, left and right are distances from the sole frame's origin to the edges: each ≥ 0".into());
    }
    if s.front + s.back <= 0.0 || s.left + s.right <= 0.0 {
        return Err(format!(
            "the rectangle has zero area ({} m long, {} m wide)",
            s.front + s.back,
            s.left + s.right
        ));
    }
    Ok(())
}

/// A thin box whose bottom face is the sole rectangle.
fn add_sole_box(model: &mut Model, foot: &Foot) {
    let frame = &model.frames[foot.frame];
    let s = foot.sole;
    let centre = Vector3::new(
        (s.front - s.back) / 2.0,
        (s.left - s.right) / 2.0,
        SOLE_BOX_THICKNESS / 2.0,
    );
    let local = Se3::new(nalgebra::Matrix3::identity(), centre);
    let link = format!("{}_sole_box", foot.label);
    model.collisions.push(CollisionGeometry {
        link,
        parent_joint: Some(foot.joint),
        placement: frame.placement * local,
        shape: Shape::Box {
            size: Vector3::new(s.front + s.back, s.left + s.right, SOLE_BOX_THICKNESS),
        },
    });
}

/// The foot body (or a body below it) carries a collision box, cylinder or sphere.
fn check_foot_collision(model: &Model, foot: &Foot) -> Checked<()> {
    let subtree = model.subtree_joints(foot.joint);
    let primitive = model.collisions.iter().any(|c| {
        c.parent_joint.is_some_and(|j| subtree.contains(&j))
            && !matches!(c.shape, Shape::Mesh { .. })
    });
    if primitive {
        return Ok(());
    }
    Err(format!(
        "the body of '{}' has no collision box, cylinder or sphere (meshes are not \
         simulated), so the foot cannot touch the ground; set contact = \"sole_box\" to \
         simulate the sole rectangle, or give the URDF a primitive",
        foot.frame_name
    ))
}

/// At the reference posture, the lowest collision primitive belongs to a foot: otherwise the
/// robot would stand on something else.
fn check_feet_lowest(model: &Model, feet: &[Foot], q: &DVector<f64>, posture: &str) -> Checked<()> {
    let mut data = Data::new(model);
    forward_kinematics_placements(model, &mut data, q.as_slice())
        .map_err(|e| format!("posture: {e}"))?;
    let mut lowest: Option<(f64, usize)> = None;
    for (k, c) in model.collisions.iter().enumerate() {
        let Some(j) = c.parent_joint else { continue };
        let Some(z) = lowest_point(&(data.o_m_i[j] * c.placement), &c.shape) else {
            continue;
        };
        if lowest.is_none_or(|(l, _)| z < l) {
            lowest = Some((z, k));
        }
    }
    let Some((z_low, k)) = lowest else {
        return Err("feet: the model has no collision box, cylinder or sphere".into());
    };
    let joint = model.collisions[k].parent_joint;
    let on_foot = feet
        .iter()
        .any(|f| joint.is_some_and(|j| model.subtree_joints(f.joint).contains(&j)));
    if !on_foot {
        return Err(format!(
            "feet: at posture '{posture}' the lowest collision shape is on link '{}' \
             ({z_low:.3} m), not on a foot; list it in ignore_collisions or fix the feet",
            model.collisions[k].link
        ));
    }
    Ok(())
}

/// Lowest world z of a primitive placed at `m` (None for a mesh).
fn lowest_point(m: &Se3, shape: &Shape) -> Option<f64> {
    let r = &m.rotation;
    let c = m.translation;
    match shape {
        Shape::Box { size } => {
            let h = size / 2.0;
            Some(c.z - (r[(2, 0)].abs() * h.x + r[(2, 1)].abs() * h.y + r[(2, 2)].abs() * h.z))
        }
        Shape::Sphere { radius } => Some(c.z - radius),
        Shape::Cylinder { radius, length } => {
            let az = r[(2, 2)].abs();
            Some(c.z - az * length / 2.0 - radius * (1.0 - az * az).max(0.0).sqrt())
        }
        Shape::Mesh { .. } => None,
    }
}
