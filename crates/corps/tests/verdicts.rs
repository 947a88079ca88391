//! Every `corps run` ends with a verdict, printed and in `metrics.json`; the command exits
//! non-zero unless it is the one the scenario expects (`expect`, `completed` by default).

use std::path::{Path, PathBuf};
use std::process::Command;

fn repo(rel: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../..")
        .join(rel)
}

/// `corps run SCENARIO -o OUT`: (success, stdout, stderr).
fn corps_run(scenario: &Path, out: &Path) -> (bool, String, String) {
    let o = Command::new(env!("CARGO_BIN_EXE_corps"))
        .arg("run")
        .arg(scenario)
        .arg("-o")
        .arg(out)
        .output()
        .expect("runs");
    (
        o.status.success(),
        String::from_utf8_lossy(&o.stdout).into_owned(),
        String::from_utf8_lossy(&o.stderr).into_owned(),
    )
}

fn verdict(out: &Path) -> serde_json::Value {
    let m: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("metrics.json")).unwrap()).unwrap();
    m["verdict"].clone()
}

#[test]
fn a_fall_is_the_verdict_and_fails_the_command_unless_expected() {
    let tmp = tempfile::tempdir().unwrap();
    let demo = repo("scenarios/control/tsid_torque_fall_push.toml");
    let (ok, stdout, stderr) = corps_run(&demo, &tmp.path().join("expected"));
    assert!(ok, "{stderr}");
    assert!(stdout.contains("verdict: fell at t = "), "{stdout}");
    assert_eq!(verdict(&tmp.path().join("expected"))["verdict"], "fell");
    // The same run, expected to complete.
    let text = std::fs::read_to_string(&demo).unwrap();
    let unexpected = tmp.path().join("unexpected.toml");
    std::fs::write(&unexpected, text.replace("expect = \"fell\"\n", "")).unwrap();
    let out = tmp.path().join("unexpected");
    let (ok, _, stderr) = corps_run(&unexpected, &out);
    assert!(!ok);
    assert!(
        stderr.contains("the run ended fell at t = ") && stderr.contains("expects completed"),
        "{stderr}"
    );
    // One error line (progress lines come every 5 s of wall time off a terminal).
    let errors = stderr.lines().filter(|l| !l.contains("real time")).count();
    assert_eq!(errors, 1, "{stderr}");
    assert!(
        out.join("log.csv").is_file(),
        "a failed run still leaves its record"
    );
}

#[test]
fn a_diverging_run_stops_at_once_with_its_reason() {
    let tmp = tempfile::tempdir().unwrap();
    let stand = std::fs::read_to_string(repo("scenarios/control/tsid_torque_stand.toml")).unwrap();
    let scenario = tmp.path().join("kick.toml");
    let kick = "[[push]]\nframe = \"base_link\"\nstart = 0.2\nduration = 0.01\nforce = [0.0, 0.0, 1e9]\n\n[sim]";
    std::fs::write(&scenario, stand.replacen("[sim]", kick, 1)).unwrap();
    let out = tmp.path().join("out");
    let (ok, _, stderr) = corps_run(&scenario, &out);
    assert!(!ok);
    assert!(
        stderr.contains("the run ended diverged at t = 0.2"),
        "{stderr}"
    );
    let v = verdict(&out);
    assert_eq!(v["verdict"], "diverged");
    assert!(v["t"].as_f64().unwrap() < 0.25, "{v}");
}

/// simple_humanoid with every default (`corps sim`, only its URDF and SRDF named): its one
/// simulated shape is the 1 m test cylinder on its waist, so it would stand on its trunk. The
/// scenario is refused before it runs, in one line, with nothing written.
#[test]
fn simple_humanoid_defaults_are_refused_before_running() {
    let tmp = tempfile::tempdir().unwrap();
    let scenario = tmp.path().join("simple.toml");
    let robot = repo("robots/simple_humanoid_description");
    std::fs::write(
        &scenario,
        format!(
            "duration = 2.0\n[robot]\nurdf = \"{}\"\nsrdf = \"{}\"\n",
            robot.join("urdf/simple_humanoid.urdf").display(),
            robot.join("srdf/simple_humanoid.srdf").display()
        ),
    )
    .unwrap();
    let out = tmp.path().join("out");
    let o = Command::new(env!("CARGO_BIN_EXE_corps"))
        .arg("sim")
        .arg(&scenario)
        .arg("-o")
        .arg(&out)
        .output()
        .expect("runs");
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success());
    assert!(
        stderr.contains("initial.place_on_ground")
            && stderr.contains("the lowest collision shape is on the base link 'BODY'"),
        "{stderr}"
    );
    assert_eq!(stderr.lines().count(), 1, "{stderr}");
    assert!(
        !out.join("log.csv").exists(),
        "a refused scenario writes nothing"
    );
}
