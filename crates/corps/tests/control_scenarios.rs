//! The closed-loop scenarios of the whole-body controllers (issue "Whole-body controllers on
//! TALOS", Deliver 6): each runs its scenario file from `scenarios/control/` exactly as
//! `corps run` does and asserts the bound on the metrics the command prints.

use corps::run::{run_file, Metrics, RunOptions};
use corps_loop::verdict::Verdict;
use std::path::PathBuf;

fn run(name: &str) -> Metrics {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../scenarios/control")
        .join(format!("{name}.toml"));
    let out = tempfile::tempdir().unwrap();
    let report = run_file(&path, Some(out.path()), None, RunOptions::quiet()).unwrap();
    let m = report.metrics;
    println!("{m}");
    for file in [
        "log.csv",
        "metrics.txt",
        "metrics.json",
        "com.png",
        "zmp.png",
    ] {
        assert!(out.path().join(file).is_file(), "{file} not written");
    }
    assert_eq!(m.fallbacks, 0, "{:?}", m.first_fallback);
    assert_eq!(m.verdict.verdict, Verdict::Completed, "{}", m.verdict);
    m
}

/// Peak CoM tracking error over the axes (m).
fn com_peak(m: &Metrics) -> f64 {
    m.com_error.iter().map(|s| s.peak).fold(0.0, f64::max)
}

/// No fall: the base stays high and nothing but the feet touches the ground.
fn assert_standing(m: &Metrics) {
    assert!(
        m.min_base_height > 0.9,
        "base fell to {} m",
        m.min_base_height
    );
    assert_eq!(
        m.other_contact_peak, 0.0,
        "a body other than the feet touched"
    );
}

fn assert_stands_still(m: &Metrics) {
    assert_standing(m);
    assert!(
        m.base_drift < 1e-3,
        "base drift {:.2} mm",
        m.base_drift * 1e3
    );
}

fn assert_tracks_sinusoid(m: &Metrics) {
    assert_standing(m);
    assert!(
        com_peak(m) < 5e-3,
        "CoM error peak {:.2} mm",
        com_peak(m) * 1e3
    );
}

/// The squat reaches 10 cm down and comes back: with a CoM error below 1 cm throughout, the
/// lowest CoM is within 1 cm of the −10 cm reference.
fn assert_squats(m: &Metrics) {
    assert_standing(m);
    assert!(
        com_peak(m) < 1e-2,
        "CoM error peak {:.2} mm",
        com_peak(m) * 1e3
    );
}

/// The right foot is lifted 5 cm (its height error stays below 1 cm) and the robot stays on
/// its left foot without slipping.
fn assert_balances_on_left_foot(m: &Metrics) {
    assert_standing(m);
    let right = &m.feet[1];
    assert!(
        right.error[2].peak < 1e-2,
        "right foot height error peak {:.2} mm",
        right.error[2].peak * 1e3
    );
    assert!(
        m.feet[0].slip < 1e-2,
        "left foot slip {:.2} mm",
        m.feet[0].slip * 1e3
    );
}

fn assert_recovers_from_push(m: &Metrics) {
    assert_standing(m);
    for foot in &m.feet {
        assert!(
            foot.slip < 1e-2,
            "{} foot slip {:.2} mm",
            foot.label,
            foot.slip * 1e3
        );
    }
}

#[test]
fn tsid_torque_stands() {
    assert_stands_still(&run("tsid_torque_stand"));
}

#[test]
fn tsid_torque_tracks_a_com_sinusoid() {
    assert_tracks_sinusoid(&run("tsid_torque_com_sinusoid"));
}

#[test]
fn tsid_torque_follows_a_com_trajectory_from_a_file() {
    // Same bound as the sinusoid: a slow CoM motion tracked within 5 mm.
    assert_tracks_sinusoid(&run("tsid_torque_com_file"));
}

#[test]
fn tsid_torque_squats() {
    assert_squats(&run("tsid_torque_squat"));
}

#[test]
fn tsid_torque_balances_on_one_foot() {
    assert_balances_on_left_foot(&run("tsid_torque_one_foot"));
}

#[test]
fn tsid_torque_recovers_from_a_front_push() {
    assert_recovers_from_push(&run("tsid_torque_push_front"));
}

#[test]
fn tsid_torque_recovers_from_a_side_push() {
    assert_recovers_from_push(&run("tsid_torque_push_side"));
}

#[test]
fn tsid_position_squats() {
    assert_squats(&run("tsid_position_squat"));
}

#[test]
fn tsid_position_balances_on_one_foot() {
    assert_balances_on_left_foot(&run("tsid_position_one_foot"));
}

#[test]
fn ik_position_squats() {
    assert_squats(&run("ik_position_squat"));
}

#[test]
fn ik_position_balances_on_one_foot() {
    assert_balances_on_left_foot(&run("ik_position_one_foot"));
}

#[test]
fn tsid_position_stands() {
    assert_stands_still(&run("tsid_position_stand"));
}

#[test]
fn ik_position_stands() {
    assert_stands_still(&run("ik_position_stand"));
}

#[test]
fn tsid_position_tracks_a_com_sinusoid() {
    assert_tracks_sinusoid(&run("tsid_position_com_sinusoid"));
}

#[test]
fn ik_position_tracks_a_com_sinusoid() {
    assert_tracks_sinusoid(&run("ik_position_com_sinusoid"));
}

#[test]
fn ik_position_with_the_stabilizer_stands() {
    assert_stands_still(&run("ik_position_stabilized_stand"));
}
