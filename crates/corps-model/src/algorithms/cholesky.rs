//! Branch-induced sparse factorization M = Lᵀ D L (Featherstone, RBDA §6.5, "LTDL"): L is
//! unit lower-triangular with non-zeros only where column i is an ancestor dof of row k, so
//! factorization and solves cost O(n·depth) instead of O(n³). Used for M⁻¹, forward dynamics
//! by CRBA and operational-space inertias.

use super::crba::crba;
use crate::data::Data;
use crate::error::Result;
use crate::model::Model;
use nalgebra::{DMatrix, DVector};

/// Factorizes `data.m` (from [`crba`]) into `data.ltdl`.
pub fn factorize_mass_matrix(model: &Model, data: &mut Data) {
    data.ltdl.copy_from(&data.m);
    // `data` was sized for this model: nv × nv.
    let _ = factorize_branch_sparse(model, &mut data.ltdl);
}

/// Factorizes in place a symmetric positive-definite matrix whose non-zeros lie within M's
/// branch pattern (entry (i, j) only where one dof is an ancestor of the other): M itself, or
/// M plus terms `Jᵀ K J` of bodies' Jacobians and a diagonal, as an implicit integrator
/// forms. Both triangles must hold the matrix. On return the lower triangle holds L (unit
/// diagonal implied), the strict upper triangle Lᵀ, and the diagonal D, for
/// [`solve_mass_matrix`]. A matrix that is not `nv × nv` is an error.
pub fn factorize_branch_sparse(model: &Model, h: &mut DMatrix<f64>) -> Result<()> {
    let n = model.nv;
    if h.nrows() != n || h.ncols() != n {
        return Err(crate::error::ModelError::Dimension {
            what: "matrix to factorize",
            got: h.len(),
            expected: n * n,
        });
    }
    // Works in the upper triangle, column-major: entry (r, c), r ≤ c, at c n + r. The
    // ancestors of an ancestor ii of k (ii included) are the rest of k's chain from ii on; the
    // chain is a few runs of consecutive dofs (a limb, the torso, the base), so column ii is
    // updated from column k over contiguous slices.
    let h = h.as_mut_slice();
    let sub = |x: &mut [f64], a: f64, y: &[f64]| {
        for (xi, yi) in x.iter_mut().zip(y) {
            *xi -= a * yi;
        }
    };
    for k in (0..n).rev() {
        let runs = model.dof_ancestor_runs(k);
        let dk = h[k * n + k];
        // Ancestors have smaller indices: columns ii < k lie before column k.
        let (before, from_k) = h.split_at_mut(k * n);
        let col_k = &mut from_k[..n];
        for (r, &(lo, hi)) in runs.iter().enumerate() {
            for ii in (lo..=hi).rev() {
                let a = col_k[ii] / dk;
                let col_ii = &mut before[ii * n..ii * n + n];
                sub(&mut col_ii[lo..=ii], a, &col_k[lo..=ii]);
                for &(lo2, hi2) in &runs[r + 1..] {
                    sub(&mut col_ii[lo2..=hi2], a, &col_k[lo2..=hi2]);
                }
                col_k[ii] = a;
            }
        }
    }
    // L into the lower triangle: L[k, ii] = U[ii, k].
    for k in 0..n {
        for &ii in model.dof_ancestors(k) {
            h[ii * n + k] = h[k * n + ii];
        }
    }
    Ok(())
}

/// Solves M x = b in place with the factorization in `ltdl` (from [`factorize_mass_matrix`],
/// or of any matrix [`factorize_branch_sparse`] takes).
pub fn solve_mass_matrix(model: &Model, ltdl: &DMatrix<f64>, b: &mut [f64]) {
    let n = model.nv;
    let h = ltdl.as_slice(); // column-major: L[k, i] = h[i * n + k] = h[k * n + i]
    for k in (0..n).rev() {
        let bk = b[k];
        let col_k = &h[k * n..k * n + n];
        for &ii in model.dof_ancestors(k) {
            b[ii] -= col_k[ii] * bk;
        }
    }
    for (k, bk) in b.iter_mut().enumerate() {
        *bk /= h[k * n + k];
    }
    solve_unit_lower(model, h, b);
}

/// `b ← L⁻¹ b` for the unit lower-triangular `L` of a column-major LᵀDL factor `h`.
fn solve_unit_lower(model: &Model, h: &[f64], b: &mut [f64]) {
    let n = model.nv;
    for k in 0..n {
        let mut acc = b[k];
        let col_k = &h[k * n..k * n + n]; // Lᵀ: col_k[ii] = L[k, ii]
        for &ii in model.dof_ancestors(k) {
            acc -= col_k[ii] * b[ii];
        }
        b[k] = acc;
    }
}

/// M(q)⁻¹ through CRBA and the branch-sparse factorization, full and symmetric, written to and
/// returned from `data.minv`: column c solves M x = e_c; the first sweep (L⁻ᵀ) only touches c
/// and its ancestors, where e_c's image is non-zero. Slower than the O(n²) recursion
/// [`crate::compute_minverse`]; an independent route to the same matrix.
pub fn compute_minverse_factorized<'d>(
    model: &Model,
    data: &'d mut Data,
    q: &[f64],
) -> Result<&'d DMatrix<f64>> {
    crba(model, data, q)?;
    factorize_mass_matrix(model, data);
    let n = model.nv;
    let h = data.ltdl.as_slice(); // column-major: L[k, i] = h[i * n + k] = h[k * n + i]
    for (k, d) in data.tmp_nv.iter_mut().enumerate() {
        *d = 1.0 / h[k * n + k];
    }
    let dinv = data.tmp_nv.as_slice();
    for (c, col) in data.minv.as_mut_slice().chunks_exact_mut(n).enumerate() {
        col.fill(0.0);
        col[c] = 1.0;
        for kk in std::iter::once(c).chain(model.dof_ancestors(c).iter().copied()) {
            let bk = col[kk];
            let col_kk = &h[kk * n..kk * n + n]; // Lᵀ: col_kk[ii] = L[kk, ii]
            for &ii in model.dof_ancestors(kk) {
                col[ii] -= col_kk[ii] * bk;
            }
        }
        for (x, d) in col.iter_mut().zip(dinv) {
            *x *= d;
        }
        solve_unit_lower(model, h, col);
    }
    Ok(&data.minv)
}

/// Forward dynamics by CRBA and the sparse factorization: q̈ = M⁻¹ (τ − h), into `data.ddq`.
/// An alternative to ABA (faster when M is needed anyway).
pub fn forward_dynamics_crba<'d>(
    model: &Model,
    data: &'d mut Data,
    q: &[f64],
    v: &[f64],
    tau: &[f64],
) -> Result<&'d DVector<f64>> {
    crate::model::check_vector("torque tau", tau, model.nv)?;
    super::rnea::nonlinear_effects(model, data, q, v)?;
    crba(model, data, q)?;
    factorize_mass_matrix(model, data);
    for ((d, t), h) in data.ddq.iter_mut().zip(tau).zip(data.nle.iter()) {
        *d = t - h;
    }
    solve_mass_matrix(model, &data.ltdl, data.ddq.as_mut_slice());
    Ok(&data.ddq)
}
