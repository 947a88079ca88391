//! The configuration space as a Lie group (Pinocchio's `integrate`, `difference`,
//! `interpolate`, `neutral`, `randomConfiguration`, `normalize`): a product of R (revolute,
//! prismatic), SO(2) (continuous joints, stored (cos θ, sin θ)) and SE(3) (the free-flyer).

use crate::error::Result;
use crate::joint::JointKind;
use crate::model::{check_vector, Model};
use crate::spatial::{exp6, log6, rotation, Motion, Se3};
use nalgebra::{DVector, Vector3};
use rand::Rng;

/// The neutral configuration: zero joint angles, identity orientation.
pub fn neutral(model: &Model) -> DVector<f64> {
    let mut q = DVector::zeros(model.nq);
    for j in &model.joints {
        match j.kind {
            JointKind::FreeFlyer => q[j.idx_q + 6] = 1.0,
            JointKind::RevoluteUnbounded { .. } => q[j.idx_q] = 1.0,
            _ => {}
        }
    }
    q
}

/// Normalizes the quaternion of a free-flyer and the (cos, sin) pair of continuous joints.
pub fn normalize(model: &Model, q: &mut [f64]) {
    for j in &model.joints {
        let s = j.idx_q;
        let range = match j.kind {
            JointKind::FreeFlyer => s + 3..s + 7,
            JointKind::RevoluteUnbounded { .. } => s..s + 2,
            _ => continue,
        };
        let n = q[range.clone()].iter().map(|x| x * x).sum::<f64>().sqrt();
        if n > 0.0 {
            q[range].iter_mut().for_each(|x| *x /= n);
        }
    }
}

fn ff_placement(q: &[f64]) -> Se3 {
    Se3::new(
        rotation::quat_to_matrix(q[3], q[4], q[5], q[6]),
        Vector3::new(q[0], q[1], q[2]),
    )
}

fn write_ff(m: &Se3, out: &mut [f64]) {
    out[..3].copy_from_slice(m.translation.as_slice());
    let mut quat = rotation::matrix_to_quat(&m.rotation);
    // Keep the quaternion in one hemisphere (w ≥ 0) for reproducibility.
    if quat[3] < 0.0 {
        quat.iter_mut().for_each(|x| *x = -*x);
    }
    out[3..7].copy_from_slice(&quat);
}

/// `q ⊕ v`: the configuration reached from q by following the velocity v for unit time.
/// The free-flyer moves by `exp6(v)` in its local frame.
pub fn integrate(model: &Model, q: &[f64], v: &[f64]) -> Result<DVector<f64>> {
    let mut out = DVector::zeros(model.nq);
    integrate_to(model, q, v, out.as_mut_slice())?;
    Ok(out)
}

/// [`integrate`] into a caller-owned buffer of size nq (no allocation).
pub fn integrate_to(model: &Model, q: &[f64], v: &[f64], out: &mut [f64]) -> Result<()> {
    model.check_configuration(q)?;
    check_vector("velocity v", v, model.nv)?;
    if out.len() != model.nq {
        return Err(crate::ModelError::Dimension {
            what: "output configuration",
            got: out.len(),
            expected: model.nq,
        });
    }
    out.copy_from_slice(q);
    for j in &model.joints {
        let (iq, iv) = (j.idx_q, j.idx_v);
        match j.kind {
            JointKind::FreeFlyer => {
                let m = ff_placement(&q[iq..]) * exp6(&Motion::from_slice(&v[iv..iv + 6]));
                write_ff(&m, &mut out[iq..iq + 7]);
                // The quaternion in q's hemisphere, as Pinocchio keeps it (a continuous
                // trajectory of quaternions, not w ≥ 0).
                let dot: f64 = (3..7).map(|k| out[iq + k] * q[iq + k]).sum();
                if dot < 0.0 {
                    out[iq + 3..iq + 7].iter_mut().for_each(|x| *x = -*x);
                }
            }
            JointKind::RevoluteUnbounded { .. } => {
                let (s, c) = v[iv].sin_cos();
                let (c0, s0) = (q[iq], q[iq + 1]);
                let (c1, s1) = (c0 * c - s0 * s, s0 * c + c0 * s);
                let n = (c1 * c1 + s1 * s1).sqrt();
                out[iq] = c1 / n;
                out[iq + 1] = s1 / n;
            }
            _ => out[iq] += v[iv],
        }
    }
    Ok(())
}

