//! Every failure is a status, never a panic; the solver stays usable after a failure.

mod common;

use corps_qp::{ActiveSetSolver, QpError, QpProblem, QpStatus, Settings};
use nalgebra::{DMatrix, DVector};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

fn good_problem() -> QpProblem {
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    common::random_feasible_qp(&mut rng, 8, 3, 10, true)
}

#[test]
fn dimension_mismatch_is_reported() {
    let mut s = ActiveSetSolver::new(8, 3, 10);
    let mut p = good_problem();
    p.c = DMatrix::zeros(9, 8);
    match s.solve(&p) {
        Err(QpError::DimensionMismatch {
            what,
            expected_rows,
            got_rows,
            ..
        }) => {
            assert_eq!((what, expected_rows, got_rows), ("C", 10, 9));
        }
        other => panic!("unexpected {other:?}"),
    }
    assert_eq!(s.status(), QpStatus::InvalidInput);
    let mut p = good_problem();
    p.g = DVector::zeros(7);
    assert!(matches!(
        s.solve(&p),
        Err(QpError::DimensionMismatch { what: "g", .. })
    ));
}

#[test]
fn non_finite_input_is_reported() {
    let mut s = ActiveSetSolver::new(8, 3, 10);
    let mut p = good_problem();
    p.h[(2, 3)] = f64::NAN;
    assert_eq!(
        s.solve(&p).unwrap_err(),
        QpError::NonFinite {
            what: "H",
            index: 2 + 3 * 8
        }
    );
    let mut p = good_problem();
    p.g[1] = f64::INFINITY;
    assert_eq!(
        s.solve(&p).unwrap_err(),
        QpError::NonFinite {
            what: "g",
            index: 1
        }
    );
    let mut p = good_problem();
    p.u[4] = f64::NAN;
    assert_eq!(
        s.solve(&p).unwrap_err(),
        QpError::NonFinite {
            what: "u",
            index: 4
        }
    );
    // Infinite bounds are fine.
    let mut p = good_problem();
    p.u[4] = f64::INFINITY;
    p.lx[0] = f64::NEG_INFINITY;
    assert!(s.solve(&p).is_ok());
}

#[test]
fn indefinite_hessian_is_reported() {
    let mut s = ActiveSetSolver::new(8, 3, 10);
    let mut p = good_problem();
    p.h = DMatrix::identity(8, 8);
    p.h[(5, 5)] = -1.0;
    assert!(matches!(
        s.solve(&p),
        Err(QpError::NotPositiveDefinite { column: 5 })
    ));
    assert_eq!(s.status(), QpStatus::NotPositiveDefinite);
    // Positive semidefinite (singular) is rejected as well.
    p.h[(5, 5)] = 0.0;
    assert!(matches!(
        s.solve(&p),
        Err(QpError::NotPositiveDefinite { .. })
    ));
}

#[test]
fn empty_interval_is_infeasible() {
    let mut s = ActiveSetSolver::new(8, 3, 10);
    let mut p = good_problem();
    p.l[0] = 1.0;
    p.u[0] = 0.0;
    assert_eq!(s.solve(&p).unwrap_err(), QpError::Infeasible);
    assert_eq!(s.status(), QpStatus::Infeasible);
}

#[test]
fn iteration_limit_is_reported() {
    let mut rng = ChaCha8Rng::seed_from_u64(9);
    let p = common::random_feasible_qp(&mut rng, 30, 5, 60, true);
    let mut s = ActiveSetSolver::new(30, 5, 60);
    let full = s.solve(&p).unwrap().iterations;
    assert!(
        full > 2,
        "the test problem needs several iterations ({full})"
    );
    let mut s = ActiveSetSolver::with_settings(
        30,
        5,
        60,
        Settings {
            max_iter: 2,
            ..Settings::default()
        },
    );
    assert_eq!(
        s.solve(&p).unwrap_err(),
        QpError::IterationLimit { max_iter: 2 }
    );
    assert_eq!(s.status(), QpStatus::IterationLimit);
}

#[test]
fn solver_recovers_after_every_kind_of_failure() {
    let p = good_problem();
    let mut reference = ActiveSetSolver::new(8, 3, 10);
    let x_ref = reference.solve(&p).unwrap().x.clone();
    let mut s = ActiveSetSolver::new(8, 3, 10);
    s.solve(&p).unwrap();
    let mut bad = p.clone();
    bad.h[(0, 0)] = f64::NAN;
    let mut indefinite = p.clone();
    indefinite.h[(0, 0)] = -5.0;
    let mut infeasible = p.clone();
    infeasible.l[0] = 2.0;
    infeasible.u[0] = 1.0;
    for broken in [&bad, &indefinite, &infeasible] {
        assert!(s.solve(broken).is_err());
        let x = s.solve(&p).unwrap().x.clone();
        assert!((&x - &x_ref).amax() < 1e-12);
        assert_eq!(s.status(), QpStatus::Optimal);
    }
}

#[test]
fn unconstrained_and_empty_problems() {
    // min ½‖x‖² − [1, 2]ᵀx → x = [1, 2].
    let mut p = QpProblem::new(2, 0, 0);
    p.g = DVector::from_vec(vec![-1.0, -2.0]);
    let mut s = ActiveSetSolver::new(2, 0, 0);
    let sol = s.solve(&p).unwrap();
    assert!((sol.x[0] - 1.0).abs() < 1e-15 && (sol.x[1] - 2.0).abs() < 1e-15);
    assert!((sol.objective + 2.5).abs() < 1e-15);
    // With x₁ ≤ 1.5 the bound becomes active with multiplier 0.5 (z_box ≥ 0 at an upper bound).
    p.ux[1] = 1.5;
    let sol = s.solve(&p).unwrap();
    assert!((sol.x[1] - 1.5).abs() < 1e-15);
    assert!((sol.z_box[1] - 0.5).abs() < 1e-15);
    assert_eq!(
        sol.active_set,
        vec![corps_qp::ActiveConstraint::UpperBound(1)]
    );
    // n = 0 is a valid (trivial) problem.
    let mut s0 = ActiveSetSolver::new(0, 0, 0);
    assert_eq!(s0.solve(&QpProblem::new(0, 0, 0)).unwrap().objective, 0.0);
}
