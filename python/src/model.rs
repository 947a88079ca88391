//! `corps.Model`, `corps.Data`, `corps.SE3` and `corps.ReferenceFrame`: Pinocchio's objects
//! and conventions (q = [x, y, z, qx, qy, qz, qw, joints…] for a free-flyer, spatial vectors
//! [linear; angular], joints in Pinocchio's depth-first order).

use crate::arrays::{homogeneous, matrix, slice, vector, VectorArg};
use crate::errors::{model_error, ModelError};
use corps_model::spatial::Se3;
use corps_model::{Data, Model, ReferenceFrame, RootJoint};
use nalgebra::{Matrix3, Vector3};
use numpy::{PyArray1, PyArray2, PyReadonlyArray1, PyReadonlyArray2};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use rand::SeedableRng;
use std::path::PathBuf;
use std::sync::Arc;

/// A robot model (immutable). Build it with `Model.from_urdf` or `Model.from_robot`.
#[pyclass(name = "Model", module = "corps", frozen)]
pub struct PyModel {
    pub inner: Arc<Model>,
}

#[pymethods]
impl PyModel {
    /// Loads a URDF file. `floating_base=True` adds Pinocchio's free-flyer root joint
    /// (`root_joint`, q = [x, y, z, qx, qy, qz, qw]); `srdf` adds its `group_state`s as
    /// reference configurations.
    #[staticmethod]
    #[pyo3(signature = (path, srdf = None, floating_base = true))]
    fn from_urdf(path: PathBuf, srdf: Option<PathBuf>, floating_base: bool) -> PyResult<Self> {
        let root = if floating_base {
            RootJoint::FreeFlyer
        } else {
            RootJoint::Fixed
        };
        let mut model =
            corps_model::build_model_from_urdf_file(&path, root).map_err(model_error)?;
        if let Some(srdf) = srdf {
            corps_model::load_reference_configurations(&mut model, &srdf).map_err(model_error)?;
        }
        Ok(Self {
            inner: Arc::new(model),
        })
    }

    /// The model of a robot description: a built-in robot (`talos`, `icub`,
    /// `icub_backpacked`, `simple_humanoid`) or a description file (`robots/*/*.toml`).
    /// Joints the description locks are not in it (iCub: 23 joints).
    #[staticmethod]
    fn from_robot(robot: &str) -> PyResult<Self> {
        let robot =
            corps_robot::Robot::resolve(robot, std::path::Path::new(".")).map_err(model_error)?;
        Ok(Self { inner: robot.model })
    }

    /// A new workspace for the algorithms (Pinocchio's `model.createData()`).
    fn create_data(&self) -> PyData {
        PyData {
            inner: Data::new(&self.inner),
            model: self.inner.clone(),
        }
    }

