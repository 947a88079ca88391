//! Whole walks simulated with control at 1 kHz (issue "Walking", speed goal: ≥ 10× faster
//! than real time). One iteration is the main job's walk — TALOS, 6 × 20 cm plus a closing
//! step under TSID torque control, 0.5 s settle + 11 s controlled = 11.5 s simulated — from
//! the scenario text to the metrics and the CSV log: planning, every simulation step and
//! control tick, the metrics. The PNG plots are off (drawing them is output, not simulation;
//! `tools/bench/walk_speed.py` times the whole `corps run` command with them).
//!
//! Measured in the same run: the walk as `corps run` steps it (`adaptive`: the simulator
//! prepares its next step on a second thread while the controller computes, as long as the
//! run's own tick times show that it gains), the same overlapping every tick (`always`), on
//! one thread (`serial`; all three bit-identical), and the anchor: the serial walk on the
//! simulator setup the torque walks used before implicit Euler (4 RK4 substeps per tick on the
//! same stiff contact).
//!
//! `cargo bench -p corps --bench walk`; real-time factor = 11.5 s / the median.

use corps::run::{Overlap, RunOptions};
use criterion::{criterion_group, criterion_main, Criterion};
use std::path::Path;
use std::time::Duration;

const SCENARIO: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../scenarios/walk/tsid_torque_20cm.toml"
);

/// The scenario text with the plots off, and optionally the RK4 anchor's integrator.
fn scenario_text(rk4_anchor: bool) -> String {
    let text = std::fs::read_to_string(SCENARIO).expect("the 20 cm walk scenario");
    let mut text = text.replacen("[output]\n", "[output]\nplots = false\n", 1);
    assert!(
        text.contains("plots = false"),
        "no [output] section to turn plots off"
    );
    if rk4_anchor {
        let implicit = "integrator = \"implicit_euler\"";
        assert!(
            text.contains(implicit),
            "the walk no longer runs implicit Euler"
        );
        text = text.replacen(implicit, "integrator = \"rk4\"\nsubsteps = 4", 1);
    }
    text
}

fn walk(c: &mut Criterion) {
    let out = tempfile::tempdir().expect("a temporary output directory");
    let mut group = c.benchmark_group("walk_tsid_torque_20cm_11.5s_simulated");
    group
        .sample_size(10)
        .warm_up_time(Duration::from_secs(2))
        .measurement_time(Duration::from_secs(15));
    let runs = [
        ("implicit_euler_adaptive", false, Overlap::Adaptive),
        ("implicit_euler_always", false, Overlap::Always),
        ("implicit_euler_serial", false, Overlap::Never),
        ("anchor_rk4_x4", true, Overlap::Never),
    ];
    for (label, rk4_anchor, overlap) in runs {
        let text = scenario_text(rk4_anchor);
        let options = RunOptions {
            overlap,
            ..RunOptions::quiet()
        };
        group.bench_function(label, |b| {
            b.iter(|| {
                let report = corps::run::run_text(
                    &text,
                    Path::new(SCENARIO),
                    Some(out.path()),
                    None,
                    options.clone(),
                )
                .expect("the walk runs");
                assert_eq!(report.metrics.fallbacks, 0, "the controller fell back");
                report
            })
        });
    }
    group.finish();
}

criterion_group!(benches, walk);
criterion_main!(benches);
