//! The equality-constrained QP on a given active set, solved directly by the null-space method
//! (Nocedal & Wright 2006, §16.2):
//!
//! ```text
//! minimize ½ xᵀ H x + gᵀ x   subject to   Nᵀ x = β        (N: n × m, the active normals)
//! N = Q [R; 0],  x = Q₁ R⁻ᵀ β + Q₂ y,  (Q₂ᵀ H Q₂) y = −Q₂ᵀ (g + H Q₁ R⁻ᵀ β),  R u = Q₁ᵀ (H x + g)
//! ```
//!
//! with `H x + g = N u` (u: the active constraints' multipliers). The solver uses it to finish
//! its proximal fallback: once the proximal iterations have found the active set, the original
//! problem's optimum on it is one factorization away, where the iterations themselves creep
//! along H's small eigenvalues (cond(H) ~ 1e12) without converging. Householder QR of N and
//! Cholesky of the reduced Hessian; every buffer is sized once ([`PolishWork::resize`]).

/// Buffers of [`solve_on_active_set`] for up to `n` variables.
#[derive(Debug, Clone, Default)]
pub(crate) struct PolishWork {
    /// The active normals (column-major, `n × m`), overwritten by their QR (R on and above
    /// the diagonal, the reflectors below it).
    pub normals: Vec<f64>,
    /// Right-hand sides β of the active constraints.
    pub beta: Vec<f64>,
    /// The normals' norms (before the QR).
    pub norms: Vec<f64>,
    tau: Vec<f64>,
    /// Q (column-major, `n × n`).
    q: Vec<f64>,
    /// H Q₂ (column-major, `n × (n − m)`).
    hq: Vec<f64>,
    /// The reduced Hessian Q₂ᵀ H Q₂ and its Cholesky factor.
    reduced: Vec<f64>,
    v1: Vec<f64>,
    v2: Vec<f64>,
}

impl PolishWork {
    pub fn resize(&mut self, n: usize) {
        self.normals = vec![0.0; n * n];
        self.beta = vec![0.0; n];
        self.norms = vec![0.0; n];
        self.tau = vec![0.0; n];
        self.q = vec![0.0; n * n];
        self.hq = vec![0.0; n * n];
        self.reduced = vec![0.0; n * n];
        self.v1 = vec![0.0; n];
        self.v2 = vec![0.0; n];
    }
}

/// A normal whose component outside the span of the ones before it is below this fraction
/// of its norm makes N rank deficient: near copies of a row (1e-10 apart) would otherwise
/// take opposite multipliers of 1e10 whose rounding swamps the optimality conditions.
const RANK_TOL: f64 = 1e-8;