    /// Robot name from the URDF.
    #[getter]
    fn name(&self) -> &str {
        &self.inner.name
    }
    /// Configuration size.
    #[getter]
    fn nq(&self) -> usize {
        self.inner.nq
    }
    /// Velocity (tangent) size.
    #[getter]
    fn nv(&self) -> usize {
        self.inner.nv
    }
    /// Number of moving joints (Pinocchio's `njoints` minus the universe).
    #[getter]
    fn njoints(&self) -> usize {
        self.inner.njoints()
    }
    /// Number of frames.
    #[getter]
    fn nframes(&self) -> usize {
        self.inner.frames.len()
    }
    /// Names of the moving joints in order (Pinocchio's `model.names[1:]`).
    #[getter]
    fn joint_names(&self) -> Vec<String> {
        self.inner.joints.iter().map(|j| j.name.clone()).collect()
    }
    /// Names of the frames in id order.
    #[getter]
    fn frame_names(&self) -> Vec<String> {
        self.inner.frames.iter().map(|f| f.name.clone()).collect()
    }
    /// Index of each joint's first entry in q.
    #[getter]
    fn idx_qs(&self) -> Vec<usize> {
        self.inner.joints.iter().map(|j| j.idx_q).collect()
    }
    /// Index of each joint's first entry in v.
    #[getter]
    fn idx_vs(&self) -> Vec<usize> {
        self.inner.joints.iter().map(|j| j.idx_v).collect()
    }
    /// Lower position limits (size nq; rad or m).
    #[getter]
    fn lower_position_limit<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        vector(py, self.inner.lower_position_limit.as_slice())
    }
    /// Upper position limits (size nq; rad or m).
    #[getter]
    fn upper_position_limit<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        vector(py, self.inner.upper_position_limit.as_slice())
    }
    /// Velocity limits (size nv; rad/s or m/s).
    #[getter]
    fn velocity_limit<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        vector(py, self.inner.velocity_limit.as_slice())
    }
    /// Effort limits (size nv; N·m or N).
    #[getter]
    fn effort_limit<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        vector(py, self.inner.effort_limit.as_slice())
    }
    /// Gravity in the world frame (m/s²).
    #[getter]
    fn gravity<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        vector(py, self.inner.gravity.as_slice())
    }
    /// Total mass (kg).
    fn total_mass(&self) -> f64 {
        self.inner.total_mass()
    }
    /// Id of the frame named `name` (Pinocchio's `getFrameId`).
    fn get_frame_id(&self, name: &str) -> PyResult<usize> {
        self.inner.frame_id(name).map_err(model_error)
    }
    /// Whether a frame is named `name`.
    fn exists_frame(&self, name: &str) -> bool {
        self.inner.frame_id(name).is_ok()
    }
    /// The moving joint (0-based index) whose body carries `frame` (id or name); None for a
    /// frame fixed to the world (Pinocchio's `frames[id].parentJoint - 1`).
    fn frame_parent_joint(&self, frame: FrameRef) -> PyResult<Option<usize>> {
        let id = frame.id(&self.inner)?;
        Ok(self.inner.frames[id].parent_joint)
    }
    /// One dict per moving joint and the body it moves (fixed children merged), parents
    /// first: `name`, `parent` (index, None at the root), `kind` (`free`, `revolute`,
    /// `continuous`, `prismatic`), `axis` (unit, joint frame), `placement` (4 × 4, in the
    /// parent joint's frame), `idx_q`, `idx_v`, `mass` (kg), `com` (m, joint frame), `inertia`
    /// (3 × 3 about the CoM, kg·m², joint frame), `effort` (N·m or N; None at the root).
    fn bodies<'py>(&self, py: Python<'py>) -> PyResult<Vec<Bound<'py, PyDict>>> {
        crate::tree::bodies(self, py)
    }
    /// One dict per collision primitive (meshes left out, as corps' simulator does): `link`,
    /// `joint` (the moving joint carrying it; None if fixed to the world), `placement` (4 × 4
    /// in that joint's frame), `shape` (`box` with `size`, full side lengths; `cylinder` with
    /// `radius` and `length` along local z; `sphere` with `radius`).
    fn collisions<'py>(&self, py: Python<'py>) -> PyResult<Vec<Bound<'py, PyDict>>> {
        crate::tree::collisions(self, py)
    }
    /// Where `frame` (id or name) is attached: the moving joint carrying it (None if fixed to
    /// the world) and its placement in that joint's frame.
    fn frame_attachment(&self, frame: FrameRef) -> PyResult<(Option<usize>, PySe3)> {
        crate::tree::frame_attachment(self, frame)
    }
    /// Id of the moving joint named `name` (0-based, no universe).
    fn get_joint_id(&self, name: &str) -> PyResult<usize> {
        self.inner.joint_id(name).map_err(model_error)
    }
    /// A named reference configuration (from the SRDF or the robot description).
    fn reference_configuration<'py>(
        &self,
        py: Python<'py>,
        name: &str,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let q = self
            .inner
            .reference_configuration(name)
            .map_err(model_error)?;
        Ok(vector(py, q.as_slice()))
    }
    /// Names of the reference configurations.
    #[getter]
    fn reference_configurations(&self) -> Vec<String> {
        (self.inner.reference_configurations.iter())
            .map(|(n, _)| n.clone())
            .collect()
    }
    fn __repr__(&self) -> String {
        format!(
            "corps.Model('{}', nq={}, nv={}, joints={}, frames={}, mass={:.3} kg)",
            self.inner.name,
            self.inner.nq,
            self.inner.nv,
            self.inner.njoints(),
            self.inner.frames.len(),
            self.inner.total_mass()
        )
    }
}

