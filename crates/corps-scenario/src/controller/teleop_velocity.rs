//! Whole-body teleoperation at velocity level (seed 001 §6.1.3–6.1.4): the operator's
//! retargeted joints, waist height and steps ([`corps_mocap`]) drive a two-layer hierarchical
//! QP on ν — layer 1 both feet in SE(3); layer 2, weighted (Table 6.1), the CoM's ground
//! projection at mid-feet (w_CoM), the waist's height and orientation (w_CoM), the neck's
//! orientation (w_neck), the upper-body posture (w_sup) and the least ν (w_ν) — with the
//! position limits scaled by µ (Eq 6.15) and the velocity limits (Eq 6.16) as bounds, the lower
//! layer solved in the higher's null space by corps' hierarchical QP. ν integrates to the
//! joint servos' position references (the IK's own state, as in position mode).
//!
//! The operator's steps, detected and normalised by [`StepDetector`], are walked by the state
//! machine of Fig 6.6 ([`super::teleop_walk`]): the swing foot's and the CoM's references move,
//! the waist holds its standing height while walking. The scenario's `[footsteps]` are queued
//! first; without an operator the robot walks them with its upper body at rest (Fig 6.6's
//! autonomous walking). A feed that stops holds its last references (the robot finishes the
//! steps it was given and rests in double support).

use super::teleop_walk::{PlannedStep, TeleopWalk, WalkReferences, WalkingSpec};
use super::WholeBodyController;
use crate::error::{invalid, Result};
use crate::mocap::Operator;
use crate::targets::Targets;
use corps_control::formulation::InverseKinematics;
use corps_control::tasks::velocity::{ComVelocityTask, FrameVelocityTask, PostureVelocityTask};
use corps_control::tasks::{Reference, Se3Reference};
use corps_control::{ControlError, FallbackReason, RobotState};
use corps_mocap::retarget::{MappedJoint, Retargeter};
use corps_mocap::skeleton::Skeleton;
use corps_mocap::source::Feed;
use corps_mocap::steps::StepDetector;
use corps_model::spatial::Motion;
use corps_model::Model;
use corps_robot::Robot;
use corps_sim::Command;
use nalgebra::{DVector, Matrix3, Rotation3, Vector2, Vector3, Vector6};
use serde::Deserialize;
use std::sync::Arc;

/// The controller's gains file.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct TeleopVelocityConfig {
    /// µ of Eq 6.15: the share of the distance to a joint limit one tick may close.
    pub limit_scaling: f64,
    /// The position bounds kept this far inside the URDF limits (rad): the servos' own error.
    pub limit_margin: f64,
    pub weights: TeleopWeights,
    pub gains: TeleopGains,
    /// The walking state machine's thresholds and timings (Table 6.2).
    pub walking: WalkingSpec,
}

/// Table 6.1's weights of the second layer.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct TeleopWeights {
    /// w_CoM: the CoM's ground projection, the waist's height and orientation.
    pub com: f64,
    pub neck: f64,
    /// w_sup: the upper-body posture.
    pub posture: f64,
    /// w_ν: the least velocity.
    pub velocity: f64,
}

/// Task gains K of Eq 6.11 and 6.14 (1/s).
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct TeleopGains {
    pub feet: f64,
    pub com: f64,
    pub waist: f64,
    pub neck: f64,
    pub posture: f64,
    /// g_d (s) of the sway damping `−g_d (ċ − ċ*)` added to the CoM reference on the measured
    /// CoM velocity (the stabilizer's, `corps_control::stabilizer` module docs).
    pub sway_damping: f64,
}

impl TeleopVelocityConfig {
    fn check(&self) -> Result<()> {
        if !(self.limit_scaling > 0.0 && self.limit_scaling <= 1.0) {
            return Err(invalid!("limit_scaling: µ must be in (0, 1]"));
        }
        if !(self.limit_margin.is_finite() && self.limit_margin >= 0.0) {
            return Err(invalid!("limit_margin: must be ≥ 0 rad"));
        }
        let w = &self.weights;
        let g = &self.gains;
        for (name, v) in [
            ("weights.com", w.com),
            ("weights.neck", w.neck),
            ("weights.posture", w.posture),
            ("weights.velocity", w.velocity),
            ("gains.feet", g.feet),
            ("gains.com", g.com),
            ("gains.waist", g.waist),
            ("gains.neck", g.neck),
            ("gains.posture", g.posture),
            ("gains.sway_damping", g.sway_damping),
        ] {
            if !(v.is_finite() && v >= 0.0) {
                return Err(invalid!("{name}: must be a finite number ≥ 0"));
            }
        }
        self.walking.check().map_err(|e| invalid!("{e}"))
    }
}

