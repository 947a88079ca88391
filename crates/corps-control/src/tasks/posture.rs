//! Joint posture task: `S q̈ = −Kp∘(q ⊖ q_ref) − Kd∘(v − v_ref) + a_ref` over the actuated
//! joints (TSID `TaskJointPosture`; S selects the joint accelerations).

use super::{TaskErrorTerms, TaskRows};
use crate::error::{ControlError, Result};
use crate::robot_state::RobotState;
use corps_model::{difference_to, Model};
use nalgebra::DVector;

#[derive(Clone, Debug)]
pub struct PostureTask {
    pub kp: DVector<f64>,
    pub kd: DVector<f64>,
    /// Joint reference (na entries each): positions are a full configuration in `q_ref`.
    pub q_ref: DVector<f64>,
    pub v_ref: DVector<f64>,
    pub a_ref: DVector<f64>,
    first: usize,
    error: DVector<f64>,
    rows: TaskRows,
    terms: TaskErrorTerms,
}

impl PostureTask {
    /// A posture task on every dof after `first` (6 for a free-flyer), holding `q_ref`.
    pub fn new(model: &Model, kp: DVector<f64>, kd: DVector<f64>, q_ref: DVector<f64>) -> Self {
        let first = if model.has_free_flyer() { 6 } else { 0 };
        let na = model.nv - first;
        let mut rows = TaskRows::new(na, model.nv);
        for k in 0..na {
            rows.a[(k, first + k)] = 1.0;
        }
        rows.selection = Some(first);
        Self {
            kp,
            kd,
            q_ref,
            v_ref: DVector::zeros(na),
            a_ref: DVector::zeros(na),
            first,
            error: DVector::zeros(model.nv),
            rows,
            terms: TaskErrorTerms::new(na),
        }
    }

    /// The rows at state `s`; an error when `q_ref` is not a configuration of `model` or a
    /// gain or reference vector has not one entry per row.
    pub fn compute(&mut self, model: &Model, s: &RobotState) -> Result<&TaskRows> {
        let n = self.rows.rows();
        for (name, len) in [
            ("kp", self.kp.len()),
            ("kd", self.kd.len()),
            ("v_ref", self.v_ref.len()),
            ("a_ref", self.a_ref.len()),
        ] {
            if len != n {
                return Err(ControlError::Config {
                    name: "posture task".into(),
                    reason: format!("{name} has {len} entries for {n} joints"),
                });
            }
        }
        // e = q ⊖ q_ref (TSID: pinocchio::difference(q_ref, q)).
        difference_to(
            model,
            self.q_ref.as_slice(),
            s.q.as_slice(),
            self.error.as_mut_slice(),
        )?;
        for k in 0..self.rows.rows() {
            let j = self.first + k;
            self.rows.b[k] =
                -self.kp[k] * self.error[j] - self.kd[k] * (s.v[j] - self.v_ref[k]) + self.a_ref[k];
            self.terms.set(
                k,
                [
                    self.error[j],
                    s.v[j] - self.v_ref[k],
                    self.kp[k],
                    self.kd[k],
                    self.v_ref[k],
                    self.a_ref[k],
                ],
            );
        }
        Ok(&self.rows)
    }
}

impl super::Task for PostureTask {
    fn level(&self) -> super::TaskLevel {
        super::TaskLevel::Acceleration
    }
    fn dim(&self) -> usize {
        self.rows.rows()
    }
    fn compute(
        &mut self,
        model: &corps_model::Model,
        s: &crate::robot_state::RobotState,
    ) -> crate::error::Result<&super::TaskRows> {
        PostureTask::compute(self, model, s)
    }
    fn error_terms(&self) -> Option<&TaskErrorTerms> {
        Some(&self.terms)
    }
    fn last_rows(&self) -> Option<&TaskRows> {
        Some(&self.rows)
    }
}
