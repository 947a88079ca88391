//! Solver outcome: the error type and a compact status code.

use thiserror::Error;

/// Why a solve did not return an optimal solution. The solver never panics on user input;
/// every failure is one of these.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum QpError {
    /// A matrix or vector of the problem does not have the size the solver was set up for.
    #[error("dimension mismatch: `{what}` is {got_rows}×{got_cols}, expected {expected_rows}×{expected_cols}")]
    DimensionMismatch {
        /// Name of the offending field (`"H"`, `"g"`, `"A"`, …).
        what: &'static str,
        /// Expected number of rows.
        expected_rows: usize,
        /// Expected number of columns.
        expected_cols: usize,
        /// Actual number of rows.
        got_rows: usize,
        /// Actual number of columns.
        got_cols: usize,
    },
    /// NaN anywhere, or ±∞ in `H`, `g`, `A`, `b` or `C` (bounds may be infinite, never NaN).
    #[error("non-finite value in `{what}` at index {index}")]
    NonFinite {
        /// Name of the offending field.
        what: &'static str,
        /// Index of the first bad entry (column-major for matrices).
        index: usize,
    },
    /// `H` is not (numerically) positive definite: the Cholesky pivot of this column failed.
    #[error("the Hessian is not positive definite (Cholesky pivot {column})")]
    NotPositiveDefinite {
        /// Column of the failed pivot.
        column: usize,
    },
    /// No point satisfies the constraints (inconsistent equalities, `l > u`, or a violated
    /// constraint that the active set cannot satisfy).
    #[error("the problem is infeasible")]
    Infeasible,
    /// The active-set iteration limit (`Settings::max_iter`) was reached.
    #[error("iteration limit ({max_iter}) reached")]
    IterationLimit {
        /// The limit that was hit.
        max_iter: usize,
    },
    /// The answer missed the optimality conditions by more than 1e-6 relative to the
    /// magnitude of their terms (the dual method on a Hessian with cond ~1e12 can produce
    /// one), and the proximal fallback did not produce one that meets them: no answer is
    /// returned rather than a wrong one.
    #[error("no answer meets the optimality conditions (ill-conditioned problem)")]
    Inaccurate,
}

/// Compact outcome of the last solve, convenient for a control loop's fallback logic.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum QpStatus {
    /// No solve has run yet (or the solver was resized since).
    NotSolved,
    /// Optimal solution found.
    Optimal,
    /// The constraints are infeasible.
    Infeasible,
    /// The iteration limit was reached.
    IterationLimit,
    /// No answer met the optimality conditions.
    Inaccurate,
    /// The Hessian is not positive definite.
    NotPositiveDefinite,
    /// Bad input: dimension mismatch or NaN/Inf.
    InvalidInput,
}

impl QpError {
    /// The status code corresponding to this error.
    pub fn status(&self) -> QpStatus {
        match self {
            QpError::DimensionMismatch { .. } | QpError::NonFinite { .. } => QpStatus::InvalidInput,
            QpError::NotPositiveDefinite { .. } => QpStatus::NotPositiveDefinite,
            QpError::Infeasible => QpStatus::Infeasible,
            QpError::IterationLimit { .. } => QpStatus::IterationLimit,
            QpError::Inaccurate => QpStatus::Inaccurate,
        }
    }
}
