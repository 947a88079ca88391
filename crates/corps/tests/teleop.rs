//! `corps teleop`: a key script drives the velocity walk headless; the robot reaches the
//! distance and heading the keys ask, a fall ends the session with its verdict, and bad input
//! stops before the robot moves.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn repo(rel: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../..")
        .join(rel)
}

fn teleop(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_corps"))
        .current_dir(repo(""))
        .arg("teleop")
        .args(args)
        .output()
        .expect("corps runs")
}

/// The number after `key` in the report (`x = 1.234 m` → 1.234).
fn figure(text: &str, key: &str) -> f64 {
    let at = text
        .find(key)
        .unwrap_or_else(|| panic!("{key:?} in {text}"))
        + key.len();
    let number: String = text[at..]
        .trim_start()
        .chars()
        .take_while(|c| c.is_ascii_digit() || *c == '.' || *c == '-')
        .collect();
    number
        .parse()
        .unwrap_or_else(|_| panic!("a number after {key:?}: {text}"))
}

/// `scenarios/teleop/forward_turn.keys`: 0.2 m/s forward from 0.5 s, turning at 0.1 rad/s
/// from 6 s, stopped at 10 s. The MPC starts with a 1.2 s double support (the robot's
/// walk_mpc settings), so the commanded distance is 0.2 × (10 − 0.5 − 1.2) = 1.66 m, and the
/// heading 0.1 × 4 = 0.4 rad = 22.9°.
#[test]
fn a_key_script_walks_the_distance_and_turns_the_heading_it_asks() {
    let dir = tempfile::tempdir().expect("a directory");
    let out = teleop(&[
        "--keys",
        "scenarios/teleop/forward_turn.keys",
        "--duration",
        "13",
        "-o",
        dir.path().to_str().expect("utf-8"),
    ]);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{stdout}{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(stdout.contains("teleop: completed"), "{stdout}");
    let distance = figure(&stdout, "travelled");
    let heading = figure(&stdout, "turned");
    let steps = figure(&stdout, "°,") as usize;
    println!(
        "distance {distance:.3} m (asked 1.66), heading {heading:.1}° (asked 22.9), {steps} steps"
    );
    assert!(
        (distance - 1.66).abs() < 0.1 * 1.66,
        "distance {distance} m, asked 1.66 m"
    );
    assert!(
        (heading - 22.9).abs() < 2.0,
        "heading {heading}°, asked 22.9°"
    );
    // 1.2 s per step from 1.7 s to 10 s and a closing step: 7 to 9 touchdowns.
    assert!((7..=9).contains(&steps), "{steps} steps");
    // The run's files are written as `corps run` writes them.
    for f in ["log.csv", "metrics.txt", "metrics.json"] {
        assert!(dir.path().join(f).is_file(), "{f}");
    }
}

/// A 300 N sideways shove for 0.2 s knocks the walking robot over: the session ends half a
/// second after the fall with the verdict, not at its 60 s duration.
#[test]
fn a_fall_ends_the_session_with_the_verdict() {
    let dir = tempfile::tempdir().expect("a directory");
    let text = std::fs::read_to_string(repo("scenarios/teleop/talos_keyboard.toml"))
        .expect("the teleop scenario");
    let scenario = dir.path().join("shoved.toml");
    std::fs::write(
        &scenario,
        format!(
            "{text}\n[[push]]\nframe = \"base_link\"\nstart = 3.0\nduration = 0.2\nforce = [0.0, 300.0, 0.0]\n"
        ),
    )
    .expect("write");
    let keys = dir.path().join("walk.keys");
    std::fs::write(&keys, "0.5 i\n").expect("write");
    let out = teleop(&[
        scenario.to_str().expect("utf-8"),
        "--keys",
        keys.to_str().expect("utf-8"),
        "--duration",
        "60",
        "-o",
        dir.path().join("out").to_str().expect("utf-8"),
    ]);
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stdout}{stderr}");
    assert!(stdout.contains("teleop: fell at t = "), "{stdout}");
    assert!(stderr.contains("the run ended fell"), "{stderr}");
    let metrics = std::fs::read_to_string(dir.path().join("out/metrics.json")).expect("metrics");
    let m: serde_json::Value = serde_json::from_str(&metrics).expect("JSON");
    let fell_at = m["verdict"]["t"].as_f64().expect("a fall time");
    let ran = m["duration"].as_f64().expect("a duration");
    assert!(
        ran < fell_at + 0.6,
        "ran {ran} s after a fall at {fell_at} s"
    );
}

fn fails_with(args: &[&str], expected: &str, out_dir: &Path) {
    let out = teleop(args);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{args:?}: {stderr}");
    assert_eq!(stderr.lines().count(), 1, "one line: {stderr}");
    assert!(stderr.contains(expected), "{args:?}: {stderr}");
    assert!(!out_dir.exists(), "{args:?} wrote {}", out_dir.display());
}

#[test]
fn bad_input_stops_before_the_robot_moves() {
    let dir = tempfile::tempdir().expect("a directory");
    let out_dir = dir.path().join("out");
    let out = out_dir.to_str().expect("utf-8");
    let keys = dir.path().join("bad.keys");
    std::fs::write(&keys, "0.5 i\n0.2 k\n").expect("write");
    let keys = keys.to_str().expect("utf-8");
    fails_with(
        &["--keys", keys, "-o", out],
        "bad.keys: line 2: time 0.2 s is before the previous key's 0.5 s",
        &out_dir,
    );
    let unknown = dir.path().join("unknown.keys");
    std::fs::write(&unknown, "1 x\n").expect("write");
    fails_with(
        &["--keys", unknown.to_str().expect("utf-8"), "-o", out],
        "unknown.keys: line 1: unknown key \"x\"",
        &out_dir,
    );
    let ok_keys = repo("scenarios/teleop/forward_turn.keys");
    let ok_keys = ok_keys.to_str().expect("utf-8");
    // A scheduled walk is not steerable; a footstep walk is not a velocity walk.
    fails_with(
        &[
            "scenarios/walk/tsid_torque_velocity.toml",
            "--keys",
            ok_keys,
            "-o",
            out,
        ],
        "motion.commands: a steered walk takes its commands live",
        &out_dir,
    );
    fails_with(
        &[
            "scenarios/walk/tsid_torque_20cm.toml",
            "--keys",
            ok_keys,
            "-o",
            out,
        ],
        "steering needs a velocity walk",
        &out_dir,
    );
    // An address that cannot be listened on.
    fails_with(
        &["--keys", ok_keys, "--stream=no-such-host:1", "-o", out],
        "--stream: listening on no-such-host:1",
        &out_dir,
    );
    // Without a script the keyboard is needed: a test's stdin is no terminal.
    fails_with(&["-o", out], "needs a terminal", &out_dir);
}