/// `q1 ⊖ q0`: the velocity v with `integrate(q0, v) = q1`.
pub fn difference(model: &Model, q0: &[f64], q1: &[f64]) -> Result<DVector<f64>> {
    let mut v = DVector::zeros(model.nv);
    difference_to(model, q0, q1, v.as_mut_slice())?;
    Ok(v)
}

/// [`difference`] into a caller-owned buffer of size nv (no allocation).
pub fn difference_to(model: &Model, q0: &[f64], q1: &[f64], v: &mut [f64]) -> Result<()> {
    model.check_configuration(q0)?;
    model.check_configuration(q1)?;
    if v.len() != model.nv {
        return Err(crate::ModelError::Dimension {
            what: "output velocity",
            got: v.len(),
            expected: model.nv,
        });
    }
    for j in &model.joints {
        let (iq, iv) = (j.idx_q, j.idx_v);
        match j.kind {
            JointKind::FreeFlyer => {
                let d = log6(&(ff_placement(&q0[iq..]).inverse() * ff_placement(&q1[iq..])));
                v[iv..iv + 6].copy_from_slice(d.to_vector().as_slice());
            }
            JointKind::RevoluteUnbounded { .. } => {
                let (c0, s0, c1, s1) = (q0[iq], q0[iq + 1], q1[iq], q1[iq + 1]);
                v[iv] = (c0 * s1 - s0 * c1).atan2(c0 * c1 + s0 * s1);
            }
            _ => v[iv] = q1[iq] - q0[iq],
        }
    }
    Ok(())
}

/// The configuration a fraction `u` of the way from q0 to q1 along the group geodesic.
pub fn interpolate(model: &Model, q0: &[f64], q1: &[f64], u: f64) -> Result<DVector<f64>> {
    let d = difference(model, q0, q1)? * u;
    integrate(model, q0, d.as_slice())
}

/// A random configuration: joints uniform within their position limits (or ±π where a limit
/// is infinite), the free-flyer position uniform in ±1 m and a uniformly random orientation.
pub fn random_configuration(model: &Model, rng: &mut impl Rng) -> DVector<f64> {
    let mut q = neutral(model);
    let bounded = |lo: f64, hi: f64, rng: &mut dyn rand::RngCore| {
        let lo = if lo.is_finite() {
            lo
        } else {
            -std::f64::consts::PI
        };
        let hi = if hi.is_finite() {
            hi
        } else {
            std::f64::consts::PI
        };
        if hi > lo {
            rng.gen_range(lo..=hi)
        } else {
            lo
        }
    };
    for j in &model.joints {
        let iq = j.idx_q;
        match j.kind {
            JointKind::FreeFlyer => {
                for k in 0..3 {
                    let (lo, hi) = (
                        model.lower_position_limit[iq + k],
                        model.upper_position_limit[iq + k],
                    );
                    q[iq + k] = if lo.is_finite() && hi.is_finite() {
                        bounded(lo, hi, rng)
                    } else {
                        rng.gen_range(-1.0..=1.0)
                    };
                }
                // Uniform random rotation (Shoemake 1992).
                let (u1, u2, u3): (f64, f64, f64) = (rng.gen(), rng.gen(), rng.gen());
                let tau = std::f64::consts::TAU;
                let (a, b) = ((1.0 - u1).sqrt(), u1.sqrt());
                q[iq + 3] = a * (tau * u2).sin();
                q[iq + 4] = a * (tau * u2).cos();
                q[iq + 5] = b * (tau * u3).sin();
                q[iq + 6] = b * (tau * u3).cos();
            }
            JointKind::RevoluteUnbounded { .. } => {
                let t: f64 = rng.gen_range(-std::f64::consts::PI..std::f64::consts::PI);
                q[iq] = t.cos();
                q[iq + 1] = t.sin();
            }
            _ => {
                q[iq] = bounded(
                    model.lower_position_limit[iq],
                    model.upper_position_limit[iq],
                    rng,
                )
            }
        }
    }
    q
}
