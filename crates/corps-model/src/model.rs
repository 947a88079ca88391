//! The immutable robot model: kinematic tree, inertias, frames, limits, collision shapes.

use crate::error::{ModelError, Result};
use crate::frame::{Frame, FrameKind};
use crate::geometry::CollisionGeometry;
use crate::joint::Joint;
use crate::spatial::Inertia;
use nalgebra::{DVector, Vector3};

/// Gravity's magnitude every part of corps uses by default (m/s²; seed 000 §3.3 and seed 002
/// §2 use 9.81). A model's `gravity` and a simulation's may differ; this is the one default.
pub const STANDARD_GRAVITY: f64 = 9.81;

/// A robot model. Built once (from URDF), then shared immutably by every part of a run;
/// all mutable buffers live in [`crate::Data`].
///
/// Joints are numbered 0..n in Pinocchio's depth-first order; `None` as a parent is the world.
#[derive(Clone, Debug)]
pub struct Model {
    /// Robot name from the URDF.
    pub name: String,
    /// Moving joints, parents before children.
    pub joints: Vec<Joint>,
    /// Inertia of the body each joint moves (fixed children merged), in the joint frame.
    pub inertias: Vec<Inertia>,
    /// Operational frames (links, joints, fixed joints).
    pub frames: Vec<Frame>,
    /// Configuration size.
    pub nq: usize,
    /// Velocity size.
    pub nv: usize,
    /// Lower position limits (size nq).
    pub lower_position_limit: DVector<f64>,
    /// Upper position limits (size nq).
    pub upper_position_limit: DVector<f64>,
    /// Velocity limits (size nv).
    pub velocity_limit: DVector<f64>,
    /// Effort limits (size nv).
    pub effort_limit: DVector<f64>,
    /// Gravity vector in the world frame (m/s²).
    pub gravity: Vector3<f64>,
    /// Named reference configurations (from SRDF `group_state`).
    pub reference_configurations: Vec<(String, DVector<f64>)>,
    /// Collision shapes (for the simulator).
    pub collisions: Vec<CollisionGeometry>,
    /// Visual shapes (meshes by the file name the URDF gives), placed as the collisions are:
    /// for viewers; no algorithm reads them.
    pub visuals: Vec<CollisionGeometry>,
    /// Number of velocity entries in the subtree of each joint (itself included).
    pub subtree_nv: Vec<usize>,
    /// For each velocity index, the velocity index of its parent in the tree (for the
    /// branch-induced sparse factorization of M); None at a root.
    pub dof_parent: Vec<Option<usize>>,
    /// For each velocity index, the joint it belongs to.
    pub dof_joint: Vec<usize>,
    /// The ancestors of every velocity index (nearest first), flattened: those of `k` are
    /// `dof_ancestors[dof_ancestors_start[k]..dof_ancestors_start[k + 1]]`. The sparse
    /// factorization walks them as slices instead of chasing parent links.
    pub dof_ancestors: Vec<usize>,
    pub dof_ancestors_start: Vec<usize>,
    /// The same ancestors as runs of consecutive velocity indices `(lo, hi)` (inclusive),
    /// nearest run first (a limb, then the torso, then the base): those of `k` are
    /// `dof_ancestor_runs[dof_ancestor_runs_start[k]..dof_ancestor_runs_start[k + 1]]`.
    pub dof_ancestor_runs: Vec<(usize, usize)>,
    pub dof_ancestor_runs_start: Vec<usize>,
}

impl Model {
    /// The ancestors of velocity index `k`, nearest first (empty at a root).
    #[inline]
    pub fn dof_ancestors(&self, k: usize) -> &[usize] {
        &self.dof_ancestors[self.dof_ancestors_start[k]..self.dof_ancestors_start[k + 1]]
    }

    /// The ancestors of velocity index `k` as runs `(lo, hi)` of consecutive indices, nearest
    /// first; within a run the chain goes `hi, hi − 1, …, lo`.
    #[inline]
    pub fn dof_ancestor_runs(&self, k: usize) -> &[(usize, usize)] {
        &self.dof_ancestor_runs
            [self.dof_ancestor_runs_start[k]..self.dof_ancestor_runs_start[k + 1]]
    }

