//! Composite rigid-body algorithm: the joint-space inertia matrix M(q) (RBDA Table 6.2), in
//! the world frame as Pinocchio 3 does, so composite inertias add without transforms:
//! `M[i, subtree(i)] = J_iᵀ (Yc_j J_j)` for every j in the subtree of i.

use super::jacobians::write_joint_columns;
use super::kinematics::placements;
use crate::data::{col_motion, set_col, Data};
use crate::error::Result;
use crate::model::Model;
use nalgebra::{DMatrix, Vector6};

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
            let f = y * s.to_vector();
            set_col(&mut data.f_cols, k, &f.fixed_rows::<3>(0).into(), &f.fixed_rows::<3>(3).into());
        }
        if with_m {
            let (start, len) = (j.idx_v, model.subtree_nv[i]);
            let jc = data.j.as_slice();
            let fc = data.f_cols.as_slice();
            for r in start..start + j.nv() {
                let jr = Vector6::from_column_slice(&jc[6 * r..6 * r + 6]);
                for c in r..start + len {
                    let fcol = Vector6::from_column_slice(&fc[6 * c..6 * c + 6]);
                    let val = jr.dot(&fcol);
                    data.m[(r, c)] = val;
                    data.m[(c, r)] = val;
                }
            }
        }
        if let Some(p) = j.parent {
            data.ycrb[p] += y;
        }
    }
}
