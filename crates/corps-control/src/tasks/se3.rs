//! Frame pose task in the frame's LOCAL coordinates (TSID `TaskSE3Equality`, local frame):
//! `J q̈ = a_des − J̇ v` with `M_err = oMf⁻¹ M_ref`, `p_err = [M_err.t; log3(M_err.R)]`,
//! `v_err = Rᵀ v_ref − v_f`, `a_des = Kp∘p_err + Kd∘v_err + Rᵀ a_ref`.

use super::{TaskErrorTerms, TaskRows};
use crate::robot_state::RobotState;
use corps_model::spatial::{rotation::log3, Motion, Se3};
use corps_model::{Model, Result};
use nalgebra::{Matrix6xX, Vector6};

/// An SE3 reference: placement in the world, velocity and acceleration in world-aligned axes
/// at the frame ([linear; angular]).
#[derive(Clone, Debug, PartialEq)]
pub struct Se3Reference {
    pub placement: Se3,
    pub velocity: Motion,
    pub acceleration: Motion,
}

/// The pose error of a frame at world placement `o_m_f` towards `m_ref`, in the frame's
/// LOCAL coordinates (TSID's `TaskSE3Equality`): `M_err = oMf⁻¹ M_ref`,
/// `e = [M_err.t; log3(M_err.R)]` ([linear; angular]). A LOCAL frame velocity `K∘e` (or
/// acceleration) drives the frame towards `m_ref`.
pub fn se3_error(o_m_f: &Se3, m_ref: &Se3) -> Motion {
    let err = o_m_f.inverse() * *m_ref;
    Motion::new(err.translation, log3(&err.rotation))
}

#[derive(Clone, Debug)]
pub struct Se3Task {
    pub frame: usize,
    pub kp: Vector6<f64>,
    pub kd: Vector6<f64>,
    pub reference: Se3Reference,
    /// Which LOCAL axes [linear; angular] the task constrains (1) or leaves free (0): a
    /// masked-out row is zero on both sides. All ones by default.
    pub mask: Vector6<f64>,
    jac: Matrix6xX<f64>,
    rows: TaskRows,
    terms: TaskErrorTerms,
}

impl Se3Task {
    pub fn new(
        nv: usize,
        frame: usize,
        kp: Vector6<f64>,
        kd: Vector6<f64>,
        reference: Se3Reference,
    ) -> Self {
        Self {
            frame,
            kp,
            kd,
            reference,
            mask: Vector6::repeat(1.0),
            jac: Matrix6xX::zeros(nv),
            rows: TaskRows::new(6, nv),
            terms: TaskErrorTerms::new(6),
        }
    }

    /// The rows computed by the last `compute`.
    pub fn rows(&self) -> &TaskRows {
        &self.rows
    }

    /// The error terms of the last `compute`.
    pub fn terms(&self) -> &TaskErrorTerms {
        &self.terms
    }

    /// Desired LOCAL frame acceleration minus the drift, and the LOCAL Jacobian.
    pub fn compute(&mut self, model: &Model, s: &RobotState) -> Result<&TaskRows> {
        let o_m_f = s.frame_placement(model, self.frame)?;
        let p_err = se3_error(&o_m_f, &self.reference.placement);
        let rt = o_m_f.rotation.transpose();
        let v_f = s.frame_velocity_local(model, self.frame)?;
        let v_ref = Motion::new(
            rt * self.reference.velocity.linear,
            rt * self.reference.velocity.angular,
        );
        let a_ref = Motion::new(
            rt * self.reference.acceleration.linear,
            rt * self.reference.acceleration.angular,
        );
        let v_err = v_ref - v_f;
        let drift = s.frame_drift_local(model, self.frame)?;
        let (pe, ve, ar, dr) = (
            p_err.to_vector(),
            v_err.to_vector(),
            a_ref.to_vector(),
            drift.to_vector(),
        );
        let vr = v_ref.to_vector();
        for k in 0..6 {
            let m = self.mask[k];
            self.rows.b[k] = m * (self.kp[k] * pe[k] + self.kd[k] * ve[k] + ar[k] - dr[k]);
            // E = −p_err and Ė = −v_err (LOCAL coordinates), a masked row all zero.
            let on = if m != 0.0 { 1.0 } else { 0.0 };
            self.terms.set(
                k,
                [
                    -m * pe[k],
                    -m * ve[k],
                    on * self.kp[k],
                    on * self.kd[k],
                    m * vr[k],
                    m * (ar[k] - dr[k]),
                ],
            );
        }
        s.frame_jacobian_local(model, self.frame, &mut self.jac)?;
        for r in 0..6 {
            for c in 0..self.jac.ncols() {
                self.rows.a[(r, c)] = self.mask[r] * self.jac[(r, c)];
            }
        }
        Ok(&self.rows)
    }
}

impl super::Task for Se3Task {
    fn level(&self) -> super::TaskLevel {
        super::TaskLevel::Acceleration
    }
    fn dim(&self) -> usize {
        6
    }
    fn compute(
        &mut self,
        model: &corps_model::Model,
        s: &crate::robot_state::RobotState,
    ) -> crate::error::Result<&super::TaskRows> {
        Ok(Se3Task::compute(self, model, s)?)
    }
    fn error_terms(&self) -> Option<&TaskErrorTerms> {
        Some(&self.terms)
    }
    fn last_rows(&self) -> Option<&TaskRows> {
        Some(&self.rows)
    }
}
