//! `corps actuator` end to end: identification from simulated experiments and from the CSV
//! they write, the thermal model, the closed-loop iLQR's JSON series, and one-line errors.

use serde_json::Value;
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

fn one_line_error(args: &[&str], needle: &str) {
    let (ok, _, err) = corps(args);
    assert!(!ok, "{args:?} succeeded");
    assert_eq!(err.trim().lines().count(), 1, "{err}");
    assert!(err.contains(needle), "{args:?}: {err}");
}

#[test]
fn identify_simulated_then_recorded() {
    let dir = tempfile::tempdir().unwrap();
    let csv = dir.path().join("elbow.csv");
    let csv = csv.to_str().unwrap();
    let (ok, out, err) = corps(&[
        "actuator",
        "identify",
        "--simulate",
        "--json",
        "--write-data",
        csv,
    ]);
    assert!(ok, "{err}");
    let v: Value = serde_json::from_str(&out).unwrap();
    for name in [
        "M_X", "M_Y", "I_j", "F_Sj", "F_Vj", "Off_j", "I_m", "F_Sm", "F_Vm", "Off_m",
    ] {
        let p = &v["parameters"][name];
        let (value, sigma, truth) = (
            p["value"].as_f64().unwrap(),
            p["sigma_percent"].as_f64().unwrap(),
            p["truth"].as_f64().unwrap(),
        );
        assert!(
            (value - truth).abs() <= 2.0 * sigma / 100.0 * value.abs(),
            "{name}: {p}"
        );
    }
    assert!(v["rmsd_Nm"].as_f64().unwrap() > 0.0 && v["cond"].as_f64().unwrap() > 1.0);
    // The recorded file gives the same parameters, without a truth.
    let (ok, out, err) = corps(&[
        "actuator",
        "identify",
        csv,
        "--payload-moment",
        "0.6",
        "--json",
    ]);
    assert!(ok, "{err}");
    let r: Value = serde_json::from_str(&out).unwrap();
    let a = v["parameters"]["I_m"]["value"].as_f64().unwrap();
    let b = r["parameters"]["I_m"]["value"].as_f64().unwrap();
    assert!((a - b).abs() < 1e-9, "{a} vs {b}");
    assert!(r["parameters"]["I_m"].get("truth").is_none());
    let (ok, out, _) = corps(&["actuator", "identify", "--simulate"]);
    assert!(ok && out.contains("RMSD") && out.contains("F_Sm"), "{out}");
}

#[test]
fn bad_identification_input_is_one_line() {
    let dir = tempfile::tempdir().unwrap();
    let bad = dir.path().join("bad.csv");
    std::fs::write(
        &bad,
        "t_s,q_rad,current_A,torque_sensor_Nm,payload\n0,0,0,0,0\n0.001,NaN,0,0,0\n",
    )
    .unwrap();
    let bad = bad.to_str().unwrap();
    one_line_error(
        &["actuator", "identify", bad, "--payload-moment", "0.6"],
        "non-finite",
    );
    one_line_error(&["actuator", "identify", bad], "--payload-moment");
    one_line_error(&["actuator", "identify"], "--simulate");
    let short = dir.path().join("short.csv");
    let mut text = String::from("t_s,q_rad,current_A,torque_sensor_Nm,payload\n");
    for k in 0..30 {
        text.push_str(&format!(
            "{},{},1,1,{}\n",
            k as f64 * 0.001,
            -1.0,
            u8::from(k >= 15)
        ));
    }
    std::fs::write(&short, text).unwrap();
    one_line_error(
        &[
            "actuator",
            "identify",
            short.to_str().unwrap(),
            "--payload-moment",
            "0.6",
        ],
        "too few",
    );
    let desc = dir.path().join("broken.toml");
    std::fs::write(&desc, "joint = \"x\"\n").unwrap();
    one_line_error(
        &[
            "actuator",
            "identify",
            "--simulate",
            "--actuator",
            desc.to_str().unwrap(),
        ],
        "broken.toml",
    );
}

