//! The stacked task energy of seed 000 Eq 5.7–5.11: the N motion tasks stacked as
//! `J ∈ R^{L×n}`, `E = X − X*`, gains `K_P`, `K_D`; a left inverse `J†` of J (Eq 5.9, J tall
//! with full column rank: a posture task and the contacts make it so), `Λ = J†ᵀ M J†`
//! (Eq 5.10), `S = ½ Eᵀ Λ K_P E` and `Ṡ = Ėᵀ Λ K_P E + ½ Eᵀ Λ̇ K_P E` (Eq 5.11), with Λ̇ by a
//! finite difference over one control step.
//!
//! Eq 5.9 takes `J† = (JᵀJ)⁻¹Jᵀ`; the power balance (Eq 5.12–5.16) uses only `J†J = I`, so it
//! holds for any left inverse, and this type takes rows with weights: `J†_W = (JᵀWJ)⁻¹JᵀW`
//! (all weights 1: Eq 5.9's). With W the tasks' weights in the QP, the acceleration stage 1
//! assumes, `J†_W (βγ b)`, is the QP's unconstrained optimum, so the passivity row binds only
//! where the QP's constraints move the solution away from it, which is what the row is for
//! (seed 000 L6360–L6385). With Eq 5.9's J† the stage-1 acceleration is the unweighted least
//! squares of the task rows, which the weighted QP does not solve, and the row binds at most
//! ticks (measured on TALOS' 1 m walk: the feet's normal forces swung ±70 N in the first
//! weight shift while the row bound; see RESULTS.md for both walks).
//!
//! Λ is never formed: each product is `xᵀΛy = (J†x)ᵀ M (J†y)`, and `Ẋᵀ Λ y = vᵀ M J† y`
//! (Eq 5.14, `JᵀΛ = M J†`); `J†x` is two triangular solves with the Cholesky factor of
//! `JᵀWJ`. It also gives the task part of the controllable power (Eq 5.18)
//! `B_σ,tasks = ẊᵀΛK_DĖ + Ẋ*ᵀΛK_PE − ½EᵀΛ̇K_PE − ẊᵀΛ(Ẍ* − J̇v)`.

use crate::error::{ControlError, Result};
use crate::tasks::TaskErrorTerms;
use nalgebra::{DMatrix, DVector};

/// The energy figures of one tick (unscaled by the valves).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct TaskPower {
    /// S (J).
    pub storage: f64,
    /// Ṡ (W).
    pub storage_rate: f64,
    /// ½ Eᵀ Λ̇ K_P E (W): zero on a tick whose stack differs from the previous one.
    pub lambda_dot_term: f64,
    /// B_σ without the force tasks' power (W).
    pub b_sigma_tasks: f64,
}

/// What one tick's stack was, to tell whether last tick's Λ is comparable.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
struct Shape {
    rows: usize,
    signature: u64,
}

/// The weighted stacked Jacobian `W^½ J`, row by row, with each row's non-zero columns, and
/// the Cholesky factor of `JᵀWJ`.
#[derive(Clone, Debug, Default)]
struct Factored {
    /// Row r of `W^½ J` at `rows[r n..(r + 1) n]`.
    rows: Vec<f64>,
    /// Row r's non-zero columns: `nonzeros[starts[r]..starts[r + 1]]`.
    nonzeros: Vec<usize>,
    starts: Vec<usize>,
    sqrt_w: Vec<f64>,
    /// Lower Cholesky factor of `JᵀWJ`, row-major (`chol[i n + j]`, j ≤ i).
    chol: Vec<f64>,
}

impl Factored {
    fn with_capacity(n: usize, rows: usize) -> Self {
        let mut starts = Vec::with_capacity(rows + 1);
        starts.push(0);
        Self {
            rows: Vec::with_capacity(rows * n),
            nonzeros: Vec::with_capacity(rows * n),
            starts,
            sqrt_w: Vec::with_capacity(rows),
            chol: vec![0.0; n * n],
        }
    }

    fn clear(&mut self) {
        self.rows.clear();
        self.nonzeros.clear();
        self.starts.truncate(1);
        self.sqrt_w.clear();
    }

