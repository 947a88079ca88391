//! A whole clip retargeted offline: every frame's joints (operator and clipped), the robot's
//! waist height and the operator's steps normalised for the robot. What a teleoperation run
//! does tick by tick, run over a file to check the mapping and plot it.

use crate::bvh::Bvh;
use crate::error::Result;
use crate::retarget::{MappedJoint, Mapping, Retargeter};
use crate::skeleton::Skeleton;
use crate::steps::{Step, StepDetector};

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
    let skeleton = Skeleton::new(bvh, mapping.units());
    let rest = mapping.rest_pose(&skeleton, bvh)?;
    let mut r = Retargeter::new(mapping, &robot, &skeleton, &rest)?;
    let mut detector = StepDetector::new(&spec.steps, r.feet(&rest));
    let mut pose = skeleton.empty_pose();
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
        skeleton.pose_into(bvh.frame(k), t, &mut pose);
        let mut operator = vec![0.0; n];
        let mut clipped = vec![0.0; n];
        r.joints_into(&pose, &mut operator, &mut clipped);
        out.waist.push(r.waist_height(&pose));
        out.steps
            .extend(detector.update(t, r.feet(&pose)).into_iter().flatten());
        out.time.push(t);
        out.operator.push(operator);
        out.clipped.push(clipped);
    }
    out.joint_clippings = r.clipped.clone();
    out.step_clippings = detector.clipped;
    Ok(out)
}
