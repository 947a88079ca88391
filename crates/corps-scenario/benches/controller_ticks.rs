//! The controller's tick in closed loop, two controllers in the same run (issue 18,
//! Deliver 6): seed 001's soft-tasks controller #2 on iCub stepping in place
//! (`scenarios/icub/fsm2_stepping.toml`, 23 torque-controlled joints + 9 held, two wrench
//! contacts or one) and TSID's torque controller on TALOS walking 20 cm steps
//! (`scenarios/walk/tsid_torque_20cm.toml`). Each round runs both in memory, alternating, and
//! reads the median of the wall-clock time around each controller tick (the run's own
//! timer: state update, references, QP assembly and solve); the ratio iCub / TALOS is the
//! figure (goal ≤ 0.7).
//!
//! `cargo bench -p corps-scenario --bench controller_ticks` (`cargo test --benches` runs a
//! short smoke).

use corps_scenario::run::{RunOptions, ScenarioRun};
use corps_scenario::scenario::Scenario;
use std::path::{Path, PathBuf};

fn scenario(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../scenarios")
        .join(rel)
}

/// Median controller tick (µs) of `rel` run for `seconds`.
fn median_tick(rel: &str, seconds: f64) -> f64 {
    let path = scenario(rel);
    let text = std::fs::read_to_string(&path).expect("the scenario");
    let s = Scenario::parse(&text)
        .and_then(|s| s.with_duration(seconds))
        .expect("the scenario parses");
    let dir = path.parent().expect("its directory");
    let run = ScenarioRun::new(&s, "bench", dir, RunOptions::default()).expect("it builds");
    let m = run.run(&mut []).expect("it runs").metrics;
    assert_eq!(m.fallbacks, 0, "{:?}", m.first_fallback);
    m.tick_time.median_us
}

fn main() {
    let bench = std::env::args().any(|a| a == "--bench");
    let (rounds, icub_s, talos_s) = if bench {
        (5, 60.0, 11.0)
    } else {
        (1, 2.0, 1.0)
    };
    let mut ratios = Vec::new();
    println!("round  iCub soft-tasks #2 median  TALOS TSID torque median  ratio");
    for round in 1..=rounds {
        let icub = median_tick("icub/fsm2_stepping.toml", icub_s);
        let talos = median_tick("walk/tsid_torque_20cm.toml", talos_s);
        ratios.push(icub / talos);
        println!(
            "{round:>5}  {icub:>22.1} µs  {talos:>21.1} µs  {:>5.2}",
            icub / talos
        );
    }
    ratios.sort_by(f64::total_cmp);
    println!(
        "median ratio iCub / TALOS: {:.2} (goal ≤ 0.7)",
        ratios[ratios.len() / 2]
    );
}
