//! Dense Cholesky factorization `H = L Lᵀ` and the inverse transpose `J₀ = L⁻ᵀ`, in place on
//! column-major buffers, without allocation.

use crate::linalg::{gemv, gemv_upper};

/// Factor the lower triangle of the column-major `n × n` matrix `a` in place into `L`
/// (left-looking, column by column: each column is one register-blocked matrix–vector
/// product with the columns to its left). The strict upper triangle is not read and is left
/// as is. Also writes `L` row-major into `lt` (`n × n`; row `j` of `L` is `lt[j n..j n + j]`
/// plus the diagonal), which the triangular solves with many right-hand sides need.
///
/// Returns `Err(j)` with the first column whose pivot is not larger than
/// `n · ε · max(1, maxᵢ |Hᵢᵢ|)` (H not numerically positive definite).
#[inline(always)]
pub(crate) fn factor_in_place<const F: bool>(
    a: &mut [f64],
    n: usize,
    lt: &mut [f64],
) -> Result<(), usize> {
    let mut max_diag: f64 = 1.0;
    for j in 0..n {
        max_diag = max_diag.max(a[j + j * n].abs());
    }
    let threshold = n as f64 * f64::EPSILON * max_diag;
    for j in 0..n {
        let row = &mut lt[j * n..(j + 1) * n];
        for (k, v) in row[..j].iter_mut().enumerate() {
            *v = a[j + k * n];
        }
        let (left, right) = a.split_at_mut(j * n);
        let col = &mut right[j..n];
        if j > 0 {
            gemv::<F>(-1.0, &left[j..], n, &row[..j], col);
        }
        let d = col[0];
        // Also catches NaN.
        if d.is_nan() || d <= threshold {
            return Err(j);
        }
        let s = d.sqrt();
        col[0] = s;
        row[j] = s;
        let inv = 1.0 / s;
        for v in &mut col[1..] {
            *v *= inv;
        }
    }
    Ok(())
}

/// Write `J₀ = L⁻ᵀ` (upper triangular, column-major with leading dimension `ld ≥ n`) into
/// `j0`, from the row-major factor `lt` written by [`factor_in_place`]. Entries below the
/// diagonal and rows `n..ld` are not written (they must hold zeros).
///
/// Column `i` of `J₀` is row `i` of `L⁻¹`: `(eᵢ − Σ_{j<i} L_ij J₀[.., j]) / L_ii`, one
/// register-blocked triangular matrix–vector product per column.
#[inline(always)]
pub(crate) fn inverse_transpose<const F: bool>(lt: &[f64], n: usize, j0: &mut [f64], ld: usize) {
    for i in 0..n {
        let dinv = 1.0 / lt[i * n + i];
        let (left, right) = j0.split_at_mut(i * ld);
        let col = &mut right[..i + 1];
        col[..i].fill(0.0);
        gemv_upper::<F>(-dinv, left, ld, &lt[i * n..i * n + i], &mut col[..i]);
        col[i] = dinv;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn factor_and_inverse_of_a_small_spd_matrix() {
        let n = 3;
        // H = [4 2 0; 2 5 1; 0 1 3], column-major.
        let h = [4.0, 2.0, 0.0, 2.0, 5.0, 1.0, 0.0, 1.0, 3.0];
        let mut l = h;
        let mut lt = [0.0; 9];
        factor_in_place::<false>(&mut l, n, &mut lt).unwrap();
        // Check L Lᵀ = H on the lower triangle.
        for i in 0..n {
            for j in 0..=i {
                let s: f64 = (0..=j).map(|k| l[i + k * n] * l[j + k * n]).sum();
                assert!((s - h[i + j * n]).abs() < 1e-14, "({i},{j})");
            }
        }
        let mut j0 = [0.0; 9];
        inverse_transpose::<false>(&lt, n, &mut j0, n);
        // J₀ᵀ H J₀ = I.
        for a in 0..n {
            for b in 0..n {
                let mut s = 0.0;
                for i in 0..n {
                    for k in 0..n {
                        s += j0[i + a * n] * h[i + k * n] * j0[k + b * n];
                    }
                }
                let e = if a == b { 1.0 } else { 0.0 };
                assert!((s - e).abs() < 1e-14);
            }
        }
    }

    #[test]
    fn indefinite_matrix_is_rejected() {
        let mut a = [1.0, 2.0, 2.0, 1.0];
        let mut lt = [0.0; 4];
        assert_eq!(factor_in_place::<false>(&mut a, 2, &mut lt), Err(1));
        let mut z = [0.0; 4];
        assert_eq!(factor_in_place::<false>(&mut z, 2, &mut lt), Err(0));
    }
}
