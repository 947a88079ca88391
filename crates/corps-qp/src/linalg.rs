//! Small dense kernels on contiguous slices: dot, axpy, plane rotation, register-blocked
//! matrix–vector products (`A x` and `Aᵀ x`, column-major `A`) and a compact-WY block of four
//! Householder reflectors.
//!
//! Every kernel is generic over `F`. `F = true` selects hand-written AVX2 + FMA versions; it
//! is only instantiated by the solver's entry point that is compiled with those target
//! features and called after a run-time CPU check, so the `unsafe` calls below are sound.
//! `F = false` is portable Rust (auto-vectorized with whatever the target allows). The
//! kernels are `#[inline(always)]` so that they are compiled into their caller.

/// `a · b + c`: fused (one rounding) on the AVX2 + FMA path, plain multiply-add otherwise
/// (a fused `mul_add` without hardware FMA would be a slow library call).
#[inline(always)]
pub(crate) fn fmadd<const F: bool>(a: f64, b: f64, c: f64) -> f64 {
    if F {
        a.mul_add(b, c)
    } else {
        a * b + c
    }
}

/// Dot product of the common prefix of `a` and `b`, with 16 independent partial sums (four
/// AVX2 vectors or eight SSE2 vectors: the FMA latency is hidden, unlike a single chain).
#[inline(always)]
pub(crate) fn dot<const F: bool>(a: &[f64], b: &[f64]) -> f64 {
    let n = a.len().min(b.len());
    let (a, b) = (&a[..n], &b[..n]);
    let mut acc = [0.0f64; 16];
    let ca = a.chunks_exact(16);
    let cb = b.chunks_exact(16);
    let (ra, rb) = (ca.remainder(), cb.remainder());
    for (x, y) in ca.zip(cb) {
        for k in 0..16 {
            acc[k] = fmadd::<F>(x[k], y[k], acc[k]);
        }
    }
    let mut acc4 = [0.0f64; 4];
    let ca = ra.chunks_exact(4);
    let cb = rb.chunks_exact(4);
    let (ra, rb) = (ca.remainder(), cb.remainder());
    for (x, y) in ca.zip(cb) {
        for k in 0..4 {
            acc4[k] = fmadd::<F>(x[k], y[k], acc4[k]);
        }
    }
    for k in 0..4 {
        acc4[k] += (acc[k] + acc[k + 4]) + (acc[k + 8] + acc[k + 12]);
    }
    let mut s = (acc4[0] + acc4[2]) + (acc4[1] + acc4[3]);
    for (x, y) in ra.iter().zip(rb) {
        s = fmadd::<F>(*x, *y, s);
    }
    s
}

/// `y += alpha · A x` with `A` column-major (`y.len() × x.len()`, leading dimension `lda`,
/// starting at `a[0]`). Register-blocked: 16 rows (F) or 8 rows of `y` stay in registers
/// while the columns stream by, two columns at a time into separate partial sums, so each
/// element of `A` costs one load and one multiply-add and there are 8 independent chains.
#[inline(always)]
pub(crate) fn gemv<const F: bool>(alpha: f64, a: &[f64], lda: usize, x: &[f64], y: &mut [f64]) {
    if F {
        gemv_w::<F, 16>(alpha, a, lda, x, y, false);
    } else {
        gemv_w::<F, 8>(alpha, a, lda, x, y, false);
    }
}

/// As [`gemv`] for an upper-triangular `A` stored with explicit zeros below the diagonal: a
/// block of rows starting at `r` skips the columns `k < r` (all zero in those rows).
#[inline(always)]
pub(crate) fn gemv_upper<const F: bool>(
    alpha: f64,
    a: &[f64],
    lda: usize,
    x: &[f64],
    y: &mut [f64],
) {
    if F {
        gemv_w::<F, 16>(alpha, a, lda, x, y, true);
    } else {
        gemv_w::<F, 8>(alpha, a, lda, x, y, true);
    }
}

