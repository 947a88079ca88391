//! Dense Cholesky factorization `H = L Lᵀ` and the inverse transpose `J₀ = L⁻ᵀ`, in place on
//! column-major buffers, without allocation. Both work block by block when `H` is block
//! diagonal (a whole-body QP's Hessian is: the accelerations' block and one block per
//! contact's forces), since `L` and `L⁻ᵀ` are then block diagonal with the same blocks.

use crate::linalg::{gemv, gemv_upper};

/// The diagonal blocks of the symmetric `n × n` column-major `a` (lower triangle read):
/// `start[j]..end[j]` is the block holding index `j`, the finest partition such that every
/// entry `a[i, k]` with `i` and `k` in different blocks is exactly zero. Reads each column
/// from the bottom up to its last non-zero only.
pub(crate) fn diagonal_blocks(a: &[f64], n: usize, start: &mut [usize], end: &mut [usize]) {
    // A block ends before b when no column k < b has a non-zero in a row i ≥ b.
    let mut reach = 0;
    let mut block_start = 0;
    for k in 0..n {
        if k > reach {
            end[block_start..k].fill(k);
            block_start = k;
        }
        start[k] = block_start;
        let column = &a[k * n + k..(k + 1) * n];
        // Trailing zeros eight at a time (a vectorized test), then the last non-zero.
        let mut len = column.len();
        while len >= 8 && column[len - 8..len].iter().all(|x| *x == 0.0) {
            len -= 8;
        }
        let last = k + column[..len].iter().rposition(|x| *x != 0.0).unwrap_or(0);
        reach = reach.max(last);
    }
    end[block_start..n].fill(n);
}