    /// Number of moving joints.
    pub fn njoints(&self) -> usize {
        self.joints.len()
    }

    /// Whether the root joint is a free-flyer.
    pub fn has_free_flyer(&self) -> bool {
        matches!(
            self.joints.first().map(|j| j.kind),
            Some(crate::JointKind::FreeFlyer)
        )
    }

    /// Index of the first actuated velocity: 6 after a free-flyer root, else 0.
    pub fn first_actuated(&self) -> usize {
        if self.has_free_flyer() {
            6
        } else {
            0
        }
    }

    /// Number of actuated degrees of freedom (`nv` less the free-flyer's 6).
    pub fn na(&self) -> usize {
        self.nv - self.first_actuated()
    }

    /// Total mass of the robot.
    pub fn total_mass(&self) -> f64 {
        self.inertias.iter().map(|i| i.mass).sum()
    }

    /// Index of the joint named `name`.
    pub fn joint_id(&self, name: &str) -> Result<usize> {
        self.joints
            .iter()
            .position(|j| j.name == name)
            .ok_or_else(|| ModelError::UnknownJoint(name.to_string()))
    }

    /// Index of the frame named `name`. A name that is both a link and a joint returns the
    /// first frame registered with it (Pinocchio's rule).
    pub fn frame_id(&self, name: &str) -> Result<usize> {
        self.frames
            .iter()
            .position(|f| f.name == name)
            .ok_or_else(|| ModelError::UnknownFrame(name.to_string()))
    }

    /// The frame with a name and a kind.
    pub fn frame_id_of_kind(&self, name: &str, kind: FrameKind) -> Result<usize> {
        self.frames
            .iter()
            .position(|f| f.name == name && f.kind == kind)
            .ok_or_else(|| ModelError::UnknownFrame(name.to_string()))
    }

    /// The named reference configuration (e.g. TALOS `half_sitting`).
    pub fn reference_configuration(&self, name: &str) -> Result<&DVector<f64>> {
        self.reference_configurations
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, q)| q)
            .ok_or_else(|| ModelError::UnknownConfiguration {
                name: name.to_string(),
                known: self
                    .reference_configurations
                    .iter()
                    .map(|(n, _)| n.as_str())
                    .collect::<Vec<_>>()
                    .join(", "),
            })
    }

    /// Whether joint `ancestor` is `joint` or one of its ancestors.
    pub fn supports(&self, ancestor: usize, joint: usize) -> bool {
        let mut j = Some(joint);
        while let Some(i) = j {
            if i == ancestor {
                return true;
            }
            j = self.joints[i].parent;
        }
        false
    }

    /// The joints of `joint`'s subtree, itself first: a contiguous range, since the subtree's
    /// velocity entries are the contiguous `idx_v .. idx_v + subtree_nv` (the layout CRBA's
    /// block structure relies on) and joints are numbered in the order of their entries.
    pub fn subtree_joints(&self, joint: usize) -> std::ops::Range<usize> {
        let nv = self.subtree_nv[joint];
        let end = match nv {
            0 => joint + 1,
            _ => self.dof_joint[self.joints[joint].idx_v + nv - 1] + 1,
        };
        joint..end
    }

    /// Checks a configuration vector: size nq, all finite.
    pub fn check_configuration(&self, q: &[f64]) -> Result<()> {
        check_vector("configuration q", q, self.nq)
    }

    /// Checks a velocity-sized vector (v, a, τ): size nv, all finite.
    pub fn check_tangent(&self, what: &'static str, v: &[f64]) -> Result<()> {
        check_vector(what, v, self.nv)
    }
}

/// Size and finiteness check of a state vector.
pub fn check_vector(what: &'static str, x: &[f64], expected: usize) -> Result<()> {
    if x.len() != expected {
        return Err(ModelError::Dimension {
            what,
            got: x.len(),
            expected,
        });
    }
    match x.iter().position(|v| !v.is_finite()) {
        Some(index) => Err(ModelError::NonFinite { what, index }),
        None => Ok(()),
    }
}