#[inline(always)]
fn gemv_w<const F: bool, const W: usize>(
    alpha: f64,
    a: &[f64],
    lda: usize,
    x: &[f64],
    y: &mut [f64],
    upper: bool,
) {
    let (m, nc) = (y.len(), x.len());
    if m == 0 || nc == 0 {
        return;
    }
    assert!(a.len() >= (nc - 1) * lda + m);
    let mut r = 0;
    #[cfg(target_arch = "x86_64")]
    if F {
        // SAFETY: as in `axpy`; the assert above bounds every element of A that is read.
        r = unsafe { avx::gemv_blocks(alpha, a, lda, x, y, upper) };
    }
    while r + W <= m {
        let mut acc0 = [0.0f64; W];
        let mut acc1 = [0.0f64; W];
        let mut k = if upper { r.min(nc) } else { 0 };
        while k + 2 <= nc {
            let c0: &[f64; W] = a[k * lda + r..][..W].try_into().unwrap();
            let c1: &[f64; W] = a[(k + 1) * lda + r..][..W].try_into().unwrap();
            let (x0, x1) = (x[k], x[k + 1]);
            for t in 0..W {
                acc0[t] = fmadd::<F>(c0[t], x0, acc0[t]);
                acc1[t] = fmadd::<F>(c1[t], x1, acc1[t]);
            }
            k += 2;
        }
        if k < nc {
            let c0: &[f64; W] = a[k * lda + r..][..W].try_into().unwrap();
            let x0 = x[k];
            for t in 0..W {
                acc0[t] = fmadd::<F>(c0[t], x0, acc0[t]);
            }
        }
        let yr: &mut [f64; W] = (&mut y[r..r + W]).try_into().unwrap();
        for t in 0..W {
            yr[t] = fmadd::<F>(alpha, acc0[t] + acc1[t], yr[t]);
        }
        r += W;
    }
    while r + 4 <= m {
        let mut acc0 = [0.0f64; 4];
        let mut acc1 = [0.0f64; 4];
        let mut k = if upper { r.min(nc) } else { 0 };
        while k + 2 <= nc {
            let c0: &[f64; 4] = a[k * lda + r..][..4].try_into().unwrap();
            let c1: &[f64; 4] = a[(k + 1) * lda + r..][..4].try_into().unwrap();
            let (x0, x1) = (x[k], x[k + 1]);
            for t in 0..4 {
                acc0[t] = fmadd::<F>(c0[t], x0, acc0[t]);
                acc1[t] = fmadd::<F>(c1[t], x1, acc1[t]);
            }
            k += 2;
        }
        if k < nc {
            let c0: &[f64; 4] = a[k * lda + r..][..4].try_into().unwrap();
            let x0 = x[k];
            for t in 0..4 {
                acc0[t] = fmadd::<F>(c0[t], x0, acc0[t]);
            }
        }
        let yr: &mut [f64; 4] = (&mut y[r..r + 4]).try_into().unwrap();
        for t in 0..4 {
            yr[t] = fmadd::<F>(alpha, acc0[t] + acc1[t], yr[t]);
        }
        r += 4;
    }
    while r < m {
        // A leftover row: a strided dot product, with four partial sums.
        let mut s = [0.0f64; 4];
        let mut k = if upper { r.min(nc) } else { 0 };
        while k + 4 <= nc {
            for t in 0..4 {
                s[t] = fmadd::<F>(a[(k + t) * lda + r], x[k + t], s[t]);
            }
            k += 4;
        }
        while k < nc {
            s[0] = fmadd::<F>(a[k * lda + r], x[k], s[0]);
            k += 1;
        }
        y[r] = fmadd::<F>(alpha, (s[0] + s[2]) + (s[1] + s[3]), y[r]);
        r += 1;
    }
}

