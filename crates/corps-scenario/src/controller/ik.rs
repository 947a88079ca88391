//! Controller A: the hierarchical velocity IK of seed 000 §3.7 (Table 4.1's stack) in
//! position mode. The IK reads its own integrated state (q_des, v_des), not the measurement
//! (L4538–L4550); q_des and v_des go to the joint servos. Feet are priority-0 frame tasks
//! that follow the foot targets, in contact or not.

use super::WholeBodyController;
use crate::error::Result;
use crate::gains::IkGainsFile;
use crate::targets::Targets;
use corps_control::formulation::{IkGains, InverseKinematics, StackFrames};
use corps_control::tasks::velocity::{ComVelocityTask, FrameVelocityTask};
use corps_control::{ControlError, FallbackReason, RobotState};
use corps_model::Model;
use corps_robot::Robot;
use corps_sim::Command;
use nalgebra::{DVector, Vector3};
use std::sync::Arc;

/// Task names of the feet in `InverseKinematics::standing_stack`, left then right.
const FEET_TASKS: [&str; 2] = ["contact_left", "contact_right"];

pub struct IkController {
    model: Arc<Model>,
    ik: InverseKinematics,
    state: RobotState,
    q_des: DVector<f64>,
    v_des: DVector<f64>,
    command: Command,
    /// The waist's starting orientation (the waist task turns it by the target yaw).
    waist_rotation0: nalgebra::Matrix3<f64>,
}

impl IkController {
    /// The stack for `robot`'s two feet and waist at the measured state (q, v), posture
    /// towards `q_posture`.
    pub fn new(
        robot: &Robot,
        gains: IkGainsFile,
        dt: f64,
        q: &DVector<f64>,
        q_posture: &DVector<f64>,
    ) -> Result<Self> {
        gains.check()?;
        let model = robot.model.clone();
        let [left, right] = super::two_feet(robot)?;
        let waist = &model.frames[robot.base].name;
        let mut state = RobotState::new(&model);
        let v0 = DVector::zeros(model.nv);
        state.update(&model, q.as_slice(), v0.as_slice())?;
        let frames = StackFrames {
            left_foot: &left.frame_name,
            right_foot: &right.frame_name,
            waist,
        };
        let g = IkGains {
            contacts: gains.contacts,
            com_height: gains.com_height,
            com: gains.com,
            waist: gains.waist,
            posture: gains.posture,
        };
        let ik = InverseKinematics::standing_stack(&model, &state, dt, &frames, &g, q_posture)?;
        let waist_rotation0 = state.frame_placement(&model, robot.base)?.rotation;
        let na = model.na();
        Ok(Self {
            ik,
            state,
            q_des: q.clone(),
            v_des: v0,
            command: Command::Position {
                q_ref: q.clone(),
                v_ref: DVector::zeros(na),
            },
            waist_rotation0,
            model,
        })
    }

    fn set_references(&mut self, targets: &Targets) -> Result<(), ControlError> {
        for name in ["com_height", "com_xy"] {
            let task = self.ik.task_mut::<ComVelocityTask>(name)?;
            task.reference.clone_from(&targets.com);
        }
        let yaw = nalgebra::Rotation3::from_axis_angle(&Vector3::z_axis(), targets.waist_yaw);
        let waist = self.ik.task_mut::<FrameVelocityTask>("waist")?;
        waist.reference.placement.rotation = yaw.matrix() * self.waist_rotation0;
        for (name, foot) in FEET_TASKS.iter().zip(&targets.feet) {
            let task = self.ik.task_mut::<FrameVelocityTask>(name)?;
            task.reference.clone_from(&foot.reference);
        }
        Ok(())
    }
}

impl WholeBodyController for IkController {
    fn tick(
        &mut self,
        t: f64,
        _q: &[f64],
        _v: &[f64],
        targets: &Targets,
        _measured: &super::Measured,
    ) -> Option<FallbackReason> {
        let model = self.model.clone();
        self.ik.update_transitions(t);
        let references = self.set_references(targets);
        position_tick(
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
}

/// One tick of a velocity IK in position mode, once its references are set (`references`, or
/// why they could not be): the IK reads its own integrated state (q_des, v_des), solves, and
/// integrates; q_des and v_des go to the joint servos. A failure holds the last target at rest.
pub(super) fn position_tick(
    model: &Model,
    ik: &mut InverseKinematics,
    state: &mut RobotState,
    q_des: &mut DVector<f64>,
    v_des: &mut DVector<f64>,
    command: &mut Command,
    references: Result<(), ControlError>,
) -> Option<FallbackReason> {
    let solved = references
        .and_then(|_| {
            state
                .update(model, q_des.as_slice(), v_des.as_slice())
                .map_err(ControlError::from)
        })
        .and_then(|_| ik.compute(model, state, q_des.as_slice()));
    let reason = match solved {
        Ok(out) => {
            q_des.copy_from(&out.q_des);
            v_des.copy_from(&out.v);
            None
        }
        Err(e) => {
            v_des.fill(0.0);
            Some(FallbackReason::Controller(e))
        }
    };
    if let Command::Position { q_ref, v_ref } = command {
        q_ref.copy_from(q_des);
        v_ref.copy_from(&v_des.rows(model.first_actuated(), model.na()));
    }
    reason
}
