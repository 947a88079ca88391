//! `corps run … --record`: the run as an MCAP file (`run.mcap`) that Foxglove opens, in its
//! desktop app or in a browser, or streamed live to it (`corps teleop --stream`, [`live`]):
//! the robot in 3D (the URDF's visual meshes, or its collision
//! primitives where a mesh file is not found), moving with the true state; the CoM and its
//! reference, the ZMP and its reference, the support polygon of the feet in contact, the
//! contact forces as arrows and the footprints where each foot landed; in a teleoperation run
//! from a clip, the operator's skeleton beside the robot; and every column of the log as
//! signals to plot, all on one time line (controlled time).
//!
//! Topics: `/tf` (`foxglove.FrameTransforms`, world → each joint frame), `/robot`
//! (`foxglove.SceneUpdate`, the robot's shapes, locked to the joint frames, written once),
//! `/markers` (`foxglove.SceneUpdate` in the world frame), `/signals` (`corps.Signals`),
//! `/operator` (`foxglove.SceneUpdate` in the world frame, teleoperation only). 3D topics are
//! written every `VIEW_PERIOD` of controlled time, signals with the log.

pub mod live;
mod mcap_file;
mod meshes;
pub mod operator;
mod schemas;
mod topics;

pub use live::LiveStream;
pub use operator::OperatorView;
use topics::{Publish, Topic};

use anyhow::{Context, Result};
use base64::Engine;
use corps_loop::Truth;
use corps_model::spatial::Se3;
use corps_model::{Model, Shape};
use corps_scenario::run::RowSink;
use corps_scenario::ScenarioError;
use nalgebra::{Matrix3, UnitQuaternion, Vector3};
use serde_json::{json, Value};
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// The recording's file name in the output directory.
pub const RECORDING_NAME: &str = "run.mcap";
/// Period of the 3D topics (s of controlled time): 50 frames a second.
const VIEW_PERIOD: f64 = 0.02;
/// A foot carries the robot above this normal force (N): it is in the support polygon.
const SUPPORT_FORCE: f64 = 20.0;
/// Arrow length per newton of contact force (m/N).
const ARROW_SCALE: f64 = 1e-3;

/// What a recording needs of the robot.
pub struct RecordingScene {
    pub model: Arc<Model>,
    /// Each foot's sole frame and its rectangle's corners in that frame.
    pub feet: Vec<(usize, [Vector3<f64>; 4])>,
    /// The operator a teleoperation run follows, drawn beside the robot.
    pub operator: Option<OperatorView>,
}

/// Turns a run into the scene's messages: into `run.mcap.partial`, renamed to `run.mcap` when
/// it finishes, or live to viewers.
pub struct Recording {
    out: Box<dyn Publish>,
    scene: RecordingScene,
    columns: Vec<String>,
    /// Indices of the columns the markers read.
    at: Columns,
    row: Vec<f64>,
    every_view: usize,
    every_log: usize,
    /// Whether each foot carried the robot at the last view (a new touchdown leaves a print).
    touching: Vec<bool>,
    /// Footprints written so far.
    footprints: usize,
}

struct Columns {
    t: usize,
    com: [usize; 3],
    com_ref: [usize; 3],
    zmp: [usize; 2],
    zmp_ref: [usize; 2],
    foot_fz: Vec<usize>,
}

impl Recording {
    /// Starts the recording in `dir` for a run with `columns` logged every `log_every` ticks
    /// of `dt` seconds.
    pub fn create(
        dir: &Path,
        scene: RecordingScene,
        columns: &[String],
        dt: f64,
        log_every: usize,
    ) -> Result<Self> {
        let mut topics = Topic::ALL.to_vec();
        if scene.operator.is_some() {
            topics.push(Topic::Operator);
        }
        let out = Box::new(mcap_file::McapFile::create(dir, &topics)?);
        Self::with_output(out, scene, columns, dt, log_every)
    }

