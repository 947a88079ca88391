//! Composite rigid-body algorithm: the joint-space inertia matrix M(q) (RBDA Table 6.2), in
//! the world frame as Pinocchio 3 does, so composite inertias add without transforms:
//! `M[i, subtree(i)] = J_iᵀ (Yc_j J_j)` for every j in the subtree of i.

use super::jacobians::write_joint_columns;
use super::kinematics::placements;
use crate::spatial::kernels::{m6_add_assign, m6v};
use crate::data::{col_motion, set_col, Data};
use crate::error::Result;
use crate::model::Model;
use nalgebra::DMatrix;

/// M(q), full and symmetric, written to and returned from `data.m`. Also leaves the world
/// Jacobians in `data.j` and the composite inertias in `data.ycrb`.
pub fn crba<'d>(model: &Model, data: &'d mut Data, q: &[f64]) -> Result<&'d DMatrix<f64>> {
    model.check_configuration(q)?;
    composite_pass(model, data, q, true);
    Ok(&data.m)
}

/// Forward: placements, world Jacobians, world body inertias; backward: composite inertias
/// and, when `with_m`, the upper triangle of M mirrored to the lower.
pub(crate) fn composite_pass(model: &Model, data: &mut Data, q: &[f64], with_m: bool) {
    placements(model, data, q);
    for i in 0..model.njoints() {
        write_joint_columns(model, data, i);
        let oi = model.inertias[i].transformed(&data.o_m_i[i]);
        oi.write_matrix(&mut data.ycrb[i]);
    }
    for (i, j) in model.joints.iter().enumerate().rev() {
        let y = data.ycrb[i];
        for k in j.idx_v..j.idx_v + j.nv() {
            let s = col_motion(&data.j, k);
            let f = m6v(&y, &s.to_vector());
            set_col(&mut data.f_cols, k, &f.fixed_rows::<3>(0).into(), &f.fixed_rows::<3>(3).into());
        }
        if with_m {
            // Lower triangle, column by column (contiguous): M[c, r] = F_cᵀ J_r.
            let (start, len, nv) = (j.idx_v, model.subtree_nv[i], model.nv);
            let jc = data.j.as_slice();
            let fc = &data.f_cols.as_slice()[..6 * (start + len)];
            let m = data.m.as_mut_slice();
            for r in start..start + j.nv() {
                let jr = &jc[6 * r..6 * r + 6];
                let column = &mut m[r * nv + r..r * nv + start + len];
                for (out, f) in column.iter_mut().zip(fc[6 * r..].chunks_exact(6)) {
                    *out = jr[0] * f[0] + jr[1] * f[1] + jr[2] * f[2] + jr[3] * f[3] + jr[4] * f[4] + jr[5] * f[5];
                }
            }
        }
        if let Some(p) = j.parent {
            m6_add_assign(&mut data.ycrb[p], &y);
        }
    }
    if with_m {
        mirror_lower_to_upper(data.m.as_mut_slice(), model.nv);
    }
}

/// Copies the lower triangle of a column-major n × n matrix onto its upper triangle.
fn mirror_lower_to_upper(m: &mut [f64], n: usize) {
    for c in 1..n {
        for r in 0..c {
            m[c * n + r] = m[r * n + c];
        }
    }
}
