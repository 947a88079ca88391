//! Seed 001 S11: the walking experiments of the teleoperation chapter, the robot walking
//! scripted footsteps on its own (`scenarios/teleop/s11/`, Fig 6.6's autonomous walking): (a)
//! 10 steps in place lifting the sole 5 cm, (b) 7 steps of 10 cm forward lifting it 2.5 cm,
//! (c) generic footsteps — sideways, forward-right, backward, wide-open feet — each stable for
//! at least 15 steps (L8106–L8150). Bounds: the verdict the scenario declares; a run that does
//! not fall walks every step of its `[footsteps]`, at least 15 for (c). A run short of that is
//! listed by name under RESULTS.md's S11 shortfalls; its numbers, and every run's largest
//! difference between a step's planned and measured length, are printed here.

use std::path::PathBuf;
use std::process::Command;

fn repo(rel: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../..")
        .join(rel)
}

#[test]
fn the_s11_footsteps_are_walked_or_the_shortfall_is_listed() {
    let dir = tempfile::tempdir().unwrap();
    let mut all: Vec<PathBuf> = std::fs::read_dir(repo("scenarios/teleop/s11"))
        .unwrap()
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    all.sort();
    assert!(all.len() >= 12, "{} S11 scenarios", all.len());
    let results = std::fs::read_to_string(repo("RESULTS.md")).unwrap();
    let shortfalls = results
        .split("### Shortfalls (S11)")
        .nth(1)
        .and_then(|s| s.split("\n## ").next())
        .expect("RESULTS.md: a '### Shortfalls (S11)' section");
    let mut table = String::new();
    for path in &all {
        let name = path.file_stem().unwrap().to_string_lossy().into_owned();
        let text = std::fs::read_to_string(path).unwrap();
        let count: u64 = (text.lines())
            .find_map(|l| l.strip_prefix("count = "))
            .unwrap()
            .parse()
            .unwrap();
        let out = dir.path().join(&name);
        let o = Command::new(env!("CARGO_BIN_EXE_corps"))
            .current_dir(repo(""))
            .args(["run", path.to_str().unwrap(), "-o", out.to_str().unwrap()])
            .output()
            .unwrap();
        assert!(
            o.status.success(),
            "{name}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
        let m: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(out.join("metrics.json")).unwrap())
                .unwrap();
        let verdict = m["verdict"]["verdict"].as_str().unwrap().to_string();
        let expected = if text.contains("\nexpect = \"fell\"") {
            "fell"
        } else {
            "completed"
        };
        assert_eq!(
            verdict, expected,
            "{name}: the verdict its scenario declares"
        );
        let walked = m["steps_walked"].as_u64().unwrap();
        let error = m["step_length_error_mm"].as_f64().unwrap();
        let worst = (m["step_lengths"].as_array().unwrap().iter())
            .map(|l| (l["walked_m"].as_f64().unwrap() - l["planned_m"].as_f64().unwrap()).abs())
            .fold(0.0, f64::max);
        assert!(error.is_finite() && worst.is_finite());
        table += &format!(
            "{name:24} {verdict:10} {walked:2} of {count:2} steps walked, step length error {error:.1} mm mean, {:.1} mm at most\n",
            worst * 1e3
        );
        if verdict == "completed" && walked == count {
            if text.contains("S11 (c)") {
                assert!(walked >= 15, "{name}: (c) asks for 15 steps or more");
            }
        } else {
            assert!(
                shortfalls.contains(&format!("`{name}`")),
                "{name}: {walked} of {count} steps, {verdict}: not listed under RESULTS.md's S11 shortfalls"
            );
        }
    }
    println!("{table}");
}
