//! SE(3) exponential and logarithm of twists `[v; ω]` (Pinocchio's `exp6` / `log6`).

use super::{motion::Motion, rotation, se3::Se3, skew};
use nalgebra::Matrix3;

/// The left Jacobian factor V(ω) = I + (1−cos θ)/θ² [ω]× + (θ − sin θ)/θ³ [ω]×².
fn v_matrix(theta2: f64, wx: &Matrix3<f64>) -> Matrix3<f64> {
    let (a, b) = if theta2 < 1e-10 {
        (0.5 - theta2 / 24.0, 1.0 / 6.0 - theta2 / 120.0)
    } else {
        let t = theta2.sqrt();
        ((1.0 - t.cos()) / theta2, (t - t.sin()) / (theta2 * t))
    };
    Matrix3::identity() + wx * a + wx * wx * b
}

/// `exp6(ν)`: the transform reached by following the constant twist ν for unit time.
pub fn exp6(nu: &Motion) -> Se3 {
    let wx = skew(&nu.angular);
    let v = v_matrix(nu.angular.norm_squared(), &wx);
    Se3::new(rotation::exp3(&nu.angular), v * nu.linear)
}

/// `log6(M)`: the twist ν with `exp6(ν) = M` (rotation angle ≤ π).
pub fn log6(m: &Se3) -> Motion {
    let w = rotation::log3(&m.rotation);
    let wx = skew(&w);
    let v = v_matrix(w.norm_squared(), &wx);
    let lin = v
        .try_inverse()
        .map(|vi| vi * m.translation)
        .unwrap_or(m.translation);
    Motion::new(lin, w)
}
