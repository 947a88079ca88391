//! Hierarchical (lexicographic) QP with strict priorities, solved as a cascade of QPs with
//! slack variables, as the Stack of Tasks and OpenSoT do.
//!
//! Level `k` has equality tasks `A_k x = b_k` and inequality tasks `l_k ≤ C_k x ≤ u_k`, each
//! row with a positive weight (several tasks with different weights can share a level: a
//! weighted level inside a priority). Level `k` solves
//!
//! ```text
//! minimize over (x, v)   ½ ‖A_k x − b_k‖²_W + ½ ‖v‖²_W + ½ ε ‖x‖²
//! subject to             l_k ≤ C_k x − v ≤ u_k                       (v: inequality slacks)
//!                        |A_j x − A_j x*_{k−1}| ≤ δ  for every level j < k (achieved residual kept)
//!                        C_j x within [l_j, u_j] widened to C_j x*_{k−1} (achieved violation kept)
//!                        lx ≤ x ≤ ux                                    (hard bounds)
//! ```
//!
//! where `x*_{k−1}` is the previous level's solution, which achieves every upper level's
//! optimum (computing all held targets from one point keeps dependent held rows consistent),
//! moved into the hard bounds (the QP solution may leave them by the solver's primal
//! tolerance). An upper level's task error is therefore held to within
//! `δ = primal_tol · (1 + |A_j x*_{k−1}|)` (`Settings::primal_tol` of the levels' solvers,
//! default 1e-9, the accuracy to which each QP satisfies its constraints anyway) by every level
//! below it: a lower level can only use the freedom the upper ones leave. ε (`regularization`,
//! default 1e-9) keeps each level's Hessian positive definite; at the last level it selects the
//! smallest-norm `x` among the remaining freedom.
//!
//! Why the held equalities are narrow two-sided rows and not equality constraints: when the
//! upper levels saturate many hard bounds, their optimum is a degenerate vertex of the lower
//! level's feasible set (more held rows and active bounds than variables, with linearly
//! dependent normals), often a single point. Held exactly, that set is empty or not at the
//! rounding level, and the conditioning of the vertex (ε makes `H` nearly singular) amplifies
//! the rounding until the dual active-set method proves "infeasibility" from it (the TALOS IK
//! of `tests/degenerate_vertex.rs`). With width δ the set has an interior at the scale of the
//! solver's own tolerance, and either side of a held row can be added and dropped like any
//! inequality. A level reported infeasible all the same (it is feasible by construction: the
//! previous level's x meets every held row and bound) is solved once more with the held
//! equalities 1,000 times wider, which keeps the upper levels to 1e-6 (1 + |target|) for that
//! solve (`tests/hierarchical_vs_clarabel.rs`: 3 of 300 degenerate hierarchies needed it).

use nalgebra::{DMatrix, DVector};
use thiserror::Error;

use crate::active_set::ActiveSetSolver;
use crate::problem::{QpProblem, Settings};
use crate::status::QpError;

/// How much wider the held equalities are when a level, feasible by construction, was
/// reported infeasible (see `HierarchicalQp::solve`).
const RETRY_WIDTH: f64 = 1e3;

/// Least regularization of a level, relative to the largest diagonal entry of its Hessian
/// (condition number at most 1e12, which the Cholesky factorization resolves).
const RELATIVE_REGULARIZATION: f64 = 1e-12;

/// One priority level: stacked equality and inequality task rows with per-row weights.
#[derive(Debug, Clone, PartialEq)]
pub struct Level {
    /// Equality task matrix (`r_eq × n`).
    pub a: DMatrix<f64>,
    /// Equality task target (`r_eq`).
    pub b: DVector<f64>,
    /// Weight of each equality row (`r_eq`, positive).
    pub eq_weights: DVector<f64>,
    /// Inequality task matrix (`r_in × n`).
    pub c: DMatrix<f64>,
    /// Lower bounds of `C x` (`r_in`, may be −∞).
    pub l: DVector<f64>,
    /// Upper bounds of `C x` (`r_in`, may be +∞).
    pub u: DVector<f64>,
    /// Weight of each inequality row (`r_in`, positive).
    pub in_weights: DVector<f64>,
}