/// `y[j] = A[.., j] · x` for the columns `j < y.len()` of the column-major `A` (leading
/// dimension `lda`), each over its first `len(j)` rows (`len(j) ≤ x.len()`, `len(j) ≤ lda`).
/// Four columns at a time share each load of `x`; 16 partial sums per group.
#[inline(always)]
pub(crate) fn gemv_t<const F: bool>(
    a: &[f64],
    lda: usize,
    x: &[f64],
    y: &mut [f64],
    len: impl Fn(usize) -> usize,
) {
    let nc = y.len();
    let mut j = 0;
    while j + 4 <= nc {
        let l = len(j).max(len(j + 1)).max(len(j + 2)).max(len(j + 3));
        let l = l.min(x.len()).min(lda);
        let base = j * lda;
        let cols = &a[base..base + 3 * lda + l];
        let (c0, rest) = cols.split_at(lda);
        let (c1, rest) = rest.split_at(lda);
        let (c2, c3) = rest.split_at(lda);
        let (c0, c1, c2, c3, xv) = (&c0[..l], &c1[..l], &c2[..l], &c3[..l], &x[..l]);
        #[cfg(target_arch = "x86_64")]
        if F {
            // SAFETY: as in `axpy`; the five slices have length l.
            let s = unsafe { avx::dot4(c0, c1, c2, c3, xv) };
            y[j..j + 4].copy_from_slice(&s);
            j += 4;
            continue;
        }
        let (mut a0, mut a1, mut a2, mut a3) = ([0.0f64; 4], [0.0f64; 4], [0.0f64; 4], [0.0f64; 4]);
        let mut i = 0;
        while i + 4 <= l {
            let xs: &[f64; 4] = xv[i..i + 4].try_into().unwrap();
            let v0: &[f64; 4] = c0[i..i + 4].try_into().unwrap();
            let v1: &[f64; 4] = c1[i..i + 4].try_into().unwrap();
            let v2: &[f64; 4] = c2[i..i + 4].try_into().unwrap();
            let v3: &[f64; 4] = c3[i..i + 4].try_into().unwrap();
            for t in 0..4 {
                a0[t] = fmadd::<F>(v0[t], xs[t], a0[t]);
            }
            for t in 0..4 {
                a1[t] = fmadd::<F>(v1[t], xs[t], a1[t]);
            }
            for t in 0..4 {
                a2[t] = fmadd::<F>(v2[t], xs[t], a2[t]);
            }
            for t in 0..4 {
                a3[t] = fmadd::<F>(v3[t], xs[t], a3[t]);
            }
            i += 4;
        }
        let mut s = [
            (a0[0] + a0[2]) + (a0[1] + a0[3]),
            (a1[0] + a1[2]) + (a1[1] + a1[3]),
            (a2[0] + a2[2]) + (a2[1] + a2[3]),
            (a3[0] + a3[2]) + (a3[1] + a3[3]),
        ];
        while i < l {
            s[0] = fmadd::<F>(c0[i], xv[i], s[0]);
            s[1] = fmadd::<F>(c1[i], xv[i], s[1]);
            s[2] = fmadd::<F>(c2[i], xv[i], s[2]);
            s[3] = fmadd::<F>(c3[i], xv[i], s[3]);
            i += 1;
        }
        y[j..j + 4].copy_from_slice(&s);
        j += 4;
    }
    while j < nc {
        let l = len(j).min(x.len()).min(lda);
        y[j] = dot::<F>(&a[j * lda..j * lda + l], &x[..l]);
        j += 1;
    }
}

/// Apply a block of (up to) four Householder reflectors from the right, in compact WY form:
/// `J[.., c0..c0 + l] ← J[.., c0..c0 + l] (I − V T Vᵀ)`, with `V` (`l × 4`) stored row-major in
/// `v` and `T` upper triangular. `J` is column-major with leading dimension `ld` (a multiple
/// of 4) and `ld` rows are updated. Per block of rows, `Y = J V` and `Y T` stay in registers
/// and every column of `J` is loaded twice and stored once for four reflectors (instead of
/// twice and once per reflector).
#[inline(always)]
pub(crate) fn apply_reflectors4<const F: bool>(
    j: &mut [f64],
    ld: usize,
    c0: usize,
    l: usize,
    v: &[f64],
    t: &[[f64; 4]; 4],
) {
    let v = &v[..4 * l];
    let j = &mut j[c0 * ld..(c0 + l) * ld];
    let mut r = 0;
    while r + 8 <= ld {
        wy_rows::<F, 8>(j, ld, r, l, v, t);
        r += 8;
    }
    while r + 4 <= ld {
        wy_rows::<F, 4>(j, ld, r, l, v, t);
        r += 4;
    }
}

