//! Velocity-level tasks for inverse kinematics (seed 000 §3.6, Eq 2.42–2.47, and §3.7,
//! Eq 4.1–4.2): each maps the robot state to rows `J v = ẋ* + K∘(x* ⊖ x)` over the joint
//! velocities v (nv, free-flyer included), i.e. the imposed error dynamics `ė = −K e`
//! plus the reference velocity as feedforward. Masks select the task axes that produce rows.

use super::se3::se3_error;
use super::{Reference, Se3Reference, TaskRows};
use crate::error::{ControlError, Result};
use crate::robot_state::RobotState;
use corps_model::{difference_to, Model};
use nalgebra::{DVector, Matrix6xX, Vector3, Vector6};

fn config_error(name: &str, reason: String) -> ControlError {
    ControlError::Config {
        name: name.into(),
        reason,
    }
}

fn check_gains(name: &str, k: &[f64]) -> Result<()> {
    match k.iter().find(|k| !(k.is_finite() && **k >= 0.0)) {
        Some(k) => Err(config_error(
            name,
            format!("gain {k} is not finite and ≥ 0"),
        )),
        None => Ok(()),
    }
}

/// Frame pose task in the frame's LOCAL coordinates: `J_local v = Kp∘e + Rᵀ v_ref`, with
/// `e = [M_err.t; log3(M_err.R)]`, `M_err = oMf⁻¹ M_ref` (the error of the acceleration-level
/// [`super::Se3Task`], shared through [`super::se3_error`]). With a constant reference it
/// holds a contact foot in place (seed 000 Eq 4.3 with the feet-tracking feedback); with the
/// mask `[false ×3, true ×3]` it is an orientation task (the waist).
pub struct FrameVelocityTask {
    pub frame: usize,
    /// Gains per axis, [linear; angular] (1/s).
    pub kp: Vector6<f64>,
    /// The reference; `velocity` (world-aligned axes at the frame) is the feedforward,
    /// `acceleration` is not used at velocity level.
    pub reference: Se3Reference,
    mask: [bool; 6],
    error: Vector6<f64>,
    jac: Matrix6xX<f64>,
    rows: TaskRows,
}

impl FrameVelocityTask {
    /// A task on `frame` with the axes of `mask` ([linear; angular]) active.
    pub fn new(
        model: &Model,
        frame: usize,
        kp: Vector6<f64>,
        mask: [bool; 6],
        reference: Se3Reference,
    ) -> Result<Self> {
        if frame >= model.frames.len() {
            return Err(ControlError::Model(corps_model::ModelError::UnknownFrame(
                format!("#{frame}"),
            )));
        }
        check_gains("frame task kp", kp.as_slice())?;
        let dim = mask.iter().filter(|m| **m).count();
        if dim == 0 {
            return Err(config_error("frame task mask", "no axis selected".into()));
        }
        Ok(Self {
            frame,
            kp,
            reference,
            mask,
            error: Vector6::zeros(),
            jac: Matrix6xX::zeros(model.nv),
            rows: TaskRows::new(dim, model.nv),
        })
    }

    pub fn mask(&self) -> [bool; 6] {
        self.mask
    }

    pub fn dim(&self) -> usize {
        self.rows.rows()
    }

    /// Number of velocity variables the task was built for.
    pub fn nv(&self) -> usize {
        self.rows.a.ncols()
    }

    /// The LOCAL pose error `e` ([linear; angular]) of the last `compute`, all six axes.
    pub fn error(&self) -> &Vector6<f64> {
        &self.error
    }

    pub fn compute(&mut self, model: &Model, s: &RobotState) -> Result<&TaskRows> {
        let o_m_f = s.frame_placement(model, self.frame)?;
        self.error = se3_error(&o_m_f, &self.reference.placement).to_vector();
        let rt = o_m_f.rotation.transpose();
        let (vl, va) = (
            rt * self.reference.velocity.linear,
            rt * self.reference.velocity.angular,
        );
        let v_ref = Vector6::new(vl[0], vl[1], vl[2], va[0], va[1], va[2]);
        s.frame_jacobian_local(model, self.frame, &mut self.jac)?;
        for (r, k) in (0..6).filter(|k| self.mask[*k]).enumerate() {
            self.rows.b[r] = self.kp[k] * self.error[k] + v_ref[k];
            for c in 0..self.jac.ncols() {
                self.rows.a[(r, c)] = self.jac[(k, c)];
            }
        }
        Ok(&self.rows)
    }
}

/// Centre-of-mass task on the masked world axes: `Jcom v = ċ_ref + Kp∘(c_ref − c)`.
pub struct ComVelocityTask {
    /// Gains per world axis (1/s).
    pub kp: Vector3<f64>,
    /// Position and velocity (feedforward) references (size 3; `acc` unused).
    pub reference: Reference,
    mask: [bool; 3],
    rows: TaskRows,
}

