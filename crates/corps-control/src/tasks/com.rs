//! Centre-of-mass task: `Jcom q̈ = a_des − J̇com v`,
//! `a_des = −Kp∘(c − c_ref) − Kd∘(ċ − ċ_ref) + c̈_ref` (TSID `TaskComEquality`).

use super::{Reference, TaskErrorTerms, TaskRows};
use crate::robot_state::RobotState;
use nalgebra::{DVector, Vector3};

#[derive(Clone, Debug)]
pub struct ComTask {
    pub kp: Vector3<f64>,
    pub kd: Vector3<f64>,
    pub reference: Reference,
    rows: TaskRows,
    terms: TaskErrorTerms,
}

impl ComTask {
    pub fn new(nv: usize, kp: Vector3<f64>, kd: Vector3<f64>) -> Self {
        Self {
            kp,
            kd,
            reference: Reference::constant(DVector::zeros(3)),
            rows: TaskRows::new(3, nv),
            terms: TaskErrorTerms::new(3),
        }
    }

    /// Desired CoM acceleration at the state.
    pub fn desired_acceleration(&self, s: &RobotState) -> Vector3<f64> {
        let r = &self.reference;
        Vector3::from_fn(|k, _| {
            -self.kp[k] * (s.data.com[k] - r.pos[k]) - self.kd[k] * (s.com_velocity[k] - r.vel[k])
                + r.acc[k]
        })
    }

    pub fn compute(&mut self, s: &RobotState) -> &TaskRows {
        let a = self.desired_acceleration(s);
        self.rows.a.copy_from(&s.data.jcom);
        let r = &self.reference;
        for k in 0..3 {
            self.rows.b[k] = a[k] - s.com_drift[k];
            self.terms.set(
                k,
                [
                    s.data.com[k] - r.pos[k],
                    s.com_velocity[k] - r.vel[k],
                    self.kp[k],
                    self.kd[k],
                    r.vel[k],
                    r.acc[k] - s.com_drift[k],
                ],
            );
        }
        &self.rows
    }
}

impl super::Task for ComTask {
    fn level(&self) -> super::TaskLevel {
        super::TaskLevel::Acceleration
    }
    fn dim(&self) -> usize {
        3
    }
    fn compute(
        &mut self,
        _model: &corps_model::Model,
        s: &crate::robot_state::RobotState,
    ) -> crate::error::Result<&super::TaskRows> {
        Ok(ComTask::compute(self, s))
    }
    fn error_terms(&self) -> Option<&TaskErrorTerms> {
        Some(&self.terms)
    }
    fn last_rows(&self) -> Option<&TaskRows> {
        Some(&self.rows)
    }
}
