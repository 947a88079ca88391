//! `[mocap]`: the operator a teleoperation scenario follows (seed 001 ch. 6) — a recorded
//! clip (`source = "bvh"`, `file`) or a live stream (`source = "udp"`, `listen`, the skeleton's
//! hierarchy from `file`), retargeted through a mapping file (`mapping`, [`corps_mocap::retarget`]).
//!
//! ```toml
//! [mocap]
//! file = "../../../shared/data/mocap/dataset-1_bye_normal_001.bvh"
//! source = "bvh"
//! mapping = "../../config/icub/retargeting.toml"
//! ```

use crate::error::{invalid, Result};
use corps_mocap::bvh::Bvh;
use corps_mocap::retarget::Mapping;
use corps_mocap::source::{ClipSource, MocapSource};
use corps_mocap::stream::UdpSource;
use serde::Deserialize;
use std::path::Path;

/// Where the operator's poses come from.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum MocapSourceKind {
    #[default]
    Bvh,
    Udp,
}

/// `[mocap]`.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct MocapSection {
    /// The clip (bvh), or a file whose HIERARCHY is the stream's skeleton (udp).
    pub file: String,
    #[serde(default)]
    pub source: MocapSourceKind,
    /// The retargeting mapping file.
    pub mapping: String,
    /// The address a udp source listens on.
    pub listen: Option<String>,
    /// No new pose for this long (s): the feed is lost and the robot holds still.
    #[serde(default = "half_second")]
    pub timeout: f64,
}

fn half_second() -> f64 {
    0.5
}

/// The section's source, its mapping and the clip (whose frame `skeleton.rest_frame` of the
/// mapping is the operator's rest pose, for a stream too).
pub struct Operator {
    pub source: Box<dyn MocapSource>,
    pub mapping: Mapping,
    pub clip: Bvh,
}

impl MocapSection {
    /// Reads the files (relative to `base_dir`) and opens the source: every fault of the
    /// clip or the mapping is an error before the robot moves.
    pub fn open(&self, base_dir: &Path) -> Result<Operator> {
        if !(self.timeout.is_finite() && self.timeout > 0.0) {
            return Err(invalid!("mocap.timeout: must be > 0 s"));
        }
        let mapping = Mapping::read(&base_dir.join(&self.mapping))
            .map_err(|e| invalid!("mocap.mapping: {e}"))?;
        let clip =
            Bvh::read(&base_dir.join(&self.file)).map_err(|e| invalid!("mocap.file: {e}"))?;
        let source: Box<dyn MocapSource> = match self.source {
            MocapSourceKind::Bvh => {
                if self.listen.is_some() {
                    return Err(invalid!("mocap.listen: only with source = \"udp\""));
                }
                let mut s = ClipSource::new(clip.clone(), mapping.units());
                s.timeout = self.timeout;
                Box::new(s)
            }
            MocapSourceKind::Udp => {
                let Some(listen) = &self.listen else {
                    return Err(invalid!(
                        "mocap.listen: source = \"udp\" needs an address to listen on"
                    ));
                };
                let mut s = UdpSource::bind(listen, &clip, mapping.units())
                    .map_err(|e| invalid!("mocap: {e}"))?;
                s.timeout = self.timeout;
                Box::new(s)
            }
        };
        Ok(Operator {
            source,
            mapping,
            clip,
        })
    }
}
