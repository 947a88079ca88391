//! The rigid-body algorithms under Pinocchio's Python names (snake_case), each checking its
//! inputs' sizes and that `data` belongs to `model`. Results are returned as new arrays and
//! also kept in `data`.

use crate::arrays::{dvector, matrix, slice, vector, VectorArg};
use crate::errors::{model_error, ModelError};
use crate::model::{
    random_configuration as random_q, FrameRef, PyData, PyModel, PyReferenceFrame, PySe3,
};
use corps_model as cm;
use nalgebra::Matrix6xX;
use numpy::{PyArray1, PyArray2};
use pyo3::prelude::*;

type Vector<'py> = PyResult<Bound<'py, PyArray1<f64>>>;
type MatrixOut<'py> = PyResult<Bound<'py, PyArray2<f64>>>;

/// Defines a Python function `name(model, data, args…)` over a corps-model algorithm of those
/// vectors, returning its result as a new array.
macro_rules! algorithm {
    ($(#[doc = $doc:expr])* $name:ident($($arg:ident),+) => $algorithm:path, $out:ident -> $ret:ty) => {
        $(#[doc = $doc])*
        #[pyfunction]
        pub fn $name<'py>(
            py: Python<'py>,
            model: &PyModel,
            mut data: PyRefMut<'_, PyData>,
            $($arg: VectorArg<'_>),+
        ) -> PyResult<Bound<'py, $ret>> {
            data.check(model)?;
            let r = $algorithm(&model.inner, &mut data.inner, $(&slice(&$arg)),+)
                .map_err(model_error)?;
            Ok($out(py, r))
        }
    };
}

algorithm! {
    /// Inverse dynamics τ = M(q) a + C(q, v) v + g(q) (RNEA; N·m, N).
    rnea(q, v, a) => cm::rnea, dvector -> PyArray1<f64>
}
algorithm! {
    /// Non-linear effects h(q, v) = C(q, v) v + g(q).
    nonlinear_effects(q, v) => cm::nonlinear_effects, dvector -> PyArray1<f64>
}
algorithm! {
    /// Forward dynamics a = M⁻¹(τ − h) (ABA; rad/s², m/s²).
    aba(q, v, tau) => cm::aba, dvector -> PyArray1<f64>
}
algorithm! {
    /// Generalized gravity g(q).
    compute_generalized_gravity(q) => cm::generalized_gravity, dvector -> PyArray1<f64>
}
algorithm! {
    /// Joint-space inertia matrix M(q) (CRBA), both triangles filled (Pinocchio fills the upper).
    crba(q) => cm::crba, matrix -> PyArray2<f64>
}
algorithm! {
    /// M(q)⁻¹ by the O(n²) recursion, both triangles filled.
    compute_minverse(q) => cm::compute_minverse, matrix -> PyArray2<f64>
}
algorithm! {
    /// Joint Jacobians in the world frame at q (6 × nv, `data.J`).
    compute_joint_jacobians(q) => cm::compute_joint_jacobians, matrix -> PyArray2<f64>
}
algorithm! {
    /// CoM Jacobian (3 × nv, world axes); also sets `data.com`.
    jacobian_center_of_mass(q) => cm::jacobian_center_of_mass, matrix -> PyArray2<f64>
}
algorithm! {
    /// Centroidal momentum matrix A_G (6 × nv, [linear; angular] about the CoM, world axes;
    /// Pinocchio's `computeCentroidalMap`).
    centroidal_map(q) => cm::compute_centroidal_map, matrix -> PyArray2<f64>
}

/// Placements (and with v, a: velocities, accelerations) of every joint; read them with
/// `data.oMi` or `frame_placement`.
#[pyfunction]
#[pyo3(signature = (model, data, q, v = None, a = None))]
pub fn forward_kinematics(
    model: &PyModel,
    mut data: PyRefMut<'_, PyData>,
    q: VectorArg<'_>,
    v: Option<VectorArg<'_>>,
    a: Option<VectorArg<'_>>,
) -> PyResult<()> {
    data.check(model)?;
    let (m, d) = (&model.inner, &mut data.inner);
    match (v, a) {
        (None, None) => cm::forward_kinematics_placements(m, d, &slice(&q)),
        (Some(v), None) => {
            let zero = vec![0.0; m.nv];
            cm::forward_kinematics(m, d, &slice(&q), &slice(&v), &zero)
        }
        (Some(v), Some(a)) => cm::forward_kinematics(m, d, &slice(&q), &slice(&v), &slice(&a)),
        (None, Some(_)) => {
            return Err(ModelError::new_err(
                "forward_kinematics: an acceleration needs a velocity",
            ))
        }
    }
    .map_err(model_error)
}

/// World placement of `frame` (id or name) from the last forward kinematics.
#[pyfunction]
pub fn frame_placement(
    model: &PyModel,
    data: PyRef<'_, PyData>,
    frame: FrameRef,
) -> PyResult<PySe3> {
    data.check(model)?;
    let id = frame.id(&model.inner)?;
    let m = cm::frame_placement(&model.inner, &data.inner, id).map_err(model_error)?;
    Ok(PySe3 { inner: m })
}

/// The Jacobian of `frame` (id or name) at q in `reference_frame` (6 × nv, [linear; angular]).
#[pyfunction]
#[pyo3(signature = (model, data, q, frame, reference_frame = PyReferenceFrame::LOCAL))]
pub fn compute_frame_jacobian<'py>(
    py: Python<'py>,
    model: &PyModel,
    mut data: PyRefMut<'_, PyData>,
    q: VectorArg<'_>,
    frame: FrameRef,
    reference_frame: PyReferenceFrame,
) -> MatrixOut<'py> {
    data.check(model)?;
    let id = frame.id(&model.inner)?;
    let mut out = Matrix6xX::zeros(model.inner.nv);
    cm::compute_frame_jacobian(
        &model.inner,
        &mut data.inner,
        &slice(&q),
        id,
        reference_frame.into(),
        &mut out,
    )
    .map_err(model_error)?;
    Ok(matrix(py, &out))
}

