//! Seed 000 S13, the safety regression, on TALOS with joint drives (flexible joints,
//! current-controlled motors, one period of delay; issue "Actuators", Deliver 1–2): TSID torque
//! control of a posture task (Table 4.11) while the right arm swings, with the "Success" and
//! "Fail" gains of Table 4.12, and the passive controller with the "Fail" gains. The thesis:
//! "Fail" diverged on the real robot, "Success" stayed stable, and the passive controller is
//! the remedy. The 20 cm walk runs on the drives too.

use corps::run::{run_file, Metrics, RunOptions};
use corps_loop::verdict::Verdict;
use std::collections::HashMap;
use std::path::PathBuf;

fn scenario(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../scenarios/actuators")
        .join(format!("{name}.toml"))
}

/// Runs a scenario (its text edited by `edit`); the metrics and the log's columns.
fn run(name: &str, edit: impl Fn(String) -> String) -> (Metrics, HashMap<String, Vec<f64>>) {
    let text = std::fs::read_to_string(scenario(name)).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join(format!("{name}.toml"));
    std::fs::write(&path, edit(text)).unwrap();
    let out = dir.path().join("out");
    let metrics = run_file(&path, Some(&out), None, RunOptions::quiet())
        .unwrap()
        .metrics;
    let log = std::fs::read_to_string(out.join("log.csv")).unwrap();
    let mut lines = log.lines();
    let header: Vec<String> = lines.next().unwrap().split(',').map(String::from).collect();
    let mut columns: HashMap<String, Vec<f64>> = HashMap::new();
    for l in lines {
        for (h, x) in header.iter().zip(l.split(',')) {
            columns
                .entry(h.clone())
                .or_default()
                .push(x.parse().unwrap_or(f64::NAN));
        }
    }
    (metrics, columns)
}

fn peak(c: &HashMap<String, Vec<f64>>, name: &str) -> f64 {
    c[name]
        .iter()
        .copied()
        .filter(|x| x.is_finite())
        .fold(0.0, f64::max)
}

fn summary(name: &str, m: &Metrics, c: &HashMap<String, Vec<f64>>) -> String {
    format!(
        "{name}: {}; posture error peak {:.3} rad, joint speed peak {:.2} rad/s, torque peak \
         {:.0} N·m",
        m.verdict,
        peak(c, "posture_error_max_rad"),
        peak(c, "joint_speed_max_rad_s"),
        peak(c, "torque_max_Nm")
    )
}

#[test]
fn s13_fail_gains_diverge_success_gains_and_the_tank_stay_bounded() {
    let keep = |t: String| t;
    let (success, cs) = run("success_gains", keep);
    let (fail, cf) = run("fail_gains", keep);
    let (passive, cp) = run("fail_gains_passive", keep);
    for (name, m, c) in [
        ("success", &success, &cs),
        ("fail", &fail, &cf),
        ("fail + tank", &passive, &cp),
    ] {
        println!("{}", summary(name, m, c));
    }
    assert_eq!(success.verdict.verdict, Verdict::Completed);
    assert!(
        matches!(
            fail.verdict.verdict,
            Verdict::Fell | Verdict::Diverged | Verdict::ControllerFailed
        ),
        "{}",
        fail.verdict
    );
    assert_eq!(
        passive.verdict.verdict,
        Verdict::Completed,
        "{}",
        passive.verdict
    );
    // Bounded: the passive run's joints never reach the speeds of the diverging run.
    assert!(peak(&cp, "joint_speed_max_rad_s") < peak(&cf, "joint_speed_max_rad_s"));
}

/// With the description's stiffer drives (1.5e4 N·m/rad, the scenarios' [actuation.drive]
/// removed) the "Fail" gains stay bounded: the thesis's divergence needs a softer drive
/// (measured in RESULTS.md). Both outcomes are stated.
#[test]
fn with_the_description_drives_the_fail_gains_stay_bounded() {
    let stiff = |t: String| {
        t.replace("stiffness = 2e3\n", "")
            .replace("damping = 3.0\n", "")
            .replace("expect = \"fell\"\n", "")
    };
    let (fail, c) = run("fail_gains", stiff);
    println!("{}", summary("fail, 1.5e4 N·m/rad drives", &fail, &c));
    assert_eq!(fail.verdict.verdict, Verdict::Completed, "{}", fail.verdict);
}

#[test]
fn the_20cm_walk_runs_on_the_drives() {
    let (m, _) = run("walk_20cm_drives", |t| t);
    println!("{m}");
    assert_eq!(m.verdict.verdict, Verdict::Completed, "{}", m.verdict);
}
