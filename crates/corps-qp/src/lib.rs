//! # corps-qp — dense convex QP for whole-body control
//!
//! Solves
//!
//! ```text
//! minimize    ½ xᵀ H x + gᵀ x
//! subject to  A x = b,   l ≤ C x ≤ u,   lx ≤ x ≤ ux
//! ```
//!
//! with `H` symmetric positive definite, dense, in `f64`, without heap allocation after
//! setup ([`ActiveSetSolver::new`] / [`ActiveSetSolver::resize`]); and strict hierarchies of
//! such problems ([`HierarchicalQp`]).
//!
//! ## Method: Goldfarb–Idnani dual active set, with a range-space equality phase
//!
//! The solver is the dual active-set method of Goldfarb & Idnani (1983), as in eiquadprog /
//! QuadProg++ and qpmad: factor `H = L Lᵀ` (own Cholesky), then start from the unconstrained
//! minimum and add violated constraints one at a time, keeping the iterate dual feasible; a
//! constraint whose multiplier would become negative is dropped. The active normals are kept
//! in the factorization `J = L⁻ᵀ Q`, `Jᵀ N = [R; 0]`, updated by Givens rotations.
//!
//! Why this method (measured, see `BENCHMARKS.md`): whole-body-control QPs are small (≈60
//! variables), dense, and solved every millisecond from a neighbouring problem. A dual active
//! set needs no feasible starting point, solves to rounding precision (it reproduces eiquadprog's
//! TSID solutions to ~1e-15) and restarts cheaply from the
//! previous active set, whereas an interior point (Clarabel) pays its full iteration count on
//! every solve and stops at a tolerance (on the TSID QPs, Clarabel leaves the corner forces
//! loose by ~1e-4 N). A primal active set would need a phase-1 feasible point at each cold start.
//!
//! Details that matter for speed, all measured on the TSID TALOS problems and TSID's random
//! 60/36/40 problems:
//! - **Equalities first, in range-space form.** `D = L⁻¹ Aᵀ` (all right-hand sides at once)
//!   and its Householder QR give `R` and the equality-constrained minimizer by two triangular
//!   solves. If that point already satisfies every inequality (the common case in TSID: no
//!   inequality is active on its TALOS problems), the solve ends there, without ever forming
//!   `J`. Otherwise `J = L⁻ᵀ` is formed and the QR's reflectors are applied to it, four at a
//!   time in compact WY form. Linearly dependent equality rows are skipped (and checked for
//!   consistency: inconsistent ones make the problem infeasible).
//! - **Two-sided rows** `l ≤ C x ≤ u` are one constraint whose violated side is added;
//!   **variable bounds** are cheap rows (their `Jᵀ n` is a row of `J`). Bounds with
//!   `|value| ≥ Settings::infinity` (1e10, TSID's sentinel) are absent.
//! - **Structure and kernels.** `J` starts upper triangular and every Givens rotation mixes
//!   two adjacent columns, so each column's nonzero prefix is tracked and only it is touched.
//!   The O(n²) work per step is matrix–vector products (`Jᵀ n`, `J w`, `C x`, the triangular
//!   solves by blocks of four rows) in register-blocked kernels with several independent
//!   accumulators, and the O(n³) work at setup (Cholesky, `L⁻ᵀ`, `L⁻¹ Aᵀ`, `J`) is organized
//!   as such products too. The kernels use AVX2 + FMA when the CPU has them (checked at run
//!   time), portable code that auto-vectorizes otherwise. The dual step of an inequality
//!   iteration only solves the trailing (inequality) block of `R`.
//! - **Degenerate vertices.** With equalities fixed first, an infeasibility proof (a violated
//!   normal that is a combination of the active ones with no droppable inequality) puts no sign
//!   condition on the equality coefficients; at a degenerate vertex (more active constraints
//!   than variables, dependent normals) rounding amplified by the vertex's conditioning can
//!   produce such a proof for a feasible problem. Before reporting `Infeasible`, the solver
//!   therefore solves again from `−H⁻¹ g` with each equality row as the pair `b ≤ aᵀ x ≤ b`,
//!   so that every coefficient of a proof has a sign condition. When H is ill-conditioned
//!   (cond ~ 1e9) such proofs can still be spurious; since feasibility does not depend on H,
//!   a last attempt solves the proximal-point sequence on `H + ρI` (ρ = 1e-3 max Hᵢᵢ), whose
//!   proofs stand and whose iterates converge to the original optimum
//!   (`tests/degenerate_vertex.rs`: 1,000 such problems, all solved).
//! - **Checked answers.** Every answer is checked against the optimality conditions
//!   (stationarity, the active sides' multiplier signs and the primal residuals, 1e-6
//!   relative to the magnitude of their terms); one
//!   that misses them (the dual method on a Hessian with cond ~1e12 can return one) goes to
//!   the proximal fallback, and if that produces none that meets them the solve ends
//!   [`QpError::Inaccurate`]: no answer rather than a wrong one. The fallback ends by solving
//!   the original problem on the active set its iterations found (null-space method: QR of
//!   the active normals, Cholesky of the reduced Hessian), where they creep along H's small
//!   eigenvalues; an accepted answer whose residual is over 1e-9 (and that is not already
//!   that solve's) is solved again that way, and the new answer kept if it is more accurate
//!   with its multipliers' signs held to 1e-9 (`tests/ill_conditioned.rs`: 80 + 32 of 1,000
//!   unsolved or refused, against 92 + 37 before).
//! - **Infeasibility certificate.** After `Infeasible`,
//!   [`ActiveSetSolver::infeasibility_certificate`] lists constraints that alone admit no
//!   point: the violated constraint with the active ones its normal combines, an empty
//!   interval, or a redundant equality with those it contradicts (checked against Clarabel on
//!   the restricted problem in `tests/random_vs_clarabel.rs`).
//!
//! ## Warm start
//!
//! With `Settings::warm_start` (default), a solve reuses, by bitwise comparison with the
//! previous call's data:
//! - `H` unchanged → its Cholesky factor and `L⁻ᵀ`;
//! - `H` and `A` unchanged → the factorization after the equality phase;
//! - `H`, `A` and `C` unchanged → the final factorization of the previous solve (only the
//!   vectors `g`, `b`, `l`, `u`, `lx`, `ux` moved): the new primal/dual point is two triangular
//!   solves away;
//! - always → the previous active set, re-added in the same order (skipping dependent rows),
//!   after which constraints with negative multipliers are dropped until the point is dual
//!   feasible, and the Goldfarb–Idnani iterations continue from there.
//!
//! ## Multipliers
//!
//! `H x + g + Aᵀ y_eq + Cᵀ z_in + z_box = 0`, with `z ≤ 0` at a lower bound and `z ≥ 0` at an
//! upper bound (OSQP / ProxQP convention; eiquadprog's `λ` is the negative).
//!
//! ## Example: one QP
//!
//! ```
//! use corps_qp::{ActiveSetSolver, QpProblem};
//! use nalgebra::{dmatrix, dvector};
//!
//! // min ½‖x‖² − x₀ − x₁  s.t.  x₀ − x₁ = 0,  x₀ + x₁ ≤ 1,  x₁ ≥ −5
//! let mut p = QpProblem::new(2, 1, 1);
//! p.g = dvector![-1.0, -1.0];
//! p.a = dmatrix![1.0, -1.0];
//! p.c = dmatrix![1.0, 1.0];
//! p.u = dvector![1.0];
//! p.lx[1] = -5.0;
//! let mut solver = ActiveSetSolver::new(2, 1, 1);
//! let sol = solver.solve(&p).unwrap();
//! assert!((sol.x[0] - 0.5).abs() < 1e-12 && (sol.x[1] - 0.5).abs() < 1e-12);
//! assert!((sol.z_in[0] - 0.5).abs() < 1e-12); // upper side active: z ≥ 0
//! ```
//!
//! ## Example: a control loop (warm start, no allocation)
//!
//! ```
//! use corps_qp::{ActiveSetSolver, QpError, QpProblem};
//!
//! let mut p = QpProblem::new(3, 0, 1);
//! p.c.fill(1.0);
//! p.u[0] = 1.0; // x₀ + x₁ + x₂ ≤ 1
//! let mut solver = ActiveSetSolver::new(3, 0, 1);
//! for tick in 0..100 {
//!     p.g.fill(-1.0 - 0.01 * tick as f64); // the reference moves slowly
//!     match solver.solve(&p) {
//!         Ok(sol) => assert!((sol.x.sum() - 1.0).abs() < 1e-12),
//!         Err(QpError::Infeasible) => { /* fall back to a safe command */ }
//!         Err(e) => panic!("{e}"),
//!     }
//! }
//! ```
//!
//! ## Example: a strict hierarchy
//!
//! ```
//! use corps_qp::{HierarchicalQp, Level};
//! use nalgebra::{dmatrix, dvector, DMatrix};
//!
//! // Priority 0: x₀ + x₁ = 1.  Priority 1: x₀ ≥ 0.8.  Priority 2: x ≈ (2, 2).
//! let top = Level::new(2).with_equality(&dmatrix![1.0, 1.0], &dvector![1.0], 1.0);
//! let mid = Level::new(2).with_inequality(&dmatrix![1.0, 0.0], &dvector![0.8], &dvector![f64::INFINITY], 1.0);
//! let low = Level::new(2).with_equality(&DMatrix::identity(2, 2), &dvector![2.0, 2.0], 1.0);
//! let mut hqp = HierarchicalQp::new(2, vec![top, mid, low]);
//! let x = hqp.solve().unwrap();
//! assert!((x[0] - 0.8).abs() < 1e-8 && (x[1] - 0.2).abs() < 1e-8);
//! ```
#![warn(missing_docs)]

mod active_set;
mod cholesky;
mod givens;
mod hierarchical;
mod linalg;
mod polish;
mod problem;
mod status;

pub use active_set::ActiveSetSolver;

/// `a · b` over the common prefix of the slices, in 16 independent partial sums: the solver's
/// own dot-product kernel (portable build), for long products elsewhere in the stack, e.g. a
/// preview controller's 1600-sample window, where a single accumulator is latency-bound.
pub fn dot(a: &[f64], b: &[f64]) -> f64 {
    linalg::dot::<false>(a, b)
}
pub use hierarchical::{HierarchicalQp, HqpError, Level};
pub use problem::{ActiveConstraint, QpProblem, Settings, Solution};
pub use status::{QpError, QpStatus};
