//! Independent closed-loop rollouts in one process on a rayon pool: the throughput of N
//! rollouts at once against one (issue "corps under load" and the loop-as-a-library issue:
//! 2 rollouts on 2 cores ≥ 1.7× one rollout's throughput). One rollout is 3 s of the 20 cm
//! TSID torque walk (0.5 s settle + 3 s controlled), in memory: no file is written. Each
//! rollout runs on one thread (`RunOptions::default`, no overlap worker).
//!
//! `cargo bench -p corps-scenario --bench rollouts`; throughput gain of N = N × t(1) / t(N).

use corps_scenario::run::{RunOptions, ScenarioRun};
use corps_scenario::scenario::Scenario;
use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use rayon::prelude::*;
use std::path::Path;
use std::time::Duration;

const SCENARIO: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../scenarios/walk/tsid_torque_20cm.toml"
);

fn rollout(scenario: &Scenario) -> usize {
    let base_dir = Path::new(SCENARIO)
        .parent()
        .expect("the scenario's directory");
    let run = ScenarioRun::new(scenario, "rollout", base_dir, RunOptions::default())
        .expect("the rollout builds");
    run.run(&mut [])
        .expect("the rollout runs")
        .metrics
        .fallbacks
}

fn rollouts(c: &mut Criterion) {
    let text = std::fs::read_to_string(SCENARIO).expect("the 20 cm walk scenario");
    let scenario = Scenario::parse(&text)
        .and_then(|s| s.with_duration(3.0))
        .expect("the 20 cm walk scenario parses");
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    let mut group = c.benchmark_group("rollouts_walk_3s_controlled");
    group
        .sample_size(10)
        .warm_up_time(Duration::from_secs(2))
        .measurement_time(Duration::from_secs(20));
    for n in [1, 2, 4].into_iter().filter(|n| *n <= 2 * cores) {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .expect("a rayon pool");
        group.bench_with_input(BenchmarkId::from_parameter(n), &n, |b, &n| {
            b.iter(|| {
                let fallbacks: usize =
                    pool.install(|| (0..n).into_par_iter().map(|_| rollout(&scenario)).sum());
                assert_eq!(fallbacks, 0);
            })
        });
    }
    group.finish();
    // The same rollouts on plain scoped threads, for comparison with the pool.
    let mut group = c.benchmark_group("rollouts_walk_3s_controlled_threads");
    group
        .sample_size(10)
        .warm_up_time(Duration::from_secs(2))
        .measurement_time(Duration::from_secs(20));
    for n in [1, 2].into_iter().filter(|n| *n <= cores) {
        group.bench_with_input(BenchmarkId::from_parameter(n), &n, |b, &n| {
            b.iter(|| {
                std::thread::scope(|s| {
                    let runs: Vec<_> = (0..n).map(|_| s.spawn(|| rollout(&scenario))).collect();
                    for r in runs {
                        assert_eq!(r.join().expect("a rollout thread"), 0);
                    }
                })
            })
        });
    }
    group.finish();
}

criterion_group!(benches, rollouts);
criterion_main!(benches);
