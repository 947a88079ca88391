//! Joint angles of a chain of revolute joints from a rotation: with the chain's axes a₁…aₙ at
//! rest (nearest the root first, in one frame), the rotation it makes is the product of
//! exponentials `D = R(a₁, q₁) ⋯ R(aₙ, qₙ)`. [`solve_chain`] finds the angles by
//! Levenberg–Marquardt on the rotation error `e = log(D R(q)ᵀ)` with the chain's spatial
//! Jacobian `ωᵢ = R(a₁, q₁) ⋯ R(aᵢ₋₁, qᵢ₋₁) aᵢ`, warm-started from the previous frame's angles
//! so that a stream of poses gives a continuous stream of angles; it also serves chains whose
//! axes are far from orthogonal (a z–x–z shoulder: its first and last axes parallel at zero
//! roll), which have no closed form. The tests check it against the closed forms where they
//! exist: three orthogonal axes give the Euler angles exactly (`Bᵀ D B = Rx(q₁) Ry(q₂) Rz(q₃)`
//! with B = [a₁ a₂ a₃], a₃ negated if B is a reflection), two axes are completed by a₁ × a₂,
//! and one axis takes the twist of D about it (swing–twist decomposition).

use nalgebra::{Matrix3, Rotation3, Vector3};

/// Angles `q` (warm start in, solution out; one per axis, 1 to 3) of the chain with `axes`
/// nearest to making `d`: least squares on the rotation vector of the error plus
/// `damping² |q − q_start|²` (0: exact where the chain can make `d`; above 0, a chain near a
/// singularity — a z–x–z shoulder with its arm hanging — moves a little instead of swinging
/// its parallel axes far apart). Returns the remaining error angle (rad).
pub fn solve_chain(axes: &[Vector3<f64>], d: &Rotation3<f64>, q: &mut [f64], damping: f64) -> f64 {
    let n = axes.len().min(3);
    let damping2 = if damping.is_finite() {
        damping * damping
    } else {
        0.0
    };
    let mut start = [0.0; 3];
    start[..n].copy_from_slice(&q[..n]);
    let cost = |e: &Vector3<f64>, q: &[f64]| {
        e.norm_squared() + damping2 * (0..n).map(|i| (q[i] - start[i]).powi(2)).sum::<f64>()
    };
    let mut lambda = 1e-6;
    let mut error = chain_error(axes, d, q);
    let mut current = cost(&error, q);
    for _ in 0..50 {
        if current < 1e-24 {
            break;
        }
        // Spatial Jacobian of the chain at q.
        let mut j = Matrix3::zeros();
        let mut r = Rotation3::identity();
        for i in 0..n {
            j.set_column(i, &(r * axes[i]));
            r *= rotation(&axes[i], q[i]);
        }
        let jt = j.transpose();
        let mut step_taken = false;
        for _ in 0..10 {
            let mut h = jt * j;
            let mut g = jt * error;
            for i in 0..3 {
                h[(i, i)] += if i < n { lambda + damping2 } else { 1.0 };
                if i < n {
                    g[i] -= damping2 * (q[i] - start[i]);
                }
            }
            let Some(delta) = h.lu().solve(&g) else {
                break;
            };
            let mut trial = [0.0; 3];
            trial[..n].copy_from_slice(&q[..n]);
            for i in 0..n {
                trial[i] += delta[i];
            }
            let e = chain_error(axes, d, &trial[..n]);
            let c = cost(&e, &trial[..n]);
            if c < current {
                q[..n].copy_from_slice(&trial[..n]);
                error = e;
                current = c;
                lambda = (lambda * 0.3).max(1e-12);
                step_taken = true;
                break;
            }
            lambda *= 10.0;
        }
        if !step_taken {
            break;
        }
    }
    // No wrapping to (−π, π]: a stream of poses keeps continuous angles (the joint limits
    // clip them later).
    error.norm()
}

fn rotation(a: &Vector3<f64>, q: f64) -> Rotation3<f64> {
    Rotation3::from_axis_angle(&nalgebra::Unit::new_normalize(*a), q)
}

