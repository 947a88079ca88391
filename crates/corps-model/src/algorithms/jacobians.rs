//! Joint Jacobians in the world frame, and frame Jacobians in LOCAL, WORLD and
//! LOCAL_WORLD_ALIGNED.

use super::kinematics::{place_joint, placements};
use crate::data::{col_motion, set_col, Data};
use crate::error::{ModelError, Result};
use crate::joint::{unit_axis, Joint, JointKind};
use crate::model::Model;
use crate::spatial::{Motion, Se3};
use nalgebra::Matrix6xX;

/// The frame in which a Jacobian, velocity or acceleration is expressed (Pinocchio's
/// `ReferenceFrame`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ReferenceFrame {
    /// The frame itself (origin and axes of the frame).
    Local,
    /// The world frame (twists at the world origin).
    World,
    /// Origin at the frame, axes of the world.
    LocalWorldAligned,
}

/// World twist of dof `k`'s unit motion, given the joint's world placement.
#[inline]
pub(crate) fn world_subspace(j: &Joint, o_m_i: &Se3, k: usize) -> Motion {
    match j.kind {
        JointKind::Revolute { axis } | JointKind::RevoluteUnbounded { axis } => {
            let w = match unit_axis(&axis) {
                Some((c, sign)) => o_m_i.rotation.column(c) * sign,
                None => o_m_i.rotation * axis,
            };
            Motion::new(o_m_i.translation.cross(&w), w)
        }
        JointKind::Prismatic { axis } => {
            Motion::new(o_m_i.rotation * axis, nalgebra::Vector3::zeros())
        }
        JointKind::FreeFlyer => {
            let mut e = [0.0; 6];
            e[k] = 1.0;
            o_m_i.act_motion(&Motion::from_slice(&e))
        }
    }
}

/// Writes the world Jacobian columns of joint `i` (placements must be current).
#[inline]
pub(crate) fn write_joint_columns(model: &Model, data: &mut Data, i: usize) {
    let j = &model.joints[i];
    for k in 0..j.nv() {
        let s = world_subspace(j, &data.o_m_i[i], k);
        set_col(&mut data.j, j.idx_v + k, &s.linear, &s.angular);
    }
}

/// The world twist `S_w q̇` of joint `j` from its Jacobian columns (written already).
#[inline]
pub(crate) fn joint_world_twist(data: &Data, j: &Joint, v: &[f64]) -> Motion {
    let mut t = Motion::zero();
    for (k, vk) in v[j.idx_v..j.idx_v + j.nv()].iter().enumerate() {
        t += col_motion(&data.j, j.idx_v + k) * *vk;
    }
    t
}

/// All joint Jacobians in the world frame (`data.j`), with the placements.
pub fn compute_joint_jacobians<'d>(
    model: &Model,
    data: &'d mut Data,
    q: &[f64],
) -> Result<&'d Matrix6xX<f64>> {
    model.check_configuration(q)?;
    joint_jacobians_pass(model, data, q, false);
    Ok(&data.j)
}

/// Placements and world Jacobian columns of every joint (q already checked); with `reuse`,
/// from the local placements a pass at the same q left (see `kinematics::local_placement`).
pub(crate) fn joint_jacobians_pass(model: &Model, data: &mut Data, q: &[f64], reuse: bool) {
    placements(model, data, q, reuse);
    for i in 0..model.njoints() {
        write_joint_columns(model, data, i);
    }
}