/// Tracking of the retargeted upper body and the operator's steps, for the metrics.
#[derive(Clone, Debug, Default)]
struct Stats {
    square_sum: Vec<f64>,
    max: Vec<f64>,
    samples: usize,
    limit_violations: usize,
    lost_ticks: usize,
    /// The robot's steps as its feet's F/T sensors see them: a foot unloaded below the walk's
    /// `f_contact`, then loaded past Table 6.2's F_touchdown (`f_touchdown`) at least
    /// [`STEP_TRAVEL`] from where it lifted.
    robot_steps: usize,
    lifted_at: [Option<Vector3<f64>>; 2],
}

/// A foot that lands this far (m) from where it lifted has stepped.
pub const STEP_TRAVEL: f64 = 0.01;

pub struct TeleopVelocityController {
    model: Arc<Model>,
    ik: InverseKinematics,
    state: RobotState,
    q_des: DVector<f64>,
    v_des: DVector<f64>,
    command: Command,
    /// The operator followed, if any (else the robot walks its scripted steps, the upper body
    /// held at its rest posture: Fig 6.6's autonomous walking).
    following: Option<Following>,
    joints: Vec<MappedJoint>,
    operator_angles: Vec<f64>,
    robot_angles: Vec<f64>,
    /// Eq 6.14's ṡ_d: the retargeted joints' velocity between the last two operator poses
    /// (na, zero on the joints not retargeted), and the time of the last pose.
    v_ref: DVector<f64>,
    previous: Vec<f64>,
    pose_time: Option<f64>,
    /// Each mapped joint's index among the actuated joints.
    actuated: Vec<usize>,
    /// The posture reference (nq): the rest posture with the retargeted joints.
    q_ref: DVector<f64>,
    /// Sole height (world) the waist height is measured from.
    sole_z: f64,
    waist_z: f64,
    /// The neck frame and a scratch model state for its reference orientation (the posture
    /// reference's, updated with each new operator pose).
    neck: Option<(usize, corps_model::Data)>,
    neck_rotation: Matrix3<f64>,
    stats: Stats,
    fed: bool,
    walk: TeleopWalk,
    /// The waist's height (world z) held while walking: the operator's when the walk began.
    waist_stand: f64,
    /// The robot's forward and left directions (world, horizontal) at the start: the operator's
    /// and the scenario's steps are given in them (the walk turns them with the robot's
    /// heading when a step begins).
    heading: [Vector2<f64>; 2],
    walk_references: WalkReferences,
    /// The soles' orientations at the start, which their turns rotate about the vertical.
    soles_rotation0: [Matrix3<f64>; 2],
    /// Whether a step turns (the soles' and the waist's orientation references then follow
    /// the turns: the waist the mean of the soles').
    turning: bool,
    waist_rotation0: Matrix3<f64>,
    sway_damping: f64,
}

/// An operator, their retargeting and their steps.
struct Following {
    operator: Operator,
    retargeter: Retargeter,
    steps: StepDetector,
}

const FEET: [&str; 2] = ["foot_left", "foot_right"];

/// A horizontal travel given in the robot's directions at the start (`heading`: forward, left),
/// in the world (as the robot stood at the start).
fn in_world(heading: [Vector2<f64>; 2], travel: Vector2<f64>) -> Vector2<f64> {
    heading[0] * travel.x + heading[1] * travel.y
}

/// `rotation` turned by `yaw` about the world's vertical.
fn turned(yaw: f64, rotation: &Matrix3<f64>) -> Matrix3<f64> {
    Rotation3::from_axis_angle(&Vector3::z_axis(), yaw).matrix() * rotation
}

