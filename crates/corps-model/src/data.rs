//! [`Data`]: every buffer the algorithms write, allocated once per model. After `Data::new`,
//! no algorithm allocates on the heap.

use crate::model::Model;
use crate::spatial::{Force, Motion, OriginInertia, Se3};
use nalgebra::{DMatrix, DVector, Matrix3xX, Matrix6, Matrix6xX, Vector3};

/// Workspace and results of the rigid-body algorithms for one [`Model`].
///
/// Quantities with an `o` prefix are in the world frame; others in the joint's local frame.
#[derive(Clone, Debug)]
pub struct Data {
    /// Placement of each joint in its parent joint's frame.
    pub li_m_i: Vec<Se3>,
    /// Placement of each joint in the world.
    pub o_m_i: Vec<Se3>,
    /// Placement of each frame in the world (after [`crate::update_frame_placements`]).
    pub o_m_f: Vec<Se3>,
    /// Spatial velocity of each joint, local.
    pub v: Vec<Motion>,
    /// Spatial acceleration of each joint, local (gravity not included).
    pub a: Vec<Motion>,
    /// Spatial acceleration of each joint including the gravity field, local (RNEA).
    pub a_gf: Vec<Motion>,
    /// Spatial force transmitted by each joint, local (RNEA).
    pub f: Vec<Force>,
    /// Spatial velocity of each joint, world.
    pub ov: Vec<Motion>,
    /// World-frame bias acceleration (ABA) or acceleration of each joint.
    pub oa: Vec<Motion>,
    /// Joint torques from RNEA.
    pub tau: DVector<f64>,
    /// Non-linear effects h(q, v) = C(q, v) v + g(q).
    pub nle: DVector<f64>,
    /// Generalized gravity g(q).
    pub g: DVector<f64>,
    /// Joint accelerations from ABA.
    pub ddq: DVector<f64>,
    /// Joint-space inertia matrix M(q) (full, symmetric). Entries coupling two dofs on
    /// different branches are zero; CRBA never writes them, so they stay as `Data::new` left them.
    pub m: DMatrix<f64>,
    /// M(q)⁻¹.
    pub minv: DMatrix<f64>,
    /// Branch-induced sparse factorization M = Lᵀ D L (D on the diagonal, L below).
    pub ltdl: DMatrix<f64>,
    /// Coriolis matrix C(q, v) with Ṁ − 2C skew-symmetric.
    pub c: DMatrix<f64>,
    /// Joint Jacobians in the world frame (column k: the twist of joint dof k, at the origin).
    pub j: Matrix6xX<f64>,
    /// Time derivative of `j`.
    pub dj: Matrix6xX<f64>,
    /// Spatial inertia matrices of the bodies in the world frame (Coriolis matrix algorithm).
    pub ycrb: Vec<Matrix6<f64>>,
    /// Composite rigid-body inertias in the world frame (CRBA, centroidal map).
    pub composite: Vec<OriginInertia>,
    /// Composite Coriolis-like matrices (Coriolis matrix algorithm) / articulated inertias (ABA,
    /// local).
    pub bcrb: Vec<Matrix6<f64>>,
    /// Per-dof spatial forces (CRBA `Ycrb S`, ABA `U`, Coriolis `Ycrb J̇ + Bcrb J`).
    pub f_cols: Matrix6xX<f64>,
    /// External wrenches on each joint's body, world frame (ABA with external forces).
    pub fext: Vec<Force>,
    /// ABA bias forces, local.
    pub pa: Vec<Force>,
    /// ABA: 1/D per dof.
    pub d_inv: DVector<f64>,
    /// ABA: u = τ − Sᵀ pA per dof.
    pub u: DVector<f64>,
    /// Centre of mass of the whole robot (world).
    pub com: Vector3<f64>,
    /// Velocity of the centre of mass (world).
    pub vcom: Vector3<f64>,
    /// Acceleration of the centre of mass (world).
    pub acom: Vector3<f64>,
    /// Jacobian of the centre of mass (3 × nv).
    pub jcom: Matrix3xX<f64>,
    /// Centroidal momentum matrix A_G (6 × nv), about the CoM, world-aligned axes.
    pub ag: Matrix6xX<f64>,
    /// Centroidal momentum h_G = A_G v, [linear; angular about the CoM].
    pub hg: Force,
    /// Centroidal momentum drift Ȧ_G v.
    pub dag_v: Force,
    /// Kinetic energy.
    pub kinetic_energy: f64,
    /// Potential energy in the gravity field.
    pub potential_energy: f64,
    /// M⁻¹ recursion: per joint, the accelerations (world, at the origin) of its body under
    /// each unit torque c ≥ its first dof.
    pub minv_acc: Vec<Matrix6xX<f64>>,
    /// Scratch vector of size nv.
    pub tmp_nv: DVector<f64>,
    /// Scratch 6 × nv matrix.
    pub tmp_6xnv: Matrix6xX<f64>,
}