#[inline(always)]
fn wy_rows<const F: bool, const W: usize>(
    j: &mut [f64],
    ld: usize,
    r: usize,
    l: usize,
    v: &[f64],
    t: &[[f64; 4]; 4],
) {
    let (mut y0, mut y1, mut y2, mut y3) = ([0.0f64; W], [0.0f64; W], [0.0f64; W], [0.0f64; W]);
    for (i, vi) in v.chunks_exact(4).enumerate().take(l) {
        let col: &[f64; W] = j[i * ld + r..][..W].try_into().unwrap();
        for k in 0..W {
            y0[k] = fmadd::<F>(col[k], vi[0], y0[k]);
        }
        for k in 0..W {
            y1[k] = fmadd::<F>(col[k], vi[1], y1[k]);
        }
        for k in 0..W {
            y2[k] = fmadd::<F>(col[k], vi[2], y2[k]);
        }
        for k in 0..W {
            y3[k] = fmadd::<F>(col[k], vi[3], y3[k]);
        }
    }
    // Y ← Y T (T upper triangular), last column first so that the inputs are still old.
    for k in 0..W {
        let (a0, a1, a2, a3) = (y0[k], y1[k], y2[k], y3[k]);
        y3[k] = fmadd::<F>(
            a0,
            t[0][3],
            fmadd::<F>(a1, t[1][3], fmadd::<F>(a2, t[2][3], a3 * t[3][3])),
        );
        y2[k] = fmadd::<F>(a0, t[0][2], fmadd::<F>(a1, t[1][2], a2 * t[2][2]));
        y1[k] = fmadd::<F>(a0, t[0][1], a1 * t[1][1]);
        y0[k] = a0 * t[0][0];
    }
    for (i, vi) in v.chunks_exact(4).enumerate().take(l) {
        let col: &mut [f64; W] = (&mut j[i * ld + r..][..W]).try_into().unwrap();
        let (m0, m1, m2, m3) = (-vi[0], -vi[1], -vi[2], -vi[3]);
        for k in 0..W {
            col[k] = fmadd::<F>(
                y0[k],
                m0,
                fmadd::<F>(
                    y1[k],
                    m1,
                    fmadd::<F>(y2[k], m2, fmadd::<F>(y3[k], m3, col[k])),
                ),
            );
        }
    }
}

/// `A −= x yᵀ` on the `x.len() × y.len()` block of the column-major `A` (leading dimension
/// `lda`): one pass over the columns with `x` kept in registers.
#[inline(always)]
pub(crate) fn ger_sub<const F: bool>(a: &mut [f64], lda: usize, x: &[f64], y: &[f64]) {
    let (m, nc) = (x.len(), y.len());
    if m == 0 || nc == 0 {
        return;
    }
    assert!(a.len() >= (nc - 1) * lda + m);
    #[cfg(target_arch = "x86_64")]
    if F {
        // SAFETY: as in `axpy`; bounds checked by the assert above.
        return unsafe { avx::ger_sub(a, lda, x, y) };
    }
    for (k, &yk) in y.iter().enumerate() {
        for (ai, &xi) in a[k * lda..k * lda + m].iter_mut().zip(x) {
            *ai -= xi * yk;
        }
    }
}

/// `y += alpha * x` over the common prefix (kept for the kernel tests; the solver now uses
/// the blocked kernels above).
#[cfg_attr(not(test), allow(dead_code))]
#[inline(always)]
pub(crate) fn axpy<const F: bool>(alpha: f64, x: &[f64], y: &mut [f64]) {
    #[cfg(target_arch = "x86_64")]
    if F {
        // SAFETY: as in `dot`.
        return unsafe { avx::axpy(alpha, x, y) };
    }
    for (yi, xi) in y.iter_mut().zip(x) {
        *yi += alpha * *xi;
    }
}

