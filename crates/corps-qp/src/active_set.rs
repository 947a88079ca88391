//! The Goldfarb–Idnani dual active-set solver with warm start.
//!
//! Notation (Goldfarb & Idnani 1983): `H = L Lᵀ`, `J = L⁻ᵀ Q` with `Q` orthogonal, and the
//! active constraint normals `N` (one column per active constraint, written as `nᵀ x ≥ β`
//! for inequalities and `nᵀ x = β` for equalities) satisfy `Jᵀ N = [R; 0]` with `R` upper
//! triangular. The first `q` columns of `J` (`J₁`) span the active normals in the `H⁻¹`
//! metric, the others (`J₂`) their complement, so `z = J₂ J₂ᵀ n` is the primal step
//! direction and `r = R⁻¹ J₁ᵀ n` the dual one. Adding a constraint rotates columns of `J₂`
//! (Givens) to fold `J₂ᵀ n` into one entry; removing one restores `R` to triangular form by
//! rotations that are applied to `J₁` too.
//!
//! All buffers are allocated by [`ActiveSetSolver::new`] / [`ActiveSetSolver::resize`]; a
//! solve only writes into them.

use crate::cholesky;
use crate::givens::Givens;
use crate::linalg::{axpy, dot, norm2};
use crate::problem::{ActiveConstraint, QpProblem, Settings, Solution};
use crate::status::{QpError, QpStatus};

/// An active constraint in the factorization: its id (equalities `0..n_eq`, inequality rows
/// `n_eq..n_eq+n_in`, variable bounds after that) and side (`+1` lower / equality, `−1` upper).
#[derive(Debug, Clone, Copy, PartialEq)]
struct Entry {
    id: usize,
    sign: f64,
}

/// Dense Goldfarb–Idnani dual active-set QP solver (see the crate docs for the method, the
/// warm start and the caches). Create it once per problem size; `solve` does not allocate.
#[derive(Debug, Clone)]
pub struct ActiveSetSolver {
    n: usize,
    ne: usize,
    ni: usize,
    /// Leading dimension of `J` and length of the padded vectors: `n` rounded up to 4.
    ld: usize,
    settings: Settings,
    fma: bool,
    status: QpStatus,
    // Copies of the problem (matrices column-major as given; g padded with zeros to `ld`),
    // bounds normalized to ±∞.
    h: Vec<f64>,
    g: Vec<f64>,
    a: Vec<f64>,
    b: Vec<f64>,
    c: Vec<f64>,
    lo: Vec<f64>,
    hi: Vec<f64>,
    lx: Vec<f64>,
    ux: Vec<f64>,
    // Factorizations. `jlen[j]` bounds the nonzero prefix of column j of J (J₀ is upper
    // triangular and each rotation only mixes two columns), rounded up to a multiple of 4.
    chol: Vec<f64>,
    j0: Vec<f64>,
    jm: Vec<f64>,
    jlen: Vec<usize>,
    rm: Vec<f64>,
    j_eq: Vec<f64>,
    jlen_eq: Vec<usize>,
    r_eq: Vec<f64>,
    q_eq: usize,
    eq_dep: Vec<bool>,
    j0_ok: bool,
    // Range-space equality phase: `dt` is Dᵀ with D = L⁻¹ Aᵀ (`n_eq × n`, column i = row i
    // of D), `dt0` the same before the QR rotations, `rots` the rotations of that QR.
    dt: Vec<f64>,
    dt0: Vec<f64>,
    rots: Vec<(usize, Givens)>,
    lam: Vec<f64>,
    // Active set and multipliers (internal sign: H x + g = Σ u_k n_k, u_k ≥ 0 for inequalities).
    active: Vec<Entry>,
    um: Vec<f64>,
    prev: Vec<Entry>,
    is_active: Vec<bool>,
    // Work vectors.
    x: Vec<f64>,
    row: Vec<f64>,
    cx: Vec<f64>,
    d: Vec<f64>,
    z: Vec<f64>,
    rv: Vec<f64>,
    v: Vec<f64>,
    w: Vec<f64>,
    // Cache validity.
    h_ok: bool,
    eq_ok: bool,
    final_ok: bool,
    sol: Solution,
}

impl ActiveSetSolver {
    /// A solver for problems with `n` variables, `n_eq` equality rows and `n_in` inequality
    /// rows, with default [`Settings`]. Allocates every buffer a solve needs.
    pub fn new(n: usize, n_eq: usize, n_in: usize) -> Self {
        Self::with_settings(n, n_eq, n_in, Settings::default())
    }

