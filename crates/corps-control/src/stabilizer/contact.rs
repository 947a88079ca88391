//! Contact vocabulary of the stabilizer: wrenches, the contact phase, the sole rectangle and
//! ZMP/CoP formulas.

use nalgebra::{Isometry3, Vector2, Vector3};

/// A wrench (force, moment about a stated point, in a stated frame).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Wrench {
    pub force: Vector3<f64>,
    pub torque: Vector3<f64>,
}

impl Wrench {
    pub fn new(force: Vector3<f64>, torque: Vector3<f64>) -> Self {
        Self { force, torque }
    }

    /// The same physical wrench with its moment taken about `to` instead of `from`
    /// (same frame): `τ_to = τ_from + (from − to) × f`.
    pub fn shift(&self, from: &Vector3<f64>, to: &Vector3<f64>) -> Self {
        Self {
            force: self.force,
            torque: self.torque + (from - to).cross(&self.force),
        }
    }

    /// A wrench expressed in the sole frame at the sole origin, expressed in the world frame
    /// with its moment about the world point `point`.
    pub fn sole_to_world(&self, sole: &Isometry3<f64>, point: &Vector3<f64>) -> Self {
        let f = sole.rotation * self.force;
        let t = sole.rotation * self.torque;
        Self {
            force: f,
            torque: t + (sole.translation.vector - point).cross(&f),
        }
    }

    /// Centre of pressure in the frame of this wrench, assuming the moment is taken about a
    /// point of the contact surface whose normal is z: `(−τ_y/f_z, τ_x/f_z)` (seed 002 §4.9
    /// with `h = 0`); zero when `f_z < 0.05 N` (unloaded).
    pub fn cop(&self) -> Vector2<f64> {
        if self.force.z < 0.05 {
            return Vector2::zeros();
        }
        Vector2::new(-self.torque.y / self.force.z, self.torque.x / self.force.z)
    }
}

pub use corps_model::support::ContactPhase;

/// Index of the left foot in per-foot arrays.
pub const LEFT: usize = 0;
/// Index of the right foot in per-foot arrays.
pub const RIGHT: usize = 1;

/// Rectangular sole around the sole frame's origin (z = contact normal), friction and ankle
/// height.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sole {
    /// Half-length along the sole x [m].
    pub half_length: f64,
    /// Half-width along the sole y [m].
    pub half_width: f64,
    /// Friction coefficient μ of the pyramid.
    pub friction: f64,
    /// Height of the ankle joint above the sole origin [m].
    pub ankle_height: f64,
}

/// Friction coefficient of the stabilizer's contact pyramids, seed 002 §2 (R L305).
pub const DEFAULT_FRICTION: f64 = 0.7;

impl Sole {
    /// A sole of the robot's (from its description) with [`DEFAULT_FRICTION`].
    pub fn new(half_length: f64, half_width: f64, ankle_height: f64) -> Self {
        Self {
            half_length,
            half_width,
            friction: DEFAULT_FRICTION,
            ankle_height,
        }
    }

    /// World (x, y) of the four sole corners for a sole frame `pose`.
    pub fn corners(&self, pose: &Isometry3<f64>) -> [Vector2<f64>; 4] {
        let mut out = [Vector2::zeros(); 4];
        for (k, (sx, sy)) in [(1.0, 1.0), (-1.0, 1.0), (-1.0, -1.0), (1.0, -1.0)]
            .iter()
            .enumerate()
        {
            let p = pose * nalgebra::Point3::new(sx * self.half_length, sy * self.half_width, 0.0);
            out[k] = Vector2::new(p.x, p.y);
        }
        out
    }

    /// Clamp a sole-frame CoP into the rectangle.
    pub fn clamp_cop(&self, cop: &Vector2<f64>) -> Vector2<f64> {
        Vector2::new(
            cop.x.clamp(-self.half_length, self.half_length),
            cop.y.clamp(-self.half_width, self.half_width),
        )
    }
}

/// ZMP on the horizontal plane through `point` of a world-frame wrench whose moment is about
/// `point`: `point_xy + (−τ_y/f_z, τ_x/f_z)` (seed 000 §3.3, Eq 2.17–2.18). `None` when
/// `f_z ≤ 0`.
pub fn zmp_of(wrench_at_point: &Wrench, point: &Vector3<f64>) -> Option<Vector2<f64>> {
    let fz = wrench_at_point.force.z;
    if fz <= 0.0 || !fz.is_finite() {
        return None;
    }
    Some(Vector2::new(
        point.x - wrench_at_point.torque.y / fz,
        point.y + wrench_at_point.torque.x / fz,
    ))
}

/// Measured ZMP from the two feet's wrenches (each in its sole frame, about the sole
/// origin), on the horizontal plane at height `ground_z`; feet with `f_z < 0.05 N` count as
/// unloaded. `None` if no foot is loaded.
pub fn zmp_from_feet(
    feet: &[Isometry3<f64>; 2],
    wrenches: &[Wrench; 2],
    ground_z: f64,
) -> Option<Vector2<f64>> {
    let o = Vector3::new(0.0, 0.0, ground_z);
    let mut sum = Wrench::default();
    for i in 0..2 {
        if wrenches[i].force.z >= 0.05 {
            let w = wrenches[i].sole_to_world(&feet[i], &o);
            sum.force += w.force;
            sum.torque += w.torque;
        }
    }
    zmp_of(&sum, &o)
}