/// World twists `data.ov` and world accelerations `data.oa` of every joint (spatial, at the
/// world origin; the root's acceleration holds −g, as ABA leaves it), from the world Jacobian
/// columns already in `data.j` at the same configuration (after [`compute_joint_jacobians`]
/// or [`crate::crba`]): `ᵒv_i = ᵒv_λ + J_i q̇_i`, `ᵒa_i = ᵒa_λ + J_i q̈_i + ᵒv_i × J_i q̇_i`
/// (RBDA Eq. 5.7–5.8 in world coordinates). A simulator that integrates without ABA uses it
/// to leave the same kinematic state as an ABA step would.
pub fn world_motions_from_jacobians(
    model: &Model,
    data: &mut Data,
    v: &[f64],
    a: &[f64],
) -> Result<()> {
    crate::model::check_vector("velocity v", v, model.nv)?;
    crate::model::check_vector("acceleration a", a, model.nv)?;
    let a0 = Motion::new(-model.gravity, nalgebra::Vector3::zeros());
    for (i, j) in model.joints.iter().enumerate() {
        let vj = joint_world_twist(data, j, v);
        let aj = joint_world_twist(data, j, a);
        let (vp, ap) = j
            .parent
            .map_or((Motion::zero(), a0), |p| (data.ov[p], data.oa[p]));
        let ov = vp + vj;
        data.ov[i] = ov;
        data.oa[i] = ap + aj + ov.cross(&vj);
    }
    Ok(())
}

/// Placements of every frame in the world (`data.o_m_f`), from the current joint placements.
pub fn update_frame_placements(model: &Model, data: &mut Data) {
    for (f, frame) in model.frames.iter().enumerate() {
        data.o_m_f[f] = match frame.parent_joint {
            Some(i) => data.o_m_i[i] * frame.placement,
            None => frame.placement,
        };
    }
}

/// World placement of frame `frame_id` from the current joint placements.
pub fn frame_placement(model: &Model, data: &Data, frame_id: usize) -> Result<Se3> {
    let frame = model
        .frames
        .get(frame_id)
        .ok_or_else(|| ModelError::UnknownFrame(format!("#{frame_id}")))?;
    Ok(match frame.parent_joint {
        Some(i) => data.o_m_i[i] * frame.placement,
        None => frame.placement,
    })
}

/// Expresses a world twist `(v_O, ω)` at a frame with world placement `o_m_f`.
#[inline]
pub(crate) fn express_world_twist(m: &Motion, o_m_f: &Se3, rf: ReferenceFrame) -> Motion {
    match rf {
        ReferenceFrame::World => *m,
        ReferenceFrame::LocalWorldAligned => {
            Motion::new(m.linear + m.angular.cross(&o_m_f.translation), m.angular)
        }
        ReferenceFrame::Local => o_m_f.act_inv_motion(m),
    }
}

/// The Jacobian of frame `frame_id` in `rf`, written to `out` (6 × nv). Needs
/// [`compute_joint_jacobians`] (or any algorithm that fills `data.j`) at the same q.
pub fn frame_jacobian(
    model: &Model,
    data: &Data,
    frame_id: usize,
    rf: ReferenceFrame,
    out: &mut Matrix6xX<f64>,
) -> Result<()> {
    if out.ncols() != model.nv {
        return Err(ModelError::Dimension {
            what: "Jacobian output columns",
            got: out.ncols(),
            expected: model.nv,
        });
    }
    let o_m_f = frame_placement(model, data, frame_id)?;
    out.fill(0.0);
    let mut joint = model.frames[frame_id].parent_joint;
    while let Some(i) = joint {
        let j = &model.joints[i];
        for k in j.idx_v..j.idx_v + j.nv() {
            let c = express_world_twist(&col_motion(&data.j, k), &o_m_f, rf);
            set_col(out, k, &c.linear, &c.angular);
        }
        joint = j.parent;
    }
    Ok(())
}

/// Longest chain from the root that [`compute_frame_jacobian`] places alone (deeper chains
/// place every joint).
const MAX_CHAIN: usize = 64;