/// Plane rotation of the common prefix: `x ← c x + s y`, `y ← c y − s x`.
#[inline(always)]
pub(crate) fn rot<const F: bool>(c: f64, s: f64, x: &mut [f64], y: &mut [f64]) {
    #[cfg(target_arch = "x86_64")]
    if F {
        // SAFETY: as in `dot`.
        return unsafe { avx::rot(c, s, x, y) };
    }
    for (xi, yi) in x.iter_mut().zip(y.iter_mut()) {
        let (a, b) = (*xi, *yi);
        *xi = c * a + s * b;
        *yi = c * b - s * a;
    }
}

/// Squared Euclidean norm.
#[inline(always)]
pub(crate) fn norm2<const F: bool>(a: &[f64]) -> f64 {
    dot::<F>(a, a)
}

#[cfg(target_arch = "x86_64")]
mod avx {
    use std::arch::x86_64::*;

    /// The row blocks of [`super::gemv`] (16 and 4 rows); returns the first row not done.
    /// The caller has checked `a.len() ≥ (x.len() − 1) lda + y.len()`.
    #[inline]
    #[target_feature(enable = "avx2,fma")]
    pub(super) unsafe fn gemv_blocks(
        alpha: f64,
        a: &[f64],
        lda: usize,
        x: &[f64],
        y: &mut [f64],
        upper: bool,
    ) -> usize {
        let (m, nc) = (y.len(), x.len());
        let (pa, px, py) = (a.as_ptr(), x.as_ptr(), y.as_mut_ptr());
        let va = _mm256_set1_pd(alpha);
        let mut r = 0;
        // SAFETY: column k < nc, rows < m: index k lda + row < (nc − 1) lda + m ≤ a.len();
        // x and y are read below their lengths.
        unsafe {
            while r + 16 <= m {
                let mut k = if upper { r.min(nc) } else { 0 };
                let z = _mm256_setzero_pd();
                let (mut a0, mut a1, mut a2, mut a3) = (z, z, z, z);
                let (mut b0, mut b1, mut b2, mut b3) = (z, z, z, z);
                while k + 2 <= nc {
                    let p0 = pa.add(k * lda + r);
                    let p1 = p0.add(lda);
                    let x0 = _mm256_broadcast_sd(&*px.add(k));
                    let x1 = _mm256_broadcast_sd(&*px.add(k + 1));
                    a0 = _mm256_fmadd_pd(_mm256_loadu_pd(p0), x0, a0);
                    a1 = _mm256_fmadd_pd(_mm256_loadu_pd(p0.add(4)), x0, a1);
                    a2 = _mm256_fmadd_pd(_mm256_loadu_pd(p0.add(8)), x0, a2);
                    a3 = _mm256_fmadd_pd(_mm256_loadu_pd(p0.add(12)), x0, a3);
                    b0 = _mm256_fmadd_pd(_mm256_loadu_pd(p1), x1, b0);
                    b1 = _mm256_fmadd_pd(_mm256_loadu_pd(p1.add(4)), x1, b1);
                    b2 = _mm256_fmadd_pd(_mm256_loadu_pd(p1.add(8)), x1, b2);
                    b3 = _mm256_fmadd_pd(_mm256_loadu_pd(p1.add(12)), x1, b3);
                    k += 2;
                }
                if k < nc {
                    let p0 = pa.add(k * lda + r);
                    let x0 = _mm256_broadcast_sd(&*px.add(k));
                    a0 = _mm256_fmadd_pd(_mm256_loadu_pd(p0), x0, a0);
                    a1 = _mm256_fmadd_pd(_mm256_loadu_pd(p0.add(4)), x0, a1);
                    a2 = _mm256_fmadd_pd(_mm256_loadu_pd(p0.add(8)), x0, a2);
                    a3 = _mm256_fmadd_pd(_mm256_loadu_pd(p0.add(12)), x0, a3);
                }
                let q = py.add(r);
                _mm256_storeu_pd(
                    q,
                    _mm256_fmadd_pd(va, _mm256_add_pd(a0, b0), _mm256_loadu_pd(q)),
                );
                let q = q.add(4);
                _mm256_storeu_pd(
                    q,
                    _mm256_fmadd_pd(va, _mm256_add_pd(a1, b1), _mm256_loadu_pd(q)),
                );
                let q = q.add(4);
                _mm256_storeu_pd(
                    q,
                    _mm256_fmadd_pd(va, _mm256_add_pd(a2, b2), _mm256_loadu_pd(q)),
                );
                let q = q.add(4);
                _mm256_storeu_pd(
                    q,
                    _mm256_fmadd_pd(va, _mm256_add_pd(a3, b3), _mm256_loadu_pd(q)),
                );
                r += 16;
            }
            while r + 4 <= m {
                let mut k = if upper { r.min(nc) } else { 0 };
                let z = _mm256_setzero_pd();
                let (mut a0, mut a1, mut a2, mut a3) = (z, z, z, z);
                while k + 4 <= nc {
                    let p0 = pa.add(k * lda + r);
                    a0 = _mm256_fmadd_pd(_mm256_loadu_pd(p0), _mm256_broadcast_sd(&*px.add(k)), a0);
                    a1 = _mm256_fmadd_pd(
                        _mm256_loadu_pd(p0.add(lda)),
                        _mm256_broadcast_sd(&*px.add(k + 1)),
                        a1,
                    );
                    a2 = _mm256_fmadd_pd(
                        _mm256_loadu_pd(p0.add(2 * lda)),
                        _mm256_broadcast_sd(&*px.add(k + 2)),
                        a2,
                    );
                    a3 = _mm256_fmadd_pd(
                        _mm256_loadu_pd(p0.add(3 * lda)),
                        _mm256_broadcast_sd(&*px.add(k + 3)),
                        a3,
                    );
                    k += 4;
                }
                while k < nc {
                    let p0 = pa.add(k * lda + r);
                    a0 = _mm256_fmadd_pd(_mm256_loadu_pd(p0), _mm256_broadcast_sd(&*px.add(k)), a0);
                    k += 1;
                }
                let s = _mm256_add_pd(_mm256_add_pd(a0, a1), _mm256_add_pd(a2, a3));
                let q = py.add(r);
                _mm256_storeu_pd(q, _mm256_fmadd_pd(va, s, _mm256_loadu_pd(q)));
                r += 4;
            }
            if r < m {
                // The last 1–3 rows as one masked 4-row block (masked-out lanes are neither
                // read nor written).
                let mask = tail_mask(m - r);
                let mut k = if upper { r.min(nc) } else { 0 };
                let z = _mm256_setzero_pd();
                let (mut a0, mut a1) = (z, z);
                while k + 2 <= nc {
                    let p0 = pa.add(k * lda + r);
                    a0 = _mm256_fmadd_pd(
                        _mm256_maskload_pd(p0, mask),
                        _mm256_broadcast_sd(&*px.add(k)),
                        a0,
                    );
                    a1 = _mm256_fmadd_pd(
                        _mm256_maskload_pd(p0.add(lda), mask),
                        _mm256_broadcast_sd(&*px.add(k + 1)),
                        a1,
                    );
                    k += 2;
                }
                if k < nc {
                    let p0 = pa.add(k * lda + r);
                    a0 = _mm256_fmadd_pd(
                        _mm256_maskload_pd(p0, mask),
                        _mm256_broadcast_sd(&*px.add(k)),
                        a0,
                    );
                }
                let q = py.add(r);
                let s = _mm256_add_pd(a0, a1);
                _mm256_maskstore_pd(q, mask, _mm256_fmadd_pd(va, s, _mm256_maskload_pd(q, mask)));
                r = m;
            }
        }
        r
    }

