//! Rotation helpers: roll–pitch–yaw, quaternions (x, y, z, w), SO(3) exp/log, Rodrigues.

use nalgebra::{Matrix3, Vector3};

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

/// Quaternion (x, y, z, w) of a rotation matrix, closed form (Shepperd 1978: pivot on the
/// largest of w², x², y², z² for accuracy). The result has w ≥ 0.
pub fn matrix_to_quat(r: &Matrix3<f64>) -> [f64; 4] {
    let (m00, m11, m22) = (r[(0, 0)], r[(1, 1)], r[(2, 2)]);
    let tr = m00 + m11 + m22;
    let mut q = if tr >= m00.max(m11).max(m22) {
        let s = 2.0 * (1.0 + tr).sqrt();
        [
            (r[(2, 1)] - r[(1, 2)]) / s,
            (r[(0, 2)] - r[(2, 0)]) / s,
            (r[(1, 0)] - r[(0, 1)]) / s,
            0.25 * s,
        ]
    } else if m00 >= m11 && m00 >= m22 {
        let s = 2.0 * (1.0 + m00 - m11 - m22).sqrt();
        [
            0.25 * s,
            (r[(0, 1)] + r[(1, 0)]) / s,
            (r[(0, 2)] + r[(2, 0)]) / s,
            (r[(2, 1)] - r[(1, 2)]) / s,
        ]
    } else if m11 >= m22 {
        let s = 2.0 * (1.0 - m00 + m11 - m22).sqrt();
        [
            (r[(0, 1)] + r[(1, 0)]) / s,
            0.25 * s,
            (r[(1, 2)] + r[(2, 1)]) / s,
            (r[(0, 2)] - r[(2, 0)]) / s,
        ]
    } else {
        let s = 2.0 * (1.0 - m00 - m11 + m22).sqrt();
        [
            (r[(0, 2)] + r[(2, 0)]) / s,
            (r[(1, 2)] + r[(2, 1)]) / s,
            0.25 * s,
            (r[(1, 0)] - r[(0, 1)]) / s,
        ]
    };
    if q[3] < 0.0 {
        q.iter_mut().for_each(|x| *x = -*x);
    }
    let n = q.iter().map(|x| x * x).sum::<f64>().sqrt();
    q.map(|x| x / n)
}

/// SO(3) exponential: the rotation `exp([ω]×)`.
pub fn exp3(w: &Vector3<f64>) -> Matrix3<f64> {
    let t = w.norm();
    if t < 1e-12 {
        return Matrix3::identity() + super::skew(w);
    }
    axis_angle_cs(&(w / t), t.cos(), t.sin())
}

/// SO(3) logarithm: the rotation vector ω with `exp3(ω) = R`, |ω| ≤ π, through the
/// quaternion (accurate at every angle, including near 0 and π).
pub fn log3(r: &Matrix3<f64>) -> Vector3<f64> {
    let [x, y, z, w] = matrix_to_quat(r);
    let v = Vector3::new(x, y, z);
    let s = v.norm();
    if s < 1e-8 {
        // angle ≈ 2 s / w: first-order series, exact to O(s³).
        return v * (2.0 / w);
    }
    v * (2.0 * s.atan2(w) / s)
}
