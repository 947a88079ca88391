//! Articulated-body algorithm: forward dynamics q̈ = M(q)⁻¹ (τ − h(q, v)) in O(n)
//! (Featherstone, RBDA Table 7.1), in each joint's own frame (Pinocchio's LOCAL convention).
//!
//! Why that frame: about the world origin (Pinocchio's WORLD convention) a light body far from
//! the origin has an articulated inertia of size m‖c‖², and D = Sᵀ I^A S of its joint is a
//! small difference of such terms (a 10 g hand link 1 m away: 1e-2 for a result of 1e-6); the
//! rank-one downdate then leaves rounding noise along the joint's axis that its parent adds
//! up. In the joint's frame the body's inertia is the model's, S is a unit axis (D is one
//! entry of I^A, the downdate cancels that row exactly), and a child reaches its parent
//! through the short joint-to-joint transform. Measured on iCub with its hands (cond(M) to
//! 1e11): the residual ‖M q̈ + h − τ‖ of the world-frame form is 50× Pinocchio's, this one's
//! on a par (tests/aba_precision.rs).
//!
//! c_i = v_i × S_i q̇_i, p_i = v_i ×* (I_i v_i) − f_ext; backward U = I^A S, D = Sᵀ U,
//! u = τ − Sᵀ p^A, I^a = I^A − U D⁻¹ Uᵀ, p^a = p^A + I^a c + U D⁻¹ u, both moved to the parent
//! (ᵏX_iᵀ I^a ᵏX_i, `m6_transformed_add`); forward q̈ = D⁻¹ (u − Uᵀ a'), a' = ᶦX_λ a_λ + c,
//! a = a' + S q̈.

use super::kinematics::place_joint;
use crate::data::Data;
use crate::error::Result;
use crate::joint::{unit_axis, Joint, JointKind};
use crate::model::{check_vector, Model};
use crate::spatial::kernels::{m6_rank1_sub, m6_transformed_add, m6v};
use crate::spatial::{Force, Motion, Se3};
use nalgebra::{DVector, Vector3, Vector6};

/// q̈ = ABA(q, v, τ), written to and returned from `data.ddq`; each joint's twist and
/// acceleration (the gravity field included) are left in `data.v` and `data.a`, local.
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
    aba_pass(
        model,
        data,
        q,
        v,
        tau,
        None::<fn(&[Se3], &[Motion], &mut [Force])>,
    );
    Ok(&data.ddq)
}

/// q̈ = ABA(q, v, τ, f_ext) with external wrenches on the bodies. After the first pass has
/// placed the bodies, `external(o_m_i, ov, f_ext)` is called with every joint's world
/// placement and world twist and a zeroed buffer of world-frame wrenches (moment about the
/// world origin), one per joint body, to fill. Used by the simulator for contact forces.
/// Besides `data.v` and `data.a`, leaves the world twists and accelerations in `data.ov` and
/// `data.oa` (spatial, at the world origin, the gravity field included).
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
    aba_pass(model, data, q, v, tau, Some(external));
    Ok(&data.ddq)
}