impl Data {
    /// Allocates every buffer for `model`.
    pub fn new(model: &Model) -> Self {
        let (n, nv, nf) = (model.njoints(), model.nv, model.frames.len());
        Self {
            li_m_i: vec![Se3::identity(); n],
            o_m_i: vec![Se3::identity(); n],
            o_m_f: vec![Se3::identity(); nf],
            v: vec![Motion::zero(); n],
            a: vec![Motion::zero(); n],
            a_gf: vec![Motion::zero(); n],
            f: vec![Force::zero(); n],
            ov: vec![Motion::zero(); n],
            oa: vec![Motion::zero(); n],
            tau: DVector::zeros(nv),
            nle: DVector::zeros(nv),
            g: DVector::zeros(nv),
            ddq: DVector::zeros(nv),
            m: DMatrix::zeros(nv, nv),
            minv: DMatrix::zeros(nv, nv),
            ltdl: DMatrix::zeros(nv, nv),
            c: DMatrix::zeros(nv, nv),
            j: Matrix6xX::zeros(nv),
            dj: Matrix6xX::zeros(nv),
            ycrb: vec![Matrix6::zeros(); n],
            bcrb: vec![Matrix6::zeros(); n],
            composite: vec![OriginInertia::default(); n],
            f_cols: Matrix6xX::zeros(nv),
            fext: vec![Force::zero(); n],
            pa: vec![Force::zero(); n],
            d_inv: DVector::zeros(nv),
            u: DVector::zeros(nv),
            com: Vector3::zeros(),
            vcom: Vector3::zeros(),
            acom: Vector3::zeros(),
            jcom: Matrix3xX::zeros(nv),
            ag: Matrix6xX::zeros(nv),
            hg: Force::zero(),
            dag_v: Force::zero(),
            kinetic_energy: 0.0,
            potential_energy: 0.0,
            minv_acc: vec![Matrix6xX::zeros(nv); n],
            tmp_nv: DVector::zeros(nv),
            tmp_6xnv: Matrix6xX::zeros(nv),
        }
    }
}

/// Column k of a 6 × nv matrix as a motion.
#[inline]
pub(crate) fn col_motion(m: &Matrix6xX<f64>, k: usize) -> Motion {
    Motion::from_slice(&m.as_slice()[6 * k..6 * k + 6])
}

/// Column k of a 6 × nv matrix as a force.
#[inline]
pub(crate) fn col_force(m: &Matrix6xX<f64>, k: usize) -> Force {
    let s = &m.as_slice()[6 * k..6 * k + 6];
    Force::new(
        Vector3::new(s[0], s[1], s[2]),
        Vector3::new(s[3], s[4], s[5]),
    )
}

/// Writes a spatial vector `[lin; ang]` into column k of a 6 × nv matrix.
#[inline]
pub(crate) fn set_col(m: &mut Matrix6xX<f64>, k: usize, lin: &Vector3<f64>, ang: &Vector3<f64>) {
    let s = &mut m.as_mut_slice()[6 * k..6 * k + 6];
    s[..3].copy_from_slice(lin.as_slice());
    s[3..].copy_from_slice(ang.as_slice());
}
