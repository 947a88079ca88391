//! Foot poses on (piecewise) flat ground, feet names and angle helpers.

use nalgebra::{Matrix2, Vector2};

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

/// A foot (sole-centre) pose: position and yaw about the vertical; the sole is horizontal.
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
}

impl FootPose {
    /// A pose from its four coordinates (the yaw is wrapped to (−π, π]).
    pub fn new(x: f64, y: f64, z: f64, yaw: f64) -> Self {
        Self {
            x,
            y,
            z,
            yaw: wrap_angle(yaw),
        }
    }

    /// Horizontal position.
    pub fn xy(&self) -> Vector2<f64> {
        Vector2::new(self.x, self.y)
    }

    /// A point given in this foot's frame (x forward, y left), in the world.
    pub fn transform(&self, local: &Vector2<f64>) -> Vector2<f64> {
        self.xy() + rotation(self.yaw) * local
    }
}

/// Time derivative of a [`FootPose`] (linear velocity and yaw rate).
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