/// The Jacobian of `frame` from the joint Jacobians already in `data` (after
/// `compute_joint_jacobians` at the same q).
#[pyfunction]
#[pyo3(signature = (model, data, frame, reference_frame = PyReferenceFrame::LOCAL))]
pub fn get_frame_jacobian<'py>(
    py: Python<'py>,
    model: &PyModel,
    data: PyRef<'_, PyData>,
    frame: FrameRef,
    reference_frame: PyReferenceFrame,
) -> MatrixOut<'py> {
    data.check(model)?;
    let id = frame.id(&model.inner)?;
    frame_jacobian(py, &model.inner, &data.inner, id, reference_frame)
}

fn frame_jacobian<'py>(
    py: Python<'py>,
    model: &cm::Model,
    data: &cm::Data,
    id: usize,
    rf: PyReferenceFrame,
) -> MatrixOut<'py> {
    let mut out = Matrix6xX::zeros(model.nv);
    cm::frame_jacobian(model, data, id, rf.into(), &mut out).map_err(model_error)?;
    Ok(matrix(py, &out))
}

/// Centre of mass (m, world); with v and a also its velocity and acceleration
/// (`data.vcom`, `data.acom`).
#[pyfunction]
#[pyo3(signature = (model, data, q, v = None, a = None))]
pub fn center_of_mass<'py>(
    py: Python<'py>,
    model: &PyModel,
    mut data: PyRefMut<'_, PyData>,
    q: VectorArg<'_>,
    v: Option<VectorArg<'_>>,
    a: Option<VectorArg<'_>>,
) -> Vector<'py> {
    data.check(model)?;
    let nv = model.inner.nv;
    let zero = vec![0.0; nv];
    let v = v.as_ref().map(slice);
    let a = a.as_ref().map(slice);
    if v.is_none() && a.is_some() {
        return Err(ModelError::new_err(
            "center_of_mass: an acceleration needs a velocity",
        ));
    }
    if v.is_none() {
        // Placements only: c = Σ m_i ᵒM_i c_i / m.
        let (m, d) = (&*model.inner, &mut data.inner);
        cm::forward_kinematics_placements(m, d, &slice(&q)).map_err(model_error)?;
        d.com = cm::com_at_placements(m, d).0;
        return Ok(vector(py, d.com.as_slice()));
    }
    let c = cm::center_of_mass(
        &model.inner,
        &mut data.inner,
        &slice(&q),
        v.as_deref().unwrap_or(&zero),
        a.as_deref().unwrap_or(&zero),
    )
    .map_err(model_error)?;
    Ok(vector(py, c.as_slice()))
}

