//! Composite rigid-body algorithm: the joint-space inertia matrix M(q) (RBDA Table 6.2), in
//! the world frame as Pinocchio 3 does, so composite inertias add without transforms
//! (kept in origin form, [`crate::spatial::OriginInertia`]):
//! `M[i, subtree(i)] = J_iᵀ (Yc_j J_j)` for every j in the subtree of i.

use super::jacobians::write_joint_columns;
use super::kinematics::placements;
use crate::data::{col_motion, set_col, Data};
use crate::error::Result;
use crate::model::Model;
use nalgebra::DMatrix;

/// M(q), full and symmetric, written to and returned from `data.m`. Also leaves the world
/// Jacobians in `data.j` and the composite inertias in `data.composite`.
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
        data.composite[i] = model.inertias[i]
            .transformed(&data.o_m_i[i])
            .to_origin_form();
    }
    let nv = model.nv;
    for (i, j) in model.joints.iter().enumerate().rev() {
        let y = data.composite[i];
        for k in j.idx_v..j.idx_v + j.nv() {
            let f = y.mul_motion(&col_motion(&data.j, k));
            set_col(&mut data.f_cols, k, &f.linear, &f.angular);
            if with_m {
                let ft = &mut data.f_t.as_mut_slice()[k..];
                let (l, a) = (&f.linear, &f.angular);
                (ft[0], ft[nv], ft[2 * nv]) = (l.x, l.y, l.z);
                (ft[3 * nv], ft[4 * nv], ft[5 * nv]) = (a.x, a.y, a.z);
            }
        }
        if with_m {
            // Lower triangle, column by column: M[c, r] = Σ_k J_r[k] F_c[k] for c in the
            // subtree, over the transposed forces (contiguous in c).
            let (start, end) = (j.idx_v, j.idx_v + model.subtree_nv[i]);
            let jc = data.j.as_slice();
            let ft = data.f_t.as_slice();
            let m = data.m.as_mut_slice();
            for r in start..start + j.nv() {
                let a = &jc[6 * r..6 * r + 6];
                let len = end - r;
                let column = &mut m[r * nv + r..r * nv + end];
                let f: [&[f64]; 6] = std::array::from_fn(|k| &ft[k * nv + r..k * nv + end]);
                let (f0, f1, f2, f3, f4, f5) = (
                    &f[0][..len],
                    &f[1][..len],
                    &f[2][..len],
                    &f[3][..len],
                    &f[4][..len],
                    &f[5][..len],
                );
                for (c, o) in column[..len].iter_mut().enumerate() {
                    *o = a[0] * f0[c]
                        + a[1] * f1[c]
                        + a[2] * f2[c]
                        + a[3] * f3[c]
                        + a[4] * f4[c]
                        + a[5] * f5[c];
                }
                // Mirror onto row r. Entries outside the branch-induced pattern are never
                // written and stay zero from `Data::new`.
                for c in r + 1..end {
                    m[c * nv + r] = m[r * nv + c];
                }
            }
        }
        if let Some(p) = j.parent {
            data.composite[p] += y;
        }
    }
}
