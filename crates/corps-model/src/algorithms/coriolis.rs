//! The Coriolis matrix C(q, v) with C v = h(q, v) − g(q) and Ṁ − 2C skew-symmetric
//! (Echeandía & Wensing 2021, as Pinocchio's `computeCoriolisMatrix`):
//! C = Σ_bodies J_bᵀ (I_b J̇_b + B_b J_b), B = ½ (v×* I − I v× + (I v)×̄*), all in the world
//! frame, accumulated over subtrees like CRBA.

use super::jacobians::{joint_world_twist, write_joint_columns};
use super::kinematics::placements;
use crate::data::{col_force, col_motion, set_col, Data};
use crate::error::Result;
use crate::model::{check_vector, Model};
use crate::spatial::kernels::{m6_add_assign, m6v};
use crate::spatial::{skew, Motion};
use nalgebra::{DMatrix, Matrix6};

/// `v×` for a spatial motion `[v; ω]`: `[[ω×, v×], [0, ω×]]`.
fn motion_cross_matrix(m: &Motion) -> Matrix6<f64> {
    let mut x = Matrix6::zeros();
    let w = skew(&m.angular);
    x.fixed_view_mut::<3, 3>(0, 0).copy_from(&w);
    x.fixed_view_mut::<3, 3>(3, 3).copy_from(&w);
    x.fixed_view_mut::<3, 3>(0, 3).copy_from(&skew(&m.linear));
    x
}

/// `B = ½ (v×* Y − Y v× + (Y v)×̄*)` with `(h×̄*) v = v ×* h`, i.e. `[[0, −f×], [−f×, −n×]]`.
fn coriolis_block(y: &Matrix6<f64>, v: &Motion) -> Matrix6<f64> {
    let vx = motion_cross_matrix(v);
    let h = y * v.to_vector();
    let fx = -skew(&h.fixed_rows::<3>(0).into());
    let nx = -skew(&h.fixed_rows::<3>(3).into());
    let mut hbar = Matrix6::zeros();
    hbar.fixed_view_mut::<3, 3>(0, 3).copy_from(&fx);
    hbar.fixed_view_mut::<3, 3>(3, 0).copy_from(&fx);
    hbar.fixed_view_mut::<3, 3>(3, 3).copy_from(&nx);
    (-vx.transpose() * y - y * vx + hbar) * 0.5
}

/// C(q, v), written to and returned from `data.c`. Also fills `data.j`, `data.dj`, `data.ov`.
pub fn coriolis_matrix<'d>(
    model: &Model,
    data: &'d mut Data,
    q: &[f64],
    v: &[f64],
) -> Result<&'d DMatrix<f64>> {
    model.check_configuration(q)?;
    check_vector("velocity v", v, model.nv)?;
    placements(model, data, q, false);
    for (i, j) in model.joints.iter().enumerate() {
        write_joint_columns(model, data, i);
        let vj = joint_world_twist(data, j, v);
        let ov = j.parent.map_or(vj, |p| data.ov[p] + vj);
        data.ov[i] = ov;
        for k in j.idx_v..j.idx_v + j.nv() {
            let d = ov.cross(&col_motion(&data.j, k));
            set_col(&mut data.dj, k, &d.linear, &d.angular);
        }
        let y = model.inertias[i].transformed(&data.o_m_i[i]).to_matrix();
        data.bcrb[i] = coriolis_block(&y, &ov);
        data.ycrb[i] = y;
    }
    for (i, j) in model.joints.iter().enumerate().rev() {
        let (y, b) = (data.ycrb[i], data.bcrb[i]);
        let (start, nvi) = (j.idx_v, j.nv());
        for k in start..start + nvi {
            let f = m6v(&y, &col_motion(&data.dj, k).to_vector())
                + m6v(&b, &col_motion(&data.j, k).to_vector());
            set_col(
                &mut data.f_cols,
                k,
                &f.fixed_rows::<3>(0).into(),
                &f.fixed_rows::<3>(3).into(),
            );
        }
        for r in start..start + nvi {
            let jr = col_motion(&data.j, r);
            // Row r, columns of the subtree (descendants and the joint itself).
            for c in start..start + model.subtree_nv[i] {
                data.c[(r, c)] = jr.dot(&col_force(&data.f_cols, c));
            }
            // Row r, columns of the strict ancestors.
            let g1 = m6v(&y, &jr.to_vector());
            let g2 = b.transpose() * jr.to_vector();
            for &c in model.dof_ancestors(start) {
                let dj = col_motion(&data.dj, c).to_vector();
                let jc = col_motion(&data.j, c).to_vector();
                data.c[(r, c)] = g1.dot(&dj) + g2.dot(&jc);
            }
        }
        if let Some(p) = j.parent {
            m6_add_assign(&mut data.ycrb[p], &y);
            m6_add_assign(&mut data.bcrb[p], &b);
        }
    }
    Ok(&data.c)
}