    /// Lane mask selecting the first `len` (1–3) of four lanes.
    #[inline]
    #[target_feature(enable = "avx2,fma")]
    fn tail_mask(len: usize) -> __m256i {
        let l = len as i64;
        _mm256_set_epi64x(
            if l > 3 { -1 } else { 0 },
            if l > 2 { -1 } else { 0 },
            if l > 1 { -1 } else { 0 },
            if l > 0 { -1 } else { 0 },
        )
    }

    /// `A −= x yᵀ` for the `x.len() × y.len()` block of the column-major `A` (leading
    /// dimension `lda`); the caller has checked `a.len() ≥ (y.len() − 1) lda + x.len()`.
    #[inline]
    #[target_feature(enable = "avx2,fma")]
    pub(super) unsafe fn ger_sub(a: &mut [f64], lda: usize, x: &[f64], y: &[f64]) {
        let m = x.len();
        let pa = a.as_mut_ptr();
        let mut r = 0;
        // SAFETY: every access is at column k < nc, row < m: below (nc − 1) lda + m.
        unsafe {
            while r < m {
                let mask = tail_mask((m - r).min(4));
                let xv = _mm256_maskload_pd(x.as_ptr().add(r), mask);
                for (k, &yk) in y.iter().enumerate() {
                    let p = pa.add(k * lda + r);
                    let v = _mm256_fnmadd_pd(xv, _mm256_set1_pd(yk), _mm256_maskload_pd(p, mask));
                    _mm256_maskstore_pd(p, mask, v);
                }
                r += 4;
            }
        }
    }

