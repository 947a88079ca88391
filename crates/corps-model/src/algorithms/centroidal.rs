//! Centre of mass, its Jacobian, and the centroidal momentum matrix A_G with its drift
//! Ȧ_G v (Orin, Goswami & Lee 2013; Pinocchio's `ccrba`, `computeCentroidalMapTimeVariation`).

use super::crba::composite_pass;
use super::kinematics::motion_pass;
use crate::data::{col_force, set_col, Data};
use crate::error::Result;
use crate::model::{check_vector, Model};
use crate::spatial::{Force, Motion};
use nalgebra::{Matrix3xX, Matrix6xX, Vector3};

/// CoM, its Jacobian and A_G from the composite inertias and Jacobians of a composite pass.
pub(crate) fn fill_from_composites(model: &Model, data: &mut Data) {
    let mut mass = 0.0;
    let mut mc = Vector3::zeros();
    for (i, j) in model.joints.iter().enumerate() {
        if j.parent.is_none() {
            mass += data.composite[i].mass;
            mc += data.composite[i].first_moment;
        }
    }
    let com = if mass > 0.0 {
        mc / mass
    } else {
        Vector3::zeros()
    };
    data.com = com;
    let inv_mass = if mass > 0.0 { 1.0 / mass } else { 0.0 };
    // The composite pass left F_k = Yc S_k (about the world origin) per dof: its linear part
    // is m_sub ċ-direction, so Jcom_k = F_k.linear / m and A_G,k = F_k moved to the CoM.
    for k in 0..model.nv {
        let h = col_force(&data.f_cols, k);
        data.jcom.column_mut(k).copy_from(&(h.linear * inv_mass));
        let hg = h.shifted_to(&com);
        set_col(&mut data.ag, k, &hg.linear, &hg.angular);
    }
}

/// Centroidal momentum matrix A_G (`data.ag`, about the CoM, world axes), the CoM
/// (`data.com`) and its Jacobian (`data.jcom`).
pub fn compute_centroidal_map<'d>(
    model: &Model,
    data: &'d mut Data,
    q: &[f64],
) -> Result<&'d Matrix6xX<f64>> {
    model.check_configuration(q)?;
    composite_pass(model, data, q, false, false);
    fill_from_composites(model, data);
    Ok(&data.ag)
}

/// Jacobian of the centre of mass (`data.jcom`, 3 × nv); also sets `data.com`.
pub fn jacobian_center_of_mass<'d>(
    model: &Model,
    data: &'d mut Data,
    q: &[f64],
) -> Result<&'d Matrix3xX<f64>> {
    compute_centroidal_map(model, data, q)?;
    Ok(&data.jcom)
}

/// Centroidal momentum h_G = A_G v (`data.hg`); also fills A_G.
pub fn compute_centroidal_momentum(
    model: &Model,
    data: &mut Data,
    q: &[f64],
    v: &[f64],
) -> Result<Force> {
    check_vector("velocity v", v, model.nv)?;
    compute_centroidal_map(model, data, q)?;
    let mut h = Force::zero();
    for (k, vk) in v.iter().enumerate() {
        h += crate::data::col_force(&data.ag, k) * *vk;
    }
    data.hg = h;
    Ok(data.hg)
}

/// The centroidal momentum drift Ȧ_G v (`data.dag_v`): the rate of change of h_G at zero
/// joint acceleration, Σ_i ᵒX_i* (I_i a_i + v_i ×* I_i v_i) with q̈ = 0, taken about the CoM.
/// (The CoM velocity term drops: ċ × m ċ = 0.) Also fills A_G, the CoM and h_G.
pub fn centroidal_momentum_drift(
    model: &Model,
    data: &mut Data,
    q: &[f64],
    v: &[f64],
) -> Result<Force> {
    compute_centroidal_momentum(model, data, q, v)?;
    motion_pass(model, data, q, Some(v), None, false);
    let mut rate = Force::zero();
    for i in 0..model.njoints() {
        let inertia = &model.inertias[i];
        let (vi, ai): (Motion, Motion) = (data.v[i], data.a[i]);
        let f = inertia.mul_motion(&ai) + vi.cross_force(&inertia.mul_motion(&vi));
        rate += data.o_m_i[i].act_force(&f);
    }
    data.dag_v = rate.shifted_to(&data.com);
    Ok(data.dag_v)
}