impl Level {
    /// An empty level for `n` variables.
    pub fn new(n: usize) -> Self {
        Self {
            a: DMatrix::zeros(0, n),
            b: DVector::zeros(0),
            eq_weights: DVector::zeros(0),
            c: DMatrix::zeros(0, n),
            l: DVector::zeros(0),
            u: DVector::zeros(0),
            in_weights: DVector::zeros(0),
        }
    }

    /// Append an equality task `a x = b` with `weight` (setup-time; allocates).
    pub fn with_equality(mut self, a: &DMatrix<f64>, b: &DVector<f64>, weight: f64) -> Self {
        let (r0, r) = (self.a.nrows(), a.nrows());
        self.a = self.a.clone().resize_vertically(r0 + r, 0.0);
        self.a.rows_mut(r0, r).copy_from(a);
        self.b = append(&self.b, b);
        self.eq_weights = append(&self.eq_weights, &DVector::from_element(r, weight));
        self
    }

    /// Append an inequality task `l ≤ c x ≤ u` with `weight` (setup-time; allocates).
    pub fn with_inequality(
        mut self,
        c: &DMatrix<f64>,
        l: &DVector<f64>,
        u: &DVector<f64>,
        weight: f64,
    ) -> Self {
        let (r0, r) = (self.c.nrows(), c.nrows());
        self.c = self.c.clone().resize_vertically(r0 + r, 0.0);
        self.c.rows_mut(r0, r).copy_from(c);
        self.l = append(&self.l, l);
        self.u = append(&self.u, u);
        self.in_weights = append(&self.in_weights, &DVector::from_element(r, weight));
        self
    }

    /// Number of equality rows.
    pub fn n_eq(&self) -> usize {
        self.a.nrows()
    }

    /// Number of inequality rows.
    pub fn n_in(&self) -> usize {
        self.c.nrows()
    }

    /// Weighted task cost `½ Σ w (A x − b)² + ½ Σ w dist(C x, [l, u])²` at `x`
    /// (allocates; for checks).
    pub fn cost(&self, x: &DVector<f64>) -> f64 {
        let e = &self.a * x - &self.b;
        let cx = &self.c * x;
        let mut s = 0.0;
        for i in 0..e.len() {
            s += 0.5 * self.eq_weights[i] * e[i] * e[i];
        }
        for i in 0..cx.len() {
            let v = (self.l[i] - cx[i]).max(cx[i] - self.u[i]).max(0.0);
            s += 0.5 * self.in_weights[i] * v * v;
        }
        s
    }
}

fn append(a: &DVector<f64>, b: &DVector<f64>) -> DVector<f64> {
    DVector::from_iterator(a.len() + b.len(), a.iter().chain(b.iter()).copied())
}

/// Why a hierarchical solve failed.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum HqpError {
    /// A level's data changed size since construction.
    #[error("level {level}: {what} has the wrong size")]
    DimensionMismatch {
        /// The level.
        level: usize,
        /// The field.
        what: &'static str,
    },
    /// A task weight is not positive and finite.
    #[error("level {level}: weights must be positive and finite")]
    BadWeight {
        /// The level.
        level: usize,
    },
    /// The QP of a level failed.
    #[error("level {level}: {source}")]
    Level {
        /// The level.
        level: usize,
        /// The QP solver's error.
        source: QpError,
    },
}

/// A strict hierarchy of [`Level`]s over `n` variables with hard bounds `lx ≤ x ≤ ux`,
/// solved level by level (see the module docs). Buffers and one warm-started
/// [`ActiveSetSolver`] per level are allocated at construction; [`HierarchicalQp::solve`]
/// does not allocate. Update the task data in place through [`HierarchicalQp::levels_mut`].
#[derive(Debug, Clone)]
pub struct HierarchicalQp {
    n: usize,
    levels: Vec<Level>,
    /// Hard lower bounds on x (`n`, may be −∞).
    pub lx: DVector<f64>,
    /// Hard upper bounds on x (`n`, may be +∞).
    pub ux: DVector<f64>,
    /// ε of the `½ ε ‖x‖²` term of every level (default 1e-9).
    pub regularization: f64,
    solvers: Vec<ActiveSetSolver>,
    problems: Vec<QpProblem>,
    eq_target: Vec<DVector<f64>>,
    in_lo: Vec<DVector<f64>>,
    in_hi: Vec<DVector<f64>>,
    x: DVector<f64>,
    /// One weighted task row `w a_r` (n), for the Hessian's rank-one updates.
    weighted_row: Vec<f64>,
}

