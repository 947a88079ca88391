//! Where the operator's poses come from: a recorded clip ([`ClipSource`]) or a live stream
//! ([`crate::stream::UdpSource`]) behind one trait. A control tick asks for the pose at its
//! time and never waits: a source always answers with the newest pose it has and how fresh
//! it is.

use crate::bvh::Bvh;
use crate::skeleton::{Pose, Skeleton, Units};

/// How fresh a source's pose is.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Feed {
    /// A pose of the operator now.
    Live,
    /// No new pose for `since` s (a stream that paused, a clip that ended): the last is held.
    Holding { since: f64 },
    /// No new pose for longer than the source's timeout: the robot should come to a still
    /// double support.
    Lost,
    /// No pose yet.
    Waiting,
}

impl Feed {
    /// The feed of a pose `since` s old: live within `hold`, held within `timeout`, then lost.
    pub fn aged(since: f64, hold: f64, timeout: f64) -> Feed {
        if since <= hold {
            Feed::Live
        } else if since <= timeout {
            Feed::Holding { since }
        } else {
            Feed::Lost
        }
    }
}

/// A source of the operator's poses.
pub trait MocapSource: Send {
    /// The operator's skeleton.
    fn skeleton(&self) -> &Skeleton;
    /// The newest pose at time `t` (s since the source started) and how fresh it is. Never
    /// blocks; never allocates after the first call.
    fn poll(&mut self, t: f64) -> (&Pose, Feed);
}

/// A recorded clip played at its own rate: the frame at `t` (the last one held after the end).
pub struct ClipSource {
    bvh: Bvh,
    skeleton: Skeleton,
    pose: Pose,
    frame: Option<usize>,
    /// After the end, how long the last pose counts as held before the feed is lost (s).
    pub timeout: f64,
}

impl ClipSource {
    /// Plays `bvh` read with `units`.
    pub fn new(bvh: Bvh, units: Units) -> ClipSource {
        let skeleton = Skeleton::new(&bvh, units);
        let pose = skeleton.empty_pose();
        ClipSource {
            bvh,
            skeleton,
            pose,
            frame: None,
            timeout: 0.5,
        }
    }

    /// The clip's duration (s): its last frame's time.
    pub fn duration(&self) -> f64 {
        (self.bvh.frames().saturating_sub(1)) as f64 * self.bvh.frame_time
    }

    /// The clip.
    pub fn bvh(&self) -> &Bvh {
        &self.bvh
    }
}

impl MocapSource for ClipSource {
    fn skeleton(&self) -> &Skeleton {
        &self.skeleton
    }

    fn poll(&mut self, t: f64) -> (&Pose, Feed) {
        let frames = self.bvh.frames();
        if frames == 0 || !t.is_finite() || t < 0.0 {
            return (&self.pose, Feed::Waiting);
        }
        let k = ((t / self.bvh.frame_time + 1e-9).floor() as usize).min(frames - 1);
        if self.frame != Some(k) {
            self.skeleton.pose_into(
                self.bvh.frame(k),
                k as f64 * self.bvh.frame_time,
                &mut self.pose,
            );
            self.frame = Some(k);
        }
        let since = t - self.duration();
        let feed = Feed::aged(since, self.bvh.frame_time, self.timeout);
        (&self.pose, feed)
    }
}