impl TeleopVelocityController {
    /// The stack for `robot` standing at `q`, following `operator` if given, and walking
    /// `footsteps` (each in the robot's own directions when it begins: x forward, y left).
    /// Turning footsteps are for walking without an operator (the neck's reference, the
    /// operator's, does not turn): with one, they are an error.
    pub fn new(
        robot: &Robot,
        config: TeleopVelocityConfig,
        dt: f64,
        q: &DVector<f64>,
        operator: Option<Operator>,
        footsteps: &[PlannedStep],
    ) -> Result<Self> {
        config.check()?;
        let model = robot.model.clone();
        let following = match operator {
            Some(operator) => Some(Self::follow_operator(robot, operator)?),
            None => None,
        };

        let mut state = RobotState::new(&model);
        let v0 = DVector::zeros(model.nv);
        state.update(&model, q.as_slice(), v0.as_slice())?;
        let mut ik = InverseKinematics::new(&model, dt)?;
        ik.limit_scaling = config.limit_scaling;
        ik.set_limit_margin(&model, config.limit_margin);
        let reference = |frame: usize| -> Result<Se3Reference> {
            Ok(Se3Reference {
                placement: state.frame_placement(&model, frame)?,
                velocity: Motion::zero(),
                acceleration: Motion::zero(),
            })
        };
        let [left, right] = super::two_feet(robot)?;
        for (name, f) in FEET.iter().zip([left, right]) {
            let task = FrameVelocityTask::new(
                &model,
                f.frame,
                Vector6::repeat(config.gains.feet),
                [true; 6],
                reference(f.frame)?,
            )?;
            ik.add_task(name, 0, 1.0, task)?;
        }
        let w = &config.weights;
        let g = &config.gains;
        let feet0 = [reference(left.frame)?, reference(right.frame)?];
        let mid = (feet0[0].placement.translation + feet0[1].placement.translation) / 2.0;
        let com = DVector::from_column_slice(&[mid.x, mid.y, state.data.com.z]);
        let com_xy = ComVelocityTask::new(
            model.nv,
            Vector3::repeat(g.com),
            [true, true, false],
            Reference::constant(com),
        )?;
        ik.add_task("com_xy", 1, w.com, com_xy)?;
        let waist = FrameVelocityTask::new(
            &model,
            robot.base,
            Vector6::repeat(g.waist),
            [false, false, true, true, true, true],
            reference(robot.base)?,
        )?;
        ik.add_task("waist", 1, w.com, waist)?;
        let neck_frame = following
            .as_ref()
            .and_then(|f| f.operator.mapping.spec.neck_frame.clone());
        let (neck, neck_rotation) = match &neck_frame {
            Some(name) => {
                let id = model.frame_id(name).map_err(|_| {
                    invalid!(
                        "mocap.mapping: neck_frame: {} has no frame '{name}'",
                        robot.name
                    )
                })?;
                let task = FrameVelocityTask::new(
                    &model,
                    id,
                    Vector6::repeat(g.neck),
                    [false, false, false, true, true, true],
                    reference(id)?,
                )?;
                ik.add_task("neck", 1, w.neck, task)?;
                let rotation = reference(id)?.placement.rotation;
                (Some((id, corps_model::Data::new(&model))), rotation)
            }
            None => (None, Matrix3::identity()),
        };
        let na = model.na();
        let mut kp = DVector::zeros(na);
        let first = model.first_actuated();
        let mut actuated = Vec::new();
        let joints = following
            .as_ref()
            .map(|f| f.retargeter.joints.clone())
            .unwrap_or_default();
        for j in &joints {
            let iv = model.joints[model.joint_id(&j.name)?].idx_v;
            kp[iv - first] = g.posture;
            actuated.push(iv - first);
        }
        if following.is_none() {
            // No operator: the upper body (every joint off the legs) holds its rest posture.
            let legs: Vec<usize> = [left.frame, right.frame]
                .iter()
                .flat_map(|&f| super::soft_tasks::stance_ik::chain_to(&model, f))
                .collect();
            for (j, joint) in model.joints.iter().enumerate() {
                if joint.nv() == 1 && joint.idx_v >= first && !legs.contains(&j) {
                    kp[joint.idx_v - first] = g.posture;
                }
            }
        }
        let posture = PostureVelocityTask::new(&model, kp, robot.posture.clone())?;
        ik.add_task("posture", 1, w.posture, posture)?;
        let least = PostureVelocityTask::new(&model, DVector::zeros(na), robot.posture.clone())?;
        ik.add_task("least_velocity", 1, w.velocity, least)?;

        let sole_z = feet0[0]
            .placement
            .translation
            .z
            .min(feet0[1].placement.translation.z);
        let waist0 = state.frame_placement(&model, robot.base)?;
        let waist_z = waist0.translation.z;
        let n = joints.len();
        let soles_rotation0 = [feet0[0].placement.rotation, feet0[1].placement.rotation];
        let soles = feet0.map(|f| f.placement.translation);
        let lateral = (soles[0] - soles[1]).xy();
        let lateral = lateral.try_normalize(1e-9).unwrap_or_else(Vector2::y);
        let heading = [Vector2::new(lateral.y, -lateral.x), lateral];
        let mut walk = TeleopWalk::new(
            config.walking.clone(),
            soles,
            Vector3::new(mid.x, mid.y, 0.0),
        );
        for step in footsteps {
            walk.push(PlannedStep {
                travel: in_world(heading, step.travel),
                ..*step
            });
        }
        let walk_references = walk.references(0.0);
        let turning = footsteps.iter().any(|s| s.turn != 0.0);
        if turning && following.is_some() {
            return Err(invalid!(
                "footsteps: turning steps (turn ≠ 0) walk without an operator; remove [mocap] or the turns"
            ));
        }
        // The free-flyer's configuration (none for a fixed base).
        let base_len = if model.has_free_flyer() { 7 } else { 0 };
        let mut q_ref = robot.posture.clone();
        // The base of the posture reference is where the robot stands (the neck's reference).
        q_ref.rows_mut(0, base_len).copy_from(&q.rows(0, base_len));
        Ok(Self {
            ik,
            state,
            q_des: q.clone(),
            v_des: v0,
            command: Command::Position {
                q_ref: q.clone(),
                v_ref: DVector::zeros(na),
            },
            following,
            joints,
            operator_angles: vec![0.0; n],
            robot_angles: vec![0.0; n],
            v_ref: DVector::zeros(na),
            previous: vec![0.0; n],
            pose_time: None,
            actuated,
            q_ref,
            sole_z,
            waist_z,
            neck_rotation,
            neck,
            stats: Stats {
                square_sum: vec![0.0; n],
                max: vec![0.0; n],
                ..Default::default()
            },
            fed: false,
            walk,
            waist_stand: waist_z,
            heading,
            walk_references,
            soles_rotation0,
            turning,
            waist_rotation0: waist0.rotation,
            sway_damping: config.gains.sway_damping,
            model,
        })
    }