/// Centre of mass position, velocity and acceleration (`data.com`, `data.vcom`, `data.acom`).
pub fn center_of_mass(
    model: &Model,
    data: &mut Data,
    q: &[f64],
    v: &[f64],
    a: &[f64],
) -> Result<Vector3<f64>> {
    super::kinematics::forward_kinematics(model, data, q, v, a)?;
    let (mut m, mut c, mut vc, mut ac) =
        (0.0, Vector3::zeros(), Vector3::zeros(), Vector3::zeros());
    for i in 0..model.njoints() {
        let inertia = &model.inertias[i];
        let (r, l) = (data.o_m_i[i].rotation, inertia.lever);
        let (vi, ai) = (data.v[i], data.a[i]);
        let vp = vi.point_velocity(&l);
        m += inertia.mass;
        c += data.o_m_i[i].act_point(&l) * inertia.mass;
        vc += r * vp * inertia.mass;
        ac += r * (ai.point_velocity(&l) + vi.angular.cross(&vp)) * inertia.mass;
    }
    let inv = if m > 0.0 { 1.0 / m } else { 0.0 };
    data.com = c * inv;
    data.vcom = vc * inv;
    data.acom = ac * inv;
    Ok(data.com)
}

/// Centre of mass and its velocity from the placements and world twists already in
/// `data.o_m_i` and `data.ov` (e.g. a simulator's end-of-step kinematics):
/// c = Σ m_i ᵒc_i / m and ċ = Σ m_i (ᵒv_i + ᵒω_i × ᵒc_i) / m, with ᵒc_i = ᵒM_i c_i.
/// No kinematic pass (no trigonometry); the caller vouches that both are current. Writes
/// nothing.
pub fn com_at_placements(model: &Model, data: &Data) -> (Vector3<f64>, Vector3<f64>) {
    let (mut m, mut c, mut vc) = (0.0, Vector3::zeros(), Vector3::zeros());
    for ((inertia, placement), twist) in model.inertias.iter().zip(&data.o_m_i).zip(&data.ov) {
        let ci = placement.act_point(&inertia.lever);
        m += inertia.mass;
        c += ci * inertia.mass;
        vc += twist.point_velocity(&ci) * inertia.mass;
    }
    let inv = if m > 0.0 { 1.0 / m } else { 0.0 };
    (c * inv, vc * inv)
}

/// Both drifts a whole-body controller needs at q̈ = 0, from one kinematic pass: the CoM
/// acceleration J̇com v (`data.acom`) and the centroidal momentum rate Ȧ_G v (`data.dag_v`,
/// about `data.com`). Needs `data.com` and the joint placements at q (both left by
/// [`crate::compute_all_terms`] at q; the placements are reused, no joint trigonometry);
/// leaves the q̈ = 0 local velocities and accelerations in `data.v`, `data.a` (frame drifts).
pub fn com_and_momentum_drifts(
    model: &Model,
    data: &mut Data,
    q: &[f64],
    v: &[f64],
) -> Result<(Vector3<f64>, Force)> {
    model.check_configuration(q)?;
    check_vector("velocity v", v, model.nv)?;
    motion_pass(model, data, q, Some(v), None, true);
    let (mut m, mut ac, mut rate) = (0.0, Vector3::zeros(), Force::zero());
    for i in 0..model.njoints() {
        let inertia = &model.inertias[i];
        let (vi, ai) = (data.v[i], data.a[i]);
        let l = inertia.lever;
        let vp = vi.point_velocity(&l);
        m += inertia.mass;
        ac +=
            data.o_m_i[i].rotation * (ai.point_velocity(&l) + vi.angular.cross(&vp)) * inertia.mass;
        let f = inertia.mul_motion(&ai) + vi.cross_force(&inertia.mul_motion(&vi));
        rate += data.o_m_i[i].act_force(&f);
    }
    data.acom = if m > 0.0 { ac / m } else { Vector3::zeros() };
    data.dag_v = rate.shifted_to(&data.com);
    Ok((data.acom, data.dag_v))
}
