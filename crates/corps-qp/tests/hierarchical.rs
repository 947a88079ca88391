//! Hierarchical QP: strict priorities (a lower level never degrades a higher one) and
//! weighted tasks inside a level.

mod common;

use corps_qp::{HierarchicalQp, Level};
use nalgebra::{DMatrix, DVector};
use proptest::prelude::*;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Three conflicting levels over n variables: (0) a few equalities and a box-like inequality
/// band, (1) more equalities than the remaining freedom (so they cannot all hold) plus an
/// inequality task, (2) a full-rank "posture" task x ≈ x_ref.
fn random_hierarchy(seed: u64, n: usize) -> (Vec<Level>, DVector<f64>, DVector<f64>) {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let r0 = rng.gen_range(1..=n / 3 + 1);
    let r1 = n;
    let x0 = common::rand_vector(&mut rng, n);
    let a0 = common::rand_matrix(&mut rng, r0, n);
    let b0 = &a0 * &x0;
    let c0 = common::rand_matrix(&mut rng, n, n);
    let l0 = &c0 * &x0 - DVector::from_element(n, 0.5);
    let u0 = &c0 * &x0 + DVector::from_element(n, 0.5);
    let a1 = common::rand_matrix(&mut rng, r1, n);
    let b1 = common::rand_vector(&mut rng, r1) * 3.0;
    let c1 = common::rand_matrix(&mut rng, 3, n);
    let l1 = DVector::from_element(3, 1.0);
    let u1 = DVector::from_element(3, 2.0);
    let x_ref = common::rand_vector(&mut rng, n) * 2.0;
    let level0 = Level::new(n)
        .with_equality(&a0, &b0, 1.0)
        .with_inequality(&c0, &l0, &u0, 1.0);
    let level1 = Level::new(n)
        .with_equality(&a1, &b1, rng.gen_range(0.1..10.0))
        .with_inequality(&c1, &l1, &u1, 2.0);
    let level2 = Level::new(n).with_equality(&DMatrix::identity(n, n), &x_ref, 1.0);
    let lx = DVector::from_element(n, -3.0);
    let ux = DVector::from_element(n, 3.0);
    (vec![level0, level1, level2], lx, ux)
}

fn solve(levels: &[Level], lx: &DVector<f64>, ux: &DVector<f64>) -> DVector<f64> {
    let n = lx.len();
    let mut h = HierarchicalQp::new(n, levels.to_vec());
    h.lx = lx.clone();
    h.ux = ux.clone();
    h.solve().expect("hierarchical solve").clone()
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 48,
        // A fixed seed: CI runs the same cases every time (set another to explore);
        // no regression files are written during CI.
        rng_seed: proptest::test_runner::RngSeed::Fixed(0xc0496),
        failure_persistence: None,
        ..ProptestConfig::default()
    })]

    /// For every level k: its cost at the solution of the whole hierarchy equals its cost at
    /// the solution of the hierarchy truncated after k (levels below k do not degrade it),
    /// and the last level does improve its own cost over what the levels above left.
    #[test]
    fn lower_levels_never_degrade_higher_ones(seed in any::<u64>(), n in 3usize..15) {
        let (levels, lx, ux) = random_hierarchy(seed, n);
        let x_full = solve(&levels, &lx, &ux);
        for k in 0..levels.len() {
            let x_trunc = solve(&levels[..=k], &lx, &ux);
            for (j, level) in levels.iter().enumerate().take(k + 1) {
                let (full, trunc) = (level.cost(&x_full), level.cost(&x_trunc));
                prop_assert!(full <= trunc + 1e-7 * (1.0 + trunc),
                    "level {j} degraded by the levels below {k}: {full} > {trunc}");
            }
        }
        // Hard bounds hold.
        for i in 0..n {
            prop_assert!(x_full[i] >= lx[i] - 1e-9 && x_full[i] <= ux[i] + 1e-9);
        }
        // Level 1 conflicts with level 0 by construction (n rows, fewer than n free
        // directions), and the posture level moves x within the freedom left.
        let x01 = solve(&levels[..2], &lx, &ux);
        prop_assert!(levels[2].cost(&x_full) <= levels[2].cost(&x01) + 1e-9);
    }
}

/// A level made of two weighted equality tasks is a weighted least-squares problem:
/// compare with the normal equations (w₁A₁ᵀA₁ + w₂A₂ᵀA₂ + εI) x = w₁A₁ᵀb₁ + w₂A₂ᵀb₂.
#[test]
fn weighted_tasks_inside_a_level() {
    let mut rng = ChaCha8Rng::seed_from_u64(17);
    let n = 6;
    let (a1, b1) = (
        common::rand_matrix(&mut rng, 4, n),
        common::rand_vector(&mut rng, 4),
    );
    let (a2, b2) = (
        common::rand_matrix(&mut rng, 5, n),
        common::rand_vector(&mut rng, 5),
    );
    let (w1, w2) = (10.0, 0.1);
    let level = Level::new(n)
        .with_equality(&a1, &b1, w1)
        .with_equality(&a2, &b2, w2);
    let mut h = HierarchicalQp::new(n, vec![level]);
    let x = h.solve().unwrap().clone();
    let m = a1.transpose() * &a1 * w1 + a2.transpose() * &a2 * w2 + DMatrix::identity(n, n) * 1e-9;
    let rhs = a1.transpose() * &b1 * w1 + a2.transpose() * &b2 * w2;
    let x_ref = m.lu().solve(&rhs).unwrap();
    assert!((&x - &x_ref).amax() < 1e-9, "{:e}", (&x - &x_ref).amax());
}

/// A classic two-level example: level 0 wants x₀ + x₁ = 1, level 1 wants x = (2, 2).
/// The result is the projection of (2, 2) onto the line: (0.5, 0.5).
#[test]
fn two_level_textbook_example() {
    let top = Level::new(2).with_equality(
        &DMatrix::from_row_slice(1, 2, &[1.0, 1.0]),
        &DVector::from_element(1, 1.0),
        1.0,
    );
    let bottom = Level::new(2).with_equality(
        &DMatrix::identity(2, 2),
        &DVector::from_element(2, 2.0),
        1.0,
    );
    let mut h = HierarchicalQp::new(2, vec![top, bottom]);
    let x = h.solve().unwrap();
    assert!(
        (x[0] - 0.5).abs() < 1e-8 && (x[1] - 0.5).abs() < 1e-8,
        "{x}"
    );
    // With an inequality task x₀ ≥ 0.8 in between, x₀ = 0.8 and x₁ = 0.2.
    let top = h.levels()[0].clone();
    let bottom = h.levels()[1].clone();
    let middle = Level::new(2).with_inequality(
        &DMatrix::from_row_slice(1, 2, &[1.0, 0.0]),
        &DVector::from_element(1, 0.8),
        &DVector::from_element(1, f64::INFINITY),
        1.0,
    );
    let mut h = HierarchicalQp::new(2, vec![top, middle, bottom]);
    let x = h.solve().unwrap();
    assert!(
        (x[0] - 0.8).abs() < 1e-8 && (x[1] - 0.2).abs() < 1e-8,
        "{x}"
    );
}
