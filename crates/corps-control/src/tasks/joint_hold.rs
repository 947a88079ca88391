//! Holding a few one-dof joints where they are: `q̈_j = −K_p (q_j − q*_j) − K_d q̇_j` for each
//! listed joint (the stiff position servo of joints a controller does not use, as iCub's
//! neck and wrists in seed 001, where 23 of 32 joints are torque-controlled, §3.1). As a
//! priority-0 task it is an equality: the controller leaves those joints to their servo.

use super::TaskRows;
use crate::error::{ControlError, Result};
use crate::robot_state::RobotState;
use corps_model::Model;

#[derive(Clone, Debug)]
pub struct JointHoldTask {
    /// (configuration index, velocity index, held position) per joint.
    joints: Vec<(usize, usize, f64)>,
    pub kp: f64,
    pub kd: f64,
    rows: TaskRows,
}

impl JointHoldTask {
    /// Holds the joints `names` of `model` at their positions in configuration `q` with gains
    /// `kp`, `kd`; an error for an unknown joint or one with more than one dof.
    pub fn new(model: &Model, names: &[String], q: &[f64], kp: f64, kd: f64) -> Result<Self> {
        let mut joints = Vec::with_capacity(names.len());
        for name in names {
            let j = &model.joints[model.joint_id(name)?];
            if j.nq() != 1 || j.nv() != 1 {
                return Err(ControlError::Config {
                    name: format!("held joint '{name}'"),
                    reason: "only one-dof joints can be held".into(),
                });
            }
            joints.push((j.idx_q, j.idx_v, q[j.idx_q]));
        }
        let mut rows = TaskRows::new(joints.len(), model.nv);
        for (k, &(_, iv, _)) in joints.iter().enumerate() {
            rows.a[(k, iv)] = 1.0;
        }
        Ok(Self {
            joints,
            kp,
            kd,
            rows,
        })
    }

    pub fn compute(&mut self, s: &RobotState) -> &TaskRows {
        for (k, &(iq, iv, held)) in self.joints.iter().enumerate() {
            self.rows.b[k] = -self.kp * (s.q[iq] - held) - self.kd * s.v[iv];
        }
        &self.rows
    }
}

impl super::Task for JointHoldTask {
    fn level(&self) -> super::TaskLevel {
        super::TaskLevel::Acceleration
    }
    fn dim(&self) -> usize {
        self.rows.rows()
    }
    fn compute(&mut self, _model: &Model, s: &RobotState) -> Result<&TaskRows> {
        Ok(JointHoldTask::compute(self, s))
    }
    fn last_rows(&self) -> Option<&TaskRows> {
        Some(&self.rows)
    }
}