    /// `chol ← cholesky(JᵀWJ)`; Err when a pivot falls below [`RANK_TOLERANCE`] × the
    /// largest diagonal (J without full column rank).
    fn factor(&mut self, n: usize) -> std::result::Result<(), ()> {
        let g = &mut self.chol;
        g.fill(0.0);
        for r in 0..self.sqrt_w.len() {
            let row = &self.rows[r * n..(r + 1) * n];
            let nz = &self.nonzeros[self.starts[r]..self.starts[r + 1]];
            if nz.len() == n {
                // A dense row (CoM, momentum): contiguous updates.
                for i in 0..n {
                    let xi = row[i];
                    for (gij, rj) in g[i * n..i * n + i + 1].iter_mut().zip(row) {
                        *gij += xi * rj;
                    }
                }
                continue;
            }
            for (a, &i) in nz.iter().enumerate() {
                let xi = row[i];
                let gi = &mut g[i * n..i * n + i + 1];
                for &j in &nz[..=a] {
                    gi[j] += xi * row[j];
                }
            }
        }
        let scale = (0..n).map(|k| g[k * n + k]).fold(0.0, f64::max);
        if !(scale > 0.0 && scale.is_finite()) {
            return Err(());
        }
        for k in 0..n {
            let (upper, lower) = g.split_at_mut((k + 1) * n);
            let rk = &mut upper[k * n..(k + 1) * n];
            let d = rk[k] - dot(&rk[..k], &rk[..k]);
            // A NaN pivot fails too.
            if d.is_nan() || d <= RANK_TOLERANCE * scale {
                return Err(());
            }
            let d = d.sqrt();
            rk[k] = d;
            let inv = 1.0 / d;
            let rk = &rk[..k];
            for ri in lower.chunks_exact_mut(n) {
                ri[k] = (ri[k] - dot(&ri[..k], rk)) * inv;
            }
        }
        Ok(())
    }

    /// `x ← (JᵀWJ)⁻¹ x` (n entries): `L y = x`, then `Lᵀ x = y` column by column of Lᵀ
    /// (rows of L).
    fn solve_gram_in_place(&self, n: usize, x: &mut [f64]) {
        let l = &self.chol;
        for i in 0..n {
            x[i] = (x[i] - dot(&l[i * n..i * n + i], &x[..i])) / l[i * n + i];
        }
        for i in (0..n).rev() {
            let xi = x[i] / l[i * n + i];
            x[i] = xi;
            for (o, lij) in x[..i].iter_mut().zip(&l[i * n..i * n + i]) {
                *o -= lij * xi;
            }
        }
    }

    /// `out = J†_W x = (JᵀWJ)⁻¹ JᵀW x` (x: one entry per row).
    fn solve(&self, n: usize, x: &[f64], out: &mut [f64]) {
        out.fill(0.0);
        for (r, (&xr, &sw)) in x.iter().zip(&self.sqrt_w).enumerate() {
            let s = xr * sw;
            if s == 0.0 {
                continue;
            }
            let row = &self.rows[r * n..(r + 1) * n];
            for &c in &self.nonzeros[self.starts[r]..self.starts[r + 1]] {
                out[c] += s * row[c];
            }
        }
        self.solve_gram_in_place(n, out);
    }

    /// `out = J†_Wᵀ y = W J (JᵀWJ)⁻¹ y` (one entry per row), `w` a scratch of n.
    fn solve_transposed(&self, n: usize, y: &[f64], w: &mut [f64], out: &mut Vec<f64>) {
        w.copy_from_slice(&y[..n]);
        self.solve_gram_in_place(n, w);
        out.clear();
        for (r, &sw) in self.sqrt_w.iter().enumerate() {
            let row = &self.rows[r * n..(r + 1) * n];
            let nz = &self.nonzeros[self.starts[r]..self.starts[r + 1]];
            out.push(sw * nz.iter().map(|&c| row[c] * w[c]).sum::<f64>());
        }
    }
}

/// `a · b` over the shorter length, four partial sums (independent chains).
fn dot(a: &[f64], b: &[f64]) -> f64 {
    let n = a.len().min(b.len());
    let (a, b) = (&a[..n], &b[..n]);
    let mut acc = [0.0; 4];
    let (ca, cb) = (a.chunks_exact(4), b.chunks_exact(4));
    let (ra, rb) = (ca.remainder(), cb.remainder());
    for (x, y) in ca.zip(cb) {
        for k in 0..4 {
            acc[k] += x[k] * y[k];
        }
    }
    let tail: f64 = ra.iter().zip(rb).map(|(x, y)| x * y).sum();
    (acc[0] + acc[1]) + (acc[2] + acc[3]) + tail
}

/// `out = M u` for a symmetric, fully stored M (column-major).
fn mat_vec(m: &DMatrix<f64>, u: &[f64], out: &mut [f64]) {
    let n = m.nrows();
    out.fill(0.0);
    for (col, &uc) in m.as_slice().chunks_exact(n).zip(u) {
        for (o, mc) in out.iter_mut().zip(col) {
            *o += mc * uc;
        }
    }
}