/// Centroidal momentum h_G = A_G v ([linear (kg·m/s); angular (kg·m²/s)] about the CoM).
#[pyfunction]
pub fn compute_centroidal_momentum<'py>(
    py: Python<'py>,
    model: &PyModel,
    mut data: PyRefMut<'_, PyData>,
    q: VectorArg<'_>,
    v: VectorArg<'_>,
) -> Vector<'py> {
    data.check(model)?;
    let h = cm::compute_centroidal_momentum(&model.inner, &mut data.inner, &slice(&q), &slice(&v))
        .map_err(model_error)?;
    let mut out = [0.0; 6];
    out[..3].copy_from_slice(h.linear.as_slice());
    out[3..].copy_from_slice(h.angular.as_slice());
    Ok(vector(py, &out))
}

/// Kinetic energy ½ vᵀ M v (J).
#[pyfunction]
pub fn compute_kinetic_energy(
    model: &PyModel,
    mut data: PyRefMut<'_, PyData>,
    q: VectorArg<'_>,
    v: VectorArg<'_>,
) -> PyResult<f64> {
    data.check(model)?;
    cm::kinetic_energy(&model.inner, &mut data.inner, &slice(&q), &slice(&v)).map_err(model_error)
}

/// Potential energy of gravity (J, zero at the world origin's height).
#[pyfunction]
pub fn compute_potential_energy(
    model: &PyModel,
    mut data: PyRefMut<'_, PyData>,
    q: VectorArg<'_>,
) -> PyResult<f64> {
    data.check(model)?;
    cm::potential_energy(&model.inner, &mut data.inner, &slice(&q)).map_err(model_error)
}

/// The neutral configuration (unit quaternion, zero joints, continuous joints at angle 0).
#[pyfunction]
pub fn neutral<'py>(py: Python<'py>, model: &PyModel) -> Bound<'py, PyArray1<f64>> {
    vector(py, cm::neutral(&model.inner).as_slice())
}

/// q ⊕ v: the configuration reached from q along v for unit time.
#[pyfunction]
pub fn integrate<'py>(
    py: Python<'py>,
    model: &PyModel,
    q: VectorArg<'_>,
    v: VectorArg<'_>,
) -> Vector<'py> {
    let out = cm::integrate(&model.inner, &slice(&q), &slice(&v)).map_err(model_error)?;
    Ok(vector(py, out.as_slice()))
}

/// q1 ⊖ q0: the tangent vector that takes q0 to q1 in unit time.
#[pyfunction]
pub fn difference<'py>(
    py: Python<'py>,
    model: &PyModel,
    q0: VectorArg<'_>,
    q1: VectorArg<'_>,
) -> Vector<'py> {
    let out = cm::difference(&model.inner, &slice(&q0), &slice(&q1)).map_err(model_error)?;
    Ok(vector(py, out.as_slice()))
}

/// A random configuration within the joint limits; `seed` makes it reproducible.
#[pyfunction]
#[pyo3(signature = (model, seed = None))]
pub fn random_configuration<'py>(
    py: Python<'py>,
    model: &PyModel,
    seed: Option<u64>,
) -> Bound<'py, PyArray1<f64>> {
    vector(py, random_q(&model.inner, seed).as_slice())
}
