//! Forward kinematics: joint placements, velocities and accelerations (local frames).

use crate::data::Data;
use crate::error::Result;
use crate::model::{check_vector, Model};
use crate::spatial::Motion;

/// Joint placements only: `li_m_i` and `o_m_i` for configuration `q`.
pub fn forward_kinematics_placements(model: &Model, data: &mut Data, q: &[f64]) -> Result<()> {
    model.check_configuration(q)?;
    placements(model, data, q, false);
    Ok(())
}

/// Placements, velocities and accelerations (local, gravity excluded) of every joint:
/// `v_i = ⁱX_λ v_λ + S_i q̇_i`, `a_i = ⁱX_λ a_λ + S_i q̈_i + v_i × S_i q̇_i` (RBDA Eq. 5.7–5.8).
pub fn forward_kinematics(
    model: &Model,
    data: &mut Data,
    q: &[f64],
    v: &[f64],
    a: &[f64],
) -> Result<()> {
    model.check_configuration(q)?;
    check_vector("velocity v", v, model.nv)?;
    check_vector("acceleration a", a, model.nv)?;
    motion_pass(model, data, q, Some(v), Some(a), false);
    Ok(())
}

/// Computes `li_m_i` and `o_m_i` (q already checked); with `reuse`, `o_m_i` only, from the
/// `li_m_i` a pass at the same q left (the joint trigonometry of one state runs once).
#[inline]
pub(crate) fn placements(model: &Model, data: &mut Data, q: &[f64], reuse: bool) {
    for (i, j) in model.joints.iter().enumerate() {
        place_joint(j, i, data, q, reuse);
    }
}

/// `li_m_i` of joint `i` at `q`, or with `reuse` the one already in `data` (computed at the
/// same q by an earlier pass).
#[inline]
pub(crate) fn local_placement(
    j: &crate::joint::Joint,
    i: usize,
    data: &mut Data,
    q: &[f64],
    reuse: bool,
) -> crate::spatial::Se3 {
    if reuse {
        data.li_m_i[i]
    } else {
        let li = j.kind.placed_transform(&j.placement, &q[j.idx_q..]);
        data.li_m_i[i] = li;
        li
    }
}

/// `li_m_i` and `o_m_i` of joint `i` (its parent already placed); with `reuse`, from the
/// `li_m_i` already in `data` (see [`local_placement`]).
#[inline]
pub(crate) fn place_joint(
    j: &crate::joint::Joint,
    i: usize,
    data: &mut Data,
    q: &[f64],
    reuse: bool,
) {
    let li = local_placement(j, i, data, q, reuse);
    data.o_m_i[i] = match j.parent {
        Some(p) => data.o_m_i[p] * li,
        None => li,
    };
}

/// Placements, local velocities and accelerations; `None` stands for a zero vector. With
/// `reuse`, the local placements are those already in `data` (see [`local_placement`]).
pub(crate) fn motion_pass(
    model: &Model,
    data: &mut Data,
    q: &[f64],
    v: Option<&[f64]>,
    a: Option<&[f64]>,
    reuse: bool,
) {
    for (i, j) in model.joints.iter().enumerate() {
        let li = local_placement(j, i, data, q, reuse);
        let vj = v.map_or(Motion::zero(), |v| j.kind.motion(&v[j.idx_v..]));
        let aj = a.map_or(Motion::zero(), |a| j.kind.motion(&a[j.idx_v..]));
        let (vi, ai, omi) = match j.parent {
            Some(p) => (
                li.act_inv_motion(&data.v[p]) + vj,
                li.act_inv_motion(&data.a[p]),
                data.o_m_i[p] * li,
            ),
            None => (vj, Motion::zero(), li),
        };
        data.o_m_i[i] = omi;
        data.v[i] = vi;
        data.a[i] = ai + aj + vi.cross(&vj);
    }
}
