//! Criterion benchmarks of corps-qp against Clarabel on
//! - TSID's random-QP size (`tests/hqp_solvers.cpp`, PR #162): 60 variables, 36 equalities,
//!   40 inequalities, positive-definite H; cold solves, and warm solves along slowly varying
//!   sequences (vectors only, and every matrix too);
//! - the 25 TALOS whole-body QPs TSID built (eiquadprog's inputs): cold solves, and the
//!   warm-started sequence of the 20 consecutive ticks 100..119.
//!
//! Run: `cargo bench -p corps-qp --bench qp -- --warm-up-time 1 --measurement-time 3`.
//! Each iteration is one solve; medians are in `target/criterion/<group>/<name>/new/estimates.json`.

#[path = "../tests/common/mod.rs"]
mod common;

use clarabel::solver::{DefaultSettingsBuilder, DefaultSolver, IPSolver};
use corps_qp::{ActiveSetSolver, QpProblem, Settings};
use criterion::{black_box, criterion_group, criterion_main, Criterion};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

const N: usize = 60;
const NE: usize = 36;
const NI: usize = 40;

fn cold() -> Settings {
    Settings {
        warm_start: false,
        ..Settings::default()
    }
}

/// A periodic, slowly varying sequence (period `len` ticks) around `base`: the vectors g, b,
/// l, u move by ~0.5 % of their range per tick; with `matrices`, H, A and C drift too.
pub fn slow_sequence(base: &QpProblem, len: usize, matrices: bool, seed: u64) -> Vec<QpProblem> {
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
            let s = (2.0 * std::f64::consts::PI * k as f64 / len as f64).sin();
            let mut p = base.clone();
            p.g += &dg * (0.3 * s);
            p.b += &db * (0.1 * s);
            p.l += &dl * (0.1 * s);
            p.u += &dl * (0.1 * s);
            if matrices {
                p.h += &dh * (0.02 * s);
                p.a += &da * (0.02 * s);
                p.c += &dc * (0.02 * s);
            }
            p
        })
        .collect()
}

pub fn random_problems(count: usize, seed: u64) -> Vec<QpProblem> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    (0..count)
        .map(|_| common::random_feasible_qp(&mut rng, N, NE, NI, false))
        .collect()
}

fn bench_corps(
    c: &mut Criterion,
    group: &str,
    name: &str,
    problems: &[QpProblem],
    settings: Settings,
) {
    let (n, ne, ni) = problems[0].dims();
    let mut solver = ActiveSetSolver::with_settings(n, ne, ni, settings);
    // One pass first, so the warm-started benchmark starts from a warm state.
    for p in problems {
        solver.solve(p).expect("corps-qp solve");
    }
    let mut k = 0usize;
    c.benchmark_group(group).bench_function(name, |b| {
        b.iter(|| {
            let p = &problems[k % problems.len()];
            k += 1;
            black_box(
                solver
                    .solve(black_box(p))
                    .map(|s| s.objective)
                    .unwrap_or(f64::NAN),
            )
        })
    });
}

fn bench_clarabel(c: &mut Criterion, group: &str, problems: &[QpProblem]) {
    let data: Vec<_> = problems.iter().map(common::clarabel_data).collect();
    let settings = DefaultSettingsBuilder::default()
        .verbose(false)
        .build()
        .unwrap();
    let mut k = 0usize;
    c.benchmark_group(group).bench_function("clarabel", |b| {
        b.iter(|| {
            let d = &data[k % data.len()];
            k += 1;
            let mut s =
                DefaultSolver::new(&d.p, &d.q, &d.a, &d.b, &d.cones, settings.clone()).unwrap();
            s.solve();
            black_box(s.solution.obj_val)
        })
    });
}

fn random_benches(c: &mut Criterion) {
    let group = "random_60_36_40";
    let problems = random_problems(50, 7);
    bench_corps(c, group, "corps_cold", &problems, cold());
    let base = &problems[0];
    let seq_vec = slow_sequence(base, 200, false, 11);
    bench_corps(
        c,
        group,
        "corps_warm_vectors_vary",
        &seq_vec,
        Settings::default(),
    );
    let seq_all = slow_sequence(base, 200, true, 11);
    bench_corps(
        c,
        group,
        "corps_warm_all_vary",
        &seq_all,
        Settings::default(),
    );
    bench_corps(c, group, "corps_cold_on_all_vary", &seq_all, cold());
    bench_clarabel(c, group, &problems);
}

fn tsid_benches(c: &mut Criterion) {
    let group = "tsid_talos_62_18_66";
    let qps = common::load_tsid();
    let all: Vec<QpProblem> = qps.iter().map(|q| q.problem.clone()).collect();
    let seq: Vec<QpProblem> = qps
        .iter()
        .filter(|q| (100..120).contains(&q.tick))
        .map(|q| q.problem.clone())
        .collect();
    assert_eq!(seq.len(), 20);
    bench_corps(c, group, "corps_cold", &all, cold());
    bench_corps(
        c,
        group,
        "corps_warm_ticks_100_119",
        &seq,
        Settings::default(),
    );
    bench_clarabel(c, group, &all);
}

criterion_group!(benches, random_benches, tsid_benches);
criterion_main!(benches);
