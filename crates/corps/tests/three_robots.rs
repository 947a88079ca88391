//! One scenario, three robots from their description files alone: the TSID torque balance
//! scenario with a push at the base (`scenarios/control/tsid_torque_push_front.toml`, 100 N ×
//! 0.1 s on TALOS' 90.27 kg, scaled with the robot's mass as the scenario says) runs on TALOS,
//! iCub and simple_humanoid with `--robot`: no fall, feet that do not slip, and the CoM back
//! within 5 mm of where it started within 3 s of the push.

use corps::run::{run_file, run_text, Metrics, RunOptions};
use corps_loop::verdict::Verdict;
use std::path::{Path, PathBuf};

fn scenario() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../scenarios/control/tsid_torque_push_front.toml")
}

fn options(robot: &str) -> RunOptions {
    RunOptions {
        robot: Some(robot.to_string()),
        ..RunOptions::quiet()
    }
}

/// (t, CoM) rows of a run's log.
fn com_track(dir: &Path) -> Vec<(f64, [f64; 3])> {
    let text = std::fs::read_to_string(dir.join("log.csv")).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |name: &str| header.iter().position(|h| *h == name).unwrap();
    let (t, x, y, z) = (col("t"), col("com_x"), col("com_y"), col("com_z"));
    lines
        .map(|l| {
            let v: Vec<f64> = l.split(',').map(|s| s.parse().unwrap()).collect();
            (v[t], [v[x], v[y], v[z]])
        })
        .collect()
}

/// Largest distance of the CoM from its start over the rows at or after `from` (m).
fn com_offset_after(track: &[(f64, [f64; 3])], from: f64) -> f64 {
    let start = track[0].1;
    track
        .iter()
        .filter(|(t, _)| *t >= from - 1e-9)
        .map(|(_, c)| {
            (0..3)
                .map(|k| (c[k] - start[k]).powi(2))
                .sum::<f64>()
                .sqrt()
        })
        .fold(0.0, f64::max)
}

fn recovers(robot: &str) -> Metrics {
    let out = tempfile::tempdir().unwrap();
    let report = run_file(&scenario(), Some(out.path()), None, options(robot)).unwrap();
    let m = report.metrics;
    let track = com_track(out.path());
    // The push starts 1 s after the handover; the run ends 3 s after it.
    let push = 1.0;
    let end = track.last().unwrap().0;
    let peak = com_offset_after(&track, push);
    let back = com_offset_after(&track, push + 2.9);
    println!(
        "{robot}: {:.2} kg, CoM moved up to {:.1} mm after the push, {:.2} mm from its start in the last 0.1 s before {:.2} s; slip {:.2}/{:.2} mm; {}",
        mass(robot),
        peak * 1e3,
        back * 1e3,
        end,
        m.feet[0].slip * 1e3,
        m.feet[1].slip * 1e3,
        m.verdict
    );
    assert_eq!(
        m.verdict.verdict,
        Verdict::Completed,
        "{robot}: {}",
        m.verdict
    );
    assert_eq!(m.fallbacks, 0, "{robot}: {:?}", m.first_fallback);
    assert_eq!(
        m.other_contact_peak, 0.0,
        "{robot}: a body other than the feet touched"
    );
    assert!(
        end >= push + 3.0 - 0.011,
        "{robot}: the run ended at {end} s"
    );
    assert!(
        peak > 2e-3,
        "{robot}: the push moved the CoM only {:.2} mm",
        peak * 1e3
    );
    assert!(
        back < 5e-3,
        "{robot}: the CoM is {:.2} mm from its start 3 s after the push",
        back * 1e3
    );
    for foot in &m.feet {
        assert!(
            foot.slip < 1e-2,
            "{robot}: {} foot slip {:.2} mm",
            foot.label,
            foot.slip * 1e3
        );
    }
    m
}

fn mass(robot: &str) -> f64 {
    corps_robot::Robot::built_in(robot)
        .unwrap()
        .unwrap()
        .model
        .total_mass()
}

#[test]
fn talos_recovers_from_the_push() {
    recovers("talos");
}

#[test]
fn icub_recovers_from_the_push_scaled_to_its_mass() {
    recovers("icub");
}

#[test]
fn simple_humanoid_recovers_from_the_push_scaled_to_its_mass() {
    recovers("simple_humanoid");
}

/// Known shortfall: iCub under TALOS' unscaled 100 N (0.35 m/s at its 28.35 kg, three times
/// TALOS' change of speed) falls with the same gains; held so that a change shows.
#[test]
fn icub_under_the_unscaled_100_n_push_falls() {
    let text = std::fs::read_to_string(scenario())
        .unwrap()
        .lines()
        .filter(|l| !l.starts_with("for_mass"))
        .collect::<Vec<_>>()
        .join("\n");
    let out = tempfile::tempdir().unwrap();
    let report = run_text(&text, &scenario(), Some(out.path()), None, options("icub")).unwrap();
    println!("icub, 100 N unscaled: {}", report.metrics.verdict);
    assert_eq!(report.metrics.verdict.verdict, Verdict::Fell);
}