/// Solves the QP above for the `m` normals and right-hand sides in `w.normals` / `w.beta`:
/// `x` (n) and the multipliers `u` (m); also leaves the normals' norms in `w.norms`. `h` is
/// column-major `n × n`. False when N is numerically rank deficient ([`RANK_TOL`]) or the
/// reduced Hessian is not positive definite.
pub(crate) fn solve_on_active_set(
    h: &[f64],
    g: &[f64],
    n: usize,
    m: usize,
    w: &mut PolishWork,
    x: &mut [f64],
    u: &mut [f64],
) -> bool {
    if m > n {
        return false;
    }
    if n == 0 {
        return true;
    }
    let nm = &mut w.normals[..n * m];
    for (norm, col) in w.norms.iter_mut().zip(nm.chunks_exact(n)) {
        *norm = col.iter().map(|v| v * v).sum::<f64>().sqrt();
    }
    // Householder QR: column k's reflector v (v_k = 1 implied) below the diagonal, τ in tau.
    for k in 0..m {
        let col = &mut nm[k * n..(k + 1) * n];
        let norm = col[k..].iter().map(|v| v * v).sum::<f64>().sqrt();
        if norm == 0.0 {
            return false;
        }
        let alpha = if col[k] > 0.0 { -norm } else { norm };
        let v0 = col[k] - alpha;
        for v in &mut col[k + 1..] {
            *v /= v0;
        }
        w.tau[k] = -v0 / alpha;
        col[k] = alpha;
        if alpha.abs() <= RANK_TOL * w.norms[k] {
            return false;
        }
        let (done, rest) = nm.split_at_mut((k + 1) * n);
        let v = &done[k * n..];
        for c in rest.chunks_exact_mut(n).take(m - k - 1) {
            reflect(v, w.tau[k], k, c);
        }
    }
    // Q = H₀ H₁ … H_{m−1} applied to the identity, from the last reflector back.
    let q = &mut w.q[..n * n];
    q.fill(0.0);
    for i in 0..n {
        q[i * n + i] = 1.0;
    }
    for k in (0..m).rev() {
        let v = &nm[k * n..(k + 1) * n];
        for c in q.chunks_exact_mut(n) {
            reflect(v, w.tau[k], k, c);
        }
    }
    let r = |i: usize, j: usize| nm[j * n + i];
    // z = R⁻ᵀ β, the particular point x_p = Q₁ z.
    let z = &mut w.v1[..m];
    for i in 0..m {
        let s: f64 = (0..i).map(|j| r(j, i) * z[j]).sum();
        z[i] = (w.beta[i] - s) / r(i, i);
    }
    for (i, xi) in x.iter_mut().enumerate().take(n) {
        *xi = (0..m).map(|j| q[j * n + i] * z[j]).sum();
    }
    // H Q₂ (n × (n − m)), the reduced Hessian and gradient.
    let nr = n - m;
    let hq = &mut w.hq[..n * nr];
    for (c, out) in hq.chunks_exact_mut(n).enumerate() {
        let qc = &q[(m + c) * n..(m + c + 1) * n];
        out.fill(0.0);
        for (k, &qk) in qc.iter().enumerate() {
            for (o, hk) in out.iter_mut().zip(&h[k * n..(k + 1) * n]) {
                *o += hk * qk;
            }
        }
    }
    let red = &mut w.reduced[..nr * nr];
    for i in 0..nr {
        for j in 0..=i {
            let qi = &q[(m + i) * n..(m + i + 1) * n];
            let v: f64 = qi
                .iter()
                .zip(&hq[j * n..(j + 1) * n])
                .map(|(a, b)| a * b)
                .sum();
            red[i * nr + j] = v;
            red[j * nr + i] = v;
        }
    }
    // grad = g + H x_p; rhs = −Q₂ᵀ grad.
    let grad = &mut w.v2[..n];
    for i in 0..n {
        grad[i] = g[i] + (0..n).map(|k| h[k * n + i] * x[k]).sum::<f64>();
    }
    let y = &mut w.v1[..nr];
    for (i, yi) in y.iter_mut().enumerate() {
        *yi = -q[(m + i) * n..(m + i + 1) * n]
            .iter()
            .zip(grad.iter())
            .map(|(a, b)| a * b)
            .sum::<f64>();
    }
    // Cholesky of the reduced Hessian (lower, row-major in `red`), then two solves.
    let scale = (0..nr).map(|i| red[i * nr + i]).fold(0.0f64, f64::max);
    for k in 0..nr {
        let d = red[k * nr + k] - (0..k).map(|j| red[k * nr + j].powi(2)).sum::<f64>();
        // A NaN pivot fails too.
        if d.is_nan() || d <= 1e-15 * scale {
            return false;
        }
        let d = d.sqrt();
        red[k * nr + k] = d;
        for i in k + 1..nr {
            let s: f64 = (0..k).map(|j| red[i * nr + j] * red[k * nr + j]).sum();
            red[i * nr + k] = (red[i * nr + k] - s) / d;
        }
    }
    for i in 0..nr {
        let s: f64 = (0..i).map(|j| red[i * nr + j] * y[j]).sum();
        y[i] = (y[i] - s) / red[i * nr + i];
    }
    for i in (0..nr).rev() {
        let s: f64 = (i + 1..nr).map(|j| red[j * nr + i] * y[j]).sum();
        y[i] = (y[i] - s) / red[i * nr + i];
    }
    for (i, xi) in x.iter_mut().enumerate().take(n) {
        *xi += (0..nr).map(|c| q[(m + c) * n + i] * y[c]).sum::<f64>();
    }
    // Multipliers: R u = Q₁ᵀ (H x + g).
    for i in 0..n {
        grad[i] = g[i] + (0..n).map(|k| h[k * n + i] * x[k]).sum::<f64>();
    }
    for (k, uk) in u.iter_mut().enumerate().take(m) {
        *uk = q[k * n..(k + 1) * n]
            .iter()
            .zip(grad.iter())
            .map(|(a, b)| a * b)
            .sum();
    }
    for i in (0..m).rev() {
        let s: f64 = (i + 1..m).map(|j| r(i, j) * u[j]).sum();
        u[i] = (u[i] - s) / r(i, i);
    }
    x[..n].iter().chain(&u[..m]).all(|v| v.is_finite())
}