/// `log(D R(q)ᵀ)`: the rotation (vector, world) still to make.
fn chain_error(axes: &[Vector3<f64>], d: &Rotation3<f64>, q: &[f64]) -> Vector3<f64> {
    let mut r = Rotation3::identity();
    for (a, v) in axes.iter().zip(q) {
        r *= rotation(a, *v);
    }
    log(&(d * r.inverse()))
}

/// The rotation vector of `e`, accurate for small angles: θ = atan2(|v|, (tr e − 1)/2) along
/// v = vee((e − eᵀ)/2) (|v| = sin θ).
fn log(e: &Rotation3<f64>) -> Vector3<f64> {
    let m = e.matrix();
    let v = Vector3::new(
        m[(2, 1)] - m[(1, 2)],
        m[(0, 2)] - m[(2, 0)],
        m[(1, 0)] - m[(0, 1)],
    ) * 0.5;
    let s = v.norm();
    let c = (m.trace() - 1.0) * 0.5;
    if s < 1e-300 {
        if c > 0.0 {
            return Vector3::zeros();
        }
        // θ = π: the axis from the symmetric part.
        return e.scaled_axis();
    }
    v * (s.atan2(c) / s)
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::UnitQuaternion;

    /// The angles of the chain with `axes` (1 to 3 unit vectors, the frame of `d`) making `d`,
    /// written to `out` (one per axis).
    fn chain_angles(axes: &[Vector3<f64>], d: &Rotation3<f64>, out: &mut [f64]) {
        match axes.len() {
            1 => out[0] = twist(d, &axes[0]),
            2 | 3 => {
                let a1 = axes[0].normalize();
                let a2 = (axes[1] - a1 * a1.dot(&axes[1])).normalize();
                let (a3, sign) = if axes.len() == 3 {
                    let mut a3 = axes[2] - a1 * a1.dot(&axes[2]);
                    a3 -= a2 * a2.dot(&a3);
                    let a3 = a3.normalize();
                    // B a proper rotation: a₃ along a₁ × a₂, its angle's sign flipped if it was not.
                    if a1.cross(&a2).dot(&a3) < 0.0 {
                        (-a3, -1.0)
                    } else {
                        (a3, 1.0)
                    }
                } else {
                    (a1.cross(&a2), 1.0)
                };
                let b = Matrix3::from_columns(&[a1, a2, a3]);
                let m = b.transpose() * d.matrix() * b;
                // Rx(q1) Ry(q2) Rz(q3): m[(0,2)] = sin q2, m[(1,2)] = −sin q1 cos q2,
                // m[(2,2)] = cos q1 cos q2, m[(0,1)] = −cos q2 sin q3, m[(0,0)] = cos q2 cos q3.
                let q2 = m[(0, 2)].clamp(-1.0, 1.0).asin();
                let q1 = (-m[(1, 2)]).atan2(m[(2, 2)]);
                let q3 = (-m[(0, 1)]).atan2(m[(0, 0)]);
                out[0] = q1;
                out[1] = q2;
                if axes.len() == 3 {
                    out[2] = sign * q3;
                }
            }
            _ => {}
        }
    }

    /// The twist angle of `d` about the unit axis `a`, in (−π, π].
    fn twist(d: &Rotation3<f64>, a: &Vector3<f64>) -> f64 {
        let q = UnitQuaternion::from_rotation_matrix(d);
        let a = a.normalize();
        let angle = 2.0 * q.imag().dot(&a).atan2(q.w);
        if angle > std::f64::consts::PI {
            angle - std::f64::consts::TAU
        } else if angle <= -std::f64::consts::PI {
            angle + std::f64::consts::TAU
        } else {
            angle
        }
    }

    fn r(a: &Vector3<f64>, q: f64) -> Rotation3<f64> {
        Rotation3::from_axis_angle(&nalgebra::Unit::new_normalize(*a), q)
    }

    #[test]
    fn three_orthogonal_axes_give_back_their_angles() {
        // A left-handed triple too (the sign of the third angle).
        for axes in [
            [Vector3::y(), -Vector3::x(), Vector3::z()],
            [Vector3::y(), Vector3::x(), Vector3::z()],
            [
                Vector3::new(0.6, 0.8, 0.0),
                Vector3::new(-0.8, 0.6, 0.0),
                -Vector3::z(),
            ],
        ] {
            for q in [[0.3, -0.5, 1.1], [-1.2, 0.9, -2.5], [0.0, 0.0, 0.0]] {
                let d = r(&axes[0], q[0]) * r(&axes[1], q[1]) * r(&axes[2], q[2]);
                let mut out = [0.0; 3];
                chain_angles(&axes, &d, &mut out);
                for k in 0..3 {
                    assert!((out[k] - q[k]).abs() < 1e-12, "{axes:?} {q:?} {out:?}");
                }
            }
        }
    }

    #[test]
    fn a_z_x_z_chain_is_solved_where_the_closed_form_cannot() {
        // TALOS's shoulder: z, then x, then z again (parallel to the first at zero roll).
        let axes = [Vector3::z(), Vector3::x(), Vector3::z()];
        let mut q = [0.0; 3];
        // A path of rotations, each solved from the previous solution.
        for k in 0..=40 {
            let s = k as f64 / 40.0;
            let target = [-1.4 * s, 1.5 * s, 0.9 * s];
            let d = r(&axes[0], target[0]) * r(&axes[1], target[1]) * r(&axes[2], target[2]);
            let residual = solve_chain(&axes, &d, &mut q, 0.0);
            assert!(residual < 1e-9, "step {k}: {residual}");
            let mut back = Rotation3::identity();
            for i in 0..3 {
                back *= r(&axes[i], q[i]);
            }
            assert!(
                (back.matrix() - d.matrix()).norm() < 1e-9,
                "step {k}: {q:?} {target:?}"
            );
        }
        // Orthogonal axes: the same angles as the closed form.
        let axes = [Vector3::y(), -Vector3::x(), Vector3::z()];
        let d = r(&axes[0], 0.3) * r(&axes[1], -0.5) * r(&axes[2], 1.1);
        let mut q = [0.0; 3];
        solve_chain(&axes, &d, &mut q, 0.0);
        let mut c = [0.0; 3];
        chain_angles(&axes, &d, &mut c);
        for i in 0..3 {
            assert!((q[i] - c[i]).abs() < 1e-9, "{q:?} {c:?}");
        }
    }

    #[test]
    fn two_axes_and_one_axis() {
        let axes = [Vector3::z(), Vector3::x()];
        let d = r(&axes[0], 0.4) * r(&axes[1], -0.7);
        let mut out = [0.0; 2];
        chain_angles(&axes, &d, &mut out);
        assert!(
            (out[0] - 0.4).abs() < 1e-12 && (out[1] + 0.7).abs() < 1e-12,
            "{out:?}"
        );
        // The solve gives the same angles from a start at rest.
        let mut q = [0.0; 2];
        let residual = solve_chain(&axes, &d, &mut q, 0.0);
        assert!(residual < 1e-9 && (q[0] - out[0]).abs() < 1e-9 && (q[1] - out[1]).abs() < 1e-9);
        // The twist about y of a rotation about y and a swing about x.
        let d = r(&Vector3::y(), 1.3) * r(&Vector3::x(), 0.2);
        let t = twist(&d, &Vector3::y());
        // Ry(a) Rx(b) = (cos a/2 cos b/2, cos a/2 sin b/2, sin a/2 cos b/2, −sin a/2 sin b/2):
        // its twist about y, 2 atan2(q_y, w), is a exactly.
        assert!((t - 1.3).abs() < 1e-12, "{t}");
        assert!((twist(&r(&Vector3::y(), -2.0), &Vector3::y()) + 2.0).abs() < 1e-12);
        let mut q = [0.0];
        solve_chain(&[Vector3::y()], &r(&Vector3::y(), -2.0), &mut q, 0.0);
        assert!((q[0] + 2.0).abs() < 1e-9, "{q:?}");
    }
}