    /// `operator` retargeted onto `robot` (the mapping's robot must be the same model).
    fn follow_operator(robot: &Robot, operator: Operator) -> Result<Following> {
        let model = &robot.model;
        let mapped = operator
            .mapping
            .robot()
            .map_err(|e| invalid!("mocap.mapping: {e}"))?;
        if mapped.model.nq != model.nq
            || (mapped.model.joints.iter().zip(&model.joints)).any(|(a, b)| a.name != b.name)
        {
            return Err(invalid!(
                "mocap.mapping: maps onto robot '{}', the scenario runs '{}' (another model)",
                mapped.name,
                robot.name
            ));
        }
        let skeleton = Skeleton::new(&operator.clip, operator.mapping.units());
        let rest = (operator.mapping)
            .rest_pose(&skeleton, &operator.clip)
            .map_err(|e| invalid!("mocap.mapping: {e}"))?;
        let retargeter = Retargeter::new(&operator.mapping, robot, &skeleton, &rest)
            .map_err(|e| invalid!("mocap: {e}"))?;
        let steps = StepDetector::new(&operator.mapping.spec.steps, retargeter.feet(&rest));
        Ok(Following {
            operator,
            retargeter,
            steps,
        })
    }

    /// Reads the operator, if any: the upper body's, waist's and neck's references and the
    /// operator's steps.
    fn read_operator(&mut self, t: f64) -> Result<(), ControlError> {
        let Some(f) = &mut self.following else {
            return Ok(());
        };
        let (pose, feed) = f.operator.source.poll(t);
        match feed {
            // The pose of the last tick (the operator's rate is below the control's): the
            // references stand; a held pose stops the feed-forward.
            Feed::Live | Feed::Holding { .. } if self.pose_time == Some(pose.time) => {
                if feed != Feed::Live {
                    self.v_ref.fill(0.0);
                }
            }
            Feed::Live | Feed::Holding { .. } => {
                self.previous.copy_from_slice(&self.robot_angles);
                f.retargeter
                    .joints_into(pose, &mut self.operator_angles, &mut self.robot_angles);
                match self.pose_time {
                    Some(before) if pose.time > before && feed == Feed::Live => {
                        // Frames closer than a control period (a jittery stream) count as one period apart.
                        let dt = (pose.time - before).max(self.ik.dt);
                        for (i, &a) in self.actuated.iter().enumerate() {
                            self.v_ref[a] = (self.robot_angles[i] - self.previous[i]) / dt;
                        }
                    }
                    Some(_) => self.v_ref.fill(0.0),
                    None => {}
                }
                self.pose_time = Some(pose.time);
                for (j, v) in self.joints.iter().zip(&self.robot_angles) {
                    self.q_ref[j.q_index] = *v;
                }
                self.waist_z = self.sole_z + f.retargeter.waist_height(pose);
                for step in f.steps.update(pose.time, f.retargeter.feet(pose)) {
                    let Some(step) = step else { continue };
                    self.walk.push(PlannedStep {
                        foot: step.foot,
                        travel: in_world(self.heading, step.robot_travel.xy()),
                        height: step.robot_height,
                        turn: 0.0,
                    });
                }
                if let Some((frame, data)) = &mut self.neck {
                    let model = &self.model;
                    corps_model::forward_kinematics_placements(model, data, self.q_ref.as_slice())?;
                    corps_model::update_frame_placements(model, data);
                    self.neck_rotation = data.o_m_f[*frame].rotation;
                }
                self.fed = true;
            }
            Feed::Lost | Feed::Waiting => {
                self.stats.lost_ticks += 1;
                self.v_ref.fill(0.0);
            }
        }
        Ok(())
    }

