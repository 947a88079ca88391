//! A whole clip retargeted offline: every frame's joints (operator and clipped), the robot's
//! waist height and the operator's steps normalised for the robot. What a teleoperation run
//! does tick by tick, run over a file to check the mapping and plot it.

use crate::bvh::Bvh;
use crate::error::Result;
use crate::retarget::{MappedJoint, Mapping, Retargeter};
use crate::skeleton::Skeleton;
use crate::source::{ClipSource, MocapSource};
use crate::steps::{Step, StepDetector};
use crate::MocapError;

/// A clip retargeted onto a robot.
#[derive(Clone, Debug)]
pub struct Retargeted {
    pub robot: String,
    pub joints: Vec<MappedJoint>,
    /// Frame times (s).
    pub time: Vec<f64>,
    /// Per frame, per mapped joint: `s_0R + Δs_H` before and after clipping (rad).
    pub operator: Vec<Vec<f64>>,
    pub clipped: Vec<Vec<f64>>,
    /// Per frame: the robot's waist height (m above its soles, Eq 6.3–6.5).
    pub waist: Vec<f64>,
    pub waist_rest_human: f64,
    pub waist_rest_robot: f64,
    /// The operator's steps, in order, each normalised for the robot.
    pub steps: Vec<Step>,
    /// Clippings per mapped joint (frames), and steps clipped to the robot's range.
    pub joint_clippings: Vec<usize>,
    pub step_clippings: usize,
}

/// Retargets every frame of `bvh` with `mapping` (its rest frame the operator's rest pose).
pub fn retarget_clip(mapping: &Mapping, bvh: &Bvh) -> Result<Retargeted> {
    let robot = mapping.robot()?;
    let spec = &mapping.spec;
    let rest_frame = spec.skeleton.rest_frame;
    if rest_frame >= bvh.frames() {
        return Err(MocapError::Mapping {
            file: mapping.file.clone(),
            message: format!(
                "skeleton.rest_frame {rest_frame}: the clip has {} frames",
                bvh.frames()
            ),
        });
    }
    let skeleton = Skeleton::new(bvh, mapping.units());
    let rest = skeleton.pose(bvh.frame(rest_frame), rest_frame as f64 * bvh.frame_time);
    let mut r = Retargeter::new(mapping, &robot, &skeleton, &rest)?;
    let feet = [
        skeleton.joint(&spec.skeleton.feet[0]).unwrap_or(0),
        skeleton.joint(&spec.skeleton.feet[1]).unwrap_or(0),
    ];
    let foot = |pose: &crate::skeleton::Pose, r: &Retargeter, k: usize| {
        r.in_body(&pose.world[feet[k]].translation.vector)
    };
    let mut detector = StepDetector::new(&spec.steps, [foot(&rest, &r, 0), foot(&rest, &r, 1)]);
    let mut source = ClipSource::new(bvh.clone(), mapping.units());
    let n = r.joints.len();
    let mut out = Retargeted {
        robot: robot.name.clone(),
        joints: r.joints.clone(),
        time: Vec::with_capacity(bvh.frames()),
        operator: Vec::with_capacity(bvh.frames()),
        clipped: Vec::with_capacity(bvh.frames()),
        waist: Vec::with_capacity(bvh.frames()),
        waist_rest_human: r.waist_rest_human,
        waist_rest_robot: r.waist_rest_robot,
        steps: Vec::new(),
        joint_clippings: Vec::new(),
        step_clippings: 0,
    };
    for k in 0..bvh.frames() {
        let t = k as f64 * bvh.frame_time;
        let (pose, _) = source.poll(t);
        let mut operator = vec![0.0; n];
        let mut clipped = vec![0.0; n];
        r.joints_into(pose, &mut operator, &mut clipped);
        out.waist.push(r.waist_height(pose));
        let feet_now = [foot(pose, &r, 0), foot(pose, &r, 1)];
        // Both feet may land on one frame: the second is read on a second call.
        for _ in 0..2 {
            match detector.update(t, feet_now) {
                Some(step) => out.steps.push(step),
                None => break,
            }
        }
        out.time.push(t);
        out.operator.push(operator);
        out.clipped.push(clipped);
    }
    out.joint_clippings = r.clipped.clone();
    out.step_clippings = detector.clipped;
    Ok(out)
}
