//! The `corps` command end to end: `model inspect`, `model eval` against Pinocchio's golden
//! values, and one-line errors with a non-zero exit status.

use serde_json::{json, Value};
use std::process::Command;

fn corps(args: &[&str]) -> (bool, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_corps"))
        .args(args)
        .output()
        .expect("runs");
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

fn repo(rel: &str) -> String {
    format!("{}/../../{}", env!("CARGO_MANIFEST_DIR"), rel)
}

fn flat(v: &Value) -> Vec<f64> {
    match v {
        Value::Array(a) => a.iter().flat_map(flat).collect(),
        Value::Number(n) => vec![n.as_f64().unwrap()],
        other => panic!("unexpected {other}"),
    }
}

fn assert_close(what: &str, a: &[f64], b: &[f64]) {
    assert_eq!(a.len(), b.len(), "{what}: sizes");
    let scale = b.iter().fold(1.0f64, |m, x| m.max(x.abs()));
    let err = a
        .iter()
        .zip(b)
        .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
    assert!(err <= 1e-9 * scale, "{what}: error {err:e}");
}

#[test]
fn inspect_describes_the_default_robot() {
    let (ok, out, _) = corps(&["model", "inspect"]);
    assert!(ok);
    assert!(
        out.contains("nq = 39, nv = 38, total mass = 90.2722 kg"),
        "{out}"
    );
    assert!(out.contains("leg_left_4_joint") && out.contains("half_sitting"));
    let (ok, out, _) = corps(&["model", "inspect", "--json"]);
    assert!(ok);
    let v: Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["joints"].as_array().unwrap().len(), 33);
}

#[test]
fn eval_matches_pinocchio_golden_values() {
    let golden: Value = serde_json::from_str(
        &std::fs::read_to_string(repo("crates/corps-model/tests/golden/talos.json")).unwrap(),
    )
    .unwrap();
    let frames = [
        "leg_left_sole_fix_joint",
        "arm_left_7_joint",
        "torso_2_link",
    ];
    let states: Vec<Value> = golden["states"].as_array().unwrap()[..3]
        .iter()
        .map(|s| json!({"q": s["q"], "v": s["v"], "a": s["a"], "tau": s["tau"]}))
        .collect();
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("states.json");
    std::fs::write(
        &input,
        json!({"frames": frames, "states": states}).to_string(),
    )
    .unwrap();
    let (ok, out, err) = corps(&[
        "model",
        "eval",
        "--urdf",
        &repo("robots/talos_data/robots/talos_reduced.urdf"),
        "--states",
        input.to_str().unwrap(),
    ]);
    assert!(ok, "{err}");
    let v: Value = serde_json::from_str(&out).unwrap();
    assert_eq!((v["nq"].as_u64(), v["nv"].as_u64()), (Some(39), Some(38)));
    for (k, r) in v["results"].as_array().unwrap().iter().enumerate() {
        let g = &golden["states"][k];
        for (ours, theirs) in [
            ("M", "M"),
            ("nle", "nle"),
            ("g", "g"),
            ("rnea", "rnea"),
            ("aba", "aba"),
            ("com", "com"),
            ("Jcom", "Jcom"),
            ("Ag", "Ag"),
            ("hg", "hg"),
        ] {
            assert_close(
                &format!("state {k} {ours}"),
                &flat(&r[ours]),
                &flat(&g[theirs]),
            );
        }
        for f in frames {
            for key in ["translation", "rotation", "J_lwa", "classical_acc_lwa"] {
                assert_close(
                    &format!("state {k} {f} {key}"),
                    &flat(&r["frames"][f][key]),
                    &flat(&g["frames"][f][key]),
                );
            }
        }
    }
}

