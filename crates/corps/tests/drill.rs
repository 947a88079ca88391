//! `corps drill`: the shared drilling scenario (fewer holes) writes its log with the columns
//! the plot and RESULTS read, its metrics and its plot, and says "ok"; a bad scenario is one
//! line naming the key and a non-zero exit, leaving an earlier run's files as they were.

use std::path::PathBuf;
use std::process::{Command, Output};

fn repo(rel: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../..")
        .join(rel)
}

fn corps(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_corps"))
        .current_dir(repo(""))
        .arg("drill")
        .args(args)
        .output()
        .expect("corps runs")
}

#[test]
fn the_drilling_scenario_runs_and_a_bad_one_is_one_line() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("run");
    let o = corps(&[
        "scenarios/drilling/ur5_drilling.toml",
        "--holes",
        "1",
        "--quiet",
        "-o",
        out.to_str().unwrap(),
    ]);
    let text = String::from_utf8_lossy(&o.stdout);
    println!("{text}");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(text.starts_with("ur5_drilling: ok"), "{text}");
    let log = std::fs::read_to_string(out.join("log.csv")).unwrap();
    let header: Vec<&str> = log.lines().next().unwrap().split(',').collect();
    for c in [
        "t",
        "clamp_N",
        "force_ref_N",
        "f_min_N",
        "f_max_N",
        "thrust_N",
        "tank_energy_J",
        "h_dot_W",
        "passivity_bound_W",
        "qp_update",
        "tau_shoulder_pan_joint",
        "q_wrist_3_joint",
    ] {
        assert!(header.contains(&c), "{c} missing");
    }
    let metrics: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("metrics.json")).unwrap()).unwrap();
    assert_eq!(metrics["verdict"], "ok");
    assert_eq!(metrics["stations_done"], 5);
    assert!(out.join("drilling.png").metadata().unwrap().len() > 10_000);

    // A bad scenario: one line, the key named, nothing overwritten.
    let bad = dir.path().join("bad.toml");
    let text = std::fs::read_to_string(repo("scenarios/drilling/ur5_drilling.toml"))
        .unwrap()
        .replace("f_min = 30.0", "f_min = 70.0")
        .replace("../../robots", &repo("robots").display().to_string());
    std::fs::write(&bad, text).unwrap();
    let before = std::fs::read(out.join("log.csv")).unwrap();
    let o = corps(&[bad.to_str().unwrap(), "-o", out.to_str().unwrap()]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success());
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
    assert!(err.contains("clamp.force"), "{err}");
    assert_eq!(std::fs::read(out.join("log.csv")).unwrap(), before);
    let o = corps(&["scenarios/drilling/ur5_drilling.toml", "--log-every", "0"]);
    assert!(!o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("--log-every"));
}
