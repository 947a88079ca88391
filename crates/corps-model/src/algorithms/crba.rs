//! Composite rigid-body algorithm: the joint-space inertia matrix M(q) (RBDA Table 6.2), in
//! the world frame as Pinocchio 3 does, so composite inertias add without transforms
//! (kept in origin form, [`crate::spatial::OriginInertia`]):
//! `M[i, subtree(i)] = J_iᵀ (Yc_j J_j)` for every j in the subtree of i.

use super::jacobians::joint_jacobians_pass;
use crate::data::{col_motion, set_col, Data};
use crate::error::Result;
use crate::model::Model;
use nalgebra::DMatrix;

/// M(q), full and symmetric, written to and returned from `data.m`. Also leaves the world
/// Jacobians in `data.j` and the composite inertias in `data.composite`.
pub fn crba<'d>(model: &Model, data: &'d mut Data, q: &[f64]) -> Result<&'d DMatrix<f64>> {
    model.check_configuration(q)?;
    composite_pass(model, data, q, true, false);
    Ok(&data.m)
}

/// M(q) from the placements and world Jacobians a pass at q left in `data` (e.g.
/// [`crate::compute_joint_jacobians`]): the composite half of [`crba`], for callers that need
/// the kinematics first and M later. Also leaves the composite inertias.
pub fn crba_at_jacobians<'d>(model: &Model, data: &'d mut Data) -> &'d DMatrix<f64> {
    composite_inertias(model, data, true);
    &data.m
}

/// Forward: placements, world Jacobians; then [`composite_inertias`]. With
/// `reuse_placements`, the joint placements are those a pass at the same q left in `data`.
pub(crate) fn composite_pass(
    model: &Model,
    data: &mut Data,
    q: &[f64],
    with_m: bool,
    reuse_placements: bool,
) {
    joint_jacobians_pass(model, data, q, reuse_placements);
    composite_inertias(model, data, with_m);
}

/// World body inertias, then backward: composite inertias and, when `with_m`, the upper
/// triangle of M mirrored to the lower (placements and Jacobian columns already in `data`).
fn composite_inertias(model: &Model, data: &mut Data, with_m: bool) {
    for i in 0..model.njoints() {
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
        }
        if with_m {
            // Row r over the subtree: M[r, c] = J_rᵀ F_c, written to both triangles.
            let (start, end) = (j.idx_v, j.idx_v + model.subtree_nv[i]);
            let jc = data.j.as_slice();
            let m = data.m.as_mut_slice();
            let fc = data.f_cols.as_slice();
            for r in start..start + j.nv() {
                let a: &[f64; 6] = jc[6 * r..6 * r + 6].try_into().expect("6 entries");
                for c in r..end {
                    let f: &[f64; 6] = fc[6 * c..6 * c + 6].try_into().expect("6 entries");
                    let x = (a[0] * f[0] + a[1] * f[1])
                        + (a[2] * f[2] + a[3] * f[3])
                        + (a[4] * f[4] + a[5] * f[5]);
                    m[r * nv + c] = x;
                    m[c * nv + r] = x;
                }
            }
        }
        if let Some(p) = j.parent {
            data.composite[p] += y;
        }
    }
}
