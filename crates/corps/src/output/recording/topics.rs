//! The topics of a recording or a live stream, with their Foxglove schema names and JSON
//! schemas, and where their messages go ([`Publish`]: an MCAP file or a live stream).

use super::schemas;
use anyhow::Result;
use std::path::PathBuf;

/// A topic of the scene.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Topic {
    /// `foxglove.FrameTransforms`: world → each joint frame.
    Tf,
    /// `foxglove.SceneUpdate`: the robot's shapes locked to the joint frames, sent once.
    Robot,
    /// `foxglove.SceneUpdate` in the world frame: CoM, ZMP, support polygon, forces, prints.
    Markers,
    /// `corps.Signals`: one log row.
    Signals,
    /// `foxglove.SceneUpdate` in the world frame: the operator's skeleton beside the robot
    /// (teleoperation runs from a clip).
    Operator,
}

impl Topic {
    /// The topics of every scene (a live stream advertises these).
    pub const ALL: [Topic; 4] = [Topic::Tf, Topic::Robot, Topic::Markers, Topic::Signals];
    /// Every topic a recording may hold: [`Topic::ALL`] and the operator's.
    pub const COUNT: usize = 5;

    pub fn name(self) -> &'static str {
        match self {
            Topic::Tf => "/tf",
            Topic::Robot => "/robot",
            Topic::Markers => "/markers",
            Topic::Signals => "/signals",
            Topic::Operator => "/operator",
        }
    }

    pub fn schema_name(self) -> &'static str {
        match self {
            Topic::Tf => "foxglove.FrameTransforms",
            Topic::Robot | Topic::Markers | Topic::Operator => "foxglove.SceneUpdate",
            Topic::Signals => "corps.Signals",
        }
    }

    pub fn schema(self) -> &'static str {
        match self {
            Topic::Tf => schemas::FRAME_TRANSFORMS,
            Topic::Robot | Topic::Markers | Topic::Operator => schemas::SCENE_UPDATE,
            Topic::Signals => schemas::SIGNALS,
        }
    }

    /// Position in [`Topic::ALL`], then [`Topic::Operator`].
    pub fn index(self) -> usize {
        self as usize
    }
}

/// Where a scene's messages go: each JSON message on its topic at controlled time `t` (s).
pub trait Publish: Send {
    fn publish(&mut self, topic: Topic, t: f64, json: Vec<u8>) -> Result<()>;
    /// Ends the output; the file it wrote, if any.
    fn finish(self: Box<Self>) -> Result<Option<PathBuf>>;
}