    /// Reads the operator and the walk, and sets the tasks' references.
    fn follow(&mut self, t: f64, measured: &super::Measured) -> Result<(), ControlError> {
        self.read_operator(t)?;
        let posture = self.ik.task_mut::<PostureVelocityTask>("posture")?;
        posture.q_ref.copy_from(&self.q_ref);
        posture.v_ref.copy_from(&self.v_ref);
        let forces = measured.foot_wrenches.map(|w| w.force.z);
        let walk = self.walk.update(t, &measured.com, &measured.feet, forces);
        self.walk_references = walk;
        for (k, name) in FEET.iter().enumerate() {
            let foot = &mut self.ik.task_mut::<FrameVelocityTask>(name)?.reference;
            foot.placement.translation = walk.feet[k];
            foot.velocity.linear = walk.feet_velocity[k];
            if self.turning {
                foot.placement.rotation = turned(walk.feet_yaw[k], &self.soles_rotation0[k]);
                foot.velocity.angular = Vector3::z() * walk.feet_yaw_rate[k];
            }
        }
        // The sway damping of corps_control::stabilizer (its module docs): the CoM reference
        // moved by −g_d (ċ − ċ*), the damping the servo-held robot's sway lacks.
        let sway = (measured.com_velocity - walk.com_velocity) * self.sway_damping;
        let com_ref = walk.com - sway;
        let com_vel = walk.com_velocity;
        let com = &mut self.ik.task_mut::<ComVelocityTask>("com_xy")?.reference;
        for k in 0..2 {
            com.pos[k] = com_ref[k];
            com.vel[k] = com_vel[k];
        }
        if !self.walk.state.walking() {
            self.waist_stand = self.waist_z;
        }
        let waist_z = self.waist_stand + walk.waist_offset;
        let waist = &mut self.ik.task_mut::<FrameVelocityTask>("waist")?.reference;
        waist.placement.translation.z = waist_z;
        if self.turning {
            let heading = (walk.feet_yaw[0] + walk.feet_yaw[1]) / 2.0;
            waist.placement.rotation = turned(heading, &self.waist_rotation0);
            waist.velocity.angular =
                Vector3::z() * ((walk.feet_yaw_rate[0] + walk.feet_yaw_rate[1]) / 2.0);
        }
        if self.neck.is_some() {
            self.ik
                .task_mut::<FrameVelocityTask>("neck")?
                .reference
                .placement
                .rotation = self.neck_rotation;
        }
        Ok(())
    }

    /// The measured upper body against the retargeted references, the joint limits, and the
    /// robot's steps.
    fn record(&mut self, q: &[f64], measured: &super::Measured) {
        let (unloaded, touchdown) = (self.walk.spec().f_contact, self.walk.spec().f_touchdown);
        for k in 0..2 {
            let fz = measured.foot_wrenches[k].force.z;
            let at = measured.feet[k].translation.vector;
            match self.stats.lifted_at[k] {
                None if fz < unloaded => self.stats.lifted_at[k] = Some(at),
                Some(from) if fz > touchdown => {
                    if (at - from).xy().norm() >= STEP_TRAVEL {
                        self.stats.robot_steps += 1;
                    }
                    self.stats.lifted_at[k] = None;
                }
                _ => {}
            }
        }
        if self.fed {
            for (i, j) in self.joints.iter().enumerate() {
                let e = (q[j.q_index] - self.robot_angles[i]).abs().to_degrees();
                self.stats.square_sum[i] += e * e;
                self.stats.max[i] = self.stats.max[i].max(e);
            }
            self.stats.samples += 1;
        }
        let m = &self.model;
        let outside = (m.joints.iter()).any(|j| {
            matches!(j.kind, corps_model::JointKind::Revolute { .. })
                && (q[j.idx_q] < m.lower_position_limit[j.idx_q] - LIMIT_TOLERANCE
                    || q[j.idx_q] > m.upper_position_limit[j.idx_q] + LIMIT_TOLERANCE)
        });
        if outside {
            self.stats.limit_violations += 1;
        }
    }
}

