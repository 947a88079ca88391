//! Articulated-body algorithm: forward dynamics q̈ = M(q)⁻¹ (τ − h(q, v)) in O(n)
//! (Featherstone, RBDA Table 7.1), in the world frame so that articulated inertias add
//! without transforms (as Pinocchio 3 does).
//!
//! World-frame form: S_i ← ᵒX_i S_i, c_i = ᵒv_i × S_i q̇_i, p_i = ᵒv_i ×* (ᵒI_i ᵒv_i);
//! backward U = I^A S, D = Sᵀ U, u = τ − Sᵀ p^A, I^a = I^A − U D⁻¹ Uᵀ,
//! p^a = p^A + I^a c + U D⁻¹ u; forward q̈ = D⁻¹ (u − Uᵀ a_λ'), a = a_λ + c + S q̈.

use super::jacobians::{joint_world_twist, write_joint_columns};
use super::kinematics::place_joint;
use crate::data::{col_motion, Data};
use crate::error::Result;
use crate::joint::JointKind;
use crate::model::{check_vector, Model};
use crate::spatial::kernels::{m6_add_assign, m6_rank1_sub, m6v};
use crate::spatial::{Force, Motion, Se3};
use nalgebra::{DVector, Vector3, Vector6};

/// q̈ = ABA(q, v, τ), written to and returned from `data.ddq`.
pub fn aba<'d>(
    model: &Model,
    data: &'d mut Data,
    q: &[f64],
    v: &[f64],
    tau: &[f64],
) -> Result<&'d DVector<f64>> {
    model.check_configuration(q)?;
    check_vector("velocity v", v, model.nv)?;
    check_vector("torque tau", tau, model.nv)?;
    aba_pass(model, data, q, v, tau, |_, _, _| {});
    Ok(&data.ddq)
}

/// q̈ = ABA(q, v, τ, f_ext) with external wrenches on the bodies. After the first pass has
/// placed the bodies, `external(o_m_i, ov, f_ext)` is called with every joint's world
/// placement and world twist and a zeroed buffer of world-frame wrenches (moment about the
/// world origin), one per joint body, to fill. Used by the simulator for contact forces.
pub fn aba_with_external_forces<'d, F>(
    model: &Model,
    data: &'d mut Data,
    q: &[f64],
    v: &[f64],
    tau: &[f64],
    external: F,
) -> Result<&'d DVector<f64>>
where
    F: FnMut(&[Se3], &[Motion], &mut [Force]),
{
    model.check_configuration(q)?;
    check_vector("velocity v", v, model.nv)?;
    check_vector("torque tau", tau, model.nv)?;
    aba_pass(model, data, q, v, tau, external);
    Ok(&data.ddq)
}

pub(crate) fn aba_pass<F>(
    model: &Model,
    data: &mut Data,
    q: &[f64],
    v: &[f64],
    tau: &[f64],
    mut external: F,
) where
    F: FnMut(&[Se3], &[Motion], &mut [Force]),
{
    // Forward: placements, world twists, bias accelerations and forces, body inertias.
    for (i, j) in model.joints.iter().enumerate() {
        place_joint(j, i, data, q, false);
        write_joint_columns(model, data, i);
        let vj = joint_world_twist(data, j, v);
        let ov = match j.parent {
            Some(p) => data.ov[p] + vj,
            None => vj,
        };
        data.ov[i] = ov;
        data.oa[i] = ov.cross(&vj); // bias acceleration c_i
        let oi = model.inertias[i].transformed(&data.o_m_i[i]);
        data.pa[i] = ov.cross_force(&oi.mul_motion(&ov));
        oi.write_matrix(&mut data.bcrb[i]);
    }
    data.fext.iter_mut().for_each(|f| *f = Force::zero());
    external(&data.o_m_i, &data.ov, &mut data.fext);
    for (pa, f) in data.pa.iter_mut().zip(&data.fext) {
        *pa -= *f;
    }
    // Backward: articulated inertias (held in data.bcrb) and bias forces.
    for (i, j) in model.joints.iter().enumerate().rev() {
        if j.kind == JointKind::FreeFlyer {
            continue; // always a root: solved directly in the forward pass
        }
        let k = j.idx_v;
        let s = col_motion(&data.j, k).to_vector();
        let ia = data.bcrb[i];
        let u_vec = m6v(&ia, &s);
        let d_inv = 1.0 / s.dot(&u_vec);
        let u = tau[k] - s.dot(&data.pa[i].to_vector());
        data.d_inv[k] = d_inv;
        data.u[k] = u;
        crate::data::set_col(
            &mut data.f_cols,
            k,
            &u_vec.fixed_rows::<3>(0).into(),
            &u_vec.fixed_rows::<3>(3).into(),
        );
        let mut ia_art = ia;
        m6_rank1_sub(&mut ia_art, &u_vec, d_inv);
        let c = data.oa[i].to_vector();
        let pa_art = data.pa[i].to_vector() + m6v(&ia_art, &c) + u_vec * (u * d_inv);
        if let Some(p) = j.parent {
            m6_add_assign(&mut data.bcrb[p], &ia_art);
            data.pa[p] += Force::from_vector(&pa_art);
        }
    }
    // Forward: accelerations.
    let a0 = Motion::new(-model.gravity, Vector3::zeros());
    for (i, j) in model.joints.iter().enumerate() {
        match j.kind {
            JointKind::FreeFlyer => {
                // Root free-flyer: I^A a = ᵒX_i^{-T} τ − p^A, then q̈ = ᵒX_i⁻¹ (a − a₀).
                let tau_w = data.o_m_i[i].act_force(&Force::from_vector(
                    &Vector6::from_column_slice(&tau[j.idx_v..j.idx_v + 6]),
                ));
                let rhs = (tau_w - data.pa[i]).to_vector();
                // I^A of a body with mass is positive definite; a massless floating tree
                // has no defined acceleration and gets NaN, which callers can detect.
                let a = data.bcrb[i]
                    .cholesky()
                    .map(|ch| ch.solve(&rhs))
                    .unwrap_or_else(|| Vector6::repeat(f64::NAN));
                let a = Motion::from_vector(&a);
                let ddq = data.o_m_i[i].act_inv_motion(&(a - a0));
                data.ddq.as_mut_slice()[j.idx_v..j.idx_v + 6]
                    .copy_from_slice(ddq.to_vector().as_slice());
                data.oa[i] = a;
            }
            _ => {
                let k = j.idx_v;
                let ap = j.parent.map_or(a0, |p| data.oa[p]);
                let a = ap + data.oa[i];
                let u_vec = crate::data::col_force(&data.f_cols, k);
                let ddq = data.d_inv[k] * (data.u[k] - a.dot(&u_vec));
                data.ddq[k] = ddq;
                data.oa[i] = a + col_motion(&data.j, k) * ddq;
            }
        }
    }
}
