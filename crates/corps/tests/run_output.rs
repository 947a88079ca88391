//! What `corps run` leaves on disk when its output cannot be written as planned: a log over
//! its size cap is refused before the run starts, a full disk stops the run with one line, a
//! killed run leaves every row up to its last flush, and two runs never share a directory.

use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

fn repo(rel: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../..")
        .join(rel)
}

fn stand() -> PathBuf {
    repo("scenarios/control/tsid_torque_stand.toml")
}

/// `corps run` with `args`: (success, stderr).
fn corps_run(args: &[&str]) -> (bool, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_corps"))
        .arg("run")
        .args(args)
        .output()
        .expect("runs");
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

fn spawn_run(args: &[&str]) -> Child {
    Command::new(env!("CARGO_BIN_EXE_corps"))
        .arg("run")
        .args(args)
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .expect("starts")
}

/// Sends SIGINT to `run` and waits: the command exits with status 130. Its stderr.
#[cfg(unix)]
fn interrupt(run: Child) -> String {
    let sent = Command::new("kill")
        .args(["-INT", &run.id().to_string()])
        .status()
        .unwrap();
    assert!(sent.success());
    let o = run.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&o.stderr).into_owned();
    assert_eq!(o.status.code(), Some(130), "{stderr}");
    stderr
}

/// `corps run SCENARIO -o OUT --duration 0.1`: (success, stderr).
fn short_run(scenario: &Path, out: &Path) -> (bool, String) {
    corps_run(&[
        scenario.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--duration",
        "0.1",
    ])
}

/// The rows of a CSV log, each checked to have as many values as the header has columns.
fn whole_rows(text: &str) -> Vec<Vec<f64>> {
    let mut lines = text.lines();
    let columns = lines.next().unwrap().split(',').count();
    let rows: Vec<Vec<f64>> = lines
        .map(|l| l.split(',').map(|x| x.parse().unwrap()).collect())
        .collect();
    assert!(rows.iter().all(|r| r.len() == columns), "a row is cut");
    rows
}

/// Waits until `path` holds rows past `t` seconds (or panics after a minute).
fn wait_for_rows(path: &Path, t: f64) {
    let start = Instant::now();
    loop {
        let text = std::fs::read_to_string(path).unwrap_or_default();
        let last = text
            .lines()
            .skip(1)
            .last()
            .and_then(|l| l.split(',').next()?.parse::<f64>().ok());
        if last.is_some_and(|x| x > t) {
            return;
        }
        assert!(
            start.elapsed() < Duration::from_secs(60),
            "no rows past {t} s"
        );
        std::thread::sleep(Duration::from_millis(50));
    }
}

#[test]
fn a_log_over_its_cap_is_refused_before_the_run_starts() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("out");
    let o = out.to_str().unwrap();
    let s = stand();
    let (ok, err) = corps_run(&[s.to_str().unwrap(), "-o", o, "--max-log-mb", "0.1"]);
    assert!(!ok);
    assert!(err.contains("would take about"), "{err}");
    assert!(err.contains("max_log_mb"), "{err}");
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(!out.exists(), "nothing written");
    let (ok, err) = corps_run(&[s.to_str().unwrap(), "-o", o, "--max-log-mb=-1"]);
    assert!(!ok && err.contains("--max-log-mb"), "{err}");
    let (ok, err) = corps_run(&[
        s.to_str().unwrap(),
        "-o",
        o,
        "--max-log-mb",
        "0.5",
        "--duration",
        "0.2",
    ]);
    assert!(ok, "{err}");
    assert!(out.join("log.csv").exists());
}

#[test]
#[cfg(target_os = "linux")]
fn a_full_disk_stops_the_run_with_one_line() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("out");
    std::fs::create_dir(&out).unwrap();
    // The log's file is a device that is always full.
    std::os::unix::fs::symlink("/dev/full", out.join("log.csv.partial")).unwrap();
    let s = stand();
    let (ok, err) = corps_run(&[s.to_str().unwrap(), "-o", out.to_str().unwrap()]);
    assert!(!ok);
    assert!(err.contains("No space left on device"), "{err}");
    assert_eq!(err.lines().count(), 1, "{err}");
}