/// The three passes; with `external`, also the world twists and accelerations `data.ov`,
/// `data.oa` (spatial, at the world origin) and the external wrenches.
pub(crate) fn aba_pass<F>(
    model: &Model,
    data: &mut Data,
    q: &[f64],
    v: &[f64],
    tau: &[f64],
    mut external: Option<F>,
) where
    F: FnMut(&[Se3], &[Motion], &mut [Force]),
{
    // Forward: placements, twists, bias accelerations and forces, body inertias (local).
    for (i, j) in model.joints.iter().enumerate() {
        place_joint(j, i, data, q, false);
        let vj = j.kind.motion(&v[j.idx_v..]);
        let vi = match j.parent {
            Some(parent) => data.li_m_i[i].act_inv_motion(&data.v[parent]) + vj,
            None => vj,
        };
        data.v[i] = vi;
        if external.is_some() {
            data.ov[i] = data.o_m_i[i].act_motion(&vi);
        }
        data.a[i] = vi.cross(&vj); // bias acceleration c_i
        let inertia = &model.inertias[i];
        data.pa[i] = vi.cross_force(&inertia.mul_motion(&vi));
        inertia.write_matrix(&mut data.bcrb[i]);
    }
    if let Some(external) = external.as_mut() {
        data.fext.iter_mut().for_each(|f| *f = Force::zero());
        external(&data.o_m_i, &data.ov, &mut data.fext);
        for ((pa, f), m) in data.pa.iter_mut().zip(&data.fext).zip(&data.o_m_i) {
            if *f != Force::zero() {
                *pa -= m.act_inv_force(f);
            }
        }
    }
    // Backward: articulated inertias (held in data.bcrb) and bias forces.
    for (i, j) in model.joints.iter().enumerate().rev() {
        if j.kind == JointKind::FreeFlyer {
            continue; // always a root: solved directly in the forward pass
        }
        let k = j.idx_v;
        let ia = &data.bcrb[i];
        let (u_vec, d_inv, u) = match revolute_unit_axis(j) {
            // A unit axis ±e_c (most URDF joints): U is a column of I^A and D one entry.
            Some((c, sign)) => {
                let u_vec: Vector6<f64> = ia.column(3 + c) * sign;
                let u = tau[k] - sign * data.pa[i].angular[c];
                (u_vec, 1.0 / ia[(3 + c, 3 + c)], u)
            }
            None => {
                let s = subspace(j).to_vector();
                let u_vec = m6v(ia, &s);
                (
                    u_vec,
                    1.0 / s.dot(&u_vec),
                    tau[k] - s.dot(&data.pa[i].to_vector()),
                )
            }
        };
        data.d_inv[k] = d_inv;
        data.u[k] = u;
        crate::data::set_col(
            &mut data.f_cols,
            k,
            &u_vec.fixed_rows::<3>(0).into(),
            &u_vec.fixed_rows::<3>(3).into(),
        );
        // I^a in place of I^A (U was read first).
        m6_rank1_sub(&mut data.bcrb[i], &u_vec, d_inv);
        let c = data.a[i].to_vector();
        let pa_art = data.pa[i].to_vector() + m6v(&data.bcrb[i], &c) + u_vec * (u * d_inv);
        if let Some(parent) = j.parent {
            let li = &data.li_m_i[i];
            let (above, from_i) = data.bcrb.split_at_mut(i);
            m6_transformed_add(
                &mut above[parent],
                &from_i[0],
                &li.rotation,
                &li.translation,
            );
            data.pa[parent] += li.act_force(&Force::from_vector(&pa_art));
        }
    }
    // Forward: accelerations (the gravity field included: the root accelerates by −g more).
    let a0 = Motion::new(-model.gravity, Vector3::zeros());
    for (i, j) in model.joints.iter().enumerate() {
        let ap = match j.parent {
            Some(parent) => data.li_m_i[i].act_inv_motion(&data.a[parent]),
            None => data.li_m_i[i].act_inv_motion(&a0),
        };
        match j.kind {
            JointKind::FreeFlyer => {
                // Root free-flyer (S = 1 in its frame): I^A a = τ − p^A, q̈ = a − ᶦX₀ a₀.
                let rhs =
                    Vector6::from_column_slice(&tau[j.idx_v..j.idx_v + 6]) - data.pa[i].to_vector();
                // I^A of a body with mass is positive definite; a massless floating tree
                // has no defined acceleration and gets NaN, which callers can detect.
                let a = data.bcrb[i]
                    .cholesky()
                    .map(|ch| ch.solve(&rhs))
                    .unwrap_or_else(|| Vector6::repeat(f64::NAN));
                data.ddq.as_mut_slice()[j.idx_v..j.idx_v + 6]
                    .copy_from_slice((a - ap.to_vector()).as_slice());
                data.a[i] = Motion::from_vector(&a);
            }
            _ => {
                let k = j.idx_v;
                let a = ap + data.a[i];
                let u_vec = crate::data::col_force(&data.f_cols, k);
                let ddq = data.d_inv[k] * (data.u[k] - a.dot(&u_vec));
                data.ddq[k] = ddq;
                data.a[i] = a + subspace(j) * ddq;
            }
        }
        if external.is_some() {
            data.oa[i] = data.o_m_i[i].act_motion(&data.a[i]);
        }
    }
}

/// S of a one-dof joint in its own frame (never asked of the root free-flyer, solved apart).
#[inline(always)]
fn subspace(j: &Joint) -> Motion {
    j.kind.axis_motion().unwrap_or_default()
}

/// `(c, ±1)` for a revolute joint about ±e_c.
#[inline(always)]
fn revolute_unit_axis(j: &Joint) -> Option<(usize, f64)> {
    match j.kind {
        JointKind::Revolute { axis } | JointKind::RevoluteUnbounded { axis } => unit_axis(&axis),
        _ => None,
    }
}
