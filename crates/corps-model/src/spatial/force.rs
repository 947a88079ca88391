//! Spatial force vectors (wrenches, momenta), stored as [linear; angular].

use nalgebra::{Vector3, Vector6};
use std::ops::{Add, AddAssign, Mul, Neg, Sub, SubAssign};

/// A spatial force `[f; n]`: force `f` and moment `n` about the frame origin.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Force {
    /// Linear part (force, or linear momentum).
    pub linear: Vector3<f64>,
    /// Angular part (moment about the origin, or angular momentum).
    pub angular: Vector3<f64>,
}

impl Force {
    /// The zero force.
    pub fn zero() -> Self {
        Self::default()
    }

    /// Builds a force from its linear and angular parts.
    pub fn new(linear: Vector3<f64>, angular: Vector3<f64>) -> Self {
        Self { linear, angular }
    }

    /// From a 6-vector `[linear; angular]`.
    pub fn from_vector(v: &Vector6<f64>) -> Self {
        Self::new(v.fixed_rows::<3>(0).into(), v.fixed_rows::<3>(3).into())
    }

    /// As a 6-vector `[linear; angular]`.
    pub fn to_vector(&self) -> Vector6<f64> {
        let (l, a) = (self.linear, self.angular);
        Vector6::new(l.x, l.y, l.z, a.x, a.y, a.z)
    }

    /// The same wrench with its moment taken about the point `p` instead of the origin:
    /// `n_p = n − p × f`.
    #[inline]
    pub fn shifted_to(&self, p: &Vector3<f64>) -> Force {
        Force::new(self.linear, self.angular - p.cross(&self.linear))
    }
}

impl Add for Force {
    type Output = Force;
    #[inline]
    fn add(self, o: Force) -> Force {
        Force::new(self.linear + o.linear, self.angular + o.angular)
    }
}

impl Sub for Force {
    type Output = Force;
    #[inline]
    fn sub(self, o: Force) -> Force {
        Force::new(self.linear - o.linear, self.angular - o.angular)
    }
}

impl AddAssign for Force {
    #[inline]
    fn add_assign(&mut self, o: Force) {
        self.linear += o.linear;
        self.angular += o.angular;
    }
}

impl SubAssign for Force {
    #[inline]
    fn sub_assign(&mut self, o: Force) {
        self.linear -= o.linear;
        self.angular -= o.angular;
    }
}

impl Neg for Force {
    type Output = Force;
    #[inline]
    fn neg(self) -> Force {
        Force::new(-self.linear, -self.angular)
    }
}

impl Mul<f64> for Force {
    type Output = Force;
    #[inline]
    fn mul(self, s: f64) -> Force {
        Force::new(self.linear * s, self.angular * s)
    }
}
