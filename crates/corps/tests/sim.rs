//! `corps sim` end to end: short scenarios write the CSV log (expected columns, one row per
//! control tick) and the PNG plots; bad scenario files fail with one line naming the key; a
//! failing run leaves the previous log untouched. Simulated durations are kept short.

use std::path::{Path, PathBuf};
use std::process::Command;

struct Run {
    ok: bool,
    stdout: String,
    stderr: String,
}

fn corps_sim(scenario: &Path, args: &[&str], cwd: &Path) -> Run {
    let out = Command::new(env!("CARGO_BIN_EXE_corps"))
        .arg("sim")
        .arg(scenario)
        .args(args)
        .current_dir(cwd)
        .output()
        .expect("runs");
    Run {
        ok: out.status.success(),
        stdout: String::from_utf8_lossy(&out.stdout).into_owned(),
        stderr: String::from_utf8_lossy(&out.stderr).into_owned(),
    }
}

fn repo(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../..")
        .join(rel)
}

/// Writes `text` as `name` in `dir` and returns its path.
fn scenario(dir: &Path, name: &str, text: &str) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

/// The CSV as a header and rows of numbers.
fn read_csv(path: &Path) -> (Vec<String>, Vec<Vec<f64>>) {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let header: Vec<String> = lines.next().unwrap().split(',').map(String::from).collect();
    let rows = lines
        .map(|l| l.split(',').map(|x| x.parse::<f64>().unwrap()).collect())
        .collect();
    (header, rows)
}

fn column(header: &[String], name: &str) -> usize {
    header
        .iter()
        .position(|h| h == name)
        .unwrap_or_else(|| panic!("no column {name}"))
}

const PLOTS: [&str; 5] = [
    "base_height.png",
    "com.png",
    "cop.png",
    "contact_forces.png",
    "joint_torques.png",
];

#[test]
fn a_short_stand_writes_the_log_and_the_plots() {
    let tmp = tempfile::tempdir().unwrap();
    let file = scenario(
        tmp.path(),
        "stand.toml",
        "duration = 0.3\n[terrain]\npreset = \"flat\"\n",
    );
    let run = corps_sim(&file, &[], tmp.path());
    assert!(run.ok, "{}", run.stderr);
    // Default output directory: out/<file stem>, relative to the current directory.
    let dir = tmp.path().join("out/stand");
    let (header, rows) = read_csv(&dir.join("log.csv"));
    for name in [
        "t_s",
        "base_x_m",
        "base_z_m",
        "base_qw",
        "base_wz_rad_s",
        "com_z_m",
        "q_leg_left_4_joint_rad",
        "v_leg_left_4_joint_rad_s",
        "tau_leg_left_4_joint_Nm",
        "ft_left_ankle_fz_N",
        "ft_right_ankle_ty_Nm",
        "ft_left_wrist_fx_N",
        "imu_qw",
        "imu_wx_rad_s",
        "imu_az_m_s2",
        "contact_fz_left_N",
        "contact_fz_right_N",
        "contact_fz_total_N",
        "meas_q_leg_left_4_joint_rad",
        "meas_ft_left_ankle_fz_N",
        "meas_imu_az_m_s2",
    ] {
        column(&header, name);
    }
    // 32 actuated joints × 3, 4 F/T sensors × 6, IMU 10, base 13, for truth and measured;
    // time, CoM 6, contact forces 3.
    assert_eq!(header.len(), 2 * (96 + 24 + 10 + 13) + 1 + 6 + 3);
    assert_eq!(rows.len(), 300, "one row per 1 ms tick");
    assert!(rows.iter().all(|r| r.len() == header.len()));
    let t = column(&header, "t_s");
    assert!((rows[0][t] - 0.001).abs() < 1e-12 && (rows[299][t] - 0.3).abs() < 1e-9);
    // Standing: the ground carries the robot's weight (90.3 kg, box feet model).
    let last = &rows[299];
    let total = last[column(&header, "contact_fz_total_N")];
    let feet =
        last[column(&header, "contact_fz_left_N")] + last[column(&header, "contact_fz_right_N")];
    assert!(
        (total - 90.27 * 9.81).abs() < 0.05 * 885.0,
        "total {total} N"
    );
    assert!((feet - total).abs() < 1.0, "feet {feet} N, total {total} N");
    assert!(last[column(&header, "base_z_m")] > 1.0);
    // No noise: the measured columns equal the truth.
    let (q, mq) = (
        column(&header, "q_leg_left_4_joint_rad"),
        column(&header, "meas_q_leg_left_4_joint_rad"),
    );
    assert_eq!(last[q], last[mq]);
    for png in PLOTS {
        let bytes = std::fs::read(dir.join(png)).unwrap();
        assert!(bytes.starts_with(b"\x89PNG\r\n\x1a\n"), "{png}");
    }
    // No temporary file is left behind.
    let names: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(names.len(), 6, "{names:?}");
    for line in [
        "simulated        0.300 s",
        "real-time factor",
        "verdict          completed",
    ] {
        assert!(run.stdout.contains(line), "{}", run.stdout);
    }
}