/// `c ← (I − τ v vᵀ) c` for the reflector of column `k`: `v` zero above k, 1 at k (implied)
/// and `v[k + 1..]` below.
#[inline]
fn reflect(v: &[f64], tau: f64, k: usize, c: &mut [f64]) {
    let dot: f64 = v[k + 1..].iter().zip(&c[k + 1..]).map(|(a, b)| a * b).sum();
    let s = (c[k] + dot) * tau;
    c[k] -= s;
    for (ci, vi) in c[k + 1..].iter_mut().zip(&v[k + 1..]) {
        *ci -= s * vi;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A random problem's answer meets its optimality conditions: `Nᵀ x = β` and
    /// `H x + g = N u`.
    #[test]
    fn meets_the_optimality_conditions() {
        let n = 6;
        let m = 3;
        let mut seed = 7u64;
        let mut rand = || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((seed >> 11) as f64 / (1u64 << 53) as f64) - 0.5
        };
        let b: Vec<f64> = (0..n * n).map(|_| rand()).collect();
        let mut h = vec![0.0; n * n];
        for i in 0..n {
            for j in 0..n {
                h[j * n + i] = (0..n).map(|k| b[i * n + k] * b[j * n + k]).sum::<f64>();
            }
            h[i * n + i] += 0.1;
        }
        let g: Vec<f64> = (0..n).map(|_| rand()).collect();
        let mut w = PolishWork::default();
        w.resize(n);
        for v in w.normals[..n * m].iter_mut() {
            *v = rand();
        }
        for v in w.beta[..m].iter_mut() {
            *v = rand();
        }
        let normals = w.normals[..n * m].to_vec();
        let beta = w.beta[..m].to_vec();
        let (mut x, mut u) = (vec![0.0; n], vec![0.0; m]);
        assert!(solve_on_active_set(&h, &g, n, m, &mut w, &mut x, &mut u));
        for k in 0..m {
            let nx: f64 = (0..n).map(|i| normals[k * n + i] * x[i]).sum();
            assert!(
                (nx - beta[k]).abs() < 1e-12,
                "constraint {k}: {nx} vs {}",
                beta[k]
            );
        }
        for i in 0..n {
            let hx: f64 = (0..n).map(|k| h[k * n + i] * x[k]).sum();
            let nu: f64 = (0..m).map(|k| normals[k * n + i] * u[k]).sum();
            assert!((hx + g[i] - nu).abs() < 1e-12, "stationarity {i}");
        }
    }

    /// No active constraint: the unconstrained minimum, H x = −g. As many as variables: the
    /// vertex, Nᵀ x = β, and the multipliers from H x + g = N u.
    #[test]
    fn handles_no_and_all_constraints() {
        let n = 3;
        let h = [4.0, 1.0, 0.0, 1.0, 3.0, 0.5, 0.0, 0.5, 2.0];
        let g = [1.0, -2.0, 0.5];
        let mut w = PolishWork::default();
        w.resize(n);
        let (mut x, mut u) = (vec![0.0; n], vec![0.0; n]);
        assert!(solve_on_active_set(&h, &g, n, 0, &mut w, &mut x, &mut u));
        for i in 0..n {
            let hx: f64 = (0..n).map(|k| h[k * n + i] * x[k]).sum();
            assert!((hx + g[i]).abs() < 1e-14);
        }
        let normals = [1.0, 0.0, 1.0, 0.0, 2.0, 0.0, 1.0, 1.0, 0.0];
        w.normals[..9].copy_from_slice(&normals);
        w.beta[..3].copy_from_slice(&[1.0, -1.0, 0.5]);
        assert!(solve_on_active_set(&h, &g, n, n, &mut w, &mut x, &mut u));
        for k in 0..n {
            let nx: f64 = (0..n).map(|i| normals[k * n + i] * x[i]).sum();
            assert!((nx - [1.0, -1.0, 0.5][k]).abs() < 1e-14);
        }
        for i in 0..n {
            let hx: f64 = (0..n).map(|k| h[k * n + i] * x[k]).sum();
            let nu: f64 = (0..n).map(|k| normals[k * n + i] * u[k]).sum();
            assert!((hx + g[i] - nu).abs() < 1e-13);
        }
    }

    #[test]
    fn handles_no_variable() {
        let mut w = PolishWork::default();
        w.resize(0);
        assert!(solve_on_active_set(
            &[],
            &[],
            0,
            0,
            &mut w,
            &mut [],
            &mut []
        ));
    }

    #[test]
    fn refuses_dependent_normals() {
        let n = 3;
        let mut w = PolishWork::default();
        w.resize(n);
        w.normals[..6].copy_from_slice(&[1.0, 2.0, 3.0, 2.0, 4.0, 6.0]);
        w.beta[..2].copy_from_slice(&[1.0, 2.0]);
        let h = [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0];
        let (mut x, mut u) = (vec![0.0; n], vec![0.0; 2]);
        assert!(!solve_on_active_set(
            &h, &[0.0; 3], n, 2, &mut w, &mut x, &mut u
        ));
    }
}
