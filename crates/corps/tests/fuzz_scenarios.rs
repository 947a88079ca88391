//! Bad scenario files never crash or hang `corps run`: shipped scenarios mutated at random (a
//! number replaced by an extreme or malformed value, an unknown key added to a section, a line
//! deleted, the file cut short) end in `Ok` or a typed error, never a panic. Every input that
//! parses is run for 2 ms of control; a run still going after 3 s of wall time (a long settle, a
//! tiny control period) is stopped through its interrupt flag, which it must honour.

use corps::run::{run_text, RunOptions};
use proptest::prelude::*;
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::time::Duration;

const SCENARIOS: [&str; 4] = [
    "control/tsid_torque_stand.toml",
    "control/tsid_torque_push_front.toml",
    "control/ik_position_com_sinusoid.toml",
    "walk/tsid_torque_20cm.toml",
];

const VALUES: [&str; 12] = [
    "0",
    "-1",
    "1e308",
    "-1e308",
    "nan",
    "inf",
    "1e-300",
    "1e9",
    "\"text\"",
    "[]",
    "[1.0, 2.0, 3.0, 4.0]",
    "{}",
];

const KEYS: [&str; 3] = ["unknown_key = 1", "duration = 2", "[unknown_section]"];

fn scenario(rel: &str) -> (PathBuf, String) {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../scenarios")
        .join(rel);
    let text = std::fs::read_to_string(&path).unwrap();
    (path, text)
}

/// One mutation of `text`, chosen by `kind` and placed by `at`.
fn mutate(text: &str, kind: usize, at: usize, value: &str, key: &str) -> String {
    let lines: Vec<&str> = text.lines().collect();
    let k = at % lines.len().max(1);
    match kind % 4 {
        // The value of the k-th `key = value` line replaced.
        0 => {
            let assignments: Vec<usize> = (0..lines.len())
                .filter(|i| lines[*i].contains(" = ") && !lines[*i].trim_start().starts_with('#'))
                .collect();
            let mut out: Vec<String> = lines.iter().map(|l| l.to_string()).collect();
            if let Some(i) = assignments.get(at % assignments.len().max(1)) {
                let name = lines[*i].split(" = ").next().unwrap_or("");
                out[*i] = format!("{name} = {value}");
            }
            out.join("\n")
        }
        // A key inserted after line k.
        1 => {
            let mut out: Vec<&str> = lines.clone();
            out.insert(k + 1, key);
            out.join("\n")
        }
        // Line k deleted.
        2 => {
            let mut out = lines.clone();
            if !out.is_empty() {
                out.remove(k);
            }
            out.join("\n")
        }
        // The file cut at a character boundary.
        _ => text.chars().take(at % (text.chars().count() + 1)).collect(),
    }
}

/// Mutated scenarios that ran and that were refused, for the report below.
static RUNS: AtomicUsize = AtomicUsize::new(0);
static ERRORS: AtomicUsize = AtomicUsize::new(0);

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 64,
        failure_persistence: None,
        rng_seed: proptest::test_runner::RngSeed::Fixed(7),
        ..ProptestConfig::default()
    })]

    /// The property, run once by the test below (which then reports its counts).
    fn a_mutated_scenario_ends_in_ok_or_an_error(
        which in 0..SCENARIOS.len(),
        kind in 0usize..4,
        at in 0usize..10_000,
        value in 0..VALUES.len(),
        key in 0..KEYS.len(),
    ) {
        let (path, text) = scenario(SCENARIOS[which]);
        let text = mutate(&text, kind, at, VALUES[value], KEYS[key]);
        let out = tempfile::tempdir().unwrap();
        let stop: &'static AtomicBool = Box::leak(Box::new(AtomicBool::new(false)));
        let options = RunOptions { interrupt: Some(stop), ..RunOptions::quiet() };
        let result = std::thread::scope(|scope| {
            let run = scope.spawn(|| {
                std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
                    run_text(&text, &path, Some(out.path()), Some(0.002), options)
                }))
            });
            let start = std::time::Instant::now();
            while !run.is_finished() {
                if start.elapsed() > Duration::from_secs(3) {
                    stop.store(true, Ordering::Relaxed);
                }
                std::thread::sleep(Duration::from_millis(5));
            }
            run.join().unwrap()
        });
        let result = result.map_err(|_| "panicked").unwrap_or_else(|e| panic!("{e} on:\n{text}"));
        match result {
            Ok(_) => { RUNS.fetch_add(1, Ordering::Relaxed); }
            Err(e) => {
                // What the command prints: one line.
                let line = format!("{e:#}");
                prop_assert!(!line.is_empty() && !line.contains('\n'), "error message: {line}");
                ERRORS.fetch_add(1, Ordering::Relaxed);
            }
        }
    }
}

#[test]
fn mutated_scenarios_end_in_ok_or_a_one_line_error() {
    a_mutated_scenario_ends_in_ok_or_an_error();
    let (runs, errors) = (RUNS.load(Ordering::Relaxed), ERRORS.load(Ordering::Relaxed));
    println!("mutated scenarios: {runs} ran, {errors} refused with one line");
    assert!(
        runs > 0 && errors > 0,
        "{runs} ran, {errors} refused: the fuzz must reach both"
    );
}
