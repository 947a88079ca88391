//! Operational frames attached to joints: links, joints, fixed joints.

use crate::spatial::Se3;

/// What a frame stands for, as in Pinocchio's `FrameType`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FrameKind {
    /// The world frame.
    Universe,
    /// The frame of a moving joint.
    Joint,
    /// The frame of a fixed joint (merged into its parent body).
    FixedJoint,
    /// A link (body) frame.
    Body,
}

impl FrameKind {
    /// Pinocchio's spelling of the kind.
    pub fn as_str(&self) -> &'static str {
        match self {
            FrameKind::Universe => "OP_FRAME",
            FrameKind::Joint => "JOINT",
            FrameKind::FixedJoint => "FIXED_JOINT",
            FrameKind::Body => "BODY",
        }
    }
}

/// A named frame rigidly attached to a joint.
#[derive(Clone, Debug, PartialEq)]
pub struct Frame {
    /// Name (link or joint name).
    pub name: String,
    /// Kind.
    pub kind: FrameKind,
    /// The joint it moves with (None = the world).
    pub parent_joint: Option<usize>,
    /// Placement in the parent joint's frame.
    pub placement: Se3,
}