/// The algorithms' workspace for one model. Attributes are copies of the last results.
#[pyclass(name = "Data", module = "corps")]
pub struct PyData {
    pub inner: Data,
    pub model: Arc<Model>,
}

impl PyData {
    /// Refuses a Data made for another model (Pinocchio would read out of bounds).
    pub fn check(&self, model: &PyModel) -> PyResult<()> {
        if Arc::ptr_eq(&self.model, &model.inner) {
            Ok(())
        } else {
            Err(ModelError::new_err(format!(
                "data was created by another model than '{}' (use model.create_data())",
                model.inner.name
            )))
        }
    }
}

#[pymethods]
impl PyData {
    /// Joint torques of the last `rnea` (size nv).
    #[getter]
    fn tau<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        vector(py, self.inner.tau.as_slice())
    }
    /// Non-linear effects h(q, v) of the last `nonlinear_effects` (size nv).
    #[getter]
    fn nle<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        vector(py, self.inner.nle.as_slice())
    }
    /// Generalized gravity of the last `compute_generalized_gravity` (size nv).
    #[getter]
    fn g<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        vector(py, self.inner.g.as_slice())
    }
    /// Joint accelerations of the last `aba` (size nv).
    #[getter]
    fn ddq<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        vector(py, self.inner.ddq.as_slice())
    }
    /// Joint-space inertia matrix of the last `crba` (nv × nv, both triangles).
    #[getter(M)]
    fn mass_matrix<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        matrix(py, &self.inner.m)
    }
    /// M⁻¹ of the last `compute_minverse` (nv × nv, both triangles).
    #[getter(Minv)]
    fn minv<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        matrix(py, &self.inner.minv)
    }
    /// Centre of mass (m, world) of the last `center_of_mass`, `centroidal_map` or
    /// `jacobian_center_of_mass` (Pinocchio's `data.com[0]`).
    #[getter]
    fn com<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        vector(py, self.inner.com.as_slice())
    }
    /// CoM velocity (m/s, world) of the last `center_of_mass` with v.
    #[getter]
    fn vcom<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        vector(py, self.inner.vcom.as_slice())
    }
    /// CoM acceleration (m/s², world) of the last `center_of_mass` with v and a.
    #[getter]
    fn acom<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        vector(py, self.inner.acom.as_slice())
    }
    /// CoM Jacobian (3 × nv, world axes).
    #[getter(Jcom)]
    fn jcom<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        matrix(py, &self.inner.jcom)
    }
    /// Centroidal momentum matrix A_G (6 × nv; [linear; angular] about the CoM, world axes).
    #[getter(Ag)]
    fn ag<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        matrix(py, &self.inner.ag)
    }
    /// Joint Jacobians in the world frame of the last `compute_joint_jacobians` (6 × nv).
    #[getter(J)]
    fn j<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        matrix(py, &self.inner.j)
    }
    /// World placement of every moving joint after forward kinematics (Pinocchio's `oMi[1:]`).
    #[getter(oMi)]
    fn o_m_i(&self) -> Vec<PySe3> {
        self.inner
            .o_m_i
            .iter()
            .map(|m| PySe3 { inner: *m })
            .collect()
    }
    fn __repr__(&self) -> String {
        format!("corps.Data(model='{}')", self.model.name)
    }
}

/// A rigid placement: rotation R and translation p (x_a = R x_b + p).
#[pyclass(name = "SE3", module = "corps", frozen)]
#[derive(Clone)]
pub struct PySe3 {
    pub inner: Se3,
}

