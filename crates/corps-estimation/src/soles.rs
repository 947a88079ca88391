//! Feet from force/torque sensors: the wrench a sensor reads, moved to the sole frame of its
//! foot, and the ZMP of the loaded feet.

use crate::FootEstimate;
use corps_model::spatial::{Force, Se3};
use nalgebra::{Vector2, Vector3, Vector6};

/// Total normal force (N) below which the ZMP is undefined (the robot is in the air).
pub const ZMP_MIN_FORCE: f64 = 10.0;

/// The reading `[f; τ]` of a sensor at placement `sole_m_sensor` in the sole frame, as the
/// wrench in the sole frame about the sole origin: `f_s = R f`, `τ_s = R τ + t × R f`.
pub(crate) fn sensor_to_sole(sole_m_sensor: &Se3, reading: &[f64; 6]) -> Vector6<f64> {
    let f = Force::from_vector(&Vector6::from_row_slice(reading));
    sole_m_sensor.act_force(&f).to_vector()
}

/// ZMP (world x, y) of the loaded feet (positive normal force: the ZMP weighs every foot by
/// its force, whatever the contact detection decided), on the plane at the force-weighted
/// mean height of their soles. With each foot's world force `f` applied at its sole origin `o` with couple
/// `τ` (world axes), the horizontal moment about `p = (x, y, z_p)` vanishes:
/// `x = Σ (o_x f_z − (o_z − z_p) f_x − τ_y) / Σ f_z`, `y = Σ (o_y f_z − (o_z − z_p) f_y + τ_x) / Σ f_z`.
/// `None` when the feet carry less than [`ZMP_MIN_FORCE`].
pub fn zmp_of_feet(feet: &[FootEstimate]) -> Option<Vector2<f64>> {
    let world = |foot: &FootEstimate| {
        let r = foot.placement.rotation;
        let f = r * Vector3::new(foot.wrench[0], foot.wrench[1], foot.wrench[2]);
        let tau = r * Vector3::new(foot.wrench[3], foot.wrench[4], foot.wrench[5]);
        (foot.placement.translation, f, tau)
    };
    let (mut fz, mut zf) = (0.0, 0.0);
    for foot in feet.iter().filter(|f| f.wrench[2] > 0.0) {
        let (o, f, _) = world(foot);
        fz += f.z;
        zf += o.z * f.z;
    }
    if fz < ZMP_MIN_FORCE {
        return None;
    }
    let plane = zf / fz;
    let (mut x, mut y) = (0.0, 0.0);
    for foot in feet.iter().filter(|f| f.wrench[2] > 0.0) {
        let (o, f, tau) = world(foot);
        x += o.x * f.z - (o.z - plane) * f.x - tau.y;
        y += o.y * f.z - (o.z - plane) * f.y + tau.x;
    }
    Some(Vector2::new(x / fz, y / fz))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn foot(x: f64, y: f64, wrench: [f64; 6]) -> FootEstimate {
        FootEstimate {
            placement: Se3::new(nalgebra::Matrix3::identity(), Vector3::new(x, y, 0.1)),
            wrench: Vector6::from_row_slice(&wrench),
            in_contact: true,
        }
    }

    #[test]
    fn the_zmp_of_point_forces_is_their_centre_of_pressure() {
        // 300 N at (0, 0.1) and 100 N at (0.2, -0.1): CoP (0.05, 0.05).
        let feet = [
            foot(0.0, 0.1, [0.0, 0.0, 300.0, 0.0, 0.0, 0.0]),
            foot(0.2, -0.1, [0.0, 0.0, 100.0, 0.0, 0.0, 0.0]),
        ];
        let p = zmp_of_feet(&feet).unwrap();
        assert!((p - Vector2::new(0.05, 0.05)).norm() < 1e-12, "{p}");
    }

    #[test]
    fn a_couple_moves_the_zmp_as_a_force_off_the_sole_origin_does() {
        // 400 N at 2 cm ahead of the sole origin: τ_y = −(0.02 · 400) about the origin.
        let moved = foot(0.0, 0.0, [0.0, 0.0, 400.0, 0.0, -8.0, 0.0]);
        let p = zmp_of_feet(&[moved]).unwrap();
        assert!((p - Vector2::new(0.02, 0.0)).norm() < 1e-12, "{p}");
        // The same force read by a sensor 5 cm above the sole, 2 cm ahead.
        let sole_m_sensor = Se3::new(nalgebra::Matrix3::identity(), Vector3::new(0.02, 0.0, 0.05));
        let w = sensor_to_sole(&sole_m_sensor, &[0.0, 0.0, 400.0, 0.0, 0.0, 0.0]);
        assert!((w[4] - (-8.0)).abs() < 1e-12, "{w}");
    }

    #[test]
    fn unloaded_feet_have_no_zmp() {
        let f = foot(0.0, 0.0, [0.0, 0.0, 5.0, 0.0, 0.0, 0.0]);
        assert!(zmp_of_feet(&[f]).is_none());
        let pulled = foot(0.0, 0.0, [0.0, 0.0, -500.0, 0.0, 0.0, 0.0]);
        assert!(zmp_of_feet(&[pulled]).is_none());
    }
}
