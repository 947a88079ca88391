//! Co-navigation (seed 000 §3.17, S10): TALOS walks behind a recorded person (streamed at a
//! quarter of their pace, the pattern generator's 0.3 m/s being below people's ~1 m/s) and
//! keeps up; at the person's own pace it loses them and the run says so; bad input about the
//! person stops before the robot moves.

use serde_json::Value;
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
        .args(args)
        .output()
        .expect("corps runs")
}

fn metrics(dir: &std::path::Path) -> Value {
    let text = std::fs::read_to_string(dir.join("metrics.json")).expect("metrics.json");
    serde_json::from_str(&text).expect("JSON")
}

/// The scenario `behind_E1540.toml` with `[human]` keys replaced, written in `dir`.
fn scenario(dir: &std::path::Path, replace: &[(&str, &str)]) -> PathBuf {
    let mut text =
        std::fs::read_to_string(repo("scenarios/conav/behind_E1540.toml")).expect("scenario");
    let data = repo("../shared/data/human-walking");
    text = text.replace(
        "file = \"../../../shared/data/human-walking/",
        &format!("file = \"{}/", data.display()),
    );
    for (key, value) in replace {
        let line = text
            .lines()
            .find(|l| l.starts_with(&format!("{key} =")))
            .unwrap_or_else(|| panic!("{key} in the scenario"))
            .to_string();
        text = text.replace(&line, &format!("{key} = {value}"));
    }
    let path = dir.join("conav.toml");
    std::fs::write(&path, text).expect("write");
    path
}

/// Behind the person at 0.3 m: the walk completes, the robot steps all along, and its CoM
/// stays on average within one step (0.3 m, the pattern generator's speed over one second)
/// of its point; at the end it stands there.
#[test]
fn the_robot_walks_behind_the_person() {
    let dir = tempfile::tempdir().expect("a directory");
    let out = corps(&[
        "run",
        "scenarios/conav/behind_E1540.toml",
        "-o",
        dir.path().to_str().expect("utf-8"),
    ]);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{stdout}{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let m = metrics(dir.path());
    assert_eq!(m["verdict"]["verdict"], "completed");
    let mean = m["mean_following_error_m"].as_f64().expect("a mean");
    let max = m["max_following_error_m"].as_f64().expect("a max");
    let steps = m["steps"].as_u64().expect("steps");
    println!("following error mean {mean:.3} m, max {max:.3} m, {steps} steps");
    assert!(mean < 0.3, "mean following error {mean} m");
    assert!(steps >= 10, "{steps} steps over a 4.2 m walk");
    assert!(m["max_lateral_step_m"].as_f64().is_some());
    for f in ["following.png", "paths.png"] {
        assert!(dir.path().join(f).is_file(), "{f}");
    }
    let log = std::fs::read_to_string(dir.path().join("log.csv")).expect("log");
    let header: Vec<&str> = log.lines().next().expect("a header").split(',').collect();
    let error = header
        .iter()
        .position(|h| *h == "follow_error_m")
        .expect("a follow_error_m column");
    let last: Vec<f64> = (log.lines().last().expect("a row").split(','))
        .map(|x| x.parse().expect("a number"))
        .collect();
    assert!(
        last[error] < 0.1,
        "at the end {} m from its point",
        last[error]
    );
}

/// At the person's own pace (about 1 m/s) the robot cannot keep up: the run ends as soon as
/// the CoM is 1 m from its point, with the verdict `lost_human`, not a fall nor a silent stop.
#[test]
fn a_person_at_their_own_pace_is_lost_and_the_run_says_so() {
    let dir = tempfile::tempdir().expect("a directory");
    let path = scenario(dir.path(), &[("rate", "1.0")]);
    let out = corps(&[
        "run",
        path.to_str().expect("utf-8"),
        "-o",
        dir.path().join("out").to_str().expect("utf-8"),
    ]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("the run ended lost_human"), "{stderr}");
    let m = metrics(&dir.path().join("out"));
    assert_eq!(m["verdict"]["verdict"], "lost_human");
    let lost_at = m["verdict"]["t"].as_f64().expect("a time");
    assert!(m["duration"].as_f64().expect("a duration") <= lost_at + 0.01);
    assert!(m["max_following_error_m"].as_f64().expect("a max") > 1.0);
}

#[test]
fn bad_input_about_the_person_stops_before_the_robot_moves() {
    for (replace, expected) in [
        (vec![("subject", "11")], "human.subject = 11: "),
        (vec![("rate", "0.0")], "human.rate = 0: must be positive"),
        (
            vec![("distance", "-1.0")],
            "human.distance = -1: must be ≥ 0",
        ),
        (vec![("file", "\"no_such_walk.dat\"")], "human.file: "),
    ] {
        let dir = tempfile::tempdir().expect("a directory");
        let path = scenario(dir.path(), &replace);
        let out_dir = dir.path().join("out");
        let out = corps(&[
            "run",
            path.to_str().expect("utf-8"),
            "-o",
            out_dir.to_str().expect("utf-8"),
        ]);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{replace:?}: {stderr}");
        assert_eq!(stderr.lines().count(), 1, "one line: {stderr}");
        assert!(stderr.contains(expected), "{replace:?}: {stderr}");
        assert!(!out_dir.exists(), "{replace:?} wrote {}", out_dir.display());
    }
    // A trajectory file of the wrong shape.
    let dir = tempfile::tempdir().expect("a directory");
    let walk = dir.path().join("short.dat");
    std::fs::write(&walk, "0 1 2\n0 1 2\n").expect("write");
    let path = scenario(dir.path(), &[("file", &format!("\"{}\"", walk.display()))]);
    let out = corps(&[
        "run",
        path.to_str().expect("utf-8"),
        "-o",
        "/nonexistent/out",
    ]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("human.file: "), "{stderr}");
}