#[test]
#[cfg(unix)]
fn a_killed_run_leaves_whole_rows_up_to_its_last_flush() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("out");
    let s = stand();
    let mut run = spawn_run(&[
        s.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--duration",
        "60",
    ]);
    let partial = out.join("log.csv.partial");
    wait_for_rows(&partial, 1.5);
    // While it runs, a second run into the same directory is refused.
    let (ok, err) = corps_run(&[s.to_str().unwrap(), "-o", out.to_str().unwrap()]);
    assert!(!ok && err.contains("another corps run"), "{err}");
    run.kill().unwrap();
    run.wait().unwrap();
    let text = std::fs::read_to_string(&partial).unwrap();
    assert!(text.ends_with('\n'), "whole rows only");
    let rows = whole_rows(&text);
    assert!(rows.last().unwrap()[0] > 1.5);
    assert!(
        !out.join("log.csv").exists(),
        "a killed run is no finished log"
    );
    // The directory is free again.
    let (ok, err) = short_run(&s, &out);
    assert!(ok, "{err}");
    assert!(out.join("log.csv").exists() && !partial.exists());
}

#[test]
#[cfg(unix)]
fn ctrl_c_stops_the_run_with_a_whole_log_marked_interrupted_and_status_130() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("out");
    let s = stand();
    let run = Command::new(env!("CARGO_BIN_EXE_corps"))
        .args(["run", s.to_str().unwrap(), "-o", out.to_str().unwrap()])
        .args(["--duration", "600"])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("starts");
    wait_for_rows(&out.join("log.csv.partial"), 1.0);
    let stderr = interrupt(run);
    let last = stderr.lines().last().unwrap_or_default();
    assert!(last.starts_with("corps: interrupted at t = "), "{stderr}");
    // The log is a finished one, of whole rows, ending where the metrics say.
    let rows = whole_rows(&std::fs::read_to_string(out.join("log.csv")).unwrap());
    let m: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("metrics.json")).unwrap()).unwrap();
    let at = m["interrupted_at"].as_f64().expect("marked interrupted");
    let last_t = rows.last().unwrap()[0];
    // `interrupted_at` is the controlled time reached (ticks run × dt); the log keeps one row
    // in `log_every` = 10 ticks of 1 ms, so its last row is at most 10 ms before.
    assert!(
        last_t > 1.0 && last_t < at && at - last_t <= 0.010 + 1e-9,
        "{last_t} {at}"
    );
    assert!(!out.join("log.csv.partial").exists());
}

#[test]
fn plots_false_removes_the_plots_of_an_earlier_run() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("out");
    let s = stand();
    let (ok, err) = short_run(&s, &out);
    assert!(ok, "{err}");
    assert!(out.join("com.png").is_file());
    let text = std::fs::read_to_string(&s).unwrap();
    let no_plots = tmp.path().join("no_plots.toml");
    let text = text.replacen("[output]\n", "[output]\nplots = false\n", 1);
    assert!(text.contains("plots = false"));
    std::fs::write(&no_plots, text).unwrap();
    let (ok, err) = short_run(&no_plots, &out);
    assert!(ok, "{err}");
    let pngs: Vec<_> = std::fs::read_dir(&out)
        .unwrap()
        .filter_map(|e| e.ok())
        .filter(|e| e.path().extension().is_some_and(|x| x == "png"))
        .collect();
    assert!(pngs.is_empty(), "stale plots: {pngs:?}");
}

#[test]
fn a_closed_stdout_ends_the_command_quietly() {
    let mut child = Command::new(env!("CARGO_BIN_EXE_corps"))
        .args(["model", "inspect", "--json"])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("starts");
    // `corps model inspect --json | head -c 0`: the reader is gone before the first write.
    drop(child.stdout.take());
    let o = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{stderr}");
    assert!(stderr.is_empty(), "{stderr}");
}

#[test]
#[cfg(unix)]
fn ctrl_c_while_the_robot_settles_exits_130_too() {
    let tmp = tempfile::tempdir().unwrap();
    let scenario = tmp.path().join("long_settle.toml");
    let text = std::fs::read_to_string(stand()).unwrap().replacen(
        "kind = \"tsid_torque\"",
        "kind = \"tsid_torque\"\nsettle = 600.0",
        1,
    );
    assert!(text.contains("settle = 600.0"));
    std::fs::write(&scenario, text).unwrap();
    let run = Command::new(env!("CARGO_BIN_EXE_corps"))
        .args(["run", scenario.to_str().unwrap(), "-o"])
        .arg(tmp.path().join("out"))
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("starts");
    std::thread::sleep(Duration::from_millis(800));
    let stderr = interrupt(run);
    assert!(stderr.contains("interrupted at t = 0.000 s"), "{stderr}");
}