    /// The four dot products `cₖ · x` (all slices of the same length).
    #[inline]
    #[target_feature(enable = "avx2,fma")]
    pub(super) unsafe fn dot4(
        c0: &[f64],
        c1: &[f64],
        c2: &[f64],
        c3: &[f64],
        x: &[f64],
    ) -> [f64; 4] {
        let n = x.len();
        assert!(c0.len() == n && c1.len() == n && c2.len() == n && c3.len() == n);
        let (p0, p1, p2, p3, px) = (
            c0.as_ptr(),
            c1.as_ptr(),
            c2.as_ptr(),
            c3.as_ptr(),
            x.as_ptr(),
        );
        let mut a0 = _mm256_setzero_pd();
        let mut a1 = _mm256_setzero_pd();
        let mut a2 = _mm256_setzero_pd();
        let mut a3 = _mm256_setzero_pd();
        let mut i = 0;
        // SAFETY: every load reads indices < n, the common length.
        unsafe {
            while i + 4 <= n {
                let xv = _mm256_loadu_pd(px.add(i));
                a0 = _mm256_fmadd_pd(_mm256_loadu_pd(p0.add(i)), xv, a0);
                a1 = _mm256_fmadd_pd(_mm256_loadu_pd(p1.add(i)), xv, a1);
                a2 = _mm256_fmadd_pd(_mm256_loadu_pd(p2.add(i)), xv, a2);
                a3 = _mm256_fmadd_pd(_mm256_loadu_pd(p3.add(i)), xv, a3);
                i += 4;
            }
        }
        let t0 = _mm256_hadd_pd(a0, a1);
        let t1 = _mm256_hadd_pd(a2, a3);
        let lo = _mm256_permute2f128_pd(t0, t1, 0x20);
        let hi = _mm256_permute2f128_pd(t0, t1, 0x31);
        let mut out = [0.0f64; 4];
        // SAFETY: `out` holds four f64.
        unsafe { _mm256_storeu_pd(out.as_mut_ptr(), _mm256_add_pd(lo, hi)) };
        while i < n {
            out[0] = c0[i].mul_add(x[i], out[0]);
            out[1] = c1[i].mul_add(x[i], out[1]);
            out[2] = c2[i].mul_add(x[i], out[2]);
            out[3] = c3[i].mul_add(x[i], out[3]);
            i += 1;
        }
        out
    }

    #[cfg_attr(not(test), allow(dead_code))]
    #[inline]
    #[target_feature(enable = "avx2,fma")]
    pub(super) unsafe fn axpy(alpha: f64, x: &[f64], y: &mut [f64]) {
        let n = x.len().min(y.len());
        let (px, py) = (x.as_ptr(), y.as_mut_ptr());
        let va = _mm256_set1_pd(alpha);
        let mut i = 0;
        // SAFETY: every access is at an index < n ≤ len of both slices.
        unsafe {
            while i + 4 <= n {
                let r = _mm256_fmadd_pd(va, _mm256_loadu_pd(px.add(i)), _mm256_loadu_pd(py.add(i)));
                _mm256_storeu_pd(py.add(i), r);
                i += 4;
            }
        }
        while i < n {
            y[i] = alpha.mul_add(x[i], y[i]);
            i += 1;
        }
    }

