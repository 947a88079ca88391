//! Rigid-body spatial inertia in compact form (mass, centre of mass, rotational inertia).

use super::kernels::{m3v, rotate_symmetric};
use super::{force::Force, motion::Motion, se3::Se3, skew};
use nalgebra::{Matrix3, Matrix6, Vector3};
use std::ops::{Add, AddAssign};

/// Spatial inertia of a rigid body expressed in some frame: mass `m`, centre of mass `c`
/// (the lever) and rotational inertia `I_c` about the centre of mass, in that frame's axes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Inertia {
    /// Mass in kg.
    pub mass: f64,
    /// Centre of mass in the frame.
    pub lever: Vector3<f64>,
    /// Rotational inertia about the centre of mass (symmetric).
    pub inertia: Matrix3<f64>,
}

impl Default for Inertia {
    fn default() -> Self {
        Self::zero()
    }
}

impl Inertia {
    /// A massless body.
    pub fn zero() -> Self {
        Self {
            mass: 0.0,
            lever: Vector3::zeros(),
            inertia: Matrix3::zeros(),
        }
    }

    /// Builds an inertia from mass, centre of mass and inertia about the centre of mass.
    pub fn new(mass: f64, lever: Vector3<f64>, inertia: Matrix3<f64>) -> Self {
        Self {
            mass,
            lever,
            inertia,
        }
    }

    /// Momentum `h = I v`: `f = m (v + ω × c)`, `n = I_c ω + c × f` (RBDA Eq. 2.63).
    #[inline]
    pub fn mul_motion(&self, v: &Motion) -> Force {
        let f = (v.linear + v.angular.cross(&self.lever)) * self.mass;
        Force::new(f, m3v(&self.inertia, &v.angular) + self.lever.cross(&f))
    }

    /// The inertia expressed in frame a, given `aMb` and this inertia in b.
    #[inline]
    pub fn transformed(&self, m: &Se3) -> Inertia {
        Inertia::new(
            self.mass,
            m.act_point(&self.lever),
            rotate_symmetric(&m.rotation, &self.inertia),
        )
    }

    /// The 6×6 matrix (about the frame origin): `[[m I, −m[c]×], [m[c]×, I_c − m[c]×[c]×]]`.
    pub fn to_matrix(&self) -> Matrix6<f64> {
        let mut y = Matrix6::zeros();
        self.write_matrix(&mut y);
        y
    }

    /// Writes the 6×6 matrix of [`Inertia::to_matrix`] into `y`.
    #[inline]
    pub fn write_matrix(&self, y: &mut Matrix6<f64>) {
        let m = self.mass;
        let c = self.lever;
        let h = c * m;
        // I_O = I_c − m [c]×[c]× = I_c + m (|c|² 1 − c cᵀ).
        let i = &self.inertia;
        let c2 = c.norm_squared();
        let io = |r: usize, s: usize| {
            let d = if r == s { c2 } else { 0.0 };
            i[(r, s)] + m * (d - c[r] * c[s])
        };
        let cols = &mut y.data.0;
        *cols = [
            [m, 0.0, 0.0, 0.0, h.z, -h.y],
            [0.0, m, 0.0, -h.z, 0.0, h.x],
            [0.0, 0.0, m, h.y, -h.x, 0.0],
            [0.0, -h.z, h.y, io(0, 0), io(1, 0), io(2, 0)],
            [h.z, 0.0, -h.x, io(0, 1), io(1, 1), io(2, 1)],
            [-h.y, h.x, 0.0, io(0, 2), io(1, 2), io(2, 2)],
        ];
    }

    /// Kinetic energy of a body moving with twist `v`: `½ vᵀ I v`.
    pub fn kinetic_energy(&self, v: &Motion) -> f64 {
        0.5 * v.dot(&self.mul_motion(v))
    }
}

impl Add for Inertia {
    type Output = Inertia;
    /// Combined inertia of two bodies expressed in the same frame (parallel-axis theorem).
    fn add(self, o: Inertia) -> Inertia {
        let m = self.mass + o.mass;
        if m <= 0.0 {
            return Inertia::new(0.0, Vector3::zeros(), self.inertia + o.inertia);
        }
        let c = (self.lever * self.mass + o.lever * o.mass) / m;
        let d1 = skew(&(self.lever - c));
        let d2 = skew(&(o.lever - c));
        let i = self.inertia + o.inertia - d1 * d1 * self.mass - d2 * d2 * o.mass;
        Inertia::new(m, c, i)
    }
}

impl AddAssign for Inertia {
    fn add_assign(&mut self, o: Inertia) {
        *self = *self + o;
    }
}

/// A rigid-body inertia about the frame origin: mass `m`, first moment `h = m c` and
/// rotational inertia about the origin `I_O = I_c + m (|c|² 1 − c cᵀ)`. Unlike [`Inertia`],
/// sums of these are plain component sums, which makes composite inertias (CRBA) cheap.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct OriginInertia {
    /// Mass.
    pub mass: f64,
    /// First moment of mass `m c`.
    pub first_moment: Vector3<f64>,
    /// Rotational inertia about the origin (symmetric).
    pub inertia: Matrix3<f64>,
}

impl OriginInertia {
    /// Momentum `h = I v`: `f = m v − h × ω`, `n = h × v + I_O ω`.
    #[inline]
    pub fn mul_motion(&self, v: &Motion) -> Force {
        Force::new(
            v.linear * self.mass - self.first_moment.cross(&v.angular),
            self.first_moment.cross(&v.linear) + m3v(&self.inertia, &v.angular),
        )
    }

    /// Centre of mass (origin if massless).
    pub fn com(&self) -> Vector3<f64> {
        if self.mass > 0.0 {
            self.first_moment / self.mass
        } else {
            Vector3::zeros()
        }
    }
}

impl AddAssign for OriginInertia {
    #[inline]
    fn add_assign(&mut self, o: OriginInertia) {
        self.mass += o.mass;
        self.first_moment += o.first_moment;
        self.inertia += o.inertia;
    }
}

impl Inertia {
    /// The same inertia in origin form.
    #[inline]
    pub fn to_origin_form(&self) -> OriginInertia {
        let (m, c) = (self.mass, self.lever);
        let h = c * m;
        let i = &self.inertia;
        // I_c + m (|c|² 1 − c cᵀ), symmetric.
        let (xx, yy, zz) = (
            i.m11 + h.y * c.y + h.z * c.z,
            i.m22 + h.x * c.x + h.z * c.z,
            i.m33 + h.x * c.x + h.y * c.y,
        );
        let (xy, xz, yz) = (i.m12 - h.x * c.y, i.m13 - h.x * c.z, i.m23 - h.y * c.z);
        OriginInertia {
            mass: m,
            first_moment: h,
            inertia: Matrix3::new(xx, xy, xz, xy, yy, yz, xz, yz, zz),
        }
    }
}
