//! Warm start: along slowly varying sequences, warm solves give the cold solution and need
//! far fewer active-set changes.

mod common;

use corps_qp::{ActiveSetSolver, QpProblem, Settings};
use proptest::prelude::*;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

/// A sequence of `len` problems drifting slowly from `base` (vectors always; with
/// `matrices`, H, A and C too).
fn drift(base: &QpProblem, len: usize, matrices: bool, seed: u64) -> Vec<QpProblem> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let (n, ne, ni) = base.dims();
    let dg = common::rand_vector(&mut rng, n);
    let db = common::rand_vector(&mut rng, ne);
    let dl = common::rand_vector(&mut rng, ni);
    let dh = common::rand_matrix(&mut rng, n, n);
    let dh = (&dh + dh.transpose()) * 0.5;
    let da = common::rand_matrix(&mut rng, ne, n);
    let dc = common::rand_matrix(&mut rng, ni, n);
    (0..len)
        .map(|k| {
            let s = 0.01 * k as f64;
            let mut p = base.clone();
            p.g += &dg * s;
            p.b += &db * (0.2 * s);
            p.l += &dl * (0.2 * s);
            p.u += &dl * (0.2 * s);
            if matrices {
                p.h += &dh * (0.05 * s);
                p.a += &da * (0.05 * s);
                p.c += &dc * (0.05 * s);
            }
            p
        })
        .collect()
}

fn run(seq: &[QpProblem], warm: bool) -> (Vec<nalgebra::DVector<f64>>, usize) {
    let (n, ne, ni) = seq[0].dims();
    let mut s = ActiveSetSolver::with_settings(
        n,
        ne,
        ni,
        Settings {
            warm_start: warm,
            ..Settings::default()
        },
    );
    let mut iters = 0;
    let xs = seq
        .iter()
        .map(|p| {
            let sol = s.solve(p).expect("solve");
            iters += sol.iterations;
            sol.x.clone()
        })
        .collect();
    (xs, iters)
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 24,
        // A fixed seed: CI runs the same cases every time (set another to explore);
        // no regression files are written during CI.
        rng_seed: proptest::test_runner::RngSeed::Fixed(0xc0498),
        failure_persistence: None,
        ..ProptestConfig::default()
    })]

    #[test]
    fn warm_solves_equal_cold_solves(seed in any::<u64>(), n in 3usize..30, matrices in any::<bool>(), bounds in any::<bool>()) {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let base = common::random_feasible_qp(&mut rng, n, n / 3, 2 * n, bounds);
        let seq = drift(&base, 15, matrices, seed ^ 1);
        let (cold, _) = run(&seq, false);
        let (warm, _) = run(&seq, true);
        for (k, (a, b)) in cold.iter().zip(&warm).enumerate() {
            prop_assert!((a - b).amax() <= 1e-9, "tick {k}: |x_warm − x_cold| = {:e}", (a - b).amax());
        }
    }
}

#[test]
fn warm_start_saves_most_iterations_on_a_control_loop() {
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let base = common::random_feasible_qp(&mut rng, 60, 36, 40, false);
    for matrices in [false, true] {
        let seq = drift(&base, 50, matrices, 8);
        let (_, cold) = run(&seq, false);
        let (_, warm) = run(&seq, true);
        eprintln!("matrices vary: {matrices}: active-set changes cold {cold}, warm {warm}");
        assert!(warm * 5 <= cold, "warm {warm} vs cold {cold}");
    }
}
