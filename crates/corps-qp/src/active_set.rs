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
use crate::linalg::{apply_reflectors4, dot, gemv, gemv_t, ger_sub, norm2};
use crate::polish::{self, PolishWork};
use crate::problem::{ActiveConstraint, QpProblem, Settings, Solution};
use crate::status::{QpError, QpStatus};

/// An active constraint in the factorization: its id (equalities `0..n_eq`, inequality rows
/// `n_eq..n_eq+n_in`, variable bounds after that) and side (`+1` lower / equality, `−1` upper).
#[derive(Debug, Clone, Copy, PartialEq)]
struct Entry {
    id: usize,
    sign: f64,
}

/// Proximal weight of [`ActiveSetSolver::solve_proximal`], relative to H's largest diagonal.
const PROX_SCALE: f64 = 1e-3;
/// Most proximal solves before the fallback gives up (and the proof stands).
const PROX_ITERS: usize = 50;
/// An accepted answer farther than this from the optimality conditions is solved once more
/// on its active set ([`ActiveSetSolver::tighten`]). At 1e-12 the hierarchical IK's levels
/// (regularized by 1e-9) were solved again at most ticks: the IK walk took 10 % longer for
/// differences of 1e-13.
const POLISH_ABOVE: f64 = 1e-9;
/// The fallback's answer must meet the original problem's optimality conditions to this
/// (relative to the terms' magnitudes), or the proof it was checking stands.
const PROX_ACCEPT: f64 = 1e-6;

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
    /// `L` row-major (rows of `L` contiguous), for the solves with many right-hand sides.
    lt: Vec<f64>,
    /// H's diagonal blocks (`block_start[j]..block_end[j]` holds j; `cholesky::diagonal_blocks`):
    /// L, L⁻ᵀ and L⁻¹ Aᵀ are computed block by block.
    block_start: Vec<usize>,
    block_end: Vec<usize>,
    j0: Vec<f64>,
    jm: Vec<f64>,
    jlen: Vec<usize>,
    rm: Vec<f64>,
    /// `1 / R_kk` for the active columns (kept in step with `rm`: divisions are slow and
    /// would sit on the dependency chain of every triangular solve).
    rinv: Vec<f64>,
    j_eq: Vec<f64>,
    jlen_eq: Vec<usize>,
    r_eq: Vec<f64>,
    q_eq: usize,
    /// Leading active entries that are never dropped: the equality phase's `q_eq` rows, or 0
    /// when the equalities are treated as two-sided rows (`eq_rows`).
    q_fixed: usize,
    /// Equality rows are handled as rows `b ≤ A x ≤ b` of the active-set iterations (either
    /// side can be added and dropped) instead of by the equality phase: the fallback of
    /// [`ActiveSetSolver::solve_equalities_as_rows`].
    eq_rows: bool,
    /// `A x` (`n_eq`), for the violation scan of the `eq_rows` mode.
    ax: Vec<f64>,
    /// Active-set changes of the current solve so far (both phases count against `max_iter`).
    iters: usize,
    eq_dep: Vec<bool>,
    j0_ok: bool,
    // Range-space equality phase: `dt` is Dᵀ with D = L⁻¹ Aᵀ (`n_eq × n`, column i = row i
    // of D), `dt0` the same before the QR, `hv`/`htau` the Householder reflectors of that QR
    // (reflector r acts on rows r..n; its vector is `hv[r n..r n + n − r]`, τ = 0: identity).
    dt: Vec<f64>,
    dt0: Vec<f64>,
    hv: Vec<f64>,
    htau: Vec<f64>,
    /// Scratch for four reflectors in WY form (`4 n`).
    wv: Vec<f64>,
    lam: Vec<f64>,
    // Active set and multipliers (internal sign: H x + g = Σ u_k n_k, u_k ≥ 0 for inequalities).
    active: Vec<Entry>,
    um: Vec<f64>,
    prev: Vec<Entry>,
    is_active: Vec<bool>,
    // Work vectors.
    x: Vec<f64>,
    /// The proximal fallback's copies of g and of H's diagonal, and its previous iterate.
    prox_g: Vec<f64>,
    prox_diag: Vec<f64>,
    prox_x: Vec<f64>,
    row: Vec<f64>,
    cx: Vec<f64>,
    d: Vec<f64>,
    z: Vec<f64>,
    rv: Vec<f64>,
    v: Vec<f64>,
    w: Vec<f64>,
    // Cache validity. `copies_ok`: the copies of H, A, C are complete and finite.
    copies_ok: bool,
    h_ok: bool,
    eq_ok: bool,
    final_ok: bool,
    sol: Solution,
    /// After `Infeasible`: constraints that together admit no point (see
    /// [`ActiveSetSolver::infeasibility_certificate`]); the copy kept across the fallback.
    certificate: Vec<ActiveConstraint>,
    certificate_kept: Vec<ActiveConstraint>,
    /// The optimality check's products: H x, Aᵀ y, Cᵀ z (n each), A x (n_eq), C x (n_in).
    kkt_work: Vec<f64>,
    /// The proximal fallback's last step: the original problem on its active set.
    polish: PolishWork,
    /// The last [`ActiveSetSolver::kkt_residual`] measured (of the solution held).
    residual: f64,
    /// The solution held is already the solve on its active set (the fallback's last step).
    polished: bool,
    /// The answer [`ActiveSetSolver::tighten`] tries to improve, and its multipliers.
    kept: Solution,
    um_kept: Vec<f64>,
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
            lt: Vec::new(),
            block_start: Vec::new(),
            block_end: Vec::new(),
            j0: Vec::new(),
            jm: Vec::new(),
            jlen: Vec::new(),
            rm: Vec::new(),
            rinv: Vec::new(),
            j_eq: Vec::new(),
            jlen_eq: Vec::new(),
            r_eq: Vec::new(),
            q_eq: 0,
            q_fixed: 0,
            eq_rows: false,
            ax: Vec::new(),
            iters: 0,
            eq_dep: Vec::new(),
            j0_ok: false,
            dt: Vec::new(),
            dt0: Vec::new(),
            hv: Vec::new(),
            htau: Vec::new(),
            wv: Vec::new(),
            lam: Vec::new(),
            active: Vec::new(),
            um: Vec::new(),
            prev: Vec::new(),
            is_active: Vec::new(),
            x: Vec::new(),
            prox_g: Vec::new(),
            prox_diag: Vec::new(),
            prox_x: Vec::new(),
            row: Vec::new(),
            cx: Vec::new(),
            d: Vec::new(),
            z: Vec::new(),
            rv: Vec::new(),
            v: Vec::new(),
            w: Vec::new(),
            copies_ok: false,
            h_ok: false,
            eq_ok: false,
            final_ok: false,
            sol: Solution::new(0, 0, 0),
            certificate: Vec::new(),
            certificate_kept: Vec::new(),
            kkt_work: Vec::new(),
            polish: PolishWork::default(),
            residual: f64::INFINITY,
            polished: false,
            kept: Solution::new(0, 0, 0),
            um_kept: Vec::new(),
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
        self.lt = zeros(n * n);
        self.block_start = vec![0; n];
        self.block_end = vec![n; n];
        self.j0 = zeros(ld * n);
        self.jm = zeros(ld * n);
        self.jlen = vec![0; n];
        self.rm = zeros(n * n);
        self.rinv = zeros(n);
        self.j_eq = zeros(ld * n);
        self.jlen_eq = vec![0; n];
        self.r_eq = zeros(n * n);
        self.q_eq = 0;
        self.q_fixed = 0;
        self.eq_rows = false;
        self.ax = zeros(n_eq);
        self.iters = 0;
        self.eq_dep = vec![false; n_eq];
        self.dt = zeros(n_eq * n);
        self.dt0 = zeros(n_eq * n);
        self.hv = zeros(n * n_eq);
        self.htau = zeros(n_eq);
        self.wv = zeros(4 * n);
        self.lam = zeros(n_eq);
        self.active = Vec::with_capacity(n);
        self.um = zeros(n);
        self.prev = Vec::with_capacity(n);
        self.is_active = vec![false; n_eq + n_in + n];
        self.x = zeros(ld);
        self.prox_g = zeros(n);
        self.prox_diag = zeros(n);
        self.prox_x = zeros(n);
        self.row = zeros(ld);
        self.cx = zeros(n_in);
        self.d = zeros(n);
        self.z = zeros(ld);
        self.rv = zeros(n);
        self.v = zeros(ld);
        self.w = zeros(ld);
        self.sol = Solution::new(n, n_eq, n_in);
        // A certificate holds at most the active set and the violated row.
        self.certificate = Vec::with_capacity(n + 2);
        self.certificate_kept = Vec::with_capacity(n + 2);
        self.kkt_work = zeros(3 * n + n_eq + n_in);
        self.polish.resize(n);
        self.kept = Solution::new(n, n_eq, n_in);
        self.um_kept = zeros(n);
        self.copies_ok = false;
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

    /// After a solve that ended [`QpError::Infeasible`]: the constraints that conflict, a set
    /// that alone admits no point (so every problem containing it is infeasible). It is the
    /// dual method's proof: the violated constraint and the active ones whose normals combine
    /// into its normal with multipliers that cannot move (an inequality side is listed as
    /// `Lower`/`Upper`, a two-sided row whose interval is empty as both), or a redundant
    /// equality row with the independent equalities it contradicts. Empty after any other
    /// outcome.
    pub fn infeasibility_certificate(&self) -> &[ActiveConstraint] {
        &self.certificate
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
        self.polished = false;
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
        let warm = self.settings.warm_start;
        if !warm {
            self.h_ok = false;
            self.eq_ok = false;
            self.final_ok = false;
            self.prev.clear();
        }
        if h_changed || !self.h_ok {
            self.factor_h::<F>()?;
        }
        if a_changed {
            self.eq_ok = false;
            self.final_ok = false;
        }
        if c_changed {
            self.final_ok = false;
        }
        // `load` left the certificate empty.
        let mut inaccurate = false;
        let first = match self.solve_both_ways::<F>() {
            // An answer that misses the optimality conditions (the dual method on an
            // ill-conditioned H can return one): solved again by the checked fallback.
            Ok(()) if !self.meets_kkt::<F>(PROX_ACCEPT) => {
                inaccurate = true;
                self.certificate.clear();
                Err(QpError::Infeasible)
            }
            r => r,
        };
        let result = match first {
            Err(QpError::Infeasible) => {
                self.certificate_kept.clone_from(&self.certificate);
                let result = self.solve_proximal::<F>();
                if result == Err(QpError::Infeasible) && self.certificate.is_empty() {
                    if inaccurate {
                        // No proof, and the first answer missed the optimality conditions.
                        return Err(QpError::Inaccurate);
                    }
                    // The fallback's answer was refused: the original proof stands.
                    self.certificate.clone_from(&self.certificate_kept);
                }
                result
            }
            r => r,
        };
        if result.is_ok() {
            self.tighten::<F>();
        }
        if result != Err(QpError::Infeasible) {
            self.certificate.clear();
        }
        result
    }

    /// An answer that meets the optimality conditions only to more than [`POLISH_ABOVE`]
    /// (an ill-conditioned H or a degenerate vertex) is solved once more on its own active set
    /// by the null-space method, and the more accurate of the two is kept. Answers already
    /// that accurate (every TSID problem: 1e-15) cost nothing more: the residual is the one
    /// the solve's acceptance measured.
    fn tighten<const F: bool>(&mut self) {
        let before = self.residual;
        if before <= POLISH_ABOVE || self.polished {
            return;
        }
        self.kept.copy_from(&self.sol);
        let (n, m) = (self.n, self.active.len());
        self.um_kept[..m].copy_from_slice(&self.um[..m]);
        // Signs held to the same accuracy: the answer kept must not trade a residual for a
        // multiplier of the wrong sign, which the residual does not measure.
        let polished =
            self.solve_on_last_active_set::<F>(POLISH_ABOVE) && self.kkt_residual::<F>() < before;
        if polished {
            self.sol.objective = self.original_objective();
        } else {
            self.sol.copy_from(&self.kept);
            self.x[..n].copy_from_slice(self.sol.x.as_slice());
            self.um[..m].copy_from_slice(&self.um_kept[..m]);
            self.residual = before;
        }
    }

    /// `½ xᵀ H x + gᵀ x` of the solution held, from the problem's own H and g (the answers of
    /// the fallbacks, whose solves saw a shifted H or g).
    fn original_objective(&self) -> f64 {
        let (n, x) = (self.n, self.sol.x.as_slice());
        let mut objective = 0.0;
        for j in 0..n {
            let hx: f64 = (0..n).map(|i| self.h[j * n + i] * x[i]).sum();
            objective += x[j] * (0.5 * hx + self.g[j]);
        }
        objective
    }

    /// Factors the copy of H (`chol`, `lt`, its diagonal blocks) and forgets what was built
    /// on the previous factor.
    #[inline(always)]
    fn factor_h<const F: bool>(&mut self) -> Result<(), QpError> {
        let n = self.n;
        self.eq_ok = false;
        self.final_ok = false;
        self.j0_ok = false;
        self.chol.copy_from_slice(&self.h);
        cholesky::diagonal_blocks(&self.h, n, &mut self.block_start, &mut self.block_end);
        let factored = cholesky::factor_in_place::<F>(
            &mut self.chol,
            n,
            &mut self.lt,
            &self.block_start,
            &self.block_end,
        );
        self.h_ok = factored.is_ok();
        factored.map_err(|column| QpError::NotPositiveDefinite { column })
    }

    /// Equality-first, then, on a proof of infeasibility, with the equalities as rows.
    #[inline(always)]
    fn solve_both_ways<const F: bool>(&mut self) -> Result<(), QpError> {
        self.iters = 0;
        self.eq_rows = false;
        match self.solve_equalities_first::<F>() {
            // The equality-first method proves infeasibility with a combination of active
            // normals whose equality coefficients have no sign condition. At a degenerate
            // vertex (more active constraints than variables, e.g. a hierarchy level whose
            // held rows and saturated bounds meet at one point) the equality rows are
            // consistent with the bounds only to rounding, and that rounding, amplified by the
            // conditioning of the vertex, is enough for a spurious proof. Solving again with
            // the equalities as two-sided rows, whose sides carry sign conditions like any
            // inequality, decides it with a proof that must hold for every row.
            Err(QpError::Infeasible) if self.ne > 0 => self.solve_equalities_as_rows::<F>(),
            r => r,
        }
    }

    /// The last word on infeasibility. Whether constraints can be met does not depend on H,
    /// but the dual method's proof degrades with cond(H) (H = BᵀB + 1e-9 I at a degenerate
    /// vertex: spurious proofs). So the problem is solved again by proximal point iterations,
    /// `x_{k+1} = argmin ½xᵀHx + gᵀx + ½ρ‖x − x_k‖²`, i.e. Hessian H + ρI (condition at most
    /// 1 + λ_max/ρ, factored once) and gradient g − ρx_k, each solve warm-started from the
    /// last: the iterates converge to the optimum of the original problem (Rockafellar 1976),
    /// in a few steps once the active set settles. A proof from these well-conditioned solves
    /// stands. ρ = [`PROX_SCALE`] · max Hᵢᵢ; at most [`PROX_ITERS`] solves, stopping when the
    /// step is below 1e-12 (relative). A converged answer that meets the original problem's
    /// optimality conditions to [`PROX_ACCEPT`] is returned with the last solve's multipliers
    /// (their KKT residual for the original problem is ρ‖x_{k+1} − x_k‖). Otherwise (the
    /// iterations creep along H's small eigenvalues without converging, or the converged
    /// answer misses the conditions) the original problem is solved on the active set the
    /// last solve ended with ([`ActiveSetSolver::solve_on_last_active_set`]), and that
    /// answer is returned if it meets the conditions with signed multipliers. Either way the
    /// objective is the original's. With neither, the solve ends `Infeasible`, as it would
    /// have without the fallback.
    fn solve_proximal<const F: bool>(&mut self) -> Result<(), QpError> {
        let n = self.n;
        let max_diag = (0..n).map(|i| self.h[i * n + i]).fold(0.0f64, f64::max);
        let rho = PROX_SCALE * max_diag.max(f64::MIN_POSITIVE);
        self.prox_g.copy_from_slice(&self.g[..n]);
        for i in 0..n {
            self.prox_diag[i] = self.h[i * n + i];
            self.h[i * n + i] += rho;
            self.prox_x[i] = 0.0;
        }
        self.prev.clear();
        let mut result = self.factor_h::<F>();
        let (mut steps, mut converged) = (0, false);
        while result.is_ok() && steps < PROX_ITERS {
            steps += 1;
            for i in 0..n {
                self.g[i] = self.prox_g[i] - rho * self.prox_x[i];
            }
            result = self.solve_both_ways::<F>();
            if result.is_err() {
                break;
            }
            let (mut step, mut size) = (0.0f64, 0.0f64);
            for i in 0..n {
                let x = self.sol.x[i];
                step = step.max((x - self.prox_x[i]).abs());
                size = size.max(x.abs());
                self.prox_x[i] = x;
            }
            if step <= 1e-12 * (1.0 + size) {
                converged = true;
                break;
            }
        }
        // The original problem back; its own factorization on the next solve.
        for i in 0..n {
            self.h[i * n + i] = self.prox_diag[i];
        }
        self.g[..n].copy_from_slice(&self.prox_g);
        self.h_ok = false;
        self.eq_ok = false;
        self.final_ok = false;
        self.prev.clear();
        if result.is_ok() {
            let accepted = (converged && self.meets_kkt::<F>(PROX_ACCEPT)) || {
                self.polished = self.solve_on_last_active_set::<F>(PROX_ACCEPT);
                self.polished
            };
            if !accepted {
                // No better answer than the proof the fallback was called to check.
                self.certificate.clear();
                return Err(QpError::Infeasible);
            }
            self.sol.objective = self.original_objective();
        }
        result
    }

    /// The original problem's optimum on the active set the last solve ended with, by the
    /// null-space method ([`crate::polish`]): the proximal iterations find the active set in a
    /// few steps but then creep along H's small eigenvalues. Accepted when the inequalities'
    /// multipliers have their sign to `sign_tol` (how negative `u ‖n‖` may be, relative to the
    /// gradient) and the answer meets the optimality conditions to [`PROX_ACCEPT`]; the
    /// solution then holds it (its objective is left to the caller).
    fn solve_on_last_active_set<const F: bool>(&mut self, sign_tol: f64) -> bool {
        let (n, ne, ni, m) = (self.n, self.ne, self.ni, self.active.len());
        if m > n {
            return false;
        }
        for (k, &e) in self.active.iter().enumerate() {
            let col = &mut self.polish.normals[k * n..(k + 1) * n];
            if e.id < ne + ni {
                let (mat, rows, i) = if e.id < ne {
                    (&self.a, ne, e.id)
                } else {
                    (&self.c, ni, e.id - ne)
                };
                for (j, v) in col.iter_mut().enumerate() {
                    *v = e.sign * mat[i + j * rows];
                }
            } else {
                col.fill(0.0);
                col[e.id - ne - ni] = e.sign;
            }
            self.polish.beta[k] = self.rhs(e);
        }
        let (x, u) = (&mut self.x[..n], &mut self.um[..m]);
        if !polish::solve_on_active_set(&self.h, &self.g[..n], n, m, &mut self.polish, x, u) {
            return false;
        }
        // A multiplier's sign is judged by the force it puts in the gradient (u ‖n‖) on the
        // scale of the gradient it balances (H x and g), not on the other multipliers'.
        let x = &self.x[..n];
        let scale = (0..n).fold(1.0f64, |s, i| {
            let hx: f64 = (0..n).map(|k| self.h[k * n + i] * x[k]).sum();
            s.max(hx.abs()).max(self.g[i].abs())
        });
        let signed = self
            .active
            .iter()
            .zip(&self.um[..m])
            .zip(&self.polish.norms[..m])
            .all(|((e, u), norm)| e.id < ne || u * norm >= -sign_tol * scale);
        if !signed {
            return false;
        }
        self.write_solution::<F>(self.sol.iterations);
        self.meets_kkt::<F>(PROX_ACCEPT)
    }

    /// Whether the solution meets the original problem's optimality conditions to `tol`
    /// ([`ActiveSetSolver::kkt_residual`]).
    fn meets_kkt<const F: bool>(&mut self, tol: f64) -> bool {
        self.kkt_residual::<F>() <= tol
    }

    /// How far the solution is from the original problem's optimality conditions, relative
    /// to the magnitude of the terms: stationarity `Hx + g + Aᵀy + Cᵀz + z_x`, the active
    /// sides' multiplier signs, and the primal residuals of every row and bound (the largest).
    /// Allocation-free, O(n (n + m)).
    fn kkt_residual<const F: bool>(&mut self) -> f64 {
        let (n, ne, ni) = (self.n, self.ne, self.ni);
        let x = self.sol.x.as_slice();
        // Stationarity terms H x, Aᵀ y, Cᵀ z (columns of the column-major copies).
        let (hx, rest) = self.kkt_work.split_at_mut(n);
        let (aty, rest) = rest.split_at_mut(n);
        let (ctz, rest) = rest.split_at_mut(n);
        let (ax, cx) = rest.split_at_mut(ne);
        hx.fill(0.0);
        gemv::<F>(1.0, &self.h, n, x, hx);
        if ne > 0 {
            gemv_t::<F>(&self.a, ne, self.sol.y_eq.as_slice(), aty, |_| ne);
            ax.fill(0.0);
            gemv::<F>(1.0, &self.a, ne, x, ax);
        } else {
            aty.fill(0.0);
        }
        if ni > 0 {
            gemv_t::<F>(&self.c, ni, self.sol.z_in.as_slice(), ctz, |_| ni);
            cx[..ni].fill(0.0);
            gemv::<F>(1.0, &self.c, ni, x, &mut cx[..ni]);
        } else {
            ctz.fill(0.0);
        }
        let (mut worst_dual, mut scale_dual) = (0.0f64, 1.0f64);
        for j in 0..n {
            let terms = [hx[j], aty[j], ctz[j], self.sol.z_box[j], self.g[j]];
            worst_dual = worst_dual.max(terms.iter().sum::<f64>().abs());
            scale_dual = terms.iter().fold(scale_dual, |m, t| m.max(1.0 + t.abs()));
        }
        let (mut worst_primal, mut scale_primal) = (0.0f64, 1.0f64);
        for (ax, b) in ax.iter().zip(&self.b) {
            worst_primal = worst_primal.max((ax - b).abs());
            scale_primal = scale_primal.max(1.0 + ax.abs());
        }
        for ((cx, lo), hi) in cx[..ni].iter().zip(&self.lo).zip(&self.hi) {
            worst_primal = worst_primal.max(lo - cx).max(cx - hi);
            scale_primal = scale_primal.max(1.0 + cx.abs());
        }
        for ((x, lx), ux) in x.iter().zip(&self.lx).zip(&self.ux) {
            worst_primal = worst_primal.max(lx - x).max(x - ux);
        }
        // Dual feasibility: an active side's multiplier must push the right way (z ≤ 0 at a
        // lower side, ≥ 0 at an upper one); a wrong sign counts by the force it puts in the
        // gradient, |z| ‖n‖. Rows' norms are computed only for the (rare) wrong signs.
        let mut worst_sign = 0.0f64;
        for c in &self.sol.active_set {
            let (z, row) = match *c {
                ActiveConstraint::Lower(i) => (self.sol.z_in[i], Some(i)),
                ActiveConstraint::Upper(i) => (-self.sol.z_in[i], Some(i)),
                ActiveConstraint::LowerBound(i) => (self.sol.z_box[i], None),
                ActiveConstraint::UpperBound(i) => (-self.sol.z_box[i], None),
                ActiveConstraint::Equality(_) => continue,
            };
            if z > 0.0 {
                let norm = row.map_or(1.0, |i| {
                    (0..n)
                        .map(|k| self.c[i + k * ni].powi(2))
                        .sum::<f64>()
                        .sqrt()
                });
                worst_sign = worst_sign.max(z * norm);
            }
        }
        self.residual = (worst_dual.max(worst_sign) / scale_dual).max(worst_primal / scale_primal);
        self.residual
    }

    /// The method of the crate docs: equality phase (range-space QR, fast path), warm start
    /// from the previous active set, Goldfarb–Idnani iterations on the inequalities.
    #[inline(always)]
    fn solve_equalities_first<const F: bool>(&mut self) -> Result<(), QpError> {
        let warm = self.settings.warm_start;
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
                self.refresh_rinv(0);
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
        self.q_fixed = self.q_eq;
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
                    self.certify_equality(k);
                    return Err(QpError::Infeasible);
                }
            }
        }
        // Dual feasibility of the warm start: drop inequalities with negative multipliers.
        loop {
            let mut kmin = usize::MAX;
            let mut umin = 0.0;
            for k in self.q_fixed..self.active.len() {
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

    /// Fallback of [`Self::solve_equalities_first`] when it reports infeasibility: the same
    /// Goldfarb–Idnani iterations from the unconstrained minimum `−H⁻¹ g` (`J = L⁻ᵀ`, no
    /// active constraint), each equality row being the inequality pair `b ≤ aᵀ x ≤ b`. Either
    /// side is added when violated and dropped when its multiplier would change sign, so an
    /// infeasibility proof needs the right sign on every row's coefficient. Linearly dependent
    /// rows need no special case: a dependent row is exchanged or proves infeasibility like
    /// any other constraint. Slower than the equality phase (the iterations add the
    /// equalities one by one), so only a fallback; the final factorization is not kept for
    /// the next warm start, the active bounds and rows are.
    #[inline(always)]
    fn solve_equalities_as_rows<const F: bool>(&mut self) -> Result<(), QpError> {
        self.eq_rows = true;
        self.final_ok = false;
        self.init_j0::<F>();
        self.active.clear();
        self.q_fixed = 0;
        self.is_active.fill(false);
        self.recompute::<F>();
        let iterations = self.main_loop::<F>()?;
        self.recompute::<F>();
        self.write_solution::<F>(iterations);
        if self.settings.warm_start {
            self.prev.clear();
            self.prev.extend_from_slice(&self.active);
        }
        Ok(())
    }

    /// `J = L⁻ᵀ` (computed once per H) with its triangular nonzero pattern.
    #[inline(always)]
    fn init_j0<const F: bool>(&mut self) {
        let (n, ld) = (self.n, self.ld);
        if !self.j0_ok {
            cholesky::inverse_transpose::<F>(&self.lt, n, &mut self.j0, ld, &self.block_start);
            self.j0_ok = true;
        }
        self.jm.copy_from_slice(&self.j0);
        for (j, len) in self.jlen.iter_mut().enumerate() {
            *len = ((j + 1).div_ceil(4) * 4).min(ld);
        }
    }

    /// Equality phase, range-space form: `D = L⁻¹ Aᵀ` (row by row, stored as `Dᵀ`), then the
    /// Householder QR `D = Q [R; 0]` that skips linearly dependent rows of A. Fills `R` (in `rm`),
    /// the equality part of the active set, `eq_dep`, and keeps the reflectors so that
    /// `J = L⁻ᵀ Q` can be built later only if an inequality needs it.
    #[inline(always)]
    fn equality_qr<const F: bool>(&mut self) {
        let (n, m) = (self.n, self.ne);
        // Row i of D (column i of Dᵀ, contiguous) is (column i of A − Σ_{j<i} L_ij D_j) / L_ii:
        // forward substitution for all m right-hand sides at once, one register-blocked
        // matrix–vector product per row over the rows j of i's block of L.
        for i in 0..n {
            let b0 = self.block_start[i];
            let (done, rest) = self.dt.split_at_mut(i * m);
            let row = &mut rest[..m];
            row.copy_from_slice(&self.a[i * m..(i + 1) * m]);
            if i > b0 {
                gemv::<F>(
                    -1.0,
                    &done[b0 * m..],
                    m,
                    &self.lt[i * n + b0..i * n + i],
                    row,
                );
            }
            let inv = 1.0 / self.lt[i * n + i];
            for v in row.iter_mut() {
                *v *= inv;
            }
        }
        self.dt0.copy_from_slice(&self.dt);
        self.active.clear();
        let tol2 = self.settings.dependence_tol * self.settings.dependence_tol;
        for k in 0..m {
            let q = self.active.len();
            let (mut head, mut tail) = (0.0, 0.0);
            for i in 0..q {
                let v = self.dt[k + i * m];
                head += v * v;
            }
            let v = &mut self.hv[q * n..(q + 1) * n - q];
            for (i, vi) in v.iter_mut().enumerate() {
                let x = self.dt[k + (q + i) * m];
                *vi = x;
                tail += x * x;
            }
            let all = head + tail;
            self.eq_dep[k] = all == 0.0 || tail <= tol2 * all;
            if self.eq_dep[k] {
                continue;
            }
            // Householder reflector I − τ v vᵀ mapping D[q.., k] to β e₁ (one square root per
            // column, no chain of dependent rotations), applied to the columns k+1..m of D.
            let alpha = v[0];
            let sigma = tail - alpha * alpha;
            let beta;
            if sigma <= 0.0 || v[1..].iter().all(|&x| x == 0.0) {
                self.htau[q] = 0.0;
                beta = alpha;
            } else {
                let norm = tail.sqrt();
                beta = if alpha >= 0.0 { -norm } else { norm };
                v[0] = alpha - beta;
                let tau = 1.0 / (beta * (beta - alpha));
                self.htau[q] = tau;
                let rest = m - k - 1;
                if rest > 0 {
                    let w = &mut self.lam[..rest];
                    w.fill(0.0);
                    gemv::<F>(1.0, &self.dt[q * m + k + 1..], m, v, w);
                    for wi in w.iter_mut() {
                        *wi *= tau;
                    }
                    ger_sub::<F>(&mut self.dt[q * m + k + 1..], m, w, v);
                }
            }
            for i in 0..q {
                self.rm[i + q * n] = self.dt[k + i * m];
            }
            self.rm[q + q * n] = beta;
            self.um[q] = 0.0;
            self.active.push(Entry { id: k, sign: 1.0 });
        }
        self.q_eq = self.active.len();
        self.refresh_rinv(0);
    }

    /// Solve the equality-constrained problem from the range-space factorization
    /// (`λ = (DᵀD)⁻¹ (b + Dᵀ L⁻¹ g)` through `R`, `x = L⁻ᵀ (D λ − L⁻¹ g)`). If `x` satisfies
    /// every inequality it is the solution: write it and return `true`. Otherwise return
    /// `false` and leave the rest to the active-set iterations.
    #[inline(always)]
    fn equality_fast_path<const F: bool>(&mut self) -> Result<bool, QpError> {
        let (n, m, ni) = (self.n, self.ne, self.ni);
        // c = L⁻¹ g (in z): forward substitution with the rows of L, four rows at a time
        // (their products with the solved part are four independent dot products).
        let mut i0 = 0;
        while i0 < n {
            let b = (n - i0).min(4);
            let mut s = [0.0f64; 4];
            let (done, rest) = self.z.split_at_mut(i0);
            gemv_t::<F>(&self.lt[i0 * n..], n, done, &mut s[..b], |_| i0);
            for t in 0..b {
                let i = i0 + t;
                let row = &self.lt[i * n..i * n + i + 1];
                let mut acc = self.g[i] - s[t];
                for (j, &l) in row[i0..i].iter().enumerate() {
                    acc -= l * rest[j];
                }
                rest[t] = acc / row[i];
            }
            i0 += b;
        }
        // rhs = b + Dᵀ c on the independent rows, in factorization order (in w).
        self.lam.fill(0.0);
        gemv::<F>(1.0, &self.dt0, m, &self.z[..n], &mut self.lam);
        let q = self.q_eq;
        for k in 0..q {
            let id = self.active[k].id;
            self.w[k] = self.b[id] + self.lam[id];
        }
        // λ = R⁻¹ R⁻ᵀ rhs.
        for k in 0..q {
            let s = dot::<F>(&self.rm[k * n..k * n + k], &self.w[..k]);
            self.w[k] = (self.w[k] - s) * self.rinv[k];
        }
        back_substitute::<F>(&self.rm, &self.rinv, n, q, &mut self.w);
        self.lam.fill(0.0);
        for k in 0..q {
            self.lam[self.active[k].id] = self.w[k];
            self.um[k] = self.w[k];
        }
        // y = D λ − c (in v), then x = L⁻ᵀ y.
        gemv_t::<F>(&self.dt0, m, &self.lam, &mut self.v[..n], |_| m);
        for i in 0..n {
            self.v[i] -= self.z[i];
        }
        // x = L⁻ᵀ y by blocks of four rows from the bottom (columns of L are contiguous).
        let mut i1 = n;
        while i1 > 0 {
            let i0 = i1.saturating_sub(4);
            let b = i1 - i0;
            let mut s = [0.0f64; 4];
            let (head, solved) = self.x.split_at_mut(i1);
            gemv_t::<F>(
                &self.chol[i0 * n + i1..],
                n,
                &solved[..n - i1],
                &mut s[..b],
                |_| n - i1,
            );
            for t in (0..b).rev() {
                let i = i0 + t;
                let col = &self.chol[i * n..i * n + i1];
                let mut acc = self.v[i] - s[t];
                for (j, &xj) in head[i + 1..i1].iter().enumerate() {
                    acc -= col[i + 1 + j] * xj;
                }
                head[i] = acc / col[i];
            }
            i1 = i0;
        }
        for k in 0..m {
            if self.eq_dep[k] {
                let res = self.eval::<F>(Entry { id: k, sign: 1.0 }) - self.b[k];
                if res.abs() > self.settings.primal_tol * (1.0 + self.b[k].abs()) {
                    self.certify_equality(k);
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
        gemv::<F>(1.0, &self.c, ni, &self.x[..n], &mut self.cx);
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
    /// and the QR reflectors applied to its columns (four at a time, compact WY).
    #[inline(always)]
    fn build_j<const F: bool>(&mut self) {
        let (n, ld) = (self.n, self.ld);
        self.init_j0::<F>();
        // J = J₀ H₀ H₁ …, four reflectors at a time in compact WY form
        // (H_r0 … H_r0+3 = I − V T Vᵀ on the columns r0..n).
        let q_eq = self.q_eq;
        let mut r0 = 0;
        while r0 < q_eq {
            let b = (q_eq - r0).min(4);
            r0 += b;
            let r0 = r0 - b;
            if self.htau[r0..r0 + b].iter().all(|&t| t == 0.0) {
                continue;
            }
            let l = n - r0;
            let v4 = &mut self.wv[..4 * l];
            v4.fill(0.0);
            for c in 0..b {
                let v = &self.hv[(r0 + c) * n..(r0 + c + 1) * n - r0 - c];
                for (i, &x) in v.iter().enumerate() {
                    v4[(i + c) * 4 + c] = x;
                }
            }
            let mut t = [[0.0f64; 4]; 4];
            for c in 0..b {
                let tau = self.htau[r0 + c];
                t[c][c] = tau;
                // T[..c, c] = −τ T[..c, ..c] (V[.., ..c]ᵀ v_c)
                let mut z = [0.0f64; 4];
                for row in v4.chunks_exact(4) {
                    for (k, zk) in z.iter_mut().enumerate().take(c) {
                        *zk += row[k] * row[c];
                    }
                }
                for (i, ti) in t.iter_mut().enumerate().take(c) {
                    let acc: f64 = (i..c).map(|k| ti[k] * z[k]).sum();
                    ti[c] = -tau * acc;
                }
            }
            apply_reflectors4::<F>(&mut self.jm, ld, r0, l, v4, &t);
            // Columns r0.. now mix the full columns after them.
            for len in &mut self.jlen[r0..] {
                *len = ld;
            }
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
        // The copies of H, A and C are known finite only after a complete successful load.
        let trusted = self.copies_ok;
        self.copies_ok = false;
        let h_changed = load_matrix("H", p.h.as_slice(), &mut self.h, trusted)?;
        copy_checked("g", p.g.as_slice(), &mut self.g[..n])?;
        copy_checked("b", p.b.as_slice(), &mut self.b)?;
        let a_changed = load_matrix("A", p.a.as_slice(), &mut self.a, trusted)?;
        let c_changed = load_matrix("C", p.c.as_slice(), &mut self.c, trusted)?;
        let inf = self.settings.infinity;
        self.certificate.clear();
        let rows = load_bounds(
            ("l", "u"),
            p.l.as_slice(),
            p.u.as_slice(),
            inf,
            &mut self.lo,
            &mut self.hi,
        );
        let bounds = rows.and_then(|()| {
            load_bounds(
                ("lx", "ux"),
                p.lx.as_slice(),
                p.ux.as_slice(),
                inf,
                &mut self.lx,
                &mut self.ux,
            )
            .map_err(|e| match e {
                Bounds::Empty(i) => Bounds::EmptyBox(i),
                other => other,
            })
        });
        match bounds {
            Ok(()) => {}
            Err(Bounds::Error(e)) => return Err(e),
            Err(Bounds::Empty(i)) => {
                self.certificate
                    .extend([ActiveConstraint::Lower(i), ActiveConstraint::Upper(i)]);
                return Err(QpError::Infeasible);
            }
            Err(Bounds::EmptyBox(i)) => {
                self.certificate.extend([
                    ActiveConstraint::LowerBound(i),
                    ActiveConstraint::UpperBound(i),
                ]);
                return Err(QpError::Infeasible);
            }
        }
        self.copies_ok = true;
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
            e.sign * self.b[e.id]
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
            let jlen = &self.jlen;
            gemv_t::<F>(&self.jm, ld, &self.row, &mut self.d[..n], |j| jlen[j]);
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
        self.rinv[q] = 1.0 / self.d[q];
        self.um[q] = 0.0;
        self.active.push(e);
    }

    /// Recompute `rinv[k] = 1 / R_kk` for the active columns `from..`.
    #[inline(always)]
    fn refresh_rinv(&mut self, from: usize) {
        let n = self.n;
        for k in from..self.active.len() {
            self.rinv[k] = 1.0 / self.rm[k + k * n];
        }
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
        self.refresh_rinv(k);
    }

    /// Primal and dual solution of the equality-constrained problem on the active set, from
    /// the factorization: `x = J w` with `w = [R⁻ᵀ β; −J₂ᵀ g]`, `u = R⁻¹ (R⁻ᵀ β + J₁ᵀ g)`.
    /// Leaves `w` in `self.w` (then `xᵀ H x = ‖w‖²`).
    #[inline(always)]
    fn recompute<const F: bool>(&mut self) {
        let (n, ld) = (self.n, self.ld);
        let q = self.active.len();
        let jlen = &self.jlen;
        gemv_t::<F>(&self.jm, ld, &self.g, &mut self.v[..n], |j| jlen[j]);
        for k in 0..q {
            let beta = self.rhs(self.active[k]);
            let s = dot::<F>(&self.rm[k * n..k * n + k], &self.w[..k]);
            self.w[k] = (beta - s) * self.rinv[k];
        }
        for k in q..n {
            self.w[k] = -self.v[k];
        }
        self.x.fill(0.0);
        gemv::<F>(1.0, &self.jm, ld, &self.w[..n], &mut self.x[..ld]);
        for k in 0..q {
            self.rv[k] = self.w[k] + self.v[k];
        }
        back_substitute::<F>(&self.rm, &self.rinv, n, q, &mut self.rv);
        self.um[..q].copy_from_slice(&self.rv[..q]);
    }

    /// The Goldfarb–Idnani iterations from the current dual-feasible state. Returns the
    /// number of active-set changes.
    #[inline(always)]
    fn main_loop<const F: bool>(&mut self) -> Result<usize, QpError> {
        let (n, ne, ni, ld) = (self.n, self.ne, self.ni, self.ld);
        let tol = self.settings.primal_tol;
        let max_iter = self.settings.max_iter;
        let mut iter = self.iters;
        loop {
            // Step 1: the most violated inactive constraint.
            self.cx.fill(0.0);
            gemv::<F>(1.0, &self.c, ni, &self.x[..n], &mut self.cx);
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
            if self.eq_rows {
                // Equality rows as two-sided rows b ≤ a x ≤ b.
                self.ax.fill(0.0);
                gemv::<F>(1.0, &self.a, ne, &self.x[..n], &mut self.ax);
                for i in 0..ne {
                    if self.is_active[i] {
                        continue;
                    }
                    let r = self.ax[i] - self.b[i];
                    if -r > best_v {
                        best_v = -r;
                        best = Entry { id: i, sign: 1.0 };
                    } else if r > best_v {
                        best_v = r;
                        best = Entry { id: i, sign: -1.0 };
                    }
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
                self.iters = iter;
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
                // Dual step r = R⁻¹ d₁, only for the droppable rows q_fixed..q: R is upper
                // triangular, so they need only the trailing block of R; the equality
                // multipliers are not read in this loop and are recomputed at its end.
                let qe = self.q_fixed;
                self.rv[qe..q].copy_from_slice(&self.d[qe..q]);
                if q > qe {
                    back_substitute::<F>(
                        &self.rm[qe + qe * n..],
                        &self.rinv[qe..],
                        n,
                        q - qe,
                        &mut self.rv[qe..],
                    );
                }
                let mut t1 = f64::INFINITY;
                let mut kdrop = usize::MAX;
                for k in qe..q {
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
                    // `row` holds the normal of p (from compute_d) when p is a row of C.
                    let px = if p.id < ne + ni {
                        dot::<F>(&self.row[..n], &self.x[..n])
                    } else {
                        self.eval::<F>(p)
                    };
                    let sp = px - self.rhs(p);
                    (-sp / tail).max(0.0)
                };
                let t = t1.min(t2);
                if t == f64::INFINITY {
                    self.iters = iter;
                    self.certify_dependent::<F>(p);
                    return Err(QpError::Infeasible);
                }
                for k in qe..q {
                    self.um[k] -= t * self.rv[k];
                }
                u_p += t;
                if !dependent {
                    // z = J₂ d₂; x += t z.
                    gemv::<F>(t, &self.jm[q * ld..], ld, &self.d[q..n], &mut self.x[..ld]);
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

    /// The constraint an active-set entry stands for.
    fn constraint_of(&self, e: Entry) -> ActiveConstraint {
        let (ne, ni) = (self.ne, self.ni);
        if e.id < ne {
            ActiveConstraint::Equality(e.id)
        } else if e.id < ne + ni {
            let i = e.id - ne;
            if e.sign > 0.0 {
                ActiveConstraint::Lower(i)
            } else {
                ActiveConstraint::Upper(i)
            }
        } else {
            let i = e.id - ne - ni;
            if e.sign > 0.0 {
                ActiveConstraint::LowerBound(i)
            } else {
                ActiveConstraint::UpperBound(i)
            }
        }
    }

    /// Certificate of the main loop's proof: `p` cannot be satisfied because its normal is
    /// the combination Σ r_k n_k of the active normals (r = R⁻¹ d₁, all of it) and no
    /// inequality with r_k > 0 can be dropped. Lists p and the rows with r_k ≠ 0 (relative
    /// to the largest, above 1e-12).
    fn certify_dependent<const F: bool>(&mut self, p: Entry) {
        let (n, q) = (self.n, self.active.len());
        self.rv[..q].copy_from_slice(&self.d[..q]);
        back_substitute::<F>(&self.rm, &self.rinv, n, q, &mut self.rv[..q]);
        let largest = self.rv[..q].iter().fold(0.0f64, |m, r| m.max(r.abs()));
        self.certificate.clear();
        let first = self.constraint_of(p);
        self.certificate.push(first);
        for k in 0..q {
            if self.rv[k].abs() > 1e-12 * largest {
                let c = self.constraint_of(self.active[k]);
                self.certificate.push(c);
            }
        }
    }

    /// Certificate of an inconsistent redundant equality `k`: it and the independent
    /// equalities (the active ones), which it depends on.
    fn certify_equality(&mut self, k: usize) {
        self.certificate.clear();
        self.certificate.push(ActiveConstraint::Equality(k));
        for idx in 0..self.active.len() {
            let e = self.active[idx];
            if e.id < self.ne && e.id != k {
                self.certificate.push(ActiveConstraint::Equality(e.id));
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
                sol.y_eq[e.id] = -e.sign * u;
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
/// (leading dimension `n`; `rinv` holds the inverted diagonal), by blocks of four rows from
/// the bottom: a block first subtracts `R[block, solved] · y[solved]` (one matrix–vector
/// product whose four rows are contiguous in every column of R), then solves its 4 × 4
/// triangle. Each block reads each entry of R right of it once and writes its own four
/// right-hand sides once.
#[inline(always)]
fn back_substitute<const F: bool>(r: &[f64], rinv: &[f64], n: usize, q: usize, rhs: &mut [f64]) {
    let mut k = q;
    while k > 0 {
        let k0 = k.saturating_sub(4);
        let (head, tail) = rhs.split_at_mut(k);
        if k < q {
            gemv::<F>(-1.0, &r[k * n + k0..], n, &tail[..q - k], &mut head[k0..k]);
        }
        for kk in (k0..k).rev() {
            let yk = head[kk] * rinv[kk];
            head[kk] = yk;
            for i in k0..kk {
                head[i] -= yk * r[i + kk * n];
            }
        }
        k = k0;
    }
}

/// Load a matrix: when the previous copy `dst` is trusted (complete and finite), compare
/// first and copy (with the finiteness check) only from the first 16-entry block that differs;
/// a matrix that did not change is read once and not written (the common warm-start case), a
/// changed one is still read only once. Untrusted: [`copy_checked`]. Returns whether any bit
/// changed.
fn load_matrix(
    what: &'static str,
    src: &[f64],
    dst: &mut [f64],
    trusted: bool,
) -> Result<bool, QpError> {
    if !trusted || src.len() != dst.len() {
        return copy_checked(what, src, dst);
    }
    let k = same_prefix(src, dst);
    if k == src.len() {
        return Ok(false);
    }
    match copy_checked(what, &src[k..], &mut dst[k..]) {
        Err(QpError::NonFinite { what, index }) => Err(QpError::NonFinite {
            what,
            index: index + k,
        }),
        Err(e) => Err(e),
        Ok(_) => Ok(true),
    }
}

/// The start of the first 16-entry block in which `a` and `b` differ bitwise (`a.len()` if
/// none); vectorized compare. `a` and `b` have the same length.
fn same_prefix(a: &[f64], b: &[f64]) -> usize {
    let ca = a.chunks_exact(16);
    let cb = b.chunks_exact(16);
    let (ra, rb) = (ca.remainder(), cb.remainder());
    for (c, (x, y)) in ca.zip(cb).enumerate() {
        let mut d = 0u64;
        for k in 0..16 {
            d |= x[k].to_bits() ^ y[k].to_bits();
        }
        if d != 0 {
            return c * 16;
        }
    }
    if ra.iter().zip(rb).all(|(x, y)| x.to_bits() == y.to_bits()) {
        a.len()
    } else {
        a.len() - ra.len()
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

/// Why two-sided bounds could not be loaded.
enum Bounds {
    Error(QpError),
    /// Row `i`'s interval is empty.
    Empty(usize),
    /// Variable `i`'s interval is empty.
    EmptyBox(usize),
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
) -> Result<(), Bounds> {
    for (index, (((&a, &b), lo), hi)) in l
        .iter()
        .zip(u)
        .zip(lo.iter_mut())
        .zip(hi.iter_mut())
        .enumerate()
    {
        if a.is_nan() {
            return Err(Bounds::Error(QpError::NonFinite {
                what: what.0,
                index,
            }));
        }
        if b.is_nan() {
            return Err(Bounds::Error(QpError::NonFinite {
                what: what.1,
                index,
            }));
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
            return Err(Bounds::Empty(index));
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