#[test]
fn errors_are_one_line_and_exit_non_zero() {
    let dir = tempfile::tempdir().unwrap();
    let cases = [
        (
            json!({"states": [{"q": [1.0, 2.0]}]}),
            "configuration q has size 2, expected 39",
        ),
        (
            json!({"frames": ["nope"], "states": []}),
            "unknown frame 'nope'",
        ),
        (json!({"frame": [], "states": []}), "unknown field `frame`"),
    ];
    for (k, (input, expected)) in cases.iter().enumerate() {
        let p = dir.path().join(format!("bad{k}.json"));
        std::fs::write(&p, input.to_string()).unwrap();
        let (ok, out, err) = corps(&["model", "eval", "--states", p.to_str().unwrap()]);
        assert!(!ok && out.is_empty(), "case {k} should fail");
        assert_eq!(err.lines().count(), 1, "one line: {err}");
        assert!(err.contains(expected), "case {k}: {err}");
    }
    let (ok, _, err) = corps(&["model", "inspect", "--urdf", "/nonexistent.urdf"]);
    assert!(!ok && err.contains("/nonexistent.urdf"));
}

#[test]
fn run_prints_metrics_and_writes_them_with_the_log_and_plots() {
    let out = tempfile::tempdir().unwrap();
    let dir = out.path().to_str().unwrap();
    let (ok, stdout, stderr) = corps(&[
        "run",
        &repo("scenarios/control/tsid_torque_stand.toml"),
        "--duration",
        "0.3",
        "-o",
        dir,
    ]);
    assert!(ok, "{stderr}");
    assert!(
        stdout.contains("TSID (torque)") && stdout.contains("CoM"),
        "{stdout}"
    );
    assert!(stdout.contains("controller time per tick"), "{stdout}");
    let metrics: Value =
        serde_json::from_str(&std::fs::read_to_string(out.path().join("metrics.json")).unwrap())
            .unwrap();
    assert!((metrics["duration"].as_f64().unwrap() - 0.3).abs() < 1e-9);
    assert_eq!(metrics["fallbacks"], json!(0));
    let log = std::fs::read_to_string(out.path().join("log.csv")).unwrap();
    // log_every = 10: 300 ticks give 30 rows after the header.
    assert_eq!(log.lines().count(), 31);
    for plot in ["com.png", "zmp.png", "feet.png", "tick_time.png"] {
        assert!(out.path().join(plot).is_file(), "{plot}");
    }
}

#[test]
fn run_and_sim_reject_each_others_scenarios_and_bad_gains_in_one_line() {
    let (ok, _, stderr) = corps(&["run", &repo("scenarios/stand_flat.toml")]);
    assert!(!ok);
    assert!(stderr.contains("no [controller] section"), "{stderr}");
    assert_eq!(stderr.trim().lines().count(), 1, "{stderr}");

    let (ok, _, stderr) = corps(&["sim", &repo("scenarios/control/tsid_torque_stand.toml")]);
    assert!(!ok);
    assert!(stderr.contains("corps run"), "{stderr}");

    let dir = tempfile::tempdir().unwrap();
    let bad = dir.path().join("bad.toml");
    std::fs::write(
        &bad,
        "duration = 1.0\n[controller]\nkind = \"tsid_torque\"\n[controller.set]\ncom.kp = -1.0\n",
    )
    .unwrap();
    let (ok, _, stderr) = corps(&["run", bad.to_str().unwrap()]);
    assert!(!ok);
    assert!(stderr.contains("com.kp"), "{stderr}");
    assert_eq!(stderr.trim().lines().count(), 1, "{stderr}");
}

#[test]
fn robot_init_drafts_a_description_that_runs_and_never_replaces_a_file() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("humanoid.toml");
    let urdf = repo("robots/simple_humanoid_description/urdf/simple_humanoid.urdf");
    let srdf = repo("robots/simple_humanoid_description/srdf/simple_humanoid.srdf");
    let o = out.to_str().unwrap();
    let (ok, stdout, stderr) = corps(&["robot", "init", &urdf, &srdf, "-o", o]);
    assert!(ok, "{stderr}");
    assert!(stdout.contains("CHECK"), "{stdout}");
    let text = std::fs::read_to_string(&out).unwrap();
    assert!(
        text.contains("[[feet]]") && text.contains("# CHECK"),
        "{text}"
    );
    // The draft loads as it is: a short simulation stands on its guessed feet.
    let run_dir = dir.path().join("run");
    let (ok, _, stderr) = corps(&[
        "sim",
        &repo("scenarios/stand_flat.toml"),
        "--robot",
        o,
        "--duration",
        "0.2",
        "-o",
        run_dir.to_str().unwrap(),
    ]);
    assert!(ok, "{stderr}");
    let (ok, _, stderr) = corps(&["robot", "init", &urdf, "-o", o]);
    assert!(!ok && stderr.contains("already exists"), "{stderr}");
    assert_eq!(std::fs::read_to_string(&out).unwrap(), text);
}

