//! The model's bodies, frames and collision shapes as plain Python data, for building the same
//! robot in another engine (the MuJoCo plant builds its scene from these, so both plants
//! simulate one model: the same masses, inertias, locked joints and added bodies).

use crate::arrays::{homogeneous, matrix, vector};
use crate::model::{FrameRef, PyModel, PySe3};
use corps_model::{JointKind, Shape};
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// `Model.bodies()`.
pub fn bodies<'py>(model: &PyModel, py: Python<'py>) -> PyResult<Vec<Bound<'py, PyDict>>> {
    let m = &*model.inner;
    let mut out = Vec::with_capacity(m.njoints());
    for (i, j) in m.joints.iter().enumerate() {
        let d = PyDict::new(py);
        let (kind, axis) = match j.kind {
            JointKind::FreeFlyer => ("free", None),
            JointKind::Revolute { axis } => ("revolute", Some(axis)),
            JointKind::RevoluteUnbounded { axis } => ("continuous", Some(axis)),
            JointKind::Prismatic { axis } => ("prismatic", Some(axis)),
        };
        d.set_item("name", &j.name)?;
        d.set_item("parent", j.parent)?;
        d.set_item("kind", kind)?;
        d.set_item("axis", axis.map(|a| vector(py, a.as_slice())))?;
        d.set_item("placement", homogeneous(py, &j.placement))?;
        d.set_item("idx_q", j.idx_q)?;
        d.set_item("idx_v", j.idx_v)?;
        let inertia = &m.inertias[i];
        d.set_item("mass", inertia.mass)?;
        d.set_item("com", vector(py, inertia.lever.as_slice()))?;
        d.set_item("inertia", matrix(py, &inertia.inertia))?;
        let effort = (j.kind != JointKind::FreeFlyer).then(|| m.effort_limit[j.idx_v]);
        d.set_item("effort", effort)?;
        out.push(d);
    }
    Ok(out)
}

/// `Model.collisions()`.
pub fn collisions<'py>(model: &PyModel, py: Python<'py>) -> PyResult<Vec<Bound<'py, PyDict>>> {
    let mut out = Vec::new();
    for c in &model.inner.collisions {
        let d = PyDict::new(py);
        match &c.shape {
            Shape::Box { size } => {
                d.set_item("shape", "box")?;
                d.set_item("size", vector(py, size.as_slice()))?;
            }
            Shape::Cylinder { radius, length } => {
                d.set_item("shape", "cylinder")?;
                d.set_item("radius", radius)?;
                d.set_item("length", length)?;
            }
            Shape::Sphere { radius } => {
                d.set_item("shape", "sphere")?;
                d.set_item("radius", radius)?;
            }
            Shape::Mesh { .. } => continue,
        }
        d.set_item("link", &c.link)?;
        d.set_item("joint", c.parent_joint)?;
        d.set_item("placement", homogeneous(py, &c.placement))?;
        out.push(d);
    }
    Ok(out)
}

/// `Model.frame_attachment()`.
pub fn frame_attachment(model: &PyModel, frame: FrameRef) -> PyResult<(Option<usize>, PySe3)> {
    let id = frame.id(&model.inner)?;
    let f = &model.inner.frames[id];
    Ok((f.parent_joint, PySe3 { inner: f.placement }))
}