/// Factor the lower triangle of the column-major `n × n` matrix `a` in place into `L`
/// (left-looking, column by column: each column is one register-blocked matrix–vector
/// product with the columns to its left in its block). `start`/`end` are the diagonal blocks
/// of [`diagonal_blocks`]; entries of `a` outside them must be zero and stay so. The strict
/// upper triangle is not read and is left as is. Also writes `L` row-major into `lt`
/// (`n × n`; row `j` of `L` is `lt[j n..j n + j]` plus the diagonal), which the triangular
/// solves with many right-hand sides need.
///
/// Returns `Err(j)` with the first column whose pivot is not larger than
/// `n · ε · max(1, maxᵢ |Hᵢᵢ|)` (H not numerically positive definite).
#[inline(always)]
pub(crate) fn factor_in_place<const F: bool>(
    a: &mut [f64],
    n: usize,
    lt: &mut [f64],
    start: &[usize],
    end: &[usize],
) -> Result<(), usize> {
    let mut max_diag: f64 = 1.0;
    for j in 0..n {
        max_diag = max_diag.max(a[j + j * n].abs());
    }
    let threshold = n as f64 * f64::EPSILON * max_diag;
    for j in 0..n {
        let (b0, b1) = (start[j], end[j]);
        let row = &mut lt[j * n..(j + 1) * n];
        row[..b0].fill(0.0);
        for (k, v) in row[..j].iter_mut().enumerate().skip(b0) {
            *v = a[j + k * n];
        }
        let (left, right) = a.split_at_mut(j * n);
        let col = &mut right[j..b1];
        if j > b0 {
            gemv::<F>(-1.0, &left[b0 * n + j..], n, &row[b0..j], col);
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
/// `j0`, from the row-major factor `lt` written by [`factor_in_place`] with the same blocks
/// `start`. Entries below the diagonal and rows `n..ld` are not written (they must hold
/// zeros).
///
/// Column `i` of `J₀` is row `i` of `L⁻¹`: `(eᵢ − Σ_{j<i} L_ij J₀[.., j]) / L_ii`, one
/// register-blocked triangular matrix–vector product per column over `i`'s block (`L_ij`
/// and the columns' rows outside it are zero).
#[inline(always)]
pub(crate) fn inverse_transpose<const F: bool>(
    lt: &[f64],
    n: usize,
    j0: &mut [f64],
    ld: usize,
    start: &[usize],
) {
    for i in 0..n {
        let b0 = start[i];
        let dinv = 1.0 / lt[i * n + i];
        let (left, right) = j0.split_at_mut(i * ld);
        let col = &mut right[..i + 1];
        col[..i].fill(0.0);
        if i > b0 {
            gemv_upper::<F>(
                -dinv,
                &left[b0 * ld + b0..],
                ld,
                &lt[i * n + b0..i * n + i],
                &mut col[b0..i],
            );
        }
        col[i] = dinv;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Blocks of `a`, then the factorization over them.
    fn factor(a: &mut [f64], n: usize, lt: &mut [f64]) -> (Result<(), usize>, Vec<usize>) {
        let (mut start, mut end) = (vec![0; n], vec![0; n]);
        diagonal_blocks(a, n, &mut start, &mut end);
        (factor_in_place::<false>(a, n, lt, &start, &end), start)
    }

    #[test]
    fn factor_and_inverse_of_a_small_spd_matrix() {
        let n = 3;
        // H = [4 2 0; 2 5 1; 0 1 3], column-major.
        let h = [4.0, 2.0, 0.0, 2.0, 5.0, 1.0, 0.0, 1.0, 3.0];
        let mut l = h;
        let mut lt = [0.0; 9];
        let (res, start) = factor(&mut l, n, &mut lt);
        res.unwrap();
        assert_eq!(
            start,
            [0, 0, 0],
            "one block (the zero corner is bridged by row 1)"
        );
        // Check L Lᵀ = H on the lower triangle.
        for i in 0..n {
            for j in 0..=i {
                let s: f64 = (0..=j).map(|k| l[i + k * n] * l[j + k * n]).sum();
                assert!((s - h[i + j * n]).abs() < 1e-14, "({i},{j})");
            }
        }
        let mut j0 = [0.0; 9];
        inverse_transpose::<false>(&lt, n, &mut j0, n, &start);
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

    /// A block-diagonal H (blocks of 5, 1, 3 and 4, each a dense SPD matrix): the blocks are
    /// found, and the blockwise L and L⁻ᵀ equal those of the dense method (one block), with
    /// exact zeros off the blocks.
    #[test]
    fn block_diagonal_factor_matches_the_dense_one() {
        let sizes = [5usize, 1, 3, 4];
        let n: usize = sizes.iter().sum();
        let mut h = vec![0.0; n * n];
        let mut o = 0;
        for (b, &s) in sizes.iter().enumerate() {
            for i in 0..s {
                for k in 0..s {
                    let x = ((i * 7 + k * 3 + b) as f64 * 0.37).sin() * 0.3;
                    h[(o + i) + (o + k) * n] += x;
                    h[(o + k) + (o + i) * n] += x;
                }
                h[(o + i) * (n + 1)] += 3.0 + i as f64;
            }
            o += s;
        }
        let mut l = h.clone();
        let mut lt = vec![0.0; n * n];
        let (res, start) = factor(&mut l, n, &mut lt);
        res.unwrap();
        assert_eq!(start, [0, 0, 0, 0, 0, 5, 6, 6, 6, 9, 9, 9, 9]);
        let mut dense = h.clone();
        let mut lt_dense = vec![0.0; n * n];
        let (zero, full) = (vec![0; n], vec![n; n]);
        factor_in_place::<false>(&mut dense, n, &mut lt_dense, &zero, &full).unwrap();
        for j in 0..n {
            for i in j..n {
                let (a, b) = (l[i + j * n], dense[i + j * n]);
                assert!((a - b).abs() < 1e-14, "L[{i},{j}] = {a} vs {b}");
                if start[i] != start[j] {
                    assert_eq!(a, 0.0, "L[{i},{j}] outside the blocks");
                }
            }
        }
        for (a, b) in lt.iter().zip(&lt_dense) {
            assert!((a - b).abs() < 1e-14, "row-major L: {a} vs {b}");
        }
        let ld = n.div_ceil(4) * 4;
        let (mut j0, mut j0_dense) = (vec![0.0; ld * n], vec![0.0; ld * n]);
        inverse_transpose::<false>(&lt, n, &mut j0, ld, &start);
        inverse_transpose::<false>(&lt_dense, n, &mut j0_dense, ld, &zero);
        for (a, b) in j0.iter().zip(&j0_dense) {
            assert!((a - b).abs() < 1e-14, "{a} vs {b}");
        }
    }

    #[test]
    fn indefinite_matrix_is_rejected() {
        let mut a = [1.0, 2.0, 2.0, 1.0];
        let mut lt = [0.0; 4];
        assert_eq!(factor(&mut a, 2, &mut lt).0, Err(1));
        let mut z = [0.0; 4];
        assert_eq!(factor(&mut z, 2, &mut lt).0, Err(0));
    }
}
