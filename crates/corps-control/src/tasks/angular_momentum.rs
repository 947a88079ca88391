//! Angular-momentum task about the CoM: `A_G,ang q̈ = −Kp∘(L − L_ref) + L̇_ref − (Ȧ_G v)_ang`
//! (TSID `TaskAMEquality`; TSID 1.10 applies no derivative gain).

use super::{TaskErrorTerms, TaskRows};
use crate::robot_state::RobotState;
use nalgebra::Vector3;

#[derive(Clone, Debug)]
pub struct AngularMomentumTask {
    pub kp: Vector3<f64>,
    pub reference: Vector3<f64>,
    pub reference_derivative: Vector3<f64>,
    rows: TaskRows,
    terms: TaskErrorTerms,
}

impl AngularMomentumTask {
    pub fn new(nv: usize, kp: Vector3<f64>) -> Self {
        Self {
            kp,
            reference: Vector3::zeros(),
            reference_derivative: Vector3::zeros(),
            rows: TaskRows::new(3, nv),
            terms: TaskErrorTerms::new(3),
        }
    }

    pub fn compute(&mut self, s: &RobotState) -> &TaskRows {
        let ag = &s.data.ag;
        for r in 0..3 {
            for c in 0..ag.ncols() {
                self.rows.a[(r, c)] = ag[(3 + r, c)];
            }
        }
        let l = s.data.hg.angular;
        let drift = s.momentum_drift.angular;
        for k in 0..3 {
            self.rows.b[k] =
                -self.kp[k] * (l[k] - self.reference[k]) + self.reference_derivative[k] - drift[k];
            // A momentum task has no position: X is ∫L, E = 0, Ė = L − L*, K_D = Kp.
            self.terms.set(
                k,
                [
                    0.0,
                    l[k] - self.reference[k],
                    0.0,
                    self.kp[k],
                    self.reference[k],
                    self.reference_derivative[k] - drift[k],
                ],
            );
        }
        &self.rows
    }
}

impl super::Task for AngularMomentumTask {
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
        Ok(AngularMomentumTask::compute(self, s))
    }
    fn error_terms(&self) -> Option<&TaskErrorTerms> {
        Some(&self.terms)
    }
    fn last_rows(&self) -> Option<&TaskRows> {
        Some(&self.rows)
    }
}