impl ComVelocityTask {
    /// A CoM task on the axes of `mask` (x, y, z), holding `reference`.
    pub fn new(nv: usize, kp: Vector3<f64>, mask: [bool; 3], reference: Reference) -> Result<Self> {
        check_gains("CoM task kp", kp.as_slice())?;
        if reference.pos.len() != 3 || reference.vel.len() != 3 {
            return Err(config_error("CoM reference", "needs 3 entries".into()));
        }
        let dim = mask.iter().filter(|m| **m).count();
        if dim == 0 {
            return Err(config_error("CoM task mask", "no axis selected".into()));
        }
        Ok(Self {
            kp,
            reference,
            mask,
            rows: TaskRows::new(dim, nv),
        })
    }

    pub fn mask(&self) -> [bool; 3] {
        self.mask
    }

    pub fn dim(&self) -> usize {
        self.rows.rows()
    }

    /// Number of velocity variables the task was built for.
    pub fn nv(&self) -> usize {
        self.rows.a.ncols()
    }

    /// Needs `s.data.jcom` and `s.data.com` (filled by [`RobotState::update`]).
    pub fn compute(&mut self, s: &RobotState) -> &TaskRows {
        let r = &self.reference;
        for (row, k) in (0..3).filter(|k| self.mask[*k]).enumerate() {
            self.rows.b[row] = r.vel[k] + self.kp[k] * (r.pos[k] - s.data.com[k]);
            for c in 0..s.data.jcom.ncols() {
                self.rows.a[(row, c)] = s.data.jcom[(k, c)];
            }
        }
        &self.rows
    }
}

/// Joint posture task over the actuated joints: `S v = v_ref − Kp∘(q ⊖ q_ref)`.
pub struct PostureVelocityTask {
    /// Gains (na, 1/s).
    pub kp: DVector<f64>,
    /// Reference configuration (nq; its free-flyer part is ignored).
    pub q_ref: DVector<f64>,
    /// Reference joint velocities (na).
    pub v_ref: DVector<f64>,
    first: usize,
    error: DVector<f64>,
    rows: TaskRows,
}

impl PostureVelocityTask {
    pub fn new(model: &Model, kp: DVector<f64>, q_ref: DVector<f64>) -> Result<Self> {
        let first = if model.has_free_flyer() { 6 } else { 0 };
        let na = model.nv - first;
        if kp.len() != na {
            return Err(config_error(
                "posture kp",
                format!("size {}, expected {na}", kp.len()),
            ));
        }
        check_gains("posture kp", kp.as_slice())?;
        model.check_configuration(q_ref.as_slice())?;
        let mut rows = TaskRows::new(na, model.nv);
        for k in 0..na {
            rows.a[(k, first + k)] = 1.0;
        }
        Ok(Self {
            kp,
            q_ref,
            v_ref: DVector::zeros(na),
            first,
            error: DVector::zeros(model.nv),
            rows,
        })
    }

    pub fn dim(&self) -> usize {
        self.rows.rows()
    }

    /// Number of velocity variables the task was built for.
    pub fn nv(&self) -> usize {
        self.rows.a.ncols()
    }

    pub fn compute(&mut self, model: &Model, s: &RobotState) -> Result<&TaskRows> {
        difference_to(
            model,
            self.q_ref.as_slice(),
            s.q.as_slice(),
            self.error.as_mut_slice(),
        )?;
        for k in 0..self.rows.rows() {
            self.rows.b[k] = self.v_ref[k] - self.kp[k] * self.error[self.first + k];
        }
        Ok(&self.rows)
    }
}

impl super::Task for FrameVelocityTask {
    fn level(&self) -> super::TaskLevel {
        super::TaskLevel::Velocity
    }
    fn dim(&self) -> usize {
        FrameVelocityTask::dim(self)
    }
    fn compute(
        &mut self,
        model: &corps_model::Model,
        s: &crate::robot_state::RobotState,
    ) -> crate::error::Result<&super::TaskRows> {
        FrameVelocityTask::compute(self, model, s)
    }
}

impl super::Task for ComVelocityTask {
    fn level(&self) -> super::TaskLevel {
        super::TaskLevel::Velocity
    }
    fn dim(&self) -> usize {
        ComVelocityTask::dim(self)
    }
    fn compute(
        &mut self,
        _model: &corps_model::Model,
        s: &crate::robot_state::RobotState,
    ) -> crate::error::Result<&super::TaskRows> {
        Ok(ComVelocityTask::compute(self, s))
    }
}

impl super::Task for PostureVelocityTask {
    fn level(&self) -> super::TaskLevel {
        super::TaskLevel::Velocity
    }
    fn dim(&self) -> usize {
        PostureVelocityTask::dim(self)
    }
    fn compute(
        &mut self,
        model: &corps_model::Model,
        s: &crate::robot_state::RobotState,
    ) -> crate::error::Result<&super::TaskRows> {
        PostureVelocityTask::compute(self, model, s)
    }
}
