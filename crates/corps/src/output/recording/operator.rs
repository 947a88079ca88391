//! The operator a teleoperation run follows, drawn beside the robot: the recorded clip's
//! skeleton (one line per bone, a dot per joint) at the frame the controller reads at the
//! same time (the frame at `t`, the last one held after the clip ends).

use corps_mocap::bvh::Bvh;
use corps_mocap::skeleton::Units;
use corps_mocap::source::{ClipSource, MocapSource};
use nalgebra::Vector3;

/// How far to the robot's left (+y) the operator stands in the view (m).
pub const BESIDE: f64 = 1.0;

/// A clip's skeleton placed beside the robot, read through the controller's own source.
pub struct OperatorView {
    source: ClipSource,
    /// World shift of the clip: its first frame's root over the point `BESIDE` to the left
    /// of the robot's first CoM, its lowest joint on the ground; set at the first view.
    shift: Option<Vector3<f64>>,
}

impl OperatorView {
    /// The view of `clip`, read with `units`.
    pub fn new(clip: Bvh, units: Units) -> OperatorView {
        OperatorView {
            source: ClipSource::new(clip, units),
            shift: None,
        }
    }

    /// The bones at time `t` as point pairs (a line list) and the joints, in the world;
    /// `robot_com` anchors the placement at the first call.
    pub fn at(
        &mut self,
        t: f64,
        robot_com: Vector3<f64>,
    ) -> (Vec<Vector3<f64>>, Vec<Vector3<f64>>) {
        if self.source.bvh().frames() == 0 {
            return (Vec::new(), Vec::new());
        }
        let shift = match self.shift {
            Some(s) => s,
            None => {
                let (first, _) = self.source.poll(0.0);
                let root = first.world[0].translation.vector;
                let lowest = (first.world.iter())
                    .map(|w| w.translation.vector.z)
                    .fold(f64::INFINITY, f64::min);
                let s = Vector3::new(robot_com.x - root.x, robot_com.y + BESIDE - root.y, -lowest);
                self.shift = Some(s);
                s
            }
        };
        // Before the first frame (t < 0) the source has no pose: the first frame stands.
        let (pose, _) = self.source.poll(t.max(0.0));
        let joints: Vec<Vector3<f64>> = (pose.world.iter())
            .map(|w| w.translation.vector + shift)
            .collect();
        let bones = (self.source.skeleton().joints.iter().enumerate())
            .filter_map(|(i, j)| j.parent.map(|p| [joints[p], joints[i]]))
            .flatten()
            .collect();
        (bones, joints)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const CLIP: &str = "HIERARCHY
ROOT Hips
{
  OFFSET 0 0 0
  CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation
  JOINT LeftUpLeg
  {
    OFFSET 10 0 0
    CHANNELS 3 Zrotation Xrotation Yrotation
    End Site
    {
      OFFSET 0 -90 0
    }
  }
}
MOTION
Frames: 2
Frame Time: 0.5
0 100 0 0 0 0 0 0 0
50 100 0 0 0 0 0 0 0
";

    /// The skeleton stands on the ground beside the robot, its bones join its joints, and it
    /// moves with the clip's frames (the root 0.5 m along the file's x, corps' y, at 0.5 s).
    #[test]
    fn the_operator_stands_beside_the_robot_and_follows_the_clip() {
        let bvh = Bvh::parse(CLIP, "test.bvh").unwrap();
        let mut view = OperatorView::new(bvh, Units::default());
        let com = Vector3::new(0.2, -0.1, 0.9);
        let (bones, joints) = view.at(0.0, com);
        assert_eq!(joints.len(), 2);
        assert_eq!(bones, vec![joints[0], joints[1]]);
        assert!((joints[0].x - 0.2).abs() < 1e-12 && (joints[0].y - 0.9).abs() < 1e-12);
        let lowest = joints.iter().map(|j| j.z).fold(f64::INFINITY, f64::min);
        assert!(lowest.abs() < 1e-12, "{lowest}");
        let (_, later) = view.at(0.7, Vector3::zeros());
        assert!((later[0] - joints[0] - Vector3::new(0.0, 0.5, 0.0)).norm() < 1e-12);
    }
}
