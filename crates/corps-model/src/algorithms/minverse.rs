//! M(q)⁻¹ in O(n²) by the articulated-body recursion applied to every unit torque at once
//! (Carpentier, "Analytical inverse of the joint space inertia matrix", 2018; the recursion
//! behind Pinocchio's `computeMinverse`), in the world frame so that the forces and
//! accelerations of all columns move between joints without transforms.
//!
//! Column c of M⁻¹ is ABA(q, 0, e_c) without gravity. Backward (leaves first), with
//! F[:, c] the bias force that the unit torque at dof c ≥ k of joint i's subtree leaves on i:
//! U = I^A S, D = Sᵀ U, M⁻¹[k, c] = D⁻¹ (δ_kc − Sᵀ F[:, c]), then F[:, c] += U M⁻¹[k, c] and
//! I^A_λ += I^A − U D⁻¹ Uᵀ. Forward (root first), for every column c ≥ k:
//! M⁻¹[k, c] −= D⁻¹ Uᵀ A_λ[:, c] and A_i[:, c] = A_λ[:, c] + S M⁻¹[k, c]. The upper
//! triangle is computed; the lower one is its mirror.

use super::jacobians::write_joint_columns;
use super::kinematics::place_joint;
use crate::data::{col_force, col_motion, set_col, Data};
use crate::error::Result;
use crate::joint::JointKind;
use crate::model::Model;
use crate::spatial::kernels::{m6_add_assign, m6_rank1_sub, m6v};
use nalgebra::{DMatrix, Matrix6, Vector6};

/// M(q)⁻¹, full and symmetric, written to and returned from `data.minv`.
pub fn compute_minverse<'d>(
    model: &Model,
    data: &'d mut Data,
    q: &[f64],
) -> Result<&'d DMatrix<f64>> {
    model.check_configuration(q)?;
    let n = model.nv;
    for (i, j) in model.joints.iter().enumerate() {
        place_joint(j, i, data, q, false);
        write_joint_columns(model, data, i);
        model.inertias[i]
            .transformed(&data.o_m_i[i])
            .write_matrix(&mut data.bcrb[i]);
    }
    data.minv.fill(0.0);
    data.tmp_6xnv.fill(0.0);
    // Backward: articulated inertias, D⁻¹ and U per dof, the rows' subtree part.
    for (i, j) in model.joints.iter().enumerate().rev() {
        let (k, sub) = (j.idx_v, model.subtree_nv[i]);
        if j.kind == JointKind::FreeFlyer {
            // Always a root (as in ABA): its block is the whole tree's.
            root_rows(data, i, k, sub);
            continue;
        }
        let s = col_motion(&data.j, k).to_vector();
        let u_vec = m6v(&data.bcrb[i], &s);
        let d_inv = 1.0 / s.dot(&u_vec);
        data.d_inv[k] = d_inv;
        set_col(
            &mut data.f_cols,
            k,
            &u_vec.fixed_rows::<3>(0).into(),
            &u_vec.fixed_rows::<3>(3).into(),
        );
        data.minv[(k, k)] = d_inv;
        let f = data.tmp_6xnv.as_mut_slice();
        for c in k + 1..k + sub {
            let fc = Vector6::from_column_slice(&f[6 * c..6 * c + 6]);
            data.minv[(k, c)] = -d_inv * s.dot(&fc);
        }
        if let Some(parent) = j.parent {
            for c in k..k + sub {
                let x = data.minv[(k, c)];
                for (fr, ur) in f[6 * c..6 * c + 6].iter_mut().zip(u_vec.iter()) {
                    *fr += ur * x;
                }
            }
            m6_rank1_sub(&mut data.bcrb[i], &u_vec, d_inv);
            let (above, from_i) = data.bcrb.split_at_mut(i);
            m6_add_assign(&mut above[parent], &from_i[0]);
        }
    }
    // Forward: the ancestors' part of each row, and each joint's accelerations A_i.
    for (i, j) in model.joints.iter().enumerate() {
        let k = j.idx_v;
        let has_children = model.subtree_nv[i] > j.nv();
        match (j.kind, j.parent) {
            (JointKind::FreeFlyer, _) | (_, None) => {
                // No parent: nothing above the rows; A_i = S M⁻¹[K, ·].
                if has_children {
                    for c in k..n {
                        let mut a = Vector6::zeros();
                        for d in 0..j.nv() {
                            a += col_motion(&data.j, k + d).to_vector() * data.minv[(k + d, c)];
                        }
                        data.minv_acc[i].set_column(c, &a);
                    }
                }
            }
            (_, Some(parent)) => {
                let u_vec = col_force(&data.f_cols, k).to_vector() * data.d_inv[k];
                let s = col_motion(&data.j, k).to_vector();
                let (before, after) = data.minv_acc.split_at_mut(i);
                let (ap, ai) = (&before[parent], &mut after[0]);
                for c in k..n {
                    let a_parent = ap.fixed_view::<6, 1>(0, c);
                    let x = data.minv[(k, c)] - u_vec.dot(&a_parent);
                    data.minv[(k, c)] = x;
                    if has_children {
                        ai.set_column(c, &(a_parent + s * x));
                    }
                }
            }
        }
    }
    for c in 0..n {
        for r in c + 1..n {
            data.minv[(r, c)] = data.minv[(c, r)];
        }
    }
    Ok(&data.minv)
}

/// Rows of a free-flyer root `i` (dofs k..k+6, subtree k..k+sub): D = Sᵀ I^A S (6 × 6),
/// M⁻¹[K, K] = D⁻¹, M⁻¹[K, c] = −D⁻¹ Sᵀ F[:, c] beyond.
fn root_rows(data: &mut Data, i: usize, k: usize, sub: usize) {
    let s = data.j.fixed_view::<6, 6>(0, k).into_owned();
    let d: Matrix6<f64> = s.transpose() * data.bcrb[i] * s;
    // D is positive definite for a body with mass; a massless tree gets NaN, as in ABA.
    let d_inv = d
        .cholesky()
        .map(|ch| ch.inverse())
        .unwrap_or_else(|| Matrix6::repeat(f64::NAN));
    data.minv.fixed_view_mut::<6, 6>(k, k).copy_from(&d_inv);
    let f = &data.tmp_6xnv;
    for c in k + 6..k + sub {
        let x = -(d_inv * (s.transpose() * f.fixed_view::<6, 1>(0, c)));
        data.minv.fixed_view_mut::<6, 1>(k, c).copy_from(&x);
    }
}
