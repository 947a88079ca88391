//! Rigid transforms `aMb = (R, p)`: maps coordinates in frame b to frame a (x_a = R x_b + p).

use super::kernels::{m3m3, m3tv, m3v};
use super::{force::Force, motion::Motion, skew};
use nalgebra::{Matrix3, Matrix6, Vector3};
use std::ops::Mul;

/// A rigid transform (rotation and translation), Pinocchio's `SE3`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Se3 {
    /// Rotation from b coordinates to a coordinates.
    pub rotation: Matrix3<f64>,
    /// Position of b's origin in a.
    pub translation: Vector3<f64>,
}

impl Default for Se3 {
    fn default() -> Self {
        Self::identity()
    }
}

impl Se3 {
    /// The identity transform.
    pub fn identity() -> Self {
        Self {
            rotation: Matrix3::identity(),
            translation: Vector3::zeros(),
        }
    }

    /// Builds a transform from its rotation and translation.
    pub fn new(rotation: Matrix3<f64>, translation: Vector3<f64>) -> Self {
        Self {
            rotation,
            translation,
        }
    }

    /// The inverse transform `bMa`.
    #[inline]
    pub fn inverse(&self) -> Se3 {
        let rt = self.rotation.transpose();
        Se3::new(rt, -m3v(&rt, &self.translation))
    }

    /// Maps a point from b to a.
    #[inline]
    pub fn act_point(&self, x: &Vector3<f64>) -> Vector3<f64> {
        m3v(&self.rotation, x) + self.translation
    }

    /// Maps a point from a to b.
    #[inline]
    pub fn act_inv_point(&self, x: &Vector3<f64>) -> Vector3<f64> {
        m3tv(&self.rotation, &(x - self.translation))
    }

    /// Motion from b to a: `ω_a = R ω`, `v_a = R v + p × ω_a`.
    #[inline]
    pub fn act_motion(&self, m: &Motion) -> Motion {
        let w = m3v(&self.rotation, &m.angular);
        Motion::new(
            m3v(&self.rotation, &m.linear) + self.translation.cross(&w),
            w,
        )
    }

    /// Motion from a to b (the inverse action).
    #[inline]
    pub fn act_inv_motion(&self, m: &Motion) -> Motion {
        let lin = m.linear - self.translation.cross(&m.angular);
        Motion::new(m3tv(&self.rotation, &lin), m3tv(&self.rotation, &m.angular))
    }

    /// Force from b to a: `f_a = R f`, `n_a = R n + p × f_a`.
    #[inline]
    pub fn act_force(&self, f: &Force) -> Force {
        let fl = m3v(&self.rotation, &f.linear);
        Force::new(
            fl,
            m3v(&self.rotation, &f.angular) + self.translation.cross(&fl),
        )
    }

    /// Force from a to b (the inverse action).
    #[inline]
    pub fn act_inv_force(&self, f: &Force) -> Force {
        let n = f.angular - self.translation.cross(&f.linear);
        Force::new(m3tv(&self.rotation, &f.linear), m3tv(&self.rotation, &n))
    }

    /// The 6×6 motion action matrix `aXb` ([linear; angular] ordering).
    pub fn action_matrix(&self) -> Matrix6<f64> {
        let mut x = Matrix6::zeros();
        let r = self.rotation;
        let pr = skew(&self.translation) * r;
        x.fixed_view_mut::<3, 3>(0, 0).copy_from(&r);
        x.fixed_view_mut::<3, 3>(3, 3).copy_from(&r);
        x.fixed_view_mut::<3, 3>(0, 3).copy_from(&pr);
        x
    }

    /// Whether every entry is finite.
    pub fn is_finite(&self) -> bool {
        self.rotation
            .iter()
            .chain(self.translation.iter())
            .all(|x| x.is_finite())
    }
}

impl Mul for Se3 {
    type Output = Se3;
    /// Composition `aMb * bMc = aMc`.
    #[inline]
    #[allow(clippy::suspicious_arithmetic_impl)]
    fn mul(self, o: Se3) -> Se3 {
        Se3::new(
            m3m3(&self.rotation, &o.rotation),
            m3v(&self.rotation, &o.translation) + self.translation,
        )
    }
}

impl Mul<&Se3> for &Se3 {
    type Output = Se3;
    #[inline]
    #[allow(clippy::suspicious_arithmetic_impl)]
    fn mul(self, o: &Se3) -> Se3 {
        Se3::new(
            m3m3(&self.rotation, &o.rotation),
            m3v(&self.rotation, &o.translation) + self.translation,
        )
    }
}