    /// Like [`ActiveSetSolver::new`] with explicit settings.
    pub fn with_settings(n: usize, n_eq: usize, n_in: usize, settings: Settings) -> Self {
        let mut s = Self {
            n: 0,
            ne: 0,
            ni: 0,
            ld: 0,
            settings,
            fma: detect_fma(),
            status: QpStatus::NotSolved,
            h: Vec::new(),
            g: Vec::new(),
            a: Vec::new(),
            b: Vec::new(),
            c: Vec::new(),
            lo: Vec::new(),
            hi: Vec::new(),
            lx: Vec::new(),
            ux: Vec::new(),
            chol: Vec::new(),
            j0: Vec::new(),
            jm: Vec::new(),
            jlen: Vec::new(),
            rm: Vec::new(),
            j_eq: Vec::new(),
            jlen_eq: Vec::new(),
            r_eq: Vec::new(),
            q_eq: 0,
            eq_dep: Vec::new(),
            j0_ok: false,
            dt: Vec::new(),
            dt0: Vec::new(),
            rots: Vec::new(),
            lam: Vec::new(),
            active: Vec::new(),
            um: Vec::new(),
            prev: Vec::new(),
            is_active: Vec::new(),
            x: Vec::new(),
            row: Vec::new(),
            cx: Vec::new(),
            d: Vec::new(),
            z: Vec::new(),
            rv: Vec::new(),
            v: Vec::new(),
            w: Vec::new(),
            h_ok: false,
            eq_ok: false,
            final_ok: false,
            sol: Solution::new(0, 0, 0),
        };
        s.resize(n, n_eq, n_in);
        s
    }

    /// Change the problem size. Reallocates the buffers and forgets the warm start.
    pub fn resize(&mut self, n: usize, n_eq: usize, n_in: usize) {
        let ld = n.div_ceil(4) * 4;
        self.n = n;
        self.ne = n_eq;
        self.ni = n_in;
        self.ld = ld;
        let zeros = |len: usize| vec![0.0; len];
        self.h = zeros(n * n);
        self.g = zeros(ld);
        self.a = zeros(n * n_eq);
        self.b = zeros(n_eq);
        self.c = zeros(n * n_in);
        self.lo = zeros(n_in);
        self.hi = zeros(n_in);
        self.lx = zeros(n);
        self.ux = zeros(n);
        self.chol = zeros(n * n);
        self.j0 = zeros(ld * n);
        self.jm = zeros(ld * n);
        self.jlen = vec![0; n];
        self.rm = zeros(n * n);
        self.j_eq = zeros(ld * n);
        self.jlen_eq = vec![0; n];
        self.r_eq = zeros(n * n);
        self.q_eq = 0;
        self.eq_dep = vec![false; n_eq];
        self.dt = zeros(n_eq * n);
        self.dt0 = zeros(n_eq * n);
        self.rots = Vec::with_capacity(n * n_eq);
        self.lam = zeros(n_eq);
        self.active = Vec::with_capacity(n);
        self.um = zeros(n);
        self.prev = Vec::with_capacity(n);
        self.is_active = vec![false; n_eq + n_in + n];
        self.x = zeros(ld);
        self.row = zeros(ld);
        self.cx = zeros(n_in);
        self.d = zeros(n);
        self.z = zeros(ld);
        self.rv = zeros(n);
        self.v = zeros(ld);
        self.w = zeros(ld);
        self.sol = Solution::new(n, n_eq, n_in);
        self.reset();
    }

    /// Forget the warm start (previous active set and cached factorizations).
    pub fn reset(&mut self) {
        self.h_ok = false;
        self.j0_ok = false;
        self.eq_ok = false;
        self.final_ok = false;
        self.prev.clear();
        self.status = QpStatus::NotSolved;
    }

    /// `(n, n_eq, n_in)` this solver is set up for.
    pub fn dims(&self) -> (usize, usize, usize) {
        (self.n, self.ne, self.ni)
    }

    /// Current settings.
    pub fn settings(&self) -> &Settings {
        &self.settings
    }

    /// Mutable settings (take effect at the next solve).
    pub fn settings_mut(&mut self) -> &mut Settings {
        &mut self.settings
    }

    /// Status of the last solve.
    pub fn status(&self) -> QpStatus {
        self.status
    }

    /// The last optimal solution (meaningful when [`ActiveSetSolver::status`] is `Optimal`).
    pub fn solution(&self) -> &Solution {
        &self.sol
    }

    /// Whether the AVX2 + FMA kernels are used on this CPU (checked once at construction).
    pub fn uses_fma(&self) -> bool {
        self.fma
    }

    /// Use the portable kernels even on a CPU with AVX2 + FMA (for testing and measurement).
    pub fn force_portable_kernels(&mut self) {
        self.fma = false;
    }

    /// Solve `problem`. Returns the solution, or why there is none; never panics and never
    /// allocates. With `Settings::warm_start`, the previous active set and every factorization
    /// whose input is bit-identical to the previous call's (`H`; `H` and `A`; `H`, `A` and `C`)
    /// are reused.
    pub fn solve(&mut self, problem: &QpProblem) -> Result<&Solution, QpError> {
        let res = self.dispatch(problem);
        match res {
            Ok(()) => {
                self.status = QpStatus::Optimal;
                Ok(&self.sol)
            }
            Err(e) => {
                self.status = e.status();
                // The final factorization and active set are not an optimal state: start the
                // next solve from the equality factorization and no previous active set.
                self.final_ok = false;
                self.prev.clear();
                Err(e)
            }
        }
    }