/// The teleoperation controller's log columns: the walking state (0 double support, 1 walking
/// double support, 2 CoM to the stance sole, 3 liftoff, 4 touchdown, 5 landing), the operator's
/// steps not yet made, the steps the robot made, the walk's CoM reference, the IK's own CoM
/// and the walk's soles references.
pub const TELEOP_CHANNELS: [&str; 9] = [
    "walk_state",
    "steps_pending",
    "steps_walked",
    "walk_com_ref_x",
    "walk_com_ref_y",
    "ik_com_x",
    "ik_com_y",
    "left_sole_ref_z",
    "right_sole_ref_z",
];

/// A measured joint counts as past its limit beyond this (rad): the servo's own error.
pub const LIMIT_TOLERANCE: f64 = 1e-3;

impl WholeBodyController for TeleopVelocityController {
    fn tick(
        &mut self,
        t: f64,
        q: &[f64],
        _v: &[f64],
        _targets: &Targets,
        measured: &super::Measured,
    ) -> Option<FallbackReason> {
        let model = self.model.clone();
        self.record(q, measured);
        let references = self.follow(t, measured);
        super::ik::position_tick(
            &model,
            &mut self.ik,
            &mut self.state,
            &mut self.q_des,
            &mut self.v_des,
            &mut self.command,
            references,
        )
    }

    fn command(&self) -> &Command {
        &self.command
    }

    fn controller_com(&self) -> Vector3<f64> {
        self.state.data.com
    }

    fn channels(&self) -> Vec<&'static str> {
        TELEOP_CHANNELS.to_vec()
    }

    fn push_channels(&self, row: &mut Vec<f64>) {
        row.push(self.walk.state.code());
        row.push(self.walk.pending() as f64);
        row.push(self.walk.steps_done as f64);
        let r = &self.walk_references;
        let c = self.state.data.com;
        row.extend([r.com.x, r.com.y, c.x, c.y, r.feet[0].z, r.feet[1].z]);
    }

    fn teleop_metrics(&self) -> Option<crate::metrics::TeleopMetrics> {
        let s = &self.stats;
        let n = s.samples.max(1) as f64;
        let per_joint: Vec<crate::metrics::JointTracking> = (self.joints.iter().enumerate())
            .map(|(i, j)| crate::metrics::JointTracking {
                joint: j.name.clone(),
                rms_deg: (s.square_sum[i] / n).sqrt(),
                max_deg: s.max[i],
                clipped_frames: (self.following.as_ref()).map_or(0, |f| f.retargeter.clipped[i]),
            })
            .collect();
        let all: f64 = s.square_sum.iter().sum::<f64>() / (n * self.joints.len().max(1) as f64);
        Some(crate::metrics::TeleopMetrics {
            operator_steps: self.following.as_ref().map_or(0, |f| f.steps.count),
            robot_steps: s.robot_steps,
            upper_body_rms_deg: all.sqrt(),
            upper_body_max_deg: s.max.iter().copied().fold(0.0, f64::max),
            joint_limit_violations: s.limit_violations,
            feed_lost_ticks: s.lost_ticks,
            steps_walked: self.walk.steps_done,
            steps_dropped: self.walk.dropped,
            step_lengths: (self.walk.lengths.iter())
                .map(|&[planned_m, walked_m]| crate::metrics::StepLength {
                    planned_m,
                    walked_m,
                })
                .collect(),
            step_length_error_mm: {
                let l = &self.walk.lengths;
                if l.is_empty() {
                    0.0
                } else {
                    l.iter().map(|[p, w]| (w - p).abs()).sum::<f64>() / l.len() as f64 * 1e3
                }
            },
            turn_planned_deg: self.walk.planned_turn().to_degrees(),
            turn_walked_deg: self.walk.measured_turn.to_degrees(),
            upper_body: per_joint,
        })
    }
}
