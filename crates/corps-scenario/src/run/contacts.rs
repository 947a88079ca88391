//! The ground forces of one tick, from the plant's true contact points.

use corps_control::stabilizer::Wrench;
use corps_loop::Truth;
use corps_model::spatial::Se3;
use nalgebra::Vector3;

/// Vertical force (N) below which the ZMP is not defined (the robot is in the air).
pub(crate) const ZMP_MIN_FZ: f64 = corps_estimation::ZMP_MIN_FORCE;

/// Contact forces of one tick.
pub(crate) struct ContactSample {
    /// ZMP (world x, y) from the ankle F/T wrenches, None when the robot is in the air
    /// (filled once the estimator has read the sensors).
    pub zmp: Option<[f64; 2]>,
    /// Height of the contact plane (force-weighted mean height of the loaded points).
    pub plane_z: f64,
    /// Vertical force on each foot (N).
    pub foot_fz: [f64; 2],
    /// Each foot's wrench in its sole frame, about the sole origin.
    pub foot_wrenches: [Wrench; 2],
    /// Total force on other bodies (N).
    pub other: f64,
    /// Norm of the total contact force (N).
    pub total: f64,
}

/// The contact plane's height, each foot's vertical force and wrench in its sole frame
/// `soles[k]` about the sole origin (feet are the bodies of `foot_joints`), the force on
/// other bodies and the total. Contact on the body of `tool_joint` (a `[press]` tool, which
/// is meant to touch) counts in the total only.
pub(crate) fn measure(
    truth: &Truth,
    foot_joints: &[usize; 2],
    tool_joint: Option<usize>,
    soles: &[Se3; 2],
) -> ContactSample {
    let (mut fz, mut zf) = (0.0, 0.0);
    let mut foot_fz = [0.0; 2];
    let mut world = [(Vector3::zeros(), Vector3::zeros()); 2];
    let mut other = 0.0;
    let mut total = Vector3::zeros();
    for c in &truth.contacts {
        let (f, p) = (&c.force, &c.position);
        total += f;
        if Some(c.joint) == tool_joint {
            continue;
        }
        fz += f.z;
        zf += p.z * f.z;
        match foot_joints.iter().position(|j| *j == c.joint) {
            Some(k) => {
                foot_fz[k] += f.z;
                world[k].0 += f;
                world[k].1 += (p - soles[k].translation).cross(f);
            }
            None => other += f.norm(),
        }
    }
    let foot_wrenches = [0, 1].map(|k| {
        let rt = soles[k].rotation.transpose();
        Wrench::new(rt * world[k].0, rt * world[k].1)
    });
    ContactSample {
        zmp: None,
        plane_z: if fz < ZMP_MIN_FZ { 0.0 } else { zf / fz },
        foot_fz,
        foot_wrenches,
        other,
        total: total.norm(),
    }
}