impl HierarchicalQp {
    /// Set up the hierarchy (level 0 has the highest priority) with default [`Settings`].
    pub fn new(n: usize, levels: Vec<Level>) -> Self {
        let mut solvers = Vec::with_capacity(levels.len());
        let mut problems = Vec::with_capacity(levels.len());
        let mut held = 0;
        for lv in &levels {
            let nv = n + lv.n_in();
            solvers.push(ActiveSetSolver::with_settings(
                nv,
                0,
                held + lv.n_in(),
                Settings::default(),
            ));
            problems.push(QpProblem::new(nv, 0, held + lv.n_in()));
            held += lv.n_eq() + lv.n_in();
        }
        Self {
            n,
            eq_target: levels.iter().map(|l| DVector::zeros(l.n_eq())).collect(),
            in_lo: levels.iter().map(|l| DVector::zeros(l.n_in())).collect(),
            in_hi: levels.iter().map(|l| DVector::zeros(l.n_in())).collect(),
            levels,
            lx: DVector::from_element(n, f64::NEG_INFINITY),
            ux: DVector::from_element(n, f64::INFINITY),
            regularization: 1e-9,
            solvers,
            problems,
            x: DVector::zeros(n),
            weighted_row: vec![0.0; n],
        }
    }

    /// The levels, highest priority first.
    pub fn levels(&self) -> &[Level] {
        &self.levels
    }

    /// Mutable access to the levels' data (keep the sizes).
    pub fn levels_mut(&mut self) -> &mut [Level] {
        &mut self.levels
    }

    /// The solution of the last successful [`HierarchicalQp::solve`].
    pub fn x(&self) -> &DVector<f64> {
        &self.x
    }

    fn check(&self) -> Result<(), HqpError> {
        let n = self.n;
        if self.lx.len() != n || self.ux.len() != n {
            return Err(HqpError::DimensionMismatch {
                level: 0,
                what: "lx/ux",
            });
        }
        for (k, lv) in self.levels.iter().enumerate() {
            let (re, ri) = (self.eq_target[k].len(), self.in_lo[k].len());
            let bad = |what| Err(HqpError::DimensionMismatch { level: k, what });
            if lv.a.shape() != (re, n) || lv.b.len() != re || lv.eq_weights.len() != re {
                return bad("equality task");
            }
            if lv.c.shape() != (ri, n)
                || lv.l.len() != ri
                || lv.u.len() != ri
                || lv.in_weights.len() != ri
            {
                return bad("inequality task");
            }
            if lv
                .eq_weights
                .iter()
                .chain(lv.in_weights.iter())
                .any(|w| !(w.is_finite() && *w > 0.0))
            {
                return Err(HqpError::BadWeight { level: k });
            }
        }
        Ok(())
    }