    /// Streams the run live through `stream`, as [`Recording::create`] records it.
    pub fn stream(
        stream: LiveStream,
        scene: RecordingScene,
        columns: &[String],
        dt: f64,
        log_every: usize,
    ) -> Result<Self> {
        Self::with_output(Box::new(stream), scene, columns, dt, log_every)
    }

    fn with_output(
        out: Box<dyn Publish>,
        scene: RecordingScene,
        columns: &[String],
        dt: f64,
        log_every: usize,
    ) -> Result<Self> {
        let c = |n: &str| crate::output::column(columns, n);
        let at = Columns {
            t: c("t")?,
            com: [c("com_x")?, c("com_y")?, c("com_z")?],
            com_ref: [c("com_ref_x")?, c("com_ref_y")?, c("com_ref_z")?],
            zmp: [c("zmp_x")?, c("zmp_y")?],
            zmp_ref: [c("zmp_ref_x")?, c("zmp_ref_y")?],
            foot_fz: vec![c("left_foot_fz")?, c("right_foot_fz")?],
        };
        let feet = scene.feet.len();
        let mut recording = Self {
            out,
            scene,
            columns: columns.to_vec(),
            at,
            row: vec![0.0; columns.len()],
            every_view: ((VIEW_PERIOD / dt).round() as usize).max(1),
            every_log: log_every.max(1),
            touching: vec![false; feet],
            footprints: 0,
        };
        recording.write_robot()?;
        Ok(recording)
    }

    fn write(&mut self, topic: Topic, t: f64, message: &Value) -> Result<()> {
        self.out.publish(topic, t, serde_json::to_vec(message)?)
    }

    /// The robot's shapes, each locked to its joint's frame, once for the whole run.
    fn write_robot(&mut self) -> Result<()> {
        let dirs = meshes::search_path();
        let model = self.scene.model.clone();
        let mut entities = Vec::new();
        let mut drawn_from_meshes = std::collections::HashSet::new();
        for (k, v) in model.visuals.iter().enumerate() {
            let (Some(joint), Shape::Mesh { filename, scale }) = (v.parent_joint, &v.shape) else {
                continue;
            };
            let Some(path) = meshes::resolve(filename, &dirs) else {
                continue;
            };
            let Some(media) = meshes::media_type(&path) else {
                continue;
            };
            let bytes = std::fs::read(&path)
                .with_context(|| format!("reading the mesh {}", path.display()))?;
            drawn_from_meshes.insert(v.link.clone());
            let mut entity = entity(0.0, &joint_frame(&model, joint), &format!("visual/{k}"));
            entity["models"] = json!([{
                    "pose": pose(&v.placement), "scale": vec3(scale),
                    "color": color(0.75, 0.75, 0.78, 1.0), "override_color": false,
                    "url": "", "media_type": media,
                    "data": base64::engine::general_purpose::STANDARD.encode(bytes),
            }]);
            entities.push(entity);
        }
        // Links without a mesh found: their collision primitives.
        for (k, c) in model.collisions.iter().enumerate() {
            let Some(joint) = c.parent_joint else {
                continue;
            };
            if drawn_from_meshes.contains(&c.link) {
                continue;
            }
            let grey = color(0.55, 0.6, 0.65, 1.0);
            let p = pose(&c.placement);
            let (key, primitive) = match &c.shape {
                Shape::Box { size } => (
                    "cubes",
                    json!({"pose": p, "size": vec3(size), "color": grey}),
                ),
                Shape::Sphere { radius } => (
                    "spheres",
                    json!({"pose": p, "size": vec3(&Vector3::repeat(2.0 * radius)), "color": grey}),
                ),
                Shape::Cylinder { radius, length } => (
                    "cylinders",
                    json!({"pose": p, "size": vec3(&Vector3::new(2.0 * radius, 2.0 * radius, *length)),
                           "bottom_scale": 1.0, "top_scale": 1.0, "color": grey}),
                ),
                Shape::Mesh { .. } => continue,
            };
            let mut entity = entity(0.0, &joint_frame(&model, joint), &format!("collision/{k}"));
            entity[key] = json!([primitive]);
            entities.push(entity);
        }
        self.write(
            Topic::Robot,
            0.0,
            &json!({"deletions": [], "entities": entities}),
        )
    }

