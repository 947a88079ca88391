//! Rotation helpers: roll–pitch–yaw, quaternions (x, y, z, w), SO(3) exp/log, Rodrigues.

use nalgebra::{Matrix3, Quaternion, UnitQuaternion, Vector3};

/// URDF `rpy`: R = Rz(yaw) Ry(pitch) Rx(roll) (fixed axes X, then Y, then Z).
pub fn rpy_to_matrix(r: f64, p: f64, y: f64) -> Matrix3<f64> {
    let (sr, cr) = r.sin_cos();
    let (sp, cp) = p.sin_cos();
    let (sy, cy) = y.sin_cos();
    Matrix3::new(
        cy * cp,
        cy * sp * sr - sy * cr,
        cy * sp * cr + sy * sr,
        sy * cp,
        sy * sp * sr + cy * cr,
        sy * sp * cr - cy * sr,
        -sp,
        cp * sr,
        cp * cr,
    )
}

/// Rotation of angle `(c, s) = (cos θ, sin θ)` about the unit `axis` (Rodrigues).
#[inline]
pub fn axis_angle_cs(axis: &Vector3<f64>, c: f64, s: f64) -> Matrix3<f64> {
    let (x, y, z) = (axis.x, axis.y, axis.z);
    let t = 1.0 - c;
    Matrix3::new(
        t * x * x + c,
        t * x * y - s * z,
        t * x * z + s * y,
        t * x * y + s * z,
        t * y * y + c,
        t * y * z - s * x,
        t * x * z - s * y,
        t * y * z + s * x,
        t * z * z + c,
    )
}

/// Rotation matrix of a quaternion stored (x, y, z, w); the quaternion is assumed unit.
#[inline]
pub fn quat_to_matrix(x: f64, y: f64, z: f64, w: f64) -> Matrix3<f64> {
    let (xx, yy, zz) = (x * x, y * y, z * z);
    let (xy, xz, yz) = (x * y, x * z, y * z);
    let (wx, wy, wz) = (w * x, w * y, w * z);
    Matrix3::new(
        1.0 - 2.0 * (yy + zz),
        2.0 * (xy - wz),
        2.0 * (xz + wy),
        2.0 * (xy + wz),
        1.0 - 2.0 * (xx + zz),
        2.0 * (yz - wx),
        2.0 * (xz - wy),
        2.0 * (yz + wx),
        1.0 - 2.0 * (xx + yy),
    )
}

/// Quaternion (x, y, z, w) of a rotation matrix.
pub fn matrix_to_quat(r: &Matrix3<f64>) -> [f64; 4] {
    let q = UnitQuaternion::from_matrix(r);
    let q: &Quaternion<f64> = q.as_ref();
    [q.i, q.j, q.k, q.w]
}

/// SO(3) exponential: the rotation `exp([ω]×)`.
pub fn exp3(w: &Vector3<f64>) -> Matrix3<f64> {
    let t = w.norm();
    if t < 1e-12 {
        return Matrix3::identity() + super::skew(w);
    }
    axis_angle_cs(&(w / t), t.cos(), t.sin())
}

/// SO(3) logarithm: the rotation vector ω with `exp3(ω) = R`, |ω| ≤ π.
pub fn log3(r: &Matrix3<f64>) -> Vector3<f64> {
    UnitQuaternion::from_matrix(r).scaled_axis()
}
