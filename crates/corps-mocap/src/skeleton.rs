//! A human skeleton's pose from one frame of channel values: each joint's rotation in its
//! parent (the product of its rotation channels in the listed order, degrees) and its
//! placement in corps' world (z up, metres). A joint with position channels is placed at
//! those values in its parent (they replace its OFFSET, as motion-capture exporters that write
//! six channels per joint mean them), one without at its OFFSET.

use crate::bvh::{Bvh, BvhJoint};
use nalgebra::{Isometry3, Matrix3, Rotation3, Translation3, UnitQuaternion, Vector3};

/// How a file's numbers map to corps' world.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Units {
    /// Metres per file unit (0.01: centimetres).
    pub length: f64,
    /// The file's vertical axis: 1 (y up, most BVH exporters) or 2 (z up).
    pub up: usize,
}

impl Default for Units {
    /// Centimetres, y up.
    fn default() -> Units {
        Units {
            length: 0.01,
            up: 1,
        }
    }
}

/// A skeleton: the hierarchy of a BVH file and how its numbers map to corps' world.
#[derive(Clone, Debug)]
pub struct Skeleton {
    pub joints: Vec<BvhJoint>,
    /// Channel values per frame.
    pub channels: usize,
    pub units: Units,
    /// File axes to corps' (a proper rotation: y up → corps x = file z, y = file x, z = file y).
    to_world: Rotation3<f64>,
}

/// One pose of the skeleton.
#[derive(Clone, Debug, PartialEq)]
pub struct Pose {
    /// Seconds since the first frame.
    pub time: f64,
    /// Each joint's rotation in its parent's frame.
    pub local: Vec<UnitQuaternion<f64>>,
    /// Each joint's frame in corps' world (z up, m).
    pub world: Vec<Isometry3<f64>>,
}

impl Skeleton {
    /// The skeleton of `bvh`.
    pub fn new(bvh: &Bvh, units: Units) -> Skeleton {
        let m = if units.up == 2 {
            Matrix3::identity()
        } else {
            Matrix3::new(0.0, 0.0, 1.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0)
        };
        Skeleton {
            joints: bvh.joints.clone(),
            channels: bvh.channels,
            units,
            to_world: Rotation3::from_matrix_unchecked(m),
        }
    }

    /// The index of the joint named `name`.
    pub fn joint(&self, name: &str) -> Option<usize> {
        self.joints.iter().position(|j| j.name == name)
    }

    /// A pose with every joint at identity, to be filled by [`Skeleton::pose_into`].
    pub fn empty_pose(&self) -> Pose {
        Pose {
            time: 0.0,
            local: vec![UnitQuaternion::identity(); self.joints.len()],
            world: vec![Isometry3::identity(); self.joints.len()],
        }
    }

    /// The pose of one frame's `values` (`channels` of them) at `time`.
    pub fn pose(&self, values: &[f64], time: f64) -> Pose {
        let mut p = self.empty_pose();
        self.pose_into(values, time, &mut p);
        p
    }

    /// [`Skeleton::pose`] into `out` (no allocation).
    pub fn pose_into(&self, values: &[f64], time: f64, out: &mut Pose) {
        out.time = time;
        let scale = self.units.length;
        let to_world = UnitQuaternion::from_rotation_matrix(&self.to_world);
        for (k, j) in self.joints.iter().enumerate() {
            let mut rotation = UnitQuaternion::identity();
            let mut position = j.offset;
            for (c, channel) in j.channels.iter().enumerate() {
                let v = values.get(j.first_channel + c).copied().unwrap_or(0.0);
                let (axis, is_rotation) = channel.axis();
                if is_rotation {
                    let a = Vector3::ith_axis(axis);
                    rotation *= UnitQuaternion::from_axis_angle(&a, v.to_radians());
                } else {
                    position[axis] = v;
                }
            }
            out.local[k] = rotation;
            let local = Isometry3::from_parts(Translation3::from(position * scale), rotation);
            out.world[k] = match j.parent {
                Some(p) => out.world[p] * local,
                None => {
                    // The root: file axes to corps' (positions scaled, orientation turned).
                    let t = self.to_world * (position * scale);
                    Isometry3::from_parts(Translation3::from(t), to_world * rotation)
                }
            };
        }
    }
}