    /// The joint frames (world → joint) at the true state.
    fn write_transforms(&mut self, t: f64, truth: &Truth) -> Result<()> {
        let model = self.scene.model.clone();
        let transforms: Vec<Value> = (truth.joint_placements.iter().enumerate())
            .map(|(i, m)| {
                let p = pose(m);
                json!({
                    "timestamp": stamp(t), "parent_frame_id": "world",
                    "child_frame_id": joint_frame(&model, i),
                    "translation": p["position"], "rotation": p["orientation"],
                })
            })
            .collect();
        self.write(Topic::Tf, t, &json!({"transforms": transforms}))
    }

    /// CoM, ZMP, support polygon, contact forces and footprints, in the world frame.
    fn write_markers(&mut self, t: f64, truth: &Truth) -> Result<()> {
        let r = &self.row;
        let point =
            |ix: &[usize]| Vector3::new(r[ix[0]], r[ix[1]], ix.get(2).map_or(0.0, |&k| r[k]));
        let sphere = |at: Vector3<f64>, size: f64, c: Value| json!({"pose": pose(&Se3::new(Matrix3::identity(), at)), "size": vec3(&Vector3::repeat(size)), "color": c});
        let spheres = vec![
            sphere(point(&self.at.com), 0.05, color(0.9, 0.2, 0.2, 1.0)),
            sphere(point(&self.at.com_ref), 0.035, color(0.2, 0.8, 0.3, 0.8)),
            sphere(point(&self.at.zmp), 0.03, color(0.2, 0.4, 0.95, 1.0)),
            sphere(point(&self.at.zmp_ref), 0.02, color(0.3, 0.8, 0.9, 0.8)),
        ];
        // The CoM's ground projection, to read it against the support polygon.
        let com = point(&self.at.com);
        let mut lines = vec![line(
            &[com, Vector3::new(com.x, com.y, 0.0)],
            0.005,
            color(0.9, 0.2, 0.2, 0.6),
            0,
        )];
        let model = self.scene.model.clone();
        let mut support = Vec::new();
        let mut prints = Vec::new();
        for (k, (frame, corners)) in self.scene.feet.iter().enumerate() {
            let placement = truth.frame_placement(&model, *frame);
            let world: Vec<Vector3<f64>> = corners.iter().map(|c| placement.act_point(c)).collect();
            // Corners in the order front-left, front-right, back-right, back-left.
            let outline = [world[0], world[1], world[3], world[2]];
            let touching = self
                .at
                .foot_fz
                .get(k)
                .is_some_and(|&c| r[c] > SUPPORT_FORCE);
            if touching {
                support.extend_from_slice(&outline);
                lines.push(line(&outline, 0.008, color(1.0, 0.75, 0.1, 1.0), 1));
                if !self.touching[k] {
                    prints.push(line(&outline, 0.004, color(0.6, 0.6, 0.6, 0.8), 1));
                }
            }
            self.touching[k] = touching;
        }
        if let Some(hull) = convex_hull(&support) {
            lines.push(line(&hull, 0.006, color(1.0, 0.5, 0.0, 1.0), 1));
        }
        let arrows: Vec<Value> = body_forces(truth)
            .iter()
            .map(|(at, f)| arrow(at, f))
            .collect();
        let world = |id: &str, key: &str, items: Vec<Value>| {
            let mut e = entity(t, "world", id);
            e["frame_locked"] = Value::Bool(false);
            e[key] = Value::Array(items);
            e
        };
        let mut entities = vec![
            world("points", "spheres", spheres),
            world("lines", "lines", lines),
            world("forces", "arrows", arrows),
        ];
        // A footprint stays for the rest of the run: each written once, when its foot lands.
        for print in prints {
            let id = format!("footprint/{}", self.footprints);
            entities.push(world(&id, "lines", vec![print]));
            self.footprints += 1;
        }
        let message = json!({"deletions": [], "entities": entities});
        self.write(Topic::Markers, t, &message)
    }