#[pymethods]
impl PySe3 {
    /// From a 3 × 3 rotation and a translation.
    #[new]
    fn new(
        rotation: PyReadonlyArray2<'_, f64>,
        translation: PyReadonlyArray1<'_, f64>,
    ) -> PyResult<Self> {
        let (r, p) = (rotation.as_array(), translation.as_array());
        if r.shape() != [3, 3] || p.len() != 3 {
            return Err(ModelError::new_err(format!(
                "SE3: rotation must be 3 × 3 and translation of size 3 (got {:?} and {})",
                r.shape(),
                p.len()
            )));
        }
        Ok(Self {
            inner: Se3::new(
                Matrix3::from_fn(|i, j| r[[i, j]]),
                Vector3::new(p[0], p[1], p[2]),
            ),
        })
    }
    /// The identity placement.
    #[staticmethod]
    #[allow(non_snake_case)]
    fn Identity() -> Self {
        Self {
            inner: Se3::identity(),
        }
    }
    /// Rotation matrix (3 × 3).
    #[getter]
    fn rotation<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        matrix(py, &self.inner.rotation)
    }
    /// Translation (m).
    #[getter]
    fn translation<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        vector(py, self.inner.translation.as_slice())
    }
    /// The 4 × 4 homogeneous matrix.
    #[getter]
    fn homogeneous<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        homogeneous(py, &self.inner)
    }
    /// The inverse placement.
    fn inverse(&self) -> Self {
        Self {
            inner: self.inner.inverse(),
        }
    }
    /// The image of point `p` (size 3).
    fn act(&self, py: Python<'_>, p: VectorArg<'_>) -> PyResult<Py<PyArray1<f64>>> {
        let s = slice(&p);
        if s.len() != 3 {
            return Err(ModelError::new_err(format!(
                "SE3.act: a point has 3 coordinates, got {}",
                s.len()
            )));
        }
        let x = self.inner.act_point(&Vector3::new(s[0], s[1], s[2]));
        Ok(vector(py, x.as_slice()).unbind())
    }
    fn __mul__(&self, other: &PySe3) -> Self {
        Self {
            inner: self.inner * other.inner,
        }
    }
    fn __repr__(&self) -> String {
        let (r, p) = (&self.inner.rotation, &self.inner.translation);
        format!(
            "corps.SE3(R=[[{:.6}, {:.6}, {:.6}], [{:.6}, {:.6}, {:.6}], [{:.6}, {:.6}, {:.6}]], p=[{:.6}, {:.6}, {:.6}])",
            r[(0, 0)], r[(0, 1)], r[(0, 2)], r[(1, 0)], r[(1, 1)], r[(1, 2)],
            r[(2, 0)], r[(2, 1)], r[(2, 2)], p[0], p[1], p[2]
        )
    }
}

/// The frame a Jacobian is expressed in (Pinocchio's `ReferenceFrame`).
#[pyclass(
    name = "ReferenceFrame",
    module = "corps",
    eq,
    eq_int,
    frozen,
    from_py_object
)]
#[derive(Clone, Copy, PartialEq)]
#[allow(non_camel_case_types, clippy::upper_case_acronyms)]
pub enum PyReferenceFrame {
    /// The frame itself: origin and axes of the frame.
    LOCAL,
    /// The world frame: twists at the world origin.
    WORLD,
    /// Origin at the frame, axes of the world.
    LOCAL_WORLD_ALIGNED,
}

impl From<PyReferenceFrame> for ReferenceFrame {
    fn from(r: PyReferenceFrame) -> Self {
        match r {
            PyReferenceFrame::LOCAL => ReferenceFrame::Local,
            PyReferenceFrame::WORLD => ReferenceFrame::World,
            PyReferenceFrame::LOCAL_WORLD_ALIGNED => ReferenceFrame::LocalWorldAligned,
        }
    }
}

/// A frame given by id or by name.
#[derive(FromPyObject)]
pub enum FrameRef {
    Id(usize),
    Name(String),
}

impl FrameRef {
    /// The frame's id in `model`.
    pub fn id(&self, model: &Model) -> PyResult<usize> {
        match self {
            FrameRef::Id(i) if *i < model.frames.len() => Ok(*i),
            FrameRef::Id(i) => Err(ModelError::new_err(format!(
                "frame id {i} out of range (the model has {} frames)",
                model.frames.len()
            ))),
            FrameRef::Name(n) => model.frame_id(n).map_err(model_error),
        }
    }
}

/// A random configuration within the joint limits (free-flyer position in ±1 m, uniform
/// orientation); `seed` makes it reproducible.
pub fn random_configuration(model: &Model, seed: Option<u64>) -> nalgebra::DVector<f64> {
    let mut rng = match seed {
        Some(s) => rand_chacha::ChaCha8Rng::seed_from_u64(s),
        None => rand_chacha::ChaCha8Rng::from_entropy(),
    };
    corps_model::random_configuration(model, &mut rng)
}