/// Buffers for the stacked energy; they grow only when a larger stack appears.
#[derive(Clone, Debug)]
pub struct StackedTaskEnergy {
    nv: usize,
    now: Factored,
    prev: Factored,
    prev_m: DMatrix<f64>,
    prev_shape: Option<Shape>,
    e: Vec<f64>,
    e_dot: Vec<f64>,
    kp_e: Vec<f64>,
    kd_e_dot: Vec<f64>,
    ref_vel: Vec<f64>,
    acc: Vec<f64>,
    /// Solutions and products of n entries.
    u: [Vec<f64>; 4],
    w: Vec<f64>,
    /// A vector of one entry per row.
    z: Vec<f64>,
}

/// Relative pivot below which `JᵀWJ` counts as singular.
const RANK_TOLERANCE: f64 = 1e-12;

impl StackedTaskEnergy {
    /// Buffers for `nv` velocities and up to `rows` task rows (more grow them).
    pub fn new(nv: usize, rows: usize) -> Self {
        let z = |k: usize| Vec::with_capacity(k);
        Self {
            nv,
            now: Factored::with_capacity(nv, rows),
            prev: Factored::with_capacity(nv, rows),
            prev_m: DMatrix::zeros(nv, nv),
            prev_shape: None,
            e: z(rows),
            e_dot: z(rows),
            kp_e: z(rows),
            kd_e_dot: z(rows),
            ref_vel: z(rows),
            acc: z(rows),
            u: std::array::from_fn(|_| vec![0.0; nv]),
            w: vec![0.0; nv],
            z: Vec::with_capacity(rows),
        }
    }

    /// Starts a new stack (call before the tick's `push`es).
    pub fn clear(&mut self) {
        self.now.clear();
        for v in [
            &mut self.e,
            &mut self.e_dot,
            &mut self.kp_e,
            &mut self.kd_e_dot,
            &mut self.ref_vel,
            &mut self.acc,
        ] {
            v.clear();
        }
    }

    /// Forgets the previous tick (after a tick that did not compute, so that Λ̇ is never
    /// taken over more than one step).
    pub fn forget(&mut self) {
        self.prev_shape = None;
    }

    /// Stacked rows so far (L).
    pub fn rows(&self) -> usize {
        self.now.sqrt_w.len()
    }

    /// Appends the first `n_rows` rows of a task of weight `weight` (≥ 0): its Jacobian rows
    /// `a` (n_rows × nv at least) and its error terms.
    pub fn push(&mut self, a: &DMatrix<f64>, n_rows: usize, weight: f64, terms: &TaskErrorTerms) {
        self.push_jacobian(a, n_rows, weight);
        self.push_terms(n_rows, terms);
    }

    /// The first half of [`Self::push`]: the Jacobian rows (then call `push_terms`).
    pub fn push_jacobian(&mut self, a: &DMatrix<f64>, n_rows: usize, weight: f64) {
        let sw = weight.max(0.0).sqrt();
        let f = &mut self.now;
        for r in 0..n_rows {
            let base = f.rows.len();
            for c in 0..self.nv {
                let x = sw * a[(r, c)];
                f.rows.push(x);
                if x != 0.0 {
                    f.nonzeros.push(c);
                }
            }
            debug_assert_eq!(f.rows.len(), base + self.nv);
            f.starts.push(f.nonzeros.len());
            f.sqrt_w.push(sw);
        }
    }

    /// The second half of [`Self::push`]: the error terms of the rows `push_jacobian` added.
    pub fn push_terms(&mut self, n_rows: usize, terms: &TaskErrorTerms) {
        for r in 0..n_rows {
            self.e.push(terms.e[r]);
            self.e_dot.push(terms.e_dot[r]);
            self.kp_e.push(terms.kp[r] * terms.e[r]);
            self.kd_e_dot.push(terms.kd[r] * terms.e_dot[r]);
            self.ref_vel.push(terms.ref_vel[r]);
            self.acc.push(terms.ref_acc_minus_drift[r]);
        }
    }

