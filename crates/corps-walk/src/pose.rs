//! Foot poses (on flat ground or on a tilted foothold), feet names and angle helpers.

use nalgebra::{Matrix2, Rotation3, Vector2, Vector3};

/// Which foot.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Foot {
    /// Left foot (+y side when facing +x, REP-103).
    Left,
    /// Right foot.
    Right,
}

impl Foot {
    /// The other foot.
    pub fn other(self) -> Foot {
        match self {
            Foot::Left => Foot::Right,
            Foot::Right => Foot::Left,
        }
    }

    /// +1 for the left foot, −1 for the right (lateral side in the robot frame).
    pub fn side(self) -> f64 {
        match self {
            Foot::Left => 1.0,
            Foot::Right => -1.0,
        }
    }
}

/// A foot (sole-centre) pose: position, heading (yaw about the vertical) and the tilt of the
/// sole (roll and pitch, zero on flat ground). The sole's orientation is the Z-Y-X Euler
/// product `R = R_z(yaw) R_y(pitch) R_x(roll)`, so the yaw stays the heading of the foot's
/// x axis in the horizontal plane whatever the tilt.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct FootPose {
    /// x (m), world frame.
    pub x: f64,
    /// y (m), world frame.
    pub y: f64,
    /// z (m), sole height.
    pub z: f64,
    /// Yaw (rad) about +z, in (−π, π].
    pub yaw: f64,
    /// Roll (rad) of the sole about its x axis (0 on flat ground).
    pub roll: f64,
    /// Pitch (rad) of the sole about its y axis (0 on flat ground).
    pub pitch: f64,
}

impl FootPose {
    /// A pose on flat ground from its four coordinates (the yaw is wrapped to (−π, π]).
    pub fn new(x: f64, y: f64, z: f64, yaw: f64) -> Self {
        Self {
            x,
            y,
            z,
            yaw: wrap_angle(yaw),
            roll: 0.0,
            pitch: 0.0,
        }
    }

    /// A foot heading `yaw` with its sole on the plane of upward unit normal `normal` through
    /// `(x, y, z)`: the roll and pitch for which the sole's z axis `R e_z` is the normal.
    /// With `n' = R_z(−yaw) n`, `R_y(p) R_x(r) e_z = (sin p cos r, −sin r, cos p cos r)`, so
    /// `r = −asin n'_y` and `p = atan2(n'_x, n'_z)`. `None` unless the normal is finite and
    /// points up (`n_z > 0`).
    pub fn on_surface(x: f64, y: f64, z: f64, yaw: f64, normal: &Vector3<f64>) -> Option<Self> {
        let norm = normal.norm();
        if !(norm.is_finite() && norm > 0.0 && normal.z > 0.0) {
            return None;
        }
        let n = Rotation3::from_axis_angle(&Vector3::z_axis(), -yaw) * (normal / norm);
        Some(Self {
            roll: -n.y.clamp(-1.0, 1.0).asin(),
            pitch: n.x.atan2(n.z),
            ..Self::new(x, y, z, yaw)
        })
    }

    /// Orientation of the sole, `R_z(yaw) R_y(pitch) R_x(roll)`.
    pub fn rotation(&self) -> Rotation3<f64> {
        Rotation3::from_euler_angles(self.roll, self.pitch, self.yaw)
    }

    /// Upward unit normal of the sole, `R e_z`.
    pub fn sole_normal(&self) -> Vector3<f64> {
        self.rotation() * Vector3::z()
    }

    /// Position (m).
    pub fn position(&self) -> Vector3<f64> {
        Vector3::new(self.x, self.y, self.z)
    }

    /// Horizontal position.
    pub fn xy(&self) -> Vector2<f64> {
        Vector2::new(self.x, self.y)
    }

    /// A point given in this foot's frame (x forward, y left), in the world, projected on the
    /// horizontal plane: the tilt is ignored (a sole tilted by θ projects to a polygon shorter
    /// by a factor cos θ across the tilt axis, 1.5 % at 10°).
    pub fn transform(&self, local: &Vector2<f64>) -> Vector2<f64> {
        self.xy() + rotation(self.yaw) * local
    }
}

/// Time derivative of a [`FootPose`] (linear velocity and Euler-angle rates).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct FootVelocity {
    /// ẋ (m/s).
    pub x: f64,
    /// ẏ (m/s).
    pub y: f64,
    /// ż (m/s).
    pub z: f64,
    /// Yaw rate (rad/s).
    pub yaw: f64,
    /// Roll rate (rad/s).
    pub roll: f64,
    /// Pitch rate (rad/s).
    pub pitch: f64,
}

impl FootVelocity {
    /// Linear velocity (m/s).
    pub fn linear(&self) -> Vector3<f64> {
        Vector3::new(self.x, self.y, self.z)
    }

    /// World angular velocity of a foot at `pose` whose Euler angles change at these rates:
    /// for `R = R_z(ψ) R_y(θ) R_x(φ)`, `ω = ψ̇ e_z + θ̇ R_z(ψ) e_y + φ̇ R_z(ψ) R_y(θ) e_x`.
    pub fn angular(&self, pose: &FootPose) -> Vector3<f64> {
        let (sy, cy) = pose.yaw.sin_cos();
        let (sp, cp) = pose.pitch.sin_cos();
        let pitch_axis = Vector3::new(-sy, cy, 0.0);
        let roll_axis = Vector3::new(cy * cp, sy * cp, -sp);
        Vector3::z() * self.yaw + pitch_axis * self.pitch + roll_axis * self.roll
    }
}

