//! Spatial motion vectors (twists, spatial accelerations), stored as [linear; angular].

use super::force::Force;
use nalgebra::{Vector3, Vector6};
use std::ops::{Add, AddAssign, Mul, Neg, Sub, SubAssign};

/// A spatial motion vector `[v; ω]`: `v` is the velocity of the point at the frame origin,
/// `ω` the angular velocity, both in the frame's coordinates (Featherstone, RBDA §2.2,
/// ordered linear-first as Pinocchio does).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Motion {
    /// Linear part (velocity of the origin point).
    pub linear: Vector3<f64>,
    /// Angular part.
    pub angular: Vector3<f64>,
}

impl Motion {
    /// The zero motion.
    pub fn zero() -> Self {
        Self::default()
    }

    /// Builds a motion from its linear and angular parts.
    pub fn new(linear: Vector3<f64>, angular: Vector3<f64>) -> Self {
        Self { linear, angular }
    }

    /// From a 6-vector `[linear; angular]`.
    pub fn from_vector(v: &Vector6<f64>) -> Self {
        Self::new(v.fixed_rows::<3>(0).into(), v.fixed_rows::<3>(3).into())
    }

    /// From a slice of 6 numbers `[linear; angular]`.
    pub fn from_slice(s: &[f64]) -> Self {
        Self::new(
            Vector3::new(s[0], s[1], s[2]),
            Vector3::new(s[3], s[4], s[5]),
        )
    }

    /// As a 6-vector `[linear; angular]`.
    pub fn to_vector(&self) -> Vector6<f64> {
        let (l, a) = (self.linear, self.angular);
        Vector6::new(l.x, l.y, l.z, a.x, a.y, a.z)
    }

    /// Motion cross product `self × m` (RBDA Eq. 2.31): `[ω×v_m + v×ω_m; ω×ω_m]`.
    #[inline]
    pub fn cross(&self, m: &Motion) -> Motion {
        Motion {
            linear: self.angular.cross(&m.linear) + self.linear.cross(&m.angular),
            angular: self.angular.cross(&m.angular),
        }
    }

    /// Dual cross product `self ×* f` (RBDA Eq. 2.32): `[ω×f; ω×n + v×f]`.
    #[inline]
    pub fn cross_force(&self, f: &Force) -> Force {
        Force {
            linear: self.angular.cross(&f.linear),
            angular: self.angular.cross(&f.angular) + self.linear.cross(&f.linear),
        }
    }

    /// Power `self · f` of a motion against a force.
    #[inline]
    pub fn dot(&self, f: &Force) -> f64 {
        self.linear.dot(&f.linear) + self.angular.dot(&f.angular)
    }

    /// Velocity of the point `p` (frame coordinates) of a body moving with this twist.
    #[inline]
    pub fn point_velocity(&self, p: &Vector3<f64>) -> Vector3<f64> {
        self.linear + self.angular.cross(p)
    }
}

impl Add for Motion {
    type Output = Motion;
    #[inline]
    fn add(self, o: Motion) -> Motion {
        Motion::new(self.linear + o.linear, self.angular + o.angular)
    }
}

impl Sub for Motion {
    type Output = Motion;
    #[inline]
    fn sub(self, o: Motion) -> Motion {
        Motion::new(self.linear - o.linear, self.angular - o.angular)
    }
}

impl AddAssign for Motion {
    #[inline]
    fn add_assign(&mut self, o: Motion) {
        self.linear += o.linear;
        self.angular += o.angular;
    }
}

impl SubAssign for Motion {
    #[inline]
    fn sub_assign(&mut self, o: Motion) {
        self.linear -= o.linear;
        self.angular -= o.angular;
    }
}

impl Neg for Motion {
    type Output = Motion;
    #[inline]
    fn neg(self) -> Motion {
        Motion::new(-self.linear, -self.angular)
    }
}

impl Mul<f64> for Motion {
    type Output = Motion;
    #[inline]
    fn mul(self, s: f64) -> Motion {
        Motion::new(self.linear * s, self.angular * s)
    }
}