    /// The energy figures at mass matrix `m` (symmetric, full) and velocity `v`, over the
    /// rows pushed since `clear`; `signature` names the stack's structure (Λ̇ is taken only
    /// between ticks of the same structure) and `dt` is the control period.
    pub fn compute(
        &mut self,
        m: &DMatrix<f64>,
        v: &DVector<f64>,
        signature: u64,
        dt: f64,
    ) -> Result<TaskPower> {
        let (n, l) = (self.nv, self.rows());
        if l < n || self.e.len() != l {
            self.forget();
            return Err(rank_error(l, n));
        }
        if m.nrows() != n || m.ncols() != n || v.len() != n {
            self.forget();
            return Err(ControlError::Config {
                name: "energy tank".into(),
                reason: format!(
                    "M is {}×{} and v has {} entries for {n} velocities",
                    m.nrows(),
                    m.ncols(),
                    v.len()
                ),
            });
        }
        if self.now.factor(n).is_err() {
            self.forget();
            return Err(rank_error(l, n));
        }
        let [u0, u1, mu1, u3] = &mut self.u;
        let (w, z) = (&mut self.w, &mut self.z);
        // Λ K_P E = J†ᵀ M J† K_P E: then EᵀΛK_PE, Ẋ*ᵀΛK_PE and ĖᵀΛK_PE are dot products.
        self.now.solve(n, &self.kp_e, u1);
        mat_vec(m, u1, mu1);
        self.now.solve_transposed(n, mu1, w, z);
        let e_lambda_kp_e = dot(&self.e, z);
        let ref_vel_term = dot(&self.ref_vel, z);
        let e_dot_term = dot(&self.e_dot, z);
        // Λ̇ term: the same form with last tick's J† and M.
        let shape = Shape { rows: l, signature };
        let lambda_dot_term = if self.prev_shape == Some(shape) {
            self.prev.solve(n, &self.kp_e, u3);
            mat_vec(&self.prev_m, u3, u0);
            self.prev.solve_transposed(n, u0, w, z);
            0.5 * (e_lambda_kp_e - dot(&self.e, z)) / dt
        } else {
            0.0
        };
        // Ẋᵀ Λ (K_D Ė − (Ẍ* − J̇v)) = (J†ᵀ M v)ᵀ (K_D Ė − Ẍ* + J̇v).
        for (a, kd) in self.acc.iter_mut().zip(&self.kd_e_dot) {
            *a = kd - *a;
        }
        mat_vec(m, v.as_slice(), u3);
        self.now.solve_transposed(n, u3, w, z);
        let velocity_term = dot(&self.acc, z);
        std::mem::swap(&mut self.now, &mut self.prev);
        self.prev_m.copy_from(m);
        self.prev_shape = Some(shape);
        Ok(TaskPower {
            storage: 0.5 * e_lambda_kp_e,
            storage_rate: e_dot_term + lambda_dot_term,
            lambda_dot_term,
            b_sigma_tasks: velocity_term + ref_vel_term - lambda_dot_term,
        })
    }
}

