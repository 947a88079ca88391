//! Joint models: the joint transform `M_J(q)` and its motion subspace `S`.

use crate::spatial::{rotation, Motion, Se3};
use nalgebra::{Matrix3, Vector3};

/// The kind of a joint, with its axis (unit, in the joint frame) where it has one.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum JointKind {
    /// 6-DoF root: q = [p; quaternion (x, y, z, w)], v = [linear; angular] in the local frame.
    FreeFlyer,
    /// Bounded rotation about `axis`: q = [θ], v = [θ̇].
    Revolute { axis: Vector3<f64> },
    /// Unbounded (URDF `continuous`) rotation: q = [cos θ, sin θ], v = [θ̇].
    RevoluteUnbounded { axis: Vector3<f64> },
    /// Translation along `axis`: q = [x], v = [ẋ].
    Prismatic { axis: Vector3<f64> },
}

impl JointKind {
    /// Size of this joint's configuration.
    pub fn nq(&self) -> usize {
        match self {
            JointKind::FreeFlyer => 7,
            JointKind::RevoluteUnbounded { .. } => 2,
            _ => 1,
        }
    }

    /// Size of this joint's velocity.
    pub fn nv(&self) -> usize {
        match self {
            JointKind::FreeFlyer => 6,
            _ => 1,
        }
    }

    /// A short name, as Pinocchio's shortnames read.
    pub fn short_name(&self) -> &'static str {
        match self {
            JointKind::FreeFlyer => "free-flyer",
            JointKind::Revolute { .. } => "revolute",
            JointKind::RevoluteUnbounded { .. } => "continuous",
            JointKind::Prismatic { .. } => "prismatic",
        }
    }

    /// The joint transform `M_J(q)` for this joint's slice of q.
    #[inline]
    pub fn transform(&self, q: &[f64]) -> Se3 {
        match self {
            JointKind::FreeFlyer => Se3::new(
                rotation::quat_to_matrix(q[3], q[4], q[5], q[6]),
                Vector3::new(q[0], q[1], q[2]),
            ),
            JointKind::Revolute { axis } => {
                let (s, c) = q[0].sin_cos();
                Se3::new(rotation::axis_angle_cs(axis, c, s), Vector3::zeros())
            }
            JointKind::RevoluteUnbounded { axis } => {
                Se3::new(rotation::axis_angle_cs(axis, q[0], q[1]), Vector3::zeros())
            }
            JointKind::Prismatic { axis } => Se3::new(Matrix3::identity(), axis * q[0]),
        }
    }

    /// `placement * M_J(q)`, with a fast path for rotations about a signed coordinate axis
    /// (only two columns of the rotation mix, instead of a full 3 × 3 product).
    #[inline]
    pub fn placed_transform(&self, placement: &Se3, q: &[f64]) -> Se3 {
        let (axis, c, s) = match self {
            JointKind::Revolute { axis } => {
                let (s, c) = q[0].sin_cos();
                (axis, c, s)
            }
            JointKind::RevoluteUnbounded { axis } => (axis, q[0], q[1]),
            _ => return *placement * self.transform(q),
        };
        match unit_axis(axis) {
            Some((k, sign)) => {
                let r = &placement.rotation;
                let s = s * sign;
                let (i, j) = ((k + 1) % 3, (k + 2) % 3);
                let (ci, cj) = (r.column(i), r.column(j));
                let mut out = *r;
                out.set_column(i, &(ci * c + cj * s));
                out.set_column(j, &(cj * c - ci * s));
                Se3::new(out, placement.translation)
            }
            None => *placement * Se3::new(rotation::axis_angle_cs(axis, c, s), Vector3::zeros()),
        }
    }

    /// The motion subspace column of a 1-DoF joint (None for the free-flyer, whose S = I).
    #[inline]
    pub fn axis_motion(&self) -> Option<Motion> {
        match self {
            JointKind::FreeFlyer => None,
            JointKind::Revolute { axis } | JointKind::RevoluteUnbounded { axis } => {
                Some(Motion::new(Vector3::zeros(), *axis))
            }
            JointKind::Prismatic { axis } => Some(Motion::new(*axis, Vector3::zeros())),
        }
    }

    /// The joint twist `S q̇` for this joint's slice of v.
    #[inline]
    pub fn motion(&self, v: &[f64]) -> Motion {
        match self.axis_motion() {
            Some(s) => s * v[0],
            None => Motion::from_slice(v),
        }
    }
}

/// `Some((k, ±1))` when `axis` is ± the k-th coordinate axis.
#[inline]
pub(crate) fn unit_axis(axis: &Vector3<f64>) -> Option<(usize, f64)> {
    for k in 0..3 {
        let (i, j) = ((k + 1) % 3, (k + 2) % 3);
        if axis[i] == 0.0 && axis[j] == 0.0 && axis[k].abs() == 1.0 {
            return Some((k, axis[k]));
        }
    }
    None
}

/// A joint of the kinematic tree.
#[derive(Clone, Debug, PartialEq)]
pub struct Joint {
    /// Name (from the URDF; `root_joint` for an added free-flyer).
    pub name: String,
    /// What kind of joint.
    pub kind: JointKind,
    /// Index of the parent joint (None = the world).
    pub parent: Option<usize>,
    /// Placement of this joint's frame in its parent joint's frame, at q = neutral.
    pub placement: Se3,
    /// First index of this joint in q.
    pub idx_q: usize,
    /// First index of this joint in v.
    pub idx_v: usize,
}

impl Joint {
    /// Size of this joint's configuration.
    pub fn nq(&self) -> usize {
        self.kind.nq()
    }
    /// Size of this joint's velocity.
    pub fn nv(&self) -> usize {
        self.kind.nv()
    }
}
