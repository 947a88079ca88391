//! Problem data, settings and solution types.

use nalgebra::{DMatrix, DVector};

/// A dense convex QP
///
/// ```text
/// minimize    ½ xᵀ H x + gᵀ x
/// subject to  A x = b
///             l ≤ C x ≤ u        (two-sided rows; a side may be ±∞)
///             lx ≤ x ≤ ux        (simple bounds; a side may be ±∞)
/// ```
///
/// with `n` variables, `n_eq` equality rows and `n_in` inequality rows. All matrices are
/// nalgebra `DMatrix` (column-major). Fill the fields in place in a control loop: the solver
/// copies what it needs and never allocates after setup. Bounds whose magnitude is at least
/// [`Settings::infinity`] (default 1e10) are treated as absent.
#[derive(Debug, Clone, PartialEq)]
pub struct QpProblem {
    /// Hessian `H` (`n × n`, symmetric positive definite; only the lower triangle is factored,
    /// the full matrix is used for the objective value).
    pub h: DMatrix<f64>,
    /// Gradient `g` (`n`).
    pub g: DVector<f64>,
    /// Equality matrix `A` (`n_eq × n`).
    pub a: DMatrix<f64>,
    /// Equality right-hand side `b` (`n_eq`).
    pub b: DVector<f64>,
    /// Inequality matrix `C` (`n_in × n`).
    pub c: DMatrix<f64>,
    /// Lower bounds `l` of `C x` (`n_in`, may hold −∞).
    pub l: DVector<f64>,
    /// Upper bounds `u` of `C x` (`n_in`, may hold +∞).
    pub u: DVector<f64>,
    /// Lower bounds of `x` (`n`, may hold −∞).
    pub lx: DVector<f64>,
    /// Upper bounds of `x` (`n`, may hold +∞).
    pub ux: DVector<f64>,
}

impl QpProblem {
    /// A problem of the given size with `H = I`, everything else zero and all bounds infinite.
    pub fn new(n: usize, n_eq: usize, n_in: usize) -> Self {
        Self {
            h: DMatrix::identity(n, n),
            g: DVector::zeros(n),
            a: DMatrix::zeros(n_eq, n),
            b: DVector::zeros(n_eq),
            c: DMatrix::zeros(n_in, n),
            l: DVector::from_element(n_in, f64::NEG_INFINITY),
            u: DVector::from_element(n_in, f64::INFINITY),
            lx: DVector::from_element(n, f64::NEG_INFINITY),
            ux: DVector::from_element(n, f64::INFINITY),
        }
    }

    /// `(n, n_eq, n_in)` as given by `H`, `A` and `C` (`n` is the number of rows of `H`).
    pub fn dims(&self) -> (usize, usize, usize) {
        (self.h.nrows(), self.a.nrows(), self.c.nrows())
    }

    /// Objective value `½ xᵀ H x + gᵀ x` at `x` (allocates; for checks, not for hot loops).
    pub fn objective(&self, x: &DVector<f64>) -> f64 {
        0.5 * x.dot(&(&self.h * x)) + self.g.dot(x)
    }
}

/// Solver settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Settings {
    /// Maximum number of active-set changes (additions plus removals) per solve.
    pub max_iter: usize,
    /// A constraint counts as violated when it is violated by more than this (absolute).
    /// Also the consistency tolerance for linearly dependent equality rows (scaled by
    /// `1 + |b|`).
    pub primal_tol: f64,
    /// A constraint normal is linearly dependent on the active ones when its component
    /// outside their span (in the metric of `H⁻¹`) is below this fraction of its norm.
    pub dependence_tol: f64,
    /// Bounds with `|value| ≥ infinity` are treated as infinite (TSID writes −1e10).
    pub infinity: f64,
    /// Reuse the previous active set and the cached factorizations (see the crate docs).
    pub warm_start: bool,
}

impl Default for Settings {
    fn default() -> Self {
        Self {
            max_iter: 1000,
            primal_tol: 1e-9,
            dependence_tol: 1e-10,
            infinity: 1e10,
            warm_start: true,
        }
    }
}

/// One active constraint of the solution (indices into the problem's rows).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ActiveConstraint {
    /// Equality row `i` of `A` (linearly dependent, redundant rows are not listed).
    Equality(usize),
    /// Inequality row `i` of `C` at its lower bound `l[i]`.
    Lower(usize),
    /// Inequality row `i` of `C` at its upper bound `u[i]`.
    Upper(usize),
    /// Variable `i` at its lower bound `lx[i]`.
    LowerBound(usize),
    /// Variable `i` at its upper bound `ux[i]`.
    UpperBound(usize),
}

/// Solution of a QP.
///
/// Multipliers follow the convention `H x + g + Aᵀ y_eq + Cᵀ z_in + z_box = 0`: `z_in[i] ≤ 0`
/// when row `i` is at its lower bound, `≥ 0` at its upper bound, `0` when inactive (same for
/// `z_box` and the variable bounds). This is the OSQP / ProxQP sign convention; eiquadprog's
/// `λ` (as in TSID's data, `H x + g = Aᵀ λ_eq + Cᵀ λ_in`) is `λ = −y`, `−z`.
#[derive(Debug, Clone, PartialEq)]
pub struct Solution {
    /// Primal solution.
    pub x: DVector<f64>,
    /// Equality multipliers (`n_eq`; 0 for rows skipped as redundant).
    pub y_eq: DVector<f64>,
    /// Inequality multipliers (`n_in`).
    pub z_in: DVector<f64>,
    /// Variable-bound multipliers (`n`).
    pub z_box: DVector<f64>,
    /// Objective value `½ xᵀ H x + gᵀ x`.
    pub objective: f64,
    /// Active-set changes in the main loop (additions plus removals).
    pub iterations: usize,
    /// Active constraints at the solution, equalities first, in factorization order.
    pub active_set: Vec<ActiveConstraint>,
}

impl Solution {
    pub(crate) fn new(n: usize, n_eq: usize, n_in: usize) -> Self {
        Self {
            x: DVector::zeros(n),
            y_eq: DVector::zeros(n_eq),
            z_in: DVector::zeros(n_in),
            z_box: DVector::zeros(n),
            objective: 0.0,
            iterations: 0,
            active_set: Vec::with_capacity(n + n_eq),
        }
    }

    /// Copies `other` (same sizes) into `self`, reusing its buffers.
    pub(crate) fn copy_from(&mut self, other: &Solution) {
        self.x.copy_from(&other.x);
        self.y_eq.copy_from(&other.y_eq);
        self.z_in.copy_from(&other.z_in);
        self.z_box.copy_from(&other.z_box);
        self.objective = other.objective;
        self.iterations = other.iterations;
        self.active_set.clone_from(&other.active_set);
    }
}
