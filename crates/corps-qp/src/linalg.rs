//! Small dense kernels on contiguous slices (dot, axpy, plane rotation).
//!
//! Every kernel is generic over `F`. `F = true` selects hand-written AVX2 + FMA versions; it
//! is only instantiated by the solver's entry point that is compiled with those target
//! features and called after a run-time CPU check, so the `unsafe` calls below are sound.
//! `F = false` is portable Rust (auto-vectorized with whatever the target allows). The
//! kernels are `#[inline(always)]` so that they are compiled into their caller.

/// Dot product of the common prefix of `a` and `b`.
#[inline(always)]
pub(crate) fn dot<const F: bool>(a: &[f64], b: &[f64]) -> f64 {
    #[cfg(target_arch = "x86_64")]
    if F {
        // SAFETY: `F = true` only runs on CPUs with AVX2 and FMA (see the module docs).
        return unsafe { avx::dot(a, b) };
    }
    let n = a.len().min(b.len());
    let (a, b) = (&a[..n], &b[..n]);
    let mut acc = [0.0f64; 4];
    let ca = a.chunks_exact(4);
    let cb = b.chunks_exact(4);
    let (ra, rb) = (ca.remainder(), cb.remainder());
    for (x, y) in ca.zip(cb) {
        for k in 0..4 {
            acc[k] += x[k] * y[k];
        }
    }
    let mut s = (acc[0] + acc[2]) + (acc[1] + acc[3]);
    for (x, y) in ra.iter().zip(rb) {
        s += x * y;
    }
    s
}

/// `y += alpha * x` over the common prefix.
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

    #[inline]
    #[target_feature(enable = "avx2,fma")]
    pub(super) unsafe fn dot(a: &[f64], b: &[f64]) -> f64 {
        let n = a.len().min(b.len());
        let (pa, pb) = (a.as_ptr(), b.as_ptr());
        let mut acc0 = _mm256_setzero_pd();
        let mut acc1 = _mm256_setzero_pd();
        let mut i = 0;
        // SAFETY: every load reads indices < n ≤ len of both slices.
        unsafe {
            while i + 8 <= n {
                acc0 =
                    _mm256_fmadd_pd(_mm256_loadu_pd(pa.add(i)), _mm256_loadu_pd(pb.add(i)), acc0);
                acc1 = _mm256_fmadd_pd(
                    _mm256_loadu_pd(pa.add(i + 4)),
                    _mm256_loadu_pd(pb.add(i + 4)),
                    acc1,
                );
                i += 8;
            }
            if i + 4 <= n {
                acc0 =
                    _mm256_fmadd_pd(_mm256_loadu_pd(pa.add(i)), _mm256_loadu_pd(pb.add(i)), acc0);
                i += 4;
            }
        }
        let acc = _mm256_add_pd(acc0, acc1);
        let s2 = _mm_add_pd(_mm256_castpd256_pd128(acc), _mm256_extractf128_pd(acc, 1));
        let mut s = _mm_cvtsd_f64(_mm_add_sd(s2, _mm_unpackhi_pd(s2, s2)));
        while i < n {
            s = a[i].mul_add(b[i], s);
            i += 1;
        }
        s
    }

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