    /// The operator's skeleton at `t`, if the run follows one.
    fn write_operator(&mut self, t: f64) -> Result<()> {
        let r = &self.row;
        let com = Vector3::new(r[self.at.com[0]], r[self.at.com[1]], r[self.at.com[2]]);
        let Some(view) = &mut self.scene.operator else {
            return Ok(());
        };
        let (bones, joints) = view.at(t, com);
        let mut e = entity(t, "world", "operator");
        e["frame_locked"] = Value::Bool(false);
        e["lines"] = json!([line(&bones, 0.02, color(0.95, 0.55, 0.1, 1.0), 2)]);
        e["spheres"] = Value::Array(
            (joints.iter())
                .map(|j| json!({"pose": pose(&Se3::new(Matrix3::identity(), *j)), "size": vec3(&Vector3::repeat(0.04)), "color": color(0.95, 0.75, 0.3, 1.0)}))
                .collect(),
        );
        self.write(
            Topic::Operator,
            t,
            &json!({"deletions": [], "entities": [e]}),
        )
    }

    /// Ends the output: the recording's summary written and the file renamed to `run.mcap`
    /// (returned), or the live stream's connections closed (None).
    pub fn finish(self) -> Result<Option<PathBuf>> {
        self.out.finish()
    }
}

impl RowSink for Recording {
    fn row(&mut self, index: usize, row: &[f64]) -> Result<(), ScenarioError> {
        self.row.copy_from_slice(row);
        if index.is_multiple_of(self.every_log) {
            let signals: serde_json::Map<String, Value> = (self.columns.iter())
                .zip(row)
                .map(|(c, v)| (c.clone(), json!(v)))
                .collect();
            let t = row[self.at.t];
            self.write(Topic::Signals, t, &Value::Object(signals))
                .map_err(|e| ScenarioError::Output(format!("{RECORDING_NAME}: {e:#}")))?;
        }
        Ok(())
    }

    fn state(&mut self, index: usize, truth: &Truth) -> Result<(), ScenarioError> {
        if !index.is_multiple_of(self.every_view) {
            return Ok(());
        }
        let t = self.row[self.at.t];
        self.write_transforms(t, truth)
            .and_then(|()| self.write_markers(t, truth))
            .and_then(|()| self.write_operator(t))
            .map_err(|e| ScenarioError::Output(format!("{RECORDING_NAME}: {e:#}")))
    }
}

/// Each body's contact force, summed, at its centre of pressure (the normal-force-weighted
/// mean of its contact points): one arrow a foot.
fn body_forces(truth: &Truth) -> Vec<(Vector3<f64>, Vector3<f64>)> {
    let mut bodies: Vec<(usize, Vector3<f64>, Vector3<f64>, f64)> = Vec::new();
    for c in &truth.contacts {
        let k = match bodies.iter().position(|b| b.0 == c.joint) {
            Some(k) => k,
            None => {
                bodies.push((c.joint, Vector3::zeros(), Vector3::zeros(), 0.0));
                bodies.len() - 1
            }
        };
        let weight = c.force.z.max(0.0);
        bodies[k].1 += c.force;
        bodies[k].2 += c.position * weight;
        bodies[k].3 += weight;
    }
    (bodies.into_iter())
        .filter(|b| b.3 > 1e-6)
        .map(|(_, f, moment, fz)| (moment / fz, f))
        .collect()
}