fn rank_error(l: usize, n: usize) -> ControlError {
    ControlError::Config {
        name: "energy tank".into(),
        reason: format!(
            "the stacked task Jacobian ({l} rows, {n} columns) has not full column rank, so \
             Λ = J†ᵀ M J† is undefined: the stack needs a posture task and the contacts \
             (seed 000 §5, L ≥ n)"
        ),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A deterministic pseudo-random matrix.
    fn matrix(rows: usize, cols: usize, seed: u64) -> DMatrix<f64> {
        let mut s = seed;
        DMatrix::from_fn(rows, cols, |_, _| {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((s >> 11) as f64 / (1u64 << 53) as f64) - 0.5
        })
    }

    #[test]
    fn the_quadratic_forms_match_lambda_formed_explicitly() {
        let (l, n) = (9, 5);
        let j = matrix(l, n, 1);
        let b = matrix(n, n, 2);
        let m = &b * b.transpose() + DMatrix::identity(n, n);
        let v = DVector::from_column_slice(matrix(n, 1, 3).as_slice());
        let mut terms = TaskErrorTerms::new(l);
        for (k, x) in matrix(l, 6, 4).row_iter().enumerate() {
            terms.set(
                k,
                [x[0], x[1], 1.0 + x[2].abs(), 1.0 + x[3].abs(), x[4], x[5]],
            );
        }
        let mut st = StackedTaskEnergy::new(n, 4);
        st.clear();
        st.push(
            &j.rows(0, 4).into_owned(),
            4,
            2.0,
            &TaskErrorTerms {
                e: terms.e.rows(0, 4).into_owned(),
                e_dot: terms.e_dot.rows(0, 4).into_owned(),
                kp: terms.kp.rows(0, 4).into_owned(),
                kd: terms.kd.rows(0, 4).into_owned(),
                ref_vel: terms.ref_vel.rows(0, 4).into_owned(),
                ref_acc_minus_drift: terms.ref_acc_minus_drift.rows(0, 4).into_owned(),
            },
        );
        let rest = TaskErrorTerms {
            e: terms.e.rows(4, 5).into_owned(),
            e_dot: terms.e_dot.rows(4, 5).into_owned(),
            kp: terms.kp.rows(4, 5).into_owned(),
            kd: terms.kd.rows(4, 5).into_owned(),
            ref_vel: terms.ref_vel.rows(4, 5).into_owned(),
            ref_acc_minus_drift: terms.ref_acc_minus_drift.rows(4, 5).into_owned(),
        };
        st.push(&j.rows(4, 5).into_owned(), 5, 0.5, &rest);
        let p = st.compute(&m, &v, 7, 1e-3).expect("full rank");
        // Explicit: J† = (JᵀWJ)⁻¹JᵀW, Λ = J†ᵀ M J†.
        let w = DMatrix::from_diagonal(&DVector::from_fn(l, |r, _| if r < 4 { 2.0 } else { 0.5 }));
        let jp = (j.transpose() * &w * &j).try_inverse().expect("invertible") * j.transpose() * &w;
        assert!(
            (&jp * &j - DMatrix::identity(n, n)).norm() < 1e-10,
            "a left inverse"
        );
        let lambda = jp.transpose() * &m * &jp;
        let kpe = terms.kp.component_mul(&terms.e);
        let kde = terms.kd.component_mul(&terms.e_dot);
        let xdot = &j * &v;
        let s = 0.5 * terms.e.dot(&(&lambda * &kpe));
        let s_dot = terms.e_dot.dot(&(&lambda * &kpe));
        let b = xdot.dot(&(&lambda * &kde)) + terms.ref_vel.dot(&(&lambda * &kpe))
            - xdot.dot(&(&lambda * &terms.ref_acc_minus_drift));
        let close = |a: f64, b: f64| (a - b).abs() <= 1e-10 * (1.0 + b.abs());
        assert!(close(p.storage, s), "{} {s}", p.storage);
        assert!(close(p.storage_rate, s_dot), "{} {s_dot}", p.storage_rate);
        assert!(close(p.b_sigma_tasks, b), "{} {b}", p.b_sigma_tasks);
        assert_eq!(p.lambda_dot_term, 0.0, "no previous tick");
        // Eq 5.14: Jᵀ Λ = M J†.
        let lhs = j.transpose() * &lambda;
        let rhs = &m * &jp;
        assert!((lhs - rhs).norm() < 1e-10 * m.norm());
    }

    #[test]
    fn lambda_dot_is_the_finite_difference_over_one_step() {
        let (l, n, dt) = (7, 4, 1e-3);
        let j0 = matrix(l, n, 10);
        let j1 = &j0 + matrix(l, n, 11) * 1e-3;
        let m0 = DMatrix::identity(n, n) * 2.0;
        let m1 = &m0 + DMatrix::identity(n, n) * 1e-3;
        let mut terms = TaskErrorTerms::new(l);
        for k in 0..l {
            terms.set(k, [0.1 * k as f64 - 0.3, 0.0, 2.0, 0.0, 0.0, 0.0]);
        }
        let v = DVector::zeros(n);
        let mut st = StackedTaskEnergy::new(n, l);
        let mut storage = [0.0; 2];
        for (k, (j, m)) in [(&j0, &m0), (&j1, &m1)].into_iter().enumerate() {
            st.clear();
            st.push(j, l, 1.0, &terms);
            let p = st.compute(m, &v, 1, dt).expect("full rank");
            storage[k] = p.storage;
            if k == 1 {
                // E fixed: ½EᵀΛ̇K_PE = (S₁ − S₀)/dt.
                let fd = (storage[1] - storage[0]) / dt;
                assert!((p.lambda_dot_term - fd).abs() < 1e-9 * (1.0 + fd.abs()));
            }
        }
    }

    #[test]
    fn a_stack_without_full_column_rank_is_refused() {
        let mut st = StackedTaskEnergy::new(4, 3);
        st.clear();
        st.push(&matrix(3, 4, 5), 3, 1.0, &TaskErrorTerms::new(3));
        assert!(st
            .compute(&DMatrix::identity(4, 4), &DVector::zeros(4), 0, 1e-3)
            .is_err());
        let mut a = matrix(6, 4, 6);
        a.column_mut(3).fill(0.0);
        st.clear();
        st.push(&a, 6, 1.0, &TaskErrorTerms::new(6));
        assert!(st
            .compute(&DMatrix::identity(4, 4), &DVector::zeros(4), 0, 1e-3)
            .is_err());
    }
}