#[test]
fn thermal_identify_and_predict() {
    let (ok, out, err) = corps(&["actuator", "thermal", "identify", "--simulate", "--json"]);
    assert!(ok, "{err}");
    let v: Value = serde_json::from_str(&out).unwrap();
    let c = &v["C_th_J_per_K"];
    assert!((c["value"].as_f64().unwrap() / c["truth"].as_f64().unwrap() - 1.0).abs() < 0.02);
    let (ok, out, err) = corps(&[
        "actuator",
        "thermal",
        "predict",
        "--hold-kg",
        "20",
        "--json",
    ]);
    assert!(ok, "{err}");
    let v: Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["safe"], Value::Bool(true), "{v}");
    one_line_error(
        &["actuator", "thermal", "predict", "--hold-kg=-3"],
        "must be finite and ≥ 0",
    );
    one_line_error(
        &["actuator", "thermal", "predict", "--hold-kg", "inf"],
        "must be finite",
    );
    one_line_error(
        &["actuator", "thermal", "predict", "--duration-s", "1e12"],
        "equilibrium",
    );
    let dir = tempfile::tempdir().unwrap();
    let flat = dir.path().join("flat.csv");
    let mut text = String::from("t_s,current_A,temperature_C\n");
    for k in 0..100 {
        text.push_str(&format!("{k},0,43\n"));
    }
    std::fs::write(&flat, text).unwrap();
    one_line_error(
        &["actuator", "thermal", "identify", flat.to_str().unwrap()],
        "rank-deficient",
    );
}

#[test]
fn mpc_prints_the_closed_loop_series() {
    let series = |extra: &[&str]| -> Value {
        let mut args = vec!["actuator", "mpc", "--payload-kg", "30", "--json"];
        args.extend_from_slice(extra);
        let (ok, out, err) = corps(&args);
        assert!(ok, "{err}");
        serde_json::from_str(&out).unwrap()
    };
    let min = |v: &Value, key: &str| {
        v[key]
            .as_array()
            .unwrap()
            .iter()
            .map(|x| x.as_f64().unwrap())
            .fold(f64::INFINITY, f64::min)
    };
    let with = series(&[]);
    let n = with["t"].as_array().unwrap().len();
    assert_eq!(n, with["q_rad"].as_array().unwrap().len());
    assert_eq!(n, with["current_A"].as_array().unwrap().len());
    assert!(min(&with, "current_A") > -6.0 && min(&with, "q_rad") > -2.35);
    let without = series(&["--no-barrier"]);
    assert!(min(&without, "current_A") < -6.0);
    one_line_error(&["actuator", "mpc", "--payload-kg=-1"], "payload");
    one_line_error(&["actuator", "mpc", "--duration-s", "1e9"], "in memory");
    one_line_error(
        &["actuator", "mpc", "--period-s", "1e-6"],
        "two control periods",
    );
    one_line_error(&["actuator", "mpc", "--payload-kg", "1e9"], "diverges");
}

#[test]
fn bad_drive_settings_are_one_line() {
    let dir = tempfile::tempdir().unwrap();
    let write = |name: &str, text: &str| {
        let p = dir.path().join(name);
        std::fs::write(&p, text).unwrap();
        p.to_str().unwrap().to_string()
    };
    let base =
        "duration = 0.05\n[controller]\nkind = \"tsid_torque\"\n[actuation]\ndrives = true\n";
    let plain = write("plain.toml", base);
    // iCub's description gives no drives.
    one_line_error(&["run", &plain, "--robot", "icub"], "no [drives] section");
    let soft = write(
        "soft.toml",
        &format!("{base}[actuation.drive]\nstiffness = -5.0\n"),
    );
    one_line_error(&["run", &soft], "stiffness");
    let typo = write(
        "typo.toml",
        &format!("{base}[actuation.drive]\nstifness = 5.0\n"),
    );
    one_line_error(&["run", &typo], "stifness");
}
