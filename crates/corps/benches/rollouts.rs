//! Independent rollouts in one process, one per thread: the throughput of N simultaneous runs
//! against one (issue "corps under load": 2 rollouts on 2 cores ≥ 1.8× one rollout's
//! throughput). One rollout is 3 s of the 20 cm TSID torque walk (0.5 s settle + 3 s
//! controlled) with its log streamed to its own directory and the plots off; each rollout runs
//! on one thread (`RunOptions::quiet`).
//!
//! `cargo bench -p corps --bench rollouts`; throughput gain of N = N × t(1) / t(N).

use corps::run::RunOptions;
use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use std::path::Path;
use std::time::Duration;

const SCENARIO: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../scenarios/walk/tsid_torque_20cm.toml"
);

fn rollouts(c: &mut Criterion) {
    let text = std::fs::read_to_string(SCENARIO).expect("the 20 cm walk scenario");
    let text = text.replacen("[output]\n", "[output]\nplots = false\n", 1);
    assert!(text.contains("plots = false"), "no [output] section");
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    let mut group = c.benchmark_group("rollouts_walk_3s_controlled");
    group
        .sample_size(10)
        .warm_up_time(Duration::from_secs(2))
        .measurement_time(Duration::from_secs(20));
    for n in [1, 2, 4].into_iter().filter(|n| *n <= 2 * cores) {
        let dirs: Vec<_> = (0..n)
            .map(|_| tempfile::tempdir().expect("an output directory"))
            .collect();
        group.bench_with_input(BenchmarkId::from_parameter(n), &n, |b, _| {
            b.iter(|| {
                std::thread::scope(|scope| {
                    let runs: Vec<_> = dirs
                        .iter()
                        .map(|dir| {
                            let text = &text;
                            scope.spawn(move || {
                                corps::run::run_text(
                                    text,
                                    Path::new(SCENARIO),
                                    Some(dir.path()),
                                    Some(3.0),
                                    RunOptions::quiet(),
                                )
                                .expect("the rollout runs")
                                .metrics
                                .fallbacks
                            })
                        })
                        .collect();
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
