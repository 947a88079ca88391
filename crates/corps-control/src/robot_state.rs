//! Everything the tasks read at one control tick, computed once: M, h, Jacobians, CoM and its
//! drift, the centroidal map and its drift, frame placements, velocities and drifts.

use corps_model::spatial::{Force, Motion, Se3};
use corps_model::{
    com_and_momentum_drifts, compute_all_terms, frame_classical_acceleration, frame_jacobian,
    frame_placement, frame_velocity, Data, Model, ReferenceFrame, Result,
};
use nalgebra::{DVector, Matrix6xX, Vector3};

/// The robot's state and the model terms at it.
pub struct RobotState {
    /// Rigid-body workspace: M (`data.m`), h (`data.nle`), world Jacobians, CoM, Jcom, A_G.
    pub data: Data,
    /// CoM velocity (world).
    pub com_velocity: Vector3<f64>,
    /// CoM drift J̇com v (world): the CoM acceleration at q̈ = 0.
    pub com_drift: Vector3<f64>,
    /// Centroidal momentum drift Ȧ_G v.
    pub momentum_drift: Force,
    /// Configuration and velocity of this state.
    pub q: DVector<f64>,
    pub v: DVector<f64>,
}

impl RobotState {
    pub fn new(model: &Model) -> Self {
        Self {
            data: Data::new(model),
            com_velocity: Vector3::zeros(),
            com_drift: Vector3::zeros(),
            momentum_drift: Force::zero(),
            q: DVector::zeros(model.nq),
            v: DVector::zeros(model.nv),
        }
    }

    /// Computes every term at (q, v). No allocation.
    pub fn update(&mut self, model: &Model, q: &[f64], v: &[f64]) -> Result<()> {
        compute_all_terms(model, &mut self.data, q, v)?;
        // One kinematic pass at q̈ = 0 gives both drifts and leaves the frame drifts.
        let (com_drift, momentum_drift) = com_and_momentum_drifts(model, &mut self.data, q, v)?;
        self.com_drift = com_drift;
        self.momentum_drift = momentum_drift;
        self.com_velocity =
            Vector3::from_fn(|r, _| (0..model.nv).map(|c| self.data.jcom[(r, c)] * v[c]).sum());
        self.q.copy_from_slice(q);
        self.v.copy_from_slice(v);
        Ok(())
    }

    /// World placement of a frame.
    pub fn frame_placement(&self, model: &Model, frame: usize) -> Result<Se3> {
        frame_placement(model, &self.data, frame)
    }

    /// LOCAL Jacobian of a frame, into `out` (6 × nv).
    pub fn frame_jacobian_local(
        &self,
        model: &Model,
        frame: usize,
        out: &mut Matrix6xX<f64>,
    ) -> Result<()> {
        frame_jacobian(model, &self.data, frame, ReferenceFrame::Local, out)
    }

    /// LOCAL velocity of a frame.
    pub fn frame_velocity_local(&self, model: &Model, frame: usize) -> Result<Motion> {
        frame_velocity(model, &self.data, frame, ReferenceFrame::Local)
    }

    /// LOCAL classical acceleration of a frame at q̈ = 0 (the drift J̇ v).
    pub fn frame_drift_local(&self, model: &Model, frame: usize) -> Result<Motion> {
        frame_classical_acceleration(model, &self.data, frame, ReferenceFrame::Local)
    }
}