#[test]
fn a_push_moves_the_robot_and_noise_is_seeded() {
    let tmp = tempfile::tempdir().unwrap();
    let text = r#"
name = "pushed"
duration = 0.4
seed = 7
[[push]]
frame = "base_link"
start = 0.1
duration = 0.1
force = [100.0, 0.0, 0.0]
[noise.encoders]
std = 1e-3
[output]
directory = "pushed_out"
plots = false
"#;
    let file = scenario(tmp.path(), "push.toml", text);
    let run = corps_sim(&file, &[], tmp.path());
    assert!(run.ok, "{}", run.stderr);
    let dir = tmp.path().join("pushed_out");
    assert!(!dir.join("com.png").exists(), "plots = false");
    let (header, rows) = read_csv(&dir.join("log.csv"));
    assert_eq!(rows.len(), 400);
    let x = column(&header, "base_x_m");
    let before = rows[99][x];
    let after = rows[399][x];
    assert!(after - before > 1e-3, "base moved {:.4} m", after - before);
    // Encoder noise: measured differs from truth, by about its standard deviation.
    let (q, mq) = (
        column(&header, "q_leg_left_4_joint_rad"),
        column(&header, "meas_q_leg_left_4_joint_rad"),
    );
    let err: Vec<f64> = rows.iter().map(|r| r[mq] - r[q]).collect();
    let rms = (err.iter().map(|e| e * e).sum::<f64>() / err.len() as f64).sqrt();
    assert!((rms - 1e-3).abs() < 2e-4, "rms {rms}");
    // Same seed, same log.
    let first = std::fs::read(dir.join("log.csv")).unwrap();
    let run = corps_sim(&file, &[], tmp.path());
    assert!(run.ok, "{}", run.stderr);
    assert!(first == std::fs::read(dir.join("log.csv")).unwrap());
    assert!(run.stdout.contains("scenario pushed"), "{}", run.stdout);
}

#[test]
fn the_shipped_scenarios_run() {
    let tmp = tempfile::tempdir().unwrap();
    for name in [
        "stand_flat",
        "push_front",
        "stairs",
        "tilted_platforms",
        "stick",
        "free_fall",
    ] {
        let file = repo(&format!("scenarios/{name}.toml"));
        let out = tmp.path().join(name);
        let run = corps_sim(
            &file,
            &["--duration", "0.05", "-o", out.to_str().unwrap()],
            tmp.path(),
        );
        assert!(run.ok, "{name}: {}", run.stderr);
        assert!(
            run.stdout.contains("verdict          completed"),
            "{name}: {}",
            run.stdout
        );
        let (_, rows) = read_csv(&out.join("log.csv"));
        assert_eq!(rows.len(), 50, "{name}");
    }
}

#[test]
fn a_robot_given_by_relative_paths_runs_without_sensors() {
    let tmp = tempfile::tempdir().unwrap();
    let robot = tmp.path().join("robot");
    std::fs::create_dir(&robot).unwrap();
    std::fs::copy(
        repo("robots/talos_data/robots/talos_reduced_box.urdf"),
        robot.join("talos.urdf"),
    )
    .unwrap();
    std::fs::copy(
        repo("robots/talos_data/srdf/talos.srdf"),
        robot.join("talos.srdf"),
    )
    .unwrap();
    let file = scenario(
        &robot,
        "s.toml",
        "duration = 0.02\n[robot]\nurdf = \"talos.urdf\"\nsrdf = \"talos.srdf\"\n",
    );
    // Run from another directory: the robot paths are relative to the scenario file.
    let run = corps_sim(&file, &["-o", "o"], tmp.path());
    assert!(run.ok, "{}", run.stderr);
    let (header, rows) = read_csv(&tmp.path().join("o/log.csv"));
    assert_eq!(rows.len(), 20);
    assert!(!header.iter().any(|h| h.starts_with("ft_")));
    assert!(!tmp.path().join("o/cop.png").exists());
    assert!(
        run.stdout.contains("max foot slip    n/a"),
        "{}",
        run.stdout
    );
}