#[test]
fn a_bad_robot_description_is_one_line_and_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    // TALOS' description beside copies of its model files, its gains files by absolute path.
    for f in ["robots/talos_reduced_box.urdf", "srdf/talos.srdf"] {
        let to = dir.path().join(f);
        std::fs::create_dir_all(to.parent().unwrap()).unwrap();
        std::fs::copy(repo(&format!("robots/talos_data/{f}")), to).unwrap();
    }
    let talos = std::fs::read_to_string(repo("robots/talos_data/talos.toml"))
        .unwrap()
        .replace("../../config", &repo("config"));
    let cases = [
        (
            "frame = \"leg_left_sole_fix_joint\"",
            "frame = \"no_sole\"",
            "feet[0].frame",
        ),
        (
            "left = 0.065, right = 0.065 }\nforce_torque = \"left_ankle\"",
            "left = 0.0, right = 0.0 }\nforce_torque = \"left_ankle\"",
            "feet[0].sole: the rectangle has zero area",
        ),
        (
            "ankle = [\"leg_left_5_joint\", \"leg_left_6_joint\"]",
            "ankle = [\"leg_left_5_joint\", \"no_joint\"]",
            "feet[0].ankle: no joint named 'no_joint'",
        ),
    ];
    for (k, (from, to, expected)) in cases.iter().enumerate() {
        assert!(talos.contains(from), "{from}");
        let path = dir.path().join(format!("bad_{k}.toml"));
        std::fs::write(&path, talos.replacen(from, to, 1)).unwrap();
        let out = dir.path().join(format!("out{k}"));
        let (ok, _, stderr) = corps(&[
            "run",
            &repo("scenarios/control/tsid_torque_push_front.toml"),
            "--robot",
            path.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
        ]);
        assert!(!ok, "{to}");
        assert!(stderr.contains(expected), "{stderr}");
        assert_eq!(stderr.trim().lines().count(), 1, "{stderr}");
        assert!(!out.exists(), "{} was written", out.display());
    }
}

/// A `[press]` the run cannot do is one line naming what is wrong: a hand the robot lacks, a
/// controller that cannot drive a contact force, gains without the force task, a bad
/// schedule.
#[test]
fn a_press_scenario_the_run_cannot_do_is_one_line() {
    let dir = tempfile::tempdir().unwrap();
    let press = "[press]\nhand = \"left\"\nforce = [[1.0, 10.0]]\n";
    for (body, expected) in [
        (
            "[controller]\nkind = \"passive_torque\"\n[press]\nhand = \"middle\"\nforce = [[1.0, 10.0]]\n",
            "no hand 'middle'",
        ),
        (
            &format!("[controller]\nkind = \"ik_position\"\n{press}") as &str,
            "torque-mode TSID",
        ),
        (
            &format!("[controller]\nkind = \"tsid_torque\"\n{press}"),
            "[force_contact]",
        ),
        (
            "[controller]\nkind = \"passive_torque\"\n[press]\nhand = \"left\"\nforce = [[0.0, 10.0]]\n",
            "press.force[0]",
        ),
        (
            "[controller]\nkind = \"passive_torque\"\n[press]\nhand = \"left\"\nforce = [[1.0, 10.0]]\nloss_delay = -1.0\n",
            "press.loss_delay",
        ),
    ] {
        let path = dir.path().join("press.toml");
        std::fs::write(&path, format!("duration = 1.0\n{body}")).unwrap();
        let (ok, _, stderr) = corps(&["run", path.to_str().unwrap()]);
        assert!(!ok, "{body}");
        assert!(stderr.contains(expected), "{body}: {stderr}");
        assert_eq!(stderr.trim().lines().count(), 1, "{stderr}");
    }
}