    fn dispatch(&mut self, p: &QpProblem) -> Result<(), QpError> {
        #[cfg(target_arch = "x86_64")]
        if self.fma {
            // SAFETY: `self.fma` is true only if the CPU reports AVX2 and FMA (`detect_fma`).
            return unsafe { self.solve_fma(p) };
        }
        self.solve_impl::<false>(p)
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma")]
    unsafe fn solve_fma(&mut self, p: &QpProblem) -> Result<(), QpError> {
        self.solve_impl::<true>(p)
    }

    #[inline(always)]
    fn solve_impl<const F: bool>(&mut self, p: &QpProblem) -> Result<(), QpError> {
        self.check_dims(p)?;
        let (h_changed, a_changed, c_changed) = match self.load(p) {
            Ok(v) => v,
            Err(e) => {
                // The copies may be partial: trust no cache.
                self.h_ok = false;
                self.eq_ok = false;
                self.final_ok = false;
                return Err(e);
            }
        };
        let n = self.n;
        let warm = self.settings.warm_start;
        if !warm {
            self.h_ok = false;
            self.eq_ok = false;
            self.final_ok = false;
            self.prev.clear();
        }
        if h_changed || !self.h_ok {
            self.eq_ok = false;
            self.final_ok = false;
            self.chol.copy_from_slice(&self.h);
            if let Err(column) = cholesky::factor_in_place::<F>(&mut self.chol, n) {
                self.h_ok = false;
                return Err(QpError::NotPositiveDefinite { column });
            }
            self.h_ok = true;
            self.j0_ok = false;
        }
        if a_changed {
            self.eq_ok = false;
            self.final_ok = false;
        }
        if c_changed {
            self.final_ok = false;
        }
        // A previous final active set may use a bound side that is now infinite.
        if self.final_ok && self.active.iter().any(|e| !self.side_finite(*e)) {
            self.final_ok = false;
        }

        if !self.final_ok {
            if self.eq_ok {
                self.jm.copy_from_slice(&self.j_eq);
                self.jlen.copy_from_slice(&self.jlen_eq);
                self.rm.copy_from_slice(&self.r_eq);
                self.active.truncate(self.q_eq);
            } else {
                self.equality_qr::<F>();
                let try_fast = !self.prev.iter().any(|e| e.id >= self.ne);
                if try_fast && self.equality_fast_path::<F>()? {
                    self.prev.clear();
                    self.prev.extend_from_slice(&self.active);
                    self.final_ok = false;
                    return Ok(());
                }
                self.build_j::<F>();
                if warm {
                    self.j_eq.copy_from_slice(&self.jm);
                    self.jlen_eq.copy_from_slice(&self.jlen);
                    self.r_eq.copy_from_slice(&self.rm);
                    self.eq_ok = true;
                }
            }
            // Re-add the previous active inequalities, in order, skipping dependent ones.
            for idx in 0..self.prev.len() {
                let e = self.prev[idx];
                if e.id < self.ne || !self.side_finite(e) {
                    continue;
                }
                self.compute_d::<F>(e);
                let q = self.active.len();
                if !self.is_dependent::<F>(q) {
                    self.add_to_factorization::<F>(e);
                }
            }
        }
        self.is_active.fill(false);
        for e in &self.active {
            self.is_active[e.id] = true;
        }

        self.recompute::<F>();
        // Redundant equality rows must be consistent with the others.
        for k in 0..self.ne {
            if self.eq_dep[k] {
                let res = self.eval::<F>(Entry { id: k, sign: 1.0 }) - self.b[k];
                if res.abs() > self.settings.primal_tol * (1.0 + self.b[k].abs()) {
                    return Err(QpError::Infeasible);
                }
            }
        }
        // Dual feasibility of the warm start: drop inequalities with negative multipliers.
        loop {
            let mut kmin = usize::MAX;
            let mut umin = 0.0;
            for k in self.q_eq..self.active.len() {
                if self.um[k] < umin {
                    umin = self.um[k];
                    kmin = k;
                }
            }
            if kmin == usize::MAX {
                break;
            }
            self.is_active[self.active[kmin].id] = false;
            self.drop_at::<F>(kmin);
            self.recompute::<F>();
        }

        let iterations = self.main_loop::<F>()?;
        if iterations > 0 {
            self.recompute::<F>();
        }
        self.write_solution::<F>(iterations);
        if warm {
            self.prev.clear();
            self.prev.extend_from_slice(&self.active);
            self.final_ok = self.eq_ok;
        }
        Ok(())
    }

    /// Equality phase, range-space form: `D = L⁻¹ Aᵀ` (row by row, stored as `Dᵀ`), then the
    /// Givens QR `D = Q [R; 0]` that skips linearly dependent rows of A. Fills `R` (in `rm`),
    /// the equality part of the active set, `eq_dep`, and records the rotations so that
    /// `J = L⁻ᵀ Q` can be built later only if an inequality needs it.
    #[inline(always)]
    fn equality_qr<const F: bool>(&mut self) {
        let (n, m) = (self.n, self.ne);
        // Column k of D solves L d = (row k of A): column-oriented forward substitution in
        // `z`, then scattered into Dᵀ.
        for k in 0..m {
            for i in 0..n {
                self.z[i] = self.a[k + i * m];
            }
            for i in 0..n {
                let di = self.z[i] / self.chol[i + i * n];
                self.z[i] = di;
                if di != 0.0 {
                    axpy::<F>(
                        -di,
                        &self.chol[i * n + i + 1..(i + 1) * n],
                        &mut self.z[i + 1..n],
                    );
                }
                self.dt[k + i * m] = di;
            }
        }
        self.dt0.copy_from_slice(&self.dt);
        self.rots.clear();
        self.active.clear();
        let tol2 = self.settings.dependence_tol * self.settings.dependence_tol;
        for k in 0..m {
            let q = self.active.len();
            let (mut all, mut tail) = (0.0, 0.0);
            for i in 0..n {
                let v = self.dt[k + i * m];
                all += v * v;
                if i >= q {
                    tail += v * v;
                }
            }
            self.eq_dep[k] = all == 0.0 || tail <= tol2 * all;
            if self.eq_dep[k] {
                continue;
            }
            for jj in (q + 1..n).rev() {
                if let Some((gr, _)) =
                    Givens::zeroing(self.dt[k + (jj - 1) * m], self.dt[k + jj * m])
                {
                    let (left, right) = self.dt.split_at_mut(jj * m);
                    gr.apply::<F>(&mut left[(jj - 1) * m..], &mut right[..m]);
                    self.dt[k + jj * m] = 0.0;
                    self.rots.push((jj - 1, gr));
                }
            }
            for i in 0..=q {
                self.rm[i + q * n] = self.dt[k + i * m];
            }
            self.um[q] = 0.0;
            self.active.push(Entry { id: k, sign: 1.0 });
        }
        self.q_eq = self.active.len();
    }

    /// Solve the equality-constrained problem from the range-space factorization
    /// (`λ = (DᵀD)⁻¹ (b + Dᵀ L⁻¹ g)` through `R`, `x = L⁻ᵀ (D λ − L⁻¹ g)`). If `x` satisfies
    /// every inequality it is the solution: write it and return `true`. Otherwise return
    /// `false` and leave the rest to the active-set iterations.
    #[inline(always)]
    fn equality_fast_path<const F: bool>(&mut self) -> Result<bool, QpError> {
        let (n, m, ni) = (self.n, self.ne, self.ni);
        // c = L⁻¹ g (in z), column-oriented forward substitution.
        self.z[..n].copy_from_slice(&self.g[..n]);
        for i in 0..n {
            let ci = self.z[i] / self.chol[i + i * n];
            self.z[i] = ci;
            if ci != 0.0 {
                axpy::<F>(
                    -ci,
                    &self.chol[i * n + i + 1..(i + 1) * n],
                    &mut self.z[i + 1..n],
                );
            }
        }
        // rhs = b + Dᵀ c on the independent rows, in factorization order (in w).
        self.lam.fill(0.0);
        for i in 0..n {
            axpy::<F>(self.z[i], &self.dt0[i * m..(i + 1) * m], &mut self.lam);
        }
        let q = self.q_eq;
        for k in 0..q {
            let id = self.active[k].id;
            self.w[k] = self.b[id] + self.lam[id];
        }
        // λ = R⁻¹ R⁻ᵀ rhs.
        for k in 0..q {
            let s = dot::<F>(&self.rm[k * n..k * n + k], &self.w[..k]);
            self.w[k] = (self.w[k] - s) / self.rm[k + k * n];
        }
        back_substitute::<F>(&self.rm, n, q, &mut self.w);
        self.lam.fill(0.0);
        for k in 0..q {
            self.lam[self.active[k].id] = self.w[k];
            self.um[k] = self.w[k];
        }
        // y = D λ − c (in v), then x = L⁻ᵀ y.
        for i in 0..n {
            self.v[i] = dot::<F>(&self.dt0[i * m..(i + 1) * m], &self.lam) - self.z[i];
        }
        for i in (0..n).rev() {
            let s = dot::<F>(&self.chol[i * n + i + 1..(i + 1) * n], &self.x[i + 1..n]);
            self.x[i] = (self.v[i] - s) / self.chol[i + i * n];
        }
        for k in 0..m {
            if self.eq_dep[k] {
                let res = self.eval::<F>(Entry { id: k, sign: 1.0 }) - self.b[k];
                if res.abs() > self.settings.primal_tol * (1.0 + self.b[k].abs()) {
                    return Err(QpError::Infeasible);
                }
            }
        }
        let tol = self.settings.primal_tol;
        if self.x[..n]
            .iter()
            .zip(&self.lx)
            .zip(&self.ux)
            .any(|((x, l), u)| l - x > tol || x - u > tol)
        {
            return Ok(false);
        }
        self.cx.fill(0.0);
        for k in 0..n {
            axpy::<F>(self.x[k], &self.c[k * ni..(k + 1) * ni], &mut self.cx);
        }
        if self
            .cx
            .iter()
            .zip(&self.lo)
            .zip(&self.hi)
            .any(|((s, l), u)| l - s > tol || s - u > tol)
        {
            return Ok(false);
        }
        // Optimal. xᵀ H x = ‖Lᵀ x‖² = ‖y‖².
        self.write_solution::<F>(0);
        self.sol.objective = 0.5 * norm2::<F>(&self.v[..n]) + dot::<F>(&self.g[..n], &self.x[..n]);
        Ok(true)
    }

    /// Build `J = L⁻ᵀ Q` for the equality factorization: `J₀ = L⁻ᵀ` (computed once per H)
    /// and the recorded QR rotations replayed on its columns.
    #[inline(always)]
    fn build_j<const F: bool>(&mut self) {
        let (n, ld) = (self.n, self.ld);
        if !self.j0_ok {
            cholesky::inverse_transpose::<F>(&self.chol, n, &mut self.j0, ld, &mut self.v);
            self.v.fill(0.0);
            self.j0_ok = true;
        }
        self.jm.copy_from_slice(&self.j0);
        for (j, len) in self.jlen.iter_mut().enumerate() {
            *len = ((j + 1).div_ceil(4) * 4).min(ld);
        }
        for idx in 0..self.rots.len() {
            let (k, gr) = self.rots[idx];
            self.rotate_j::<F>(k, gr);
        }
    }

    fn check_dims(&self, p: &QpProblem) -> Result<(), QpError> {
        let (n, ne, ni) = (self.n, self.ne, self.ni);
        type Check = (&'static str, (usize, usize), (usize, usize));
        let checks: [Check; 9] = [
            ("H", p.h.shape(), (n, n)),
            ("g", p.g.shape(), (n, 1)),
            ("A", p.a.shape(), (ne, n)),
            ("b", p.b.shape(), (ne, 1)),
            ("C", p.c.shape(), (ni, n)),
            ("l", p.l.shape(), (ni, 1)),
            ("u", p.u.shape(), (ni, 1)),
            ("lx", p.lx.shape(), (n, 1)),
            ("ux", p.ux.shape(), (n, 1)),
        ];
        for (what, got, expected) in checks {
            if got != expected {
                return Err(QpError::DimensionMismatch {
                    what,
                    expected_rows: expected.0,
                    expected_cols: expected.1,
                    got_rows: got.0,
                    got_cols: got.1,
                });
            }
        }
        Ok(())
    }

    /// Copy the problem into the internal buffers, checking finiteness; returns whether `H`,
    /// `A` and `C` changed (bitwise) since the previous call.
    fn load(&mut self, p: &QpProblem) -> Result<(bool, bool, bool), QpError> {
        let n = self.n;
        let h_changed = copy_checked("H", p.h.as_slice(), &mut self.h)?;
        copy_checked("g", p.g.as_slice(), &mut self.g[..n])?;
        copy_checked("b", p.b.as_slice(), &mut self.b)?;
        let a_changed = copy_checked("A", p.a.as_slice(), &mut self.a)?;
        let c_changed = copy_checked("C", p.c.as_slice(), &mut self.c)?;
        let inf = self.settings.infinity;
        load_bounds(
            ("l", "u"),
            p.l.as_slice(),
            p.u.as_slice(),
            inf,
            &mut self.lo,
            &mut self.hi,
        )?;
        load_bounds(
            ("lx", "ux"),
            p.lx.as_slice(),
            p.ux.as_slice(),
            inf,
            &mut self.lx,
            &mut self.ux,
        )?;
        Ok((h_changed, a_changed, c_changed))
    }

    #[inline(always)]
    fn side_finite(&self, e: Entry) -> bool {
        let (ne, ni) = (self.ne, self.ni);
        if e.id < ne {
            true
        } else if e.id < ne + ni {
            let i = e.id - ne;
            if e.sign > 0.0 {
                self.lo[i].is_finite()
            } else {
                self.hi[i].is_finite()
            }
        } else {
            let i = e.id - ne - ni;
            if e.sign > 0.0 {
                self.lx[i].is_finite()
            } else {
                self.ux[i].is_finite()
            }
        }
    }

    /// Right-hand side β of the constraint `nᵀ x ≥ β` (or `= β`).
    #[inline(always)]
    fn rhs(&self, e: Entry) -> f64 {
        let (ne, ni) = (self.ne, self.ni);
        if e.id < ne {
            self.b[e.id]
        } else if e.id < ne + ni {
            let i = e.id - ne;
            if e.sign > 0.0 {
                self.lo[i]
            } else {
                -self.hi[i]
            }
        } else {
            let i = e.id - ne - ni;
            if e.sign > 0.0 {
                self.lx[i]
            } else {
                -self.ux[i]
            }
        }
    }

    /// `nᵀ x` for the constraint's normal `n` (strided dot over the row).
    #[inline(always)]
    fn eval<const F: bool>(&self, e: Entry) -> f64 {
        let (n, ne, ni) = (self.n, self.ne, self.ni);
        if e.id < ne + ni {
            let (m, rows, i) = if e.id < ne {
                (&self.a, ne, e.id)
            } else {
                (&self.c, ni, e.id - ne)
            };
            let mut s = 0.0;
            for k in 0..n {
                s += m[i + k * rows] * self.x[k];
            }
            e.sign * s
        } else {
            e.sign * self.x[e.id - ne - ni]
        }
    }

    /// `d = Jᵀ n` for the constraint's normal `n`.
    #[inline(always)]
    fn compute_d<const F: bool>(&mut self, e: Entry) {
        let (n, ne, ni, ld) = (self.n, self.ne, self.ni, self.ld);
        if e.id < ne + ni {
            let (m, rows, i) = if e.id < ne {
                (&self.a, ne, e.id)
            } else {
                (&self.c, ni, e.id - ne)
            };
            for k in 0..n {
                self.row[k] = e.sign * m[i + k * rows];
            }
            for j in 0..n {
                let len = self.jlen[j];
                self.d[j] = dot::<F>(&self.jm[j * ld..j * ld + len], &self.row[..len]);
            }
        } else {
            let i = e.id - ne - ni;
            for j in 0..n {
                self.d[j] = if i < self.jlen[j] {
                    e.sign * self.jm[i + j * ld]
                } else {
                    0.0
                };
            }
        }
    }

    /// Whether the normal whose `d = Jᵀ n` is in `self.d` depends linearly on the `q` active
    /// normals: `‖d[q..]‖ ≤ tol · ‖d‖`.
    #[inline(always)]
    fn is_dependent<const F: bool>(&self, q: usize) -> bool {
        let all = norm2::<F>(&self.d[..self.n]);
        let tail = norm2::<F>(&self.d[q..self.n]);
        let tol = self.settings.dependence_tol;
        all == 0.0 || tail <= tol * tol * all
    }

    /// Rotate columns `k` and `k + 1` of J over their nonzero prefix.
    #[inline(always)]
    fn rotate_j<const F: bool>(&mut self, k: usize, gr: Givens) {
        let ld = self.ld;
        let len = self.jlen[k].max(self.jlen[k + 1]);
        self.jlen[k] = len;
        self.jlen[k + 1] = len;
        let (left, right) = self.jm.split_at_mut((k + 1) * ld);
        gr.apply::<F>(&mut left[k * ld..k * ld + len], &mut right[..len]);
    }

    /// Append the constraint whose `d = Jᵀ n` is in `self.d` to the factorization: rotate
    /// `d[q..]` into `d[q]` (same rotations on the columns of `J`) and store `d[..=q]` as the
    /// new column of `R`.
    #[inline(always)]
    fn add_to_factorization<const F: bool>(&mut self, e: Entry) {
        let n = self.n;
        let q = self.active.len();
        for jj in (q + 1..n).rev() {
            if let Some((gr, h)) = Givens::zeroing(self.d[jj - 1], self.d[jj]) {
                self.d[jj - 1] = h;
                self.d[jj] = 0.0;
                self.rotate_j::<F>(jj - 1, gr);
            }
        }
        self.rm[q * n..q * n + q + 1].copy_from_slice(&self.d[..=q]);
        self.um[q] = 0.0;
        self.active.push(e);
    }

    /// Remove the active constraint at position `k` and restore `R` to triangular form.
    #[inline(always)]
    fn drop_at<const F: bool>(&mut self, k: usize) {
        let n = self.n;
        let q = self.active.len();
        self.active.remove(k);
        for p in k..q - 1 {
            self.um[p] = self.um[p + 1];
            self.rm.copy_within((p + 1) * n..(p + 1) * n + p + 2, p * n);
        }
        let q = q - 1;
        for p in k..q {
            let (a, b) = (self.rm[p + p * n], self.rm[p + 1 + p * n]);
            if let Some((gr, h)) = Givens::zeroing(a, b) {
                self.rm[p + p * n] = h;
                self.rm[p + 1 + p * n] = 0.0;
                for col in p + 1..q {
                    let (x, y) = gr.apply_pair(self.rm[p + col * n], self.rm[p + 1 + col * n]);
                    self.rm[p + col * n] = x;
                    self.rm[p + 1 + col * n] = y;
                }
                self.rotate_j::<F>(p, gr);
            }
        }
    }

    /// Primal and dual solution of the equality-constrained problem on the active set, from
    /// the factorization: `x = J w` with `w = [R⁻ᵀ β; −J₂ᵀ g]`, `u = R⁻¹ (R⁻ᵀ β + J₁ᵀ g)`.
    /// Leaves `w` in `self.w` (then `xᵀ H x = ‖w‖²`).
    #[inline(always)]
    fn recompute<const F: bool>(&mut self) {
        let (n, ld) = (self.n, self.ld);
        let q = self.active.len();
        for j in 0..n {
            let len = self.jlen[j];
            self.v[j] = dot::<F>(&self.jm[j * ld..j * ld + len], &self.g[..len]);
        }
        for k in 0..q {
            let beta = self.rhs(self.active[k]);
            let s = dot::<F>(&self.rm[k * n..k * n + k], &self.w[..k]);
            self.w[k] = (beta - s) / self.rm[k + k * n];
        }
        for k in q..n {
            self.w[k] = -self.v[k];
        }
        self.x.fill(0.0);
        for k in 0..n {
            let len = self.jlen[k];
            axpy::<F>(
                self.w[k],
                &self.jm[k * ld..k * ld + len],
                &mut self.x[..len],
            );
        }
        for k in 0..q {
            self.rv[k] = self.w[k] + self.v[k];
        }
        back_substitute::<F>(&self.rm, n, q, &mut self.rv);
        self.um[..q].copy_from_slice(&self.rv[..q]);
    }

    /// The Goldfarb–Idnani iterations from the current dual-feasible state. Returns the
    /// number of active-set changes.
    #[inline(always)]
    fn main_loop<const F: bool>(&mut self) -> Result<usize, QpError> {
        let (n, ne, ni, ld) = (self.n, self.ne, self.ni, self.ld);
        let tol = self.settings.primal_tol;
        let max_iter = self.settings.max_iter;
        let mut iter = 0usize;
        loop {
            // Step 1: the most violated inactive constraint.
            self.cx.fill(0.0);
            for k in 0..n {
                axpy::<F>(self.x[k], &self.c[k * ni..(k + 1) * ni], &mut self.cx);
            }
            let mut best = Entry {
                id: usize::MAX,
                sign: 0.0,
            };
            let mut best_v = tol;
            for i in 0..ni {
                if self.is_active[ne + i] {
                    continue;
                }
                let s = self.cx[i];
                if self.lo[i] - s > best_v {
                    best_v = self.lo[i] - s;
                    best = Entry {
                        id: ne + i,
                        sign: 1.0,
                    };
                } else if s - self.hi[i] > best_v {
                    best_v = s - self.hi[i];
                    best = Entry {
                        id: ne + i,
                        sign: -1.0,
                    };
                }
            }
            for i in 0..n {
                if self.is_active[ne + ni + i] {
                    continue;
                }
                let s = self.x[i];
                if self.lx[i] - s > best_v {
                    best_v = self.lx[i] - s;
                    best = Entry {
                        id: ne + ni + i,
                        sign: 1.0,
                    };
                } else if s - self.ux[i] > best_v {
                    best_v = s - self.ux[i];
                    best = Entry {
                        id: ne + ni + i,
                        sign: -1.0,
                    };
                }
            }
            if best.id == usize::MAX {
                return Ok(iter);
            }
            let p = best;
            let mut u_p = 0.0;
            // Step 2: move until p is satisfied, dropping blocking constraints on the way.
            loop {
                iter += 1;
                if iter > max_iter {
                    return Err(QpError::IterationLimit { max_iter });
                }
                self.compute_d::<F>(p);
                let q = self.active.len();
                self.rv[..q].copy_from_slice(&self.d[..q]);
                back_substitute::<F>(&self.rm, n, q, &mut self.rv);
                let mut t1 = f64::INFINITY;
                let mut kdrop = usize::MAX;
                for k in self.q_eq..q {
                    if self.rv[k] > 0.0 {
                        let t = self.um[k] / self.rv[k];
                        if t < t1 {
                            t1 = t;
                            kdrop = k;
                        }
                    }
                }
                let dependent = self.is_dependent::<F>(q);
                let t2 = if dependent {
                    f64::INFINITY
                } else {
                    let tail = norm2::<F>(&self.d[q..n]);
                    let sp = self.eval::<F>(p) - self.rhs(p);
                    (-sp / tail).max(0.0)
                };
                let t = t1.min(t2);
                if t == f64::INFINITY {
                    return Err(QpError::Infeasible);
                }
                for k in 0..q {
                    self.um[k] -= t * self.rv[k];
                }
                u_p += t;
                if !dependent {
                    // z = J₂ d₂; x += t z.
                    self.z.fill(0.0);
                    for j in q..n {
                        let len = self.jlen[j];
                        axpy::<F>(
                            self.d[j],
                            &self.jm[j * ld..j * ld + len],
                            &mut self.z[..len],
                        );
                    }
                    axpy::<F>(t, &self.z, &mut self.x);
                    if t2 <= t1 {
                        self.add_to_factorization::<F>(p);
                        self.um[q] = u_p;
                        self.is_active[p.id] = true;
                        break;
                    }
                }
                self.is_active[self.active[kdrop].id] = false;
                self.drop_at::<F>(kdrop);
            }
        }
    }

    #[inline(always)]
    fn write_solution<const F: bool>(&mut self, iterations: usize) {
        let (n, ne, ni) = (self.n, self.ne, self.ni);
        let sol = &mut self.sol;
        sol.x.as_mut_slice().copy_from_slice(&self.x[..n]);
        sol.y_eq.fill(0.0);
        sol.z_in.fill(0.0);
        sol.z_box.fill(0.0);
        sol.active_set.clear();
        for (k, e) in self.active.iter().enumerate() {
            let u = self.um[k];
            if e.id < ne {
                sol.y_eq[e.id] = -u;
                sol.active_set.push(ActiveConstraint::Equality(e.id));
            } else if e.id < ne + ni {
                let i = e.id - ne;
                sol.z_in[i] = -e.sign * u;
                sol.active_set.push(if e.sign > 0.0 {
                    ActiveConstraint::Lower(i)
                } else {
                    ActiveConstraint::Upper(i)
                });
            } else {
                let i = e.id - ne - ni;
                sol.z_box[i] = -e.sign * u;
                sol.active_set.push(if e.sign > 0.0 {
                    ActiveConstraint::LowerBound(i)
                } else {
                    ActiveConstraint::UpperBound(i)
                });
            }
        }
        // x = J w and Jᵀ H J = I, so xᵀ H x = ‖w‖² (w from the last `recompute`).
        sol.objective = 0.5 * norm2::<F>(&self.w[..n]) + dot::<F>(&self.g[..n], &self.x[..n]);
        sol.iterations = iterations;
    }
}

/// Solve `R y = rhs` in place for the leading `q × q` block of the column-major `R`
/// (leading dimension `n`), column-oriented.
#[inline(always)]
fn back_substitute<const F: bool>(r: &[f64], n: usize, q: usize, rhs: &mut [f64]) {
    for k in (0..q).rev() {
        let yk = rhs[k] / r[k + k * n];
        rhs[k] = yk;
        if yk != 0.0 {
            axpy::<F>(-yk, &r[k * n..k * n + k], &mut rhs[..k]);
        }
    }
}

/// Copy `src` into `dst` rejecting non-finite values; returns whether any bit changed.
/// Branch-free over the data so that it vectorizes.
fn copy_checked(what: &'static str, src: &[f64], dst: &mut [f64]) -> Result<bool, QpError> {
    const EXP: u64 = 0x7ff0_0000_0000_0000;
    let mut diff = 0u64;
    let mut bad = 0u64;
    for (s, d) in src.iter().zip(dst.iter_mut()) {
        let sb = s.to_bits();
        diff |= sb ^ d.to_bits();
        bad |= u64::from((sb & EXP) == EXP);
        *d = *s;
    }
    if bad != 0 {
        let index = src.iter().position(|v| !v.is_finite()).unwrap_or(0);
        return Err(QpError::NonFinite { what, index });
    }
    Ok(diff != 0)
}

/// Copy two-sided bounds, mapping `|v| ≥ inf` to ±∞; NaN is an error, and an empty interval
/// (`l > u`, `l = +∞` or `u = −∞`) makes the problem infeasible.
fn load_bounds(
    what: (&'static str, &'static str),
    l: &[f64],
    u: &[f64],
    inf: f64,
    lo: &mut [f64],
    hi: &mut [f64],
) -> Result<(), QpError> {
    for (index, (((&a, &b), lo), hi)) in l
        .iter()
        .zip(u)
        .zip(lo.iter_mut())
        .zip(hi.iter_mut())
        .enumerate()
    {
        if a.is_nan() {
            return Err(QpError::NonFinite {
                what: what.0,
                index,
            });
        }
        if b.is_nan() {
            return Err(QpError::NonFinite {
                what: what.1,
                index,
            });
        }
        let a = if a <= -inf {
            f64::NEG_INFINITY
        } else if a >= inf {
            f64::INFINITY
        } else {
            a
        };
        let b = if b >= inf {
            f64::INFINITY
        } else if b <= -inf {
            f64::NEG_INFINITY
        } else {
            b
        };
        if a > b || a == f64::INFINITY || b == f64::NEG_INFINITY {
            return Err(QpError::Infeasible);
        }
        *lo = a;
        *hi = b;
    }
    Ok(())
}

fn detect_fma() -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        std::arch::is_x86_feature_detected!("avx2") && std::arch::is_x86_feature_detected!("fma")
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        false
    }
}