    /// Solve the hierarchy. Returns `x`; the task errors each level achieved are kept by all
    /// lower levels.
    pub fn solve(&mut self) -> Result<&DVector<f64>, HqpError> {
        self.check()?;
        let n = self.n;
        let eps = self.regularization;
        for k in 0..self.levels.len() {
            // Hold every upper level at what the previous level's solution x_{k−1} achieves: it
            // satisfies them all (to rounding), and computing every held target from the same
            // point keeps dependent held rows exactly consistent. Targets recorded from each
            // level's own solution disagree at rounding level on dependent rows (e.g. CoM and
            // feet tasks of an IK), which the solver rightly reports as infeasible.
            if k > 0 {
                for j in 0..k {
                    let up = &self.levels[j];
                    for r in 0..up.n_eq() {
                        self.eq_target[j][r] = (0..n).map(|c| up.a[(r, c)] * self.x[c]).sum();
                    }
                    for r in 0..up.n_in() {
                        let cx: f64 = (0..n).map(|c| up.c[(r, c)] * self.x[c]).sum();
                        self.in_lo[j][r] = up.l[r].min(cx);
                        self.in_hi[j][r] = up.u[r].max(cx);
                    }
                }
            }
            let lv = &self.levels[k];
            let ri = lv.n_in();
            let p = &mut self.problems[k];
            // Cost: ½‖A x − b‖²_W + ½ ε‖x‖² + ½‖v‖²_W.
            p.h.fill(0.0);
            p.g.fill(0.0);
            let ld = p.h.nrows();
            for r in 0..lv.n_eq() {
                let w = lv.eq_weights[r];
                // H[.., j] += (w a_r) a_rj over contiguous columns of H.
                for (i, wa) in self.weighted_row.iter_mut().enumerate() {
                    *wa = w * lv.a[(r, i)];
                }
                let h = p.h.as_mut_slice();
                for j in 0..n {
                    let arj = lv.a[(r, j)];
                    if arj == 0.0 {
                        continue;
                    }
                    p.g[j] -= w * arj * lv.b[r];
                    let column = &mut h[j * ld..j * ld + n];
                    for (hij, wa) in column.iter_mut().zip(&self.weighted_row) {
                        *hij += wa * arj;
                    }
                }
            }
            // ε, but at least 1e-12 of the largest diagonal entry: with task rows and weights
            // spanning orders of magnitude AᵀWA reaches 1e9 while some directions stay at 0,
            // and an absolute ε below its rounding leaves H numerically singular.
            let largest = (0..n).fold(0.0f64, |m, i| m.max(p.h[(i, i)]));
            let eps = eps.max(RELATIVE_REGULARIZATION * largest);
            for i in 0..n {
                p.h[(i, i)] += eps;
            }
            for r in 0..ri {
                p.h[(n + r, n + r)] = lv.in_weights[r];
            }
            // This level's inequalities with slacks, then the held inequalities and equalities
            // of the levels above.
            p.c.fill(0.0);
            for r in 0..ri {
                for c in 0..n {
                    p.c[(r, c)] = lv.c[(r, c)];
                }
                p.c[(r, n + r)] = -1.0;
                p.l[r] = lv.l[r];
                p.u[r] = lv.u[r];
            }
            let mut row = ri;
            for j in 0..k {
                let up = &self.levels[j];
                for r in 0..up.n_in() {
                    for c in 0..n {
                        p.c[(row, c)] = up.c[(r, c)];
                    }
                    p.l[row] = self.in_lo[j][r];
                    p.u[row] = self.in_hi[j][r];
                    row += 1;
                }
            }
            let tol = self.solvers[k].settings().primal_tol;
            let held_eq = row;
            for j in 0..k {
                let up = &self.levels[j];
                for r in 0..up.n_eq() {
                    for c in 0..n {
                        p.c[(row, c)] = up.a[(r, c)];
                    }
                    let t = self.eq_target[j][r];
                    let delta = tol * (1.0 + t.abs());
                    p.l[row] = t - delta;
                    p.u[row] = t + delta;
                    row += 1;
                }
            }
            p.lx.rows_mut(0, n).copy_from(&self.lx);
            p.ux.rows_mut(0, n).copy_from(&self.ux);
            // The level is feasible by construction (x_{k−1} meets every held row and bound),
            // so a proof of infeasibility is spurious: at a degenerate vertex the held rows'
            // width δ can be below what the vertex's conditioning resolves. Tried once more
            // with the held equalities RETRY_WIDTH times wider (the upper levels then kept to
            // that width for this solve).
            let solver = &mut self.solvers[k];
            let level_error = |source| HqpError::Level { level: k, source };
            match solver.solve(p).map(|_| ()) {
                Ok(()) => {}
                Err(QpError::Infeasible) => {
                    for r in held_eq..row {
                        let (mid, half) = (0.5 * (p.l[r] + p.u[r]), 0.5 * (p.u[r] - p.l[r]));
                        (p.l[r], p.u[r]) = (mid - RETRY_WIDTH * half, mid + RETRY_WIDTH * half);
                    }
                    solver.solve(p).map_err(level_error)?;
                }
                Err(e) => return Err(level_error(e)),
            }
            let sol = solver.solution();
            // Keep x inside the hard bounds: the QP solution may leave them by up to the
            // solver's primal tolerance, and the levels below hold their targets at this x. At
            // a degenerate vertex (upper levels saturating many bounds, so that the held rows
            // and the active bounds meet in one point) targets computed from a point outside
            // the box are inconsistent with the box, and the level below is infeasible by that
            // amount. Inside the box, x is feasible for every lower level by construction.
            for i in 0..n {
                self.x[i] = sol.x[i].max(self.lx[i]).min(self.ux[i]);
            }
        }
        Ok(&self.x)
    }
}
