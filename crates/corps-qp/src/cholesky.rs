//! Dense Cholesky factorization `H = L Lᵀ` and the inverse transpose `J₀ = L⁻ᵀ`, in place on
//! column-major buffers, without allocation.

use crate::linalg::axpy;

/// Factor the lower triangle of the column-major `n × n` matrix `a` in place into `L`
/// (left-looking, column by column). The strict upper triangle is not read and is left as is.
///
/// Returns `Err(j)` with the first column whose pivot is not larger than
/// `n · ε · max(1, maxᵢ |Hᵢᵢ|)` (H not numerically positive definite).
#[inline(always)]
pub(crate) fn factor_in_place<const F: bool>(a: &mut [f64], n: usize) -> Result<(), usize> {
    let mut max_diag: f64 = 1.0;
    for j in 0..n {
        max_diag = max_diag.max(a[j + j * n].abs());
    }
    let threshold = n as f64 * f64::EPSILON * max_diag;
    for j in 0..n {
        let (left, right) = a.split_at_mut(j * n);
        let col = &mut right[j..n];
        for k in 0..j {
            let ljk = left[k * n + j];
            if ljk != 0.0 {
                axpy::<F>(-ljk, &left[k * n + j..k * n + n], col);
            }
        }
        let d = col[0];
        // Also catches NaN.
        if d.is_nan() || d <= threshold {
            return Err(j);
        }
        let s = d.sqrt();
        col[0] = s;
        let inv = 1.0 / s;
        for v in &mut col[1..] {
            *v *= inv;
        }
    }
    Ok(())
}

/// Write `J₀ = L⁻ᵀ` (upper triangular, column-major with leading dimension `ld ≥ n`) into
/// `j0`, from the factor `l` computed by [`factor_in_place`]. Rows `n..ld` are not written.
/// `tmp` is a scratch vector of length `n`.
///
/// Column `k` of `L⁻¹` is found by forward substitution and stored as row `k` of `J₀`.
#[inline(always)]
pub(crate) fn inverse_transpose<const F: bool>(
    l: &[f64],
    n: usize,
    j0: &mut [f64],
    ld: usize,
    tmp: &mut [f64],
) {
    for k in 0..n {
        let t = &mut tmp[..n];
        t.fill(0.0);
        t[k] = 1.0;
        for i in k..n {
            let xi = t[i] / l[i + i * n];
            t[i] = xi;
            if xi != 0.0 {
                axpy::<F>(-xi, &l[i * n + i + 1..i * n + n], &mut t[i + 1..]);
            }
        }
        // Row k of J₀ = column k of L⁻¹ (zero above the diagonal of L⁻¹).
        for (c, &v) in t.iter().enumerate() {
            j0[k + c * ld] = v;
        }
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
        factor_in_place::<false>(&mut l, n).unwrap();
        // Check L Lᵀ = H on the lower triangle.
        for i in 0..n {
            for j in 0..=i {
                let s: f64 = (0..=j).map(|k| l[i + k * n] * l[j + k * n]).sum();
                assert!((s - h[i + j * n]).abs() < 1e-14, "({i},{j})");
            }
        }
        let mut j0 = [0.0; 9];
        let mut tmp = [0.0; 3];
        inverse_transpose::<false>(&l, n, &mut j0, n, &mut tmp);
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
        assert_eq!(factor_in_place::<false>(&mut a, 2), Err(1));
        let mut z = [0.0; 4];
        assert_eq!(factor_in_place::<false>(&mut z, 2), Err(0));
    }
}