    #[inline]
    #[target_feature(enable = "avx2,fma")]
    pub(super) unsafe fn rot(c: f64, s: f64, x: &mut [f64], y: &mut [f64]) {
        let n = x.len().min(y.len());
        let (px, py) = (x.as_mut_ptr(), y.as_mut_ptr());
        let (vc, vs) = (_mm256_set1_pd(c), _mm256_set1_pd(s));
        let mut i = 0;
        // SAFETY: every access is at an index < n ≤ len of both slices.
        unsafe {
            while i + 4 <= n {
                let a = _mm256_loadu_pd(px.add(i));
                let b = _mm256_loadu_pd(py.add(i));
                _mm256_storeu_pd(px.add(i), _mm256_fmadd_pd(vc, a, _mm256_mul_pd(vs, b)));
                _mm256_storeu_pd(py.add(i), _mm256_fnmadd_pd(vs, a, _mm256_mul_pd(vc, b)));
                i += 4;
            }
        }
        while i < n {
            let (a, b) = (x[i], y[i]);
            x[i] = c.mul_add(a, s * b);
            y[i] = (-s).mul_add(a, c * b);
            i += 1;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dot_matches_the_sequential_sum_at_every_length_class() {
        // Around the 16- and 4-wide blocks, with remainders, an empty product, and a preview
        // controller's window.
        for len in [0usize, 1, 3, 4, 15, 16, 17, 21, 320, 1601] {
            let a: Vec<f64> = (0..len).map(|j| (0.37 * j as f64).sin()).collect();
            let b: Vec<f64> = (0..len).map(|j| 1.0 + (0.11 * j as f64).cos()).collect();
            let sequential: f64 = a.iter().zip(&b).map(|(x, y)| x * y).sum();
            let scale: f64 = a.iter().zip(&b).map(|(x, y)| (x * y).abs()).sum();
            let got = crate::dot(&a, &b);
            assert!(
                (got - sequential).abs() <= 1e-14 * scale.max(1.0),
                "len {len}: {got} vs {sequential}"
            );
        }
    }

    #[test]
    fn kernels_agree_between_paths() {
        let a: Vec<f64> = (0..13).map(|i| (i as f64 * 0.37).sin()).collect();
        let b: Vec<f64> = (0..13).map(|i| (i as f64 * 0.91).cos()).collect();
        let exact: f64 = a.iter().zip(&b).map(|(x, y)| x * y).sum();
        assert!((dot::<false>(&a, &b) - exact).abs() < 1e-14);
        let (mut y0, mut y1) = (b.clone(), b.clone());
        axpy::<false>(0.5, &a, &mut y0);
        for (k, v) in y1.iter_mut().enumerate() {
            *v += 0.5 * a[k];
        }
        assert_eq!(y0, y1);
        let (mut x, mut y) = (a.clone(), b.clone());
        rot::<false>(0.6, 0.8, &mut x, &mut y);
        for k in 0..13 {
            assert!((x[k] - (0.6 * a[k] + 0.8 * b[k])).abs() < 1e-15);
            assert!((y[k] - (0.6 * b[k] - 0.8 * a[k])).abs() < 1e-15);
        }
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") && std::arch::is_x86_feature_detected!("fma")
        {
            assert!((dot::<true>(&a, &b) - exact).abs() < 1e-14);
            let mut y2 = b.clone();
            axpy::<true>(0.5, &a, &mut y2);
            let (mut x3, mut y3) = (a.clone(), b.clone());
            rot::<true>(0.6, 0.8, &mut x3, &mut y3);
            for k in 0..13 {
                assert!((y2[k] - y1[k]).abs() < 1e-15);
                assert!((x3[k] - x[k]).abs() < 1e-15 && (y3[k] - y[k]).abs() < 1e-15);
            }
        }
    }
}
