//! A push delivers exactly its impulse, once: 100 N for 0.1 s adds 10 N·s to the linear
//! momentum of a free-floating robot (no terrain, no gravity, so the push is the only external
//! force and joint torques are internal), measured as the total mass times the CoM velocity.

use corps::run::{run_text, RunOptions};
use std::path::Path;

const FLOATING: &str = r#"
duration = 0.5
[terrain]
preset = "none"
[[push]]
frame = "base_link"
start = 0.2
duration = 0.1
force = [100.0, 0.0, 0.0]
[sim]
integrator = "rk4"
gravity = [0.0, 0.0, 0.0]
[output]
plots = false
"#;

/// TALOS' mass with box feet (kg), as `corps model inspect` prints it.
const MASS: f64 = 90.2722;

fn csv(path: &Path) -> (Vec<String>, Vec<Vec<f64>>) {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let header = lines.next().unwrap().split(',').map(String::from).collect();
    let rows = lines
        .map(|l| l.split(',').map(|x| x.parse().unwrap()).collect())
        .collect();
    (header, rows)
}

fn col(header: &[String], name: &str) -> usize {
    header.iter().position(|h| h == name).unwrap()
}

#[test]
fn a_controller_run_applies_its_push_once() {
    // The controller has no contact to use and falls back to its safe command; its torques
    // are internal and cannot change the momentum.
    let text =
        format!("{FLOATING}\n[controller]\nkind = \"tsid_torque\"\n[motion]\nkind = \"stand\"\n");
    let out = tempfile::tempdir().unwrap();
    run_text(
        &text,
        Path::new("floating.toml"),
        Some(out.path()),
        None,
        RunOptions::quiet(),
    )
    .unwrap();
    let (h, rows) = csv(&out.path().join("log.csv"));
    let (t, x) = (col(&h, "t"), col(&h, "com_x"));
    // CoM velocity between 0.32 and 0.45 s (after the push), from the CoM positions.
    let at = |time: f64| rows.iter().find(|r| (r[t] - time).abs() < 1e-9).unwrap()[x];
    let p = MASS * (at(0.45) - at(0.32)) / 0.13;
    let before = MASS * (at(0.19) - at(0.05)) / 0.14;
    assert!(before.abs() < 1e-3, "momentum before the push {before}");
    assert!((p - 10.0).abs() < 1e-2, "momentum after the push {p} N·s");
}

#[test]
fn a_simulation_applies_its_push_once() {
    let tmp = tempfile::tempdir().unwrap();
    let file = tmp.path().join("floating.toml");
    std::fs::write(
        &file,
        format!("{FLOATING}\n[actuation]\nmode = \"torque\"\n"),
    )
    .unwrap();
    let out = tmp.path().join("out");
    let status = std::process::Command::new(env!("CARGO_BIN_EXE_corps"))
        .args(["sim", file.to_str().unwrap(), "-o", out.to_str().unwrap()])
        .output()
        .unwrap();
    assert!(
        status.status.success(),
        "{}",
        String::from_utf8_lossy(&status.stderr)
    );
    let (h, rows) = csv(&out.join("log.csv"));
    let p = MASS * rows.last().unwrap()[col(&h, "com_vx_m_s")];
    assert!((p - 10.0).abs() < 1e-5, "momentum after the push {p} N·s");
}

/// The controller sees the encoders through the estimator: noise on them reaches the
/// commanded torques (and so the work the joints do), with the same seed the same way.
#[test]
fn encoder_noise_reaches_the_commanded_torques() {
    let stand = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../../scenarios/control/tsid_torque_stand.toml"),
    )
    .unwrap()
    .replacen("[output]\n", "[output]\nplots = false\n", 1);
    let work = |noise: &str| {
        let text = format!("{stand}\n{noise}");
        let out = tempfile::tempdir().unwrap();
        let m = run_text(
            &text,
            Path::new("stand.toml"),
            Some(out.path()),
            Some(0.3),
            RunOptions::quiet(),
        )
        .unwrap()
        .metrics;
        assert_eq!(m.fallbacks, 0, "{:?}", m.first_fallback);
        m.work
    };
    let clean = work("");
    let noisy = work("[noise.encoders]\nstd = 1e-3\n");
    assert_ne!(clean, noisy, "encoder noise changed nothing");
    assert_eq!(
        noisy,
        work("[noise.encoders]\nstd = 1e-3\n"),
        "reproducible with the seed"
    );
    // Ground truth ignores the sensors' noise.
    let truth = "[estimator]\nkind = \"ground_truth\"\n";
    assert_eq!(
        work(truth),
        work(&format!("{truth}[noise.encoders]\nstd = 1e-3\n"))
    );
}