/// Wraps an angle to (−π, π].
pub fn wrap_angle(a: f64) -> f64 {
    let two_pi = 2.0 * std::f64::consts::PI;
    let mut r = a % two_pi;
    if r <= -std::f64::consts::PI {
        r += two_pi;
    } else if r > std::f64::consts::PI {
        r -= two_pi;
    }
    r
}

/// Shortest signed angle from `from` to `to`, in (−π, π].
pub fn angle_difference(to: f64, from: f64) -> f64 {
    wrap_angle(to - from)
}

/// 2-D rotation matrix of angle `yaw`.
pub fn rotation(yaw: f64) -> Matrix2<f64> {
    let (s, c) = yaw.sin_cos();
    Matrix2::new(c, -s, s, c)
}

/// Waist (trunk) yaw from the feet yaws: their circular mean, `θ_l + wrap(θ_r − θ_l)/2`,
/// wrapped to (−π, π]. Seed 002 §4.4/§4.13: "the waist yaw is the average of the two feet
/// yaws", recomputed whenever the feet move (the stale-waist bug of R L714–731). A plain
/// arithmetic mean would give 0 for feet at ±(π − ε), i.e. a waist facing backwards.
pub fn waist_yaw(left_yaw: f64, right_yaw: f64) -> f64 {
    wrap_angle(left_yaw + 0.5 * angle_difference(right_yaw, left_yaw))
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    #[test]
    fn wrap_and_difference() {
        assert!((wrap_angle(3.0 * PI) - PI).abs() < 1e-12);
        assert!((wrap_angle(-PI) - PI).abs() < 1e-12);
        assert!((wrap_angle(0.5 - 4.0 * PI) - 0.5).abs() < 1e-12);
        assert!((angle_difference(-PI + 0.1, PI - 0.1) - 0.2).abs() < 1e-12);
    }

    #[test]
    fn a_foot_on_a_surface_has_its_sole_normal_along_the_surface_normal() {
        for &(yaw, n) in &[
            (0.0, Vector3::new(0.0, -0.17, 0.98)),
            (0.7, Vector3::new(0.2, 0.1, 0.9)),
            (-2.5, Vector3::new(-0.3, 0.25, 0.8)),
            (PI, Vector3::z()),
        ] {
            let f = FootPose::on_surface(0.1, 0.2, 0.05, yaw, &n).unwrap();
            assert!(
                (f.sole_normal() - n.normalize()).norm() < 1e-12,
                "{yaw} {n:?}"
            );
            // the yaw stays the heading: the sole's x axis lies in the vertical plane of yaw
            let x = f.rotation() * Vector3::x();
            assert!((x.y * yaw.cos() - x.x * yaw.sin()).abs() < 1e-12);
            assert!(x.x * yaw.cos() + x.y * yaw.sin() > 0.0);
        }
        let flat = FootPose::on_surface(0.0, 0.0, 0.0, 0.3, &Vector3::z()).unwrap();
        assert_eq!(flat, FootPose::new(0.0, 0.0, 0.0, 0.3));
        assert!(FootPose::on_surface(0.0, 0.0, 0.0, 0.0, &Vector3::new(1.0, 0.0, 0.0)).is_none());
        assert!(FootPose::on_surface(0.0, 0.0, 0.0, 0.0, &Vector3::new(0.0, 0.0, -1.0)).is_none());
    }

    #[test]
    fn euler_rates_map_to_the_angular_velocity() {
        // ω = vee(Ṙ Rᵀ), Ṙ by central differences of the Euler angles
        let p = FootPose {
            roll: 0.2,
            pitch: -0.15,
            ..FootPose::new(0.0, 0.0, 0.0, 0.8)
        };
        let v = FootVelocity {
            roll: 0.3,
            pitch: -0.5,
            yaw: 0.7,
            ..Default::default()
        };
        let h = 1e-6;
        let at = |s: f64| {
            FootPose {
                roll: p.roll + s * v.roll,
                pitch: p.pitch + s * v.pitch,
                yaw: p.yaw + s * v.yaw,
                ..p
            }
            .rotation()
            .into_inner()
        };
        let w = (at(h) - at(-h)) / (2.0 * h) * p.rotation().into_inner().transpose();
        let omega = Vector3::new(w[(2, 1)], w[(0, 2)], w[(1, 0)]);
        assert!((omega - v.angular(&p)).norm() < 1e-8, "{omega:?}");
    }

    #[test]
    fn waist_yaw_is_circular_mean() {
        assert!((waist_yaw(0.2, 0.4) - 0.3).abs() < 1e-12);
        // feet on both sides of ±π: the waist faces −x, not +x
        let w = waist_yaw(PI - 0.1, -PI + 0.1);
        assert!((w.abs() - PI).abs() < 1e-12, "{w}");
        let w = waist_yaw(PI - 0.1, -PI + 0.3);
        assert!((angle_difference(w, -PI + 0.1)).abs() < 1e-12, "{w}");
        // symmetric in its arguments
        for &(a, b) in &[(0.3, -2.9), (3.1, -3.1), (-1.0, 2.0)] {
            assert!(angle_difference(waist_yaw(a, b), waist_yaw(b, a)).abs() < 1e-12);
        }
    }
}
