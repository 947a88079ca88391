//! A scenario run as a library call: nothing written, the result in memory, and runs that
//! are `Send` and reproducible when run side by side on threads.

use corps_scenario::run::{RunOptions, ScenarioRun};
use corps_scenario::scenario::Scenario;
use std::path::Path;

const DIR: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../../scenarios/control");

fn push_scenario(duration: f64) -> Scenario {
    let text = std::fs::read_to_string(Path::new(DIR).join("tsid_torque_push_front.toml"))
        .expect("the push scenario");
    Scenario::parse(&text)
        .and_then(|s| s.with_duration(duration))
        .expect("the push scenario parses")
}

fn run(scenario: &Scenario) -> corps_scenario::run::RunResult {
    ScenarioRun::new(scenario, "push", Path::new(DIR), RunOptions::default())
        .expect("the run builds")
        .run(&mut [])
        .expect("the run runs")
}

#[test]
fn a_run_returns_its_series_metrics_and_verdict_in_memory() {
    let scenario = push_scenario(1.0);
    let result = run(&scenario);
    let m = &result.metrics;
    assert_eq!(m.verdict.verdict, corps_loop::verdict::Verdict::Completed);
    assert_eq!(m.fallbacks, 0);
    assert!((m.duration - 1.0).abs() < 1e-9);
    assert_eq!(result.columns[0], "t");
    assert_eq!(result.series.columns().len(), result.columns.len());
    // 1 s at 1 kHz: every tick is kept (the bound is 8192 points).
    let t = result.series.column(0);
    assert_eq!(t.len(), 1000);
    assert!((t[999] - 0.999).abs() < 1e-9);
}

#[test]
fn runs_side_by_side_on_threads_give_the_serial_run_to_the_bit() {
    let scenario = push_scenario(0.6);
    let serial = run(&scenario);
    let runs: Vec<_> = std::thread::scope(|s| {
        let handles: Vec<_> = (0..2).map(|_| s.spawn(|| run(&scenario))).collect();
        handles.into_iter().map(|h| h.join().unwrap()).collect()
    });
    for r in runs {
        for (k, name) in serial.columns.iter().enumerate() {
            if name == "tick_us" {
                continue;
            }
            let (a, b) = (serial.series.column(k), r.series.column(k));
            assert!(
                a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits()),
                "column {name} differs"
            );
        }
        assert_eq!(
            r.metrics.com_error[0].peak,
            serial.metrics.com_error[0].peak
        );
    }
}

#[test]
fn a_scenario_run_is_send() {
    fn send<T: Send>() {}
    send::<ScenarioRun>();
    send::<corps_scenario::run::RunResult>();
}

#[test]
fn a_scenario_without_a_controller_is_refused_before_any_tick() {
    let text = std::fs::read_to_string(Path::new(DIR).join("tsid_torque_push_front.toml")).unwrap();
    let start = text.find("[controller]").unwrap();
    let end = text[start..]
        .find("\n[")
        .map_or(text.len(), |e| start + e + 1);
    let bare = format!("{}{}", &text[..start], &text[end..]);
    let scenario = Scenario::parse(&bare).expect("a sim scenario parses");
    let e = ScenarioRun::new(&scenario, "bare", Path::new(DIR), RunOptions::default())
        .err()
        .expect("refused");
    assert!(e.to_string().contains("no [controller]"), "{e}");
}