/// A `foxglove.SceneUpdate` entity with no shapes yet: `id` in frame `frame` at time `t`,
/// kept until replaced (lifetime 0) and locked to its frame.
fn entity(t: f64, frame: &str, id: &str) -> Value {
    json!({"timestamp": stamp(t), "frame_id": frame, "id": id, "lifetime": stamp(0.0),
           "frame_locked": true, "metadata": []})
}

/// The frame name of joint `i` in the recording.
fn joint_frame(model: &Model, i: usize) -> String {
    format!("joint/{}", model.joints[i].name)
}

fn stamp(t: f64) -> Value {
    let ns = (t.max(0.0) * 1e9).round() as u64;
    json!({"sec": ns / 1_000_000_000, "nsec": ns % 1_000_000_000})
}

fn vec3(v: &Vector3<f64>) -> Value {
    json!({"x": v.x, "y": v.y, "z": v.z})
}

fn color(r: f64, g: f64, b: f64, a: f64) -> Value {
    json!({"r": r, "g": g, "b": b, "a": a})
}

fn pose(m: &Se3) -> Value {
    let q = UnitQuaternion::from_matrix(&m.rotation);
    json!({"position": vec3(&m.translation),
           "orientation": {"x": q.i, "y": q.j, "z": q.k, "w": q.w}})
}

/// A polyline (`kind` 0: strip, 1: closed loop, 2: separate segments, two points each).
fn line(points: &[Vector3<f64>], thickness: f64, c: Value, kind: u8) -> Value {
    json!({"type": kind, "pose": pose(&Se3::identity()), "thickness": thickness,
           "scale_invariant": false, "points": points.iter().map(vec3).collect::<Vec<_>>(),
           "color": c, "colors": [], "indices": []})
}

/// A force `f` (N) at `at`, drawn `ARROW_SCALE` m per newton along it.
fn arrow(at: &Vector3<f64>, f: &Vector3<f64>) -> Value {
    let length = f.norm() * ARROW_SCALE;
    let rotation = UnitQuaternion::rotation_between(&Vector3::x(), f).unwrap_or_else(|| {
        UnitQuaternion::from_axis_angle(&Vector3::y_axis(), std::f64::consts::PI)
    });
    let m = Se3::new(rotation.to_rotation_matrix().into_inner(), *at);
    json!({"pose": pose(&m), "shaft_length": 0.8 * length, "shaft_diameter": 0.006,
           "head_length": 0.2 * length, "head_diameter": 0.015, "color": color(0.1, 0.7, 0.2, 1.0)})
}

/// The convex hull of `points` on the ground (z = 0), counter-clockwise; None below three.
fn convex_hull(points: &[Vector3<f64>]) -> Option<Vec<Vector3<f64>>> {
    let mut p: Vec<(f64, f64)> = points.iter().map(|v| (v.x, v.y)).collect();
    if p.len() < 3 {
        return None;
    }
    p.sort_by(|a, b| a.partial_cmp(b).unwrap_or(std::cmp::Ordering::Equal));
    let cross = |o: (f64, f64), a: (f64, f64), b: (f64, f64)| {
        (a.0 - o.0) * (b.1 - o.1) - (a.1 - o.1) * (b.0 - o.0)
    };
    let mut hull: Vec<(f64, f64)> = Vec::new();
    for pass in 0..2 {
        let start = hull.len();
        let points: Box<dyn Iterator<Item = &(f64, f64)>> = if pass == 0 {
            Box::new(p.iter())
        } else {
            Box::new(p.iter().rev())
        };
        for &q in points {
            while hull.len() >= start + 2
                && cross(hull[hull.len() - 2], hull[hull.len() - 1], q) <= 0.0
            {
                hull.pop();
            }
            hull.push(q);
        }
        hull.pop();
    }
    Some(
        hull.into_iter()
            .map(|(x, y)| Vector3::new(x, y, 0.0))
            .collect(),
    )
}