#[test]
fn bad_scenarios_fail_with_one_line_naming_the_key() {
    let tmp = tempfile::tempdir().unwrap();
    let push = |frame: &str| {
        format!("duration = 0.1\n[[push]]\nframe = \"{frame}\"\nstart = 0.0\nduration = 0.1\nforce = [1.0, 0.0, 0.0]\n")
    };
    let cases: Vec<(String, &str)> = vec![
        ("duraton = 1.0\n".into(), "unknown field `duraton`"),
        (
            "duration = 1.0\n[terrain]\npreset = \"moon\"\n".into(),
            "terrain.preset: unknown variant `moon`",
        ),
        (
            "duration = -1.0\n".into(),
            "duration: must be a positive number",
        ),
        (push("nose"), "push[0].frame: unknown frame 'nose'"),
        (
            "duration = 0.1\n[initial]\nconfiguration = \"crouch\"\n".into(),
            "initial.configuration: unknown reference configuration 'crouch'",
        ),
        (
            "duration = 0.1\n[sim]\nsubsteps = 0\n".into(),
            "sim.substeps",
        ),
        (
            "duration = 0.1\n[actuation]\nmode = \"magic\"\n".into(),
            "actuation.mode",
        ),
        (
            "duration = 0.1\n[noise.force]\nstd = -2.0\n".into(),
            "noise.force.std",
        ),
        (
            "duration = 0.1\n[terrain]\npreset = \"tilted_platforms\"\n[initial]\nbase_xy = [0.75, 0.0]\n"
                .into(),
            "initial: the robot starts",
        ),
        (
            "duration = 0.1\n[robot]\nurdf = \"missing.urdf\"\n".into(),
            "robot: loading",
        ),
        (
            "duration = 0.1\nduration = 0.2\n".into(),
            "line 2: duplicate key `duration`",
        ),
    ];
    for (k, (text, expected)) in cases.iter().enumerate() {
        let file = scenario(tmp.path(), &format!("bad{k}.toml"), text);
        let run = corps_sim(&file, &["-o", "out"], tmp.path());
        assert!(!run.ok, "{text}");
        assert_eq!(run.stderr.lines().count(), 1, "{text}: {}", run.stderr);
        assert!(
            run.stderr
                .starts_with(&format!("corps: error: {}", file.display())),
            "{}",
            run.stderr
        );
        assert!(run.stderr.contains(expected), "{text}: {}", run.stderr);
    }
    let run = corps_sim(&tmp.path().join("nowhere.toml"), &[], tmp.path());
    assert!(!run.ok);
    assert_eq!(
        run.stderr.trim(),
        format!(
            "corps: error: {}: no such scenario file",
            tmp.path().join("nowhere.toml").display()
        )
    );
    let run = corps_sim(
        &scenario(tmp.path(), "ok.toml", "duration = 1.0\n"),
        &["--duration=-3"],
        tmp.path(),
    );
    assert!(
        !run.ok
            && run
                .stderr
                .contains("--duration: duration: must be a positive"),
        "{}",
        run.stderr
    );
}

#[test]
fn a_diverging_run_ends_with_its_verdict_and_a_bad_file_touches_nothing() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("out");
    let good = scenario(tmp.path(), "good.toml", "duration = 0.05\n");
    assert!(corps_sim(&good, &["-o", "out"], tmp.path()).ok);
    // A gigantic push makes the simulation diverge part-way through the run (t = 0.02 s):
    // the run ends there with the verdict `diverged`, its log up to then, and exit status 1.
    let diverging = scenario(
        tmp.path(),
        "diverging.toml",
        "duration = 1.0\n[[push]]\nframe = \"base_link\"\nstart = 0.02\nduration = 0.01\nforce = [0.0, 0.0, 1e9]\n",
    );
    let run = corps_sim(&diverging, &["-o", "out"], tmp.path());
    assert!(!run.ok);
    assert!(
        run.stdout.contains("verdict          diverged at t = 0.02"),
        "{}",
        run.stdout
    );
    assert!(
        run.stderr.contains("the run ended diverged"),
        "{}",
        run.stderr
    );
    assert_eq!(run.stderr.lines().count(), 1, "{}", run.stderr);
    let (header, rows) = read_csv(&out.join("log.csv"));
    let t = column(&header, "t_s");
    assert!(
        rows.last().unwrap()[t] < 0.03,
        "the log stops at the divergence"
    );
    let log = std::fs::read(out.join("log.csv")).unwrap();
    let plot = std::fs::read(out.join("com.png")).unwrap();
    // A bad file fails before touching anything either.
    let bad = scenario(
        tmp.path(),
        "bad.toml",
        "duration = 0.05\n[terrain]\npreset = \"moon\"\n",
    );
    assert!(!corps_sim(&bad, &["-o", "out"], tmp.path()).ok);
    assert!(std::fs::read(out.join("log.csv")).unwrap() == log);
    assert!(std::fs::read(out.join("com.png")).unwrap() == plot);
    let leftovers: Vec<_> = std::fs::read_dir(&out)
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .filter(|n| n.to_string_lossy().starts_with('.'))
        .collect();
    assert!(leftovers.is_empty(), "{leftovers:?}");
}
