//! Recursive Newton–Euler: inverse dynamics τ = M(q) q̈ + C(q, q̇) q̇ + g(q) (RBDA Table 5.1),
//! and its special cases, the non-linear effects and the generalized gravity.

use super::kinematics::local_placement;
use crate::data::Data;
use crate::error::Result;
use crate::model::{check_vector, Model};
use crate::spatial::{Force, Motion};

/// τ = RNEA(q, v, a), written to and returned from `data.tau`.
pub fn rnea<'d>(
    model: &Model,
    data: &'d mut Data,
    q: &[f64],
    v: &[f64],
    a: &[f64],
) -> Result<&'d nalgebra::DVector<f64>> {
    model.check_configuration(q)?;
    check_vector("velocity v", v, model.nv)?;
    check_vector("acceleration a", a, model.nv)?;
    rnea_pass(model, data, q, Some(v), Some(a), true, false);
    Ok(&data.tau)
}

/// h(q, v) = C(q, v) v + g(q), written to `data.nle`.
pub fn nonlinear_effects<'d>(
    model: &Model,
    data: &'d mut Data,
    q: &[f64],
    v: &[f64],
) -> Result<&'d nalgebra::DVector<f64>> {
    model.check_configuration(q)?;
    check_vector("velocity v", v, model.nv)?;
    rnea_pass(model, data, q, Some(v), None, true, false);
    data.nle.copy_from(&data.tau);
    Ok(&data.nle)
}

/// h(q, v) as [`nonlinear_effects`], at the configuration whose joint placements
/// `data.li_m_i` already hold (a CRBA, kinematics or RNEA pass at q just ran): no joint
/// trigonometry. The caller vouches for q, as for [`crate::world_motions_from_jacobians`].
pub fn nonlinear_effects_at_placements<'d>(
    model: &Model,
    data: &'d mut Data,
    v: &[f64],
) -> Result<&'d nalgebra::DVector<f64>> {
    check_vector("velocity v", v, model.nv)?;
    rnea_pass(model, data, &[], Some(v), None, true, true);
    data.nle.copy_from(&data.tau);
    Ok(&data.nle)
}

/// g(q), written to `data.g`.
pub fn generalized_gravity<'d>(
    model: &Model,
    data: &'d mut Data,
    q: &[f64],
) -> Result<&'d nalgebra::DVector<f64>> {
    model.check_configuration(q)?;
    rnea_pass(model, data, q, None, None, true, false);
    data.g.copy_from(&data.tau);
    Ok(&data.g)
}

/// The RNEA passes on checked inputs; `None` stands for zero. Result in `data.tau`.
pub(crate) fn rnea_pass(
    model: &Model,
    data: &mut Data,
    q: &[f64],
    v: Option<&[f64]>,
    a: Option<&[f64]>,
    gravity: bool,
    reuse_placements: bool,
) {
    let a0 = if gravity {
        Motion::new(-model.gravity, nalgebra::Vector3::zeros())
    } else {
        Motion::zero()
    };
    for (i, j) in model.joints.iter().enumerate() {
        let li = local_placement(j, i, data, q, reuse_placements);
        let vj = v.map_or(Motion::zero(), |v| j.kind.motion(&v[j.idx_v..]));
        let aj = a.map_or(Motion::zero(), |a| j.kind.motion(&a[j.idx_v..]));
        let (vi, ap) = match j.parent {
            Some(p) => (li.act_inv_motion(&data.v[p]) + vj, data.a_gf[p]),
            None => (vj, a0),
        };
        let ai = li.act_inv_motion(&ap) + aj + vi.cross(&vj);
        let inertia = &model.inertias[i];
        data.v[i] = vi;
        data.a_gf[i] = ai;
        data.f[i] = inertia.mul_motion(&ai) + vi.cross_force(&inertia.mul_motion(&vi));
    }
    for (i, j) in model.joints.iter().enumerate().rev() {
        let fi = data.f[i];
        write_joint_force(j, &fi, data.tau.as_mut_slice());
        if let Some(p) = j.parent {
            let fp = data.li_m_i[i].act_force(&fi);
            data.f[p] += fp;
        }
    }
}

/// τ_i = S_iᵀ f_i for one joint.
#[inline]
pub(crate) fn write_joint_force(j: &crate::joint::Joint, f: &Force, tau: &mut [f64]) {
    match j.kind.axis_motion() {
        Some(s) => tau[j.idx_v] = s.dot(f),
        None => {
            tau[j.idx_v..j.idx_v + 3].copy_from_slice(f.linear.as_slice());
            tau[j.idx_v + 3..j.idx_v + 6].copy_from_slice(f.angular.as_slice());
        }
    }
}