/// The Jacobian of frame `frame_id` at `q` in `rf`, written to `out` (6 × nv): Pinocchio's
/// `computeFrameJacobian`. Places the frame's supporting joints and writes their world
/// Jacobian columns only; the other placements and columns of `data` are left as they were.
pub fn compute_frame_jacobian(
    model: &Model,
    data: &mut Data,
    q: &[f64],
    frame_id: usize,
    rf: ReferenceFrame,
    out: &mut Matrix6xX<f64>,
) -> Result<()> {
    model.check_configuration(q)?;
    let frame = model
        .frames
        .get(frame_id)
        .ok_or_else(|| ModelError::UnknownFrame(format!("#{frame_id}")))?;
    let mut chain = [0usize; MAX_CHAIN];
    let mut depth = 0;
    let mut joint = frame.parent_joint;
    while let Some(i) = joint {
        if depth == MAX_CHAIN {
            placements(model, data, q, false);
            depth = 0;
            break;
        }
        chain[depth] = i;
        depth += 1;
        joint = model.joints[i].parent;
    }
    for &i in chain[..depth].iter().rev() {
        place_joint(&model.joints[i], i, data, q, false);
    }
    let mut joint = frame.parent_joint;
    while let Some(i) = joint {
        write_joint_columns(model, data, i);
        joint = model.joints[i].parent;
    }
    frame_jacobian(model, data, frame_id, rf, out)
}

/// Velocity of frame `frame_id` in `rf`, after [`crate::forward_kinematics`].
pub fn frame_velocity(
    model: &Model,
    data: &Data,
    frame_id: usize,
    rf: ReferenceFrame,
) -> Result<Motion> {
    let (local, o_m_f) = local_frame_quantity(model, data, frame_id, |d, i| d.v[i])?;
    Ok(express_local(&local, &o_m_f, rf))
}

/// Spatial acceleration of frame `frame_id` in `rf`, after [`crate::forward_kinematics`].
pub fn frame_acceleration(
    model: &Model,
    data: &Data,
    frame_id: usize,
    rf: ReferenceFrame,
) -> Result<Motion> {
    let (local, o_m_f) = local_frame_quantity(model, data, frame_id, |d, i| d.a[i])?;
    Ok(express_local(&local, &o_m_f, rf))
}

/// Classical acceleration of frame `frame_id` in `rf`: the spatial acceleration with
/// `ω × v` added to its linear part (both expressed in `rf`), as Pinocchio's
/// `getFrameClassicalAcceleration`. In LOCAL and LOCAL_WORLD_ALIGNED it is the acceleration
/// of the frame's origin point. With q̈ = 0 it is the Jacobian drift J̇ q̇.
/// Needs [`crate::forward_kinematics`].
pub fn frame_classical_acceleration(
    model: &Model,
    data: &Data,
    frame_id: usize,
    rf: ReferenceFrame,
) -> Result<Motion> {
    let v = frame_velocity(model, data, frame_id, rf)?;
    let mut a = frame_acceleration(model, data, frame_id, rf)?;
    a.linear += v.angular.cross(&v.linear);
    Ok(a)
}

fn local_frame_quantity(
    model: &Model,
    data: &Data,
    frame_id: usize,
    get: impl Fn(&Data, usize) -> Motion,
) -> Result<(Motion, Se3)> {
    let frame = model
        .frames
        .get(frame_id)
        .ok_or_else(|| ModelError::UnknownFrame(format!("#{frame_id}")))?;
    let o_m_f = frame_placement(model, data, frame_id)?;
    Ok(match frame.parent_joint {
        Some(i) => (frame.placement.act_inv_motion(&get(data, i)), o_m_f),
        None => (Motion::zero(), o_m_f),
    })
}

fn express_local(local: &Motion, o_m_f: &Se3, rf: ReferenceFrame) -> Motion {
    match rf {
        ReferenceFrame::Local => *local,
        ReferenceFrame::LocalWorldAligned => Motion::new(
            o_m_f.rotation * local.linear,
            o_m_f.rotation * local.angular,
        ),
        ReferenceFrame::World => o_m_f.act_motion(local),
    }
}
