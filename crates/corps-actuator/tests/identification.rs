//! Identification of the elbow drive (seed 000 §6, Table 3.1) on simulated records with the
//! thesis's sensors: 19-bit encoder, current noise giving the thesis's 0.6 N·m fit RMSD,
//! a torque sensor; and the errors bad records give.

mod common;

use corps_actuator::identification::{
    identify, IdentificationData, IdentificationSettings, Segment, PARAMETER_NAMES,
};
use corps_actuator::records::{read_csv, truth, write_csv, RecordSimulation};
use corps_actuator::ActuatorError;

/// Each parameter's error in units of its own estimated σ.
fn z_scores(seed: u64) -> (Vec<f64>, corps_actuator::identification::Identified) {
    let d = common::elbow();
    let sim = RecordSimulation {
        seed,
        ..RecordSimulation::default()
    };
    let r = identify(&sim.run(&d), &IdentificationSettings::default()).unwrap();
    let truth = truth(&d, &sim.payload());
    let z = (0..PARAMETER_NAMES.len() - 1)
        .map(|i| (r.values[i] - truth[i]) / (r.sigma_percent[i] / 100.0 * r.values[i].abs()))
        .collect();
    (z, r)
}

#[test]
fn the_parameters_come_back_within_their_standard_deviations() {
    let (z, r) = z_scores(1);
    let d = common::elbow();
    let truth = truth(&d, &RecordSimulation::default().payload());
    println!("param     identified     truth    σ%    |error|/σ");
    for i in 0..z.len() {
        println!(
            "{:6} {:12.4} {:9.4} {:6.2} {:8.2}",
            PARAMETER_NAMES[i],
            r.values[i],
            truth[i],
            r.sigma_percent[i],
            z[i].abs()
        );
    }
    println!(
        "RMSD {:.3} N·m (thesis 0.6), cond(W_b) {:.1} (thesis 36), {} samples",
        r.rmsd_nm, r.cond, r.samples
    );
    let outside: Vec<&str> = (0..z.len())
        .filter(|&i| z[i].abs() > 2.0)
        .map(|i| PARAMETER_NAMES[i])
        .collect();
    assert!(outside.is_empty(), "outside 2σ: {outside:?}");
    assert!((r.rmsd_nm - 0.6).abs() < 0.1, "RMSD {}", r.rmsd_nm);
    assert!(r.cond < 100.0, "cond {}", r.cond);
}

/// Over independent noise draws the estimated σ must be honest: about 95 % of the errors
/// inside 2σ and no parameter biased.
#[test]
fn the_standard_deviations_are_calibrated_over_noise_draws() {
    let seeds = 20;
    let mut inside = 0;
    let mut total = 0;
    let mut mean = vec![0.0; PARAMETER_NAMES.len() - 1];
    for seed in 1..=seeds {
        let (z, _) = z_scores(100 + seed);
        for (i, zi) in z.iter().enumerate() {
            mean[i] += zi / seeds as f64;
            total += 1;
            inside += usize::from(zi.abs() <= 2.0);
        }
    }
    let coverage = inside as f64 / total as f64;
    println!(
        "{inside}/{total} errors inside 2σ ({:.1} %, nominal 95.4 %)",
        100.0 * coverage
    );
    for (i, m) in mean.iter().enumerate() {
        println!("{:6} mean error {m:+.2} σ", PARAMETER_NAMES[i]);
        // The mean of 20 unit-variance draws has σ 0.22: 0.75 is 3.4 of them.
        assert!(m.abs() < 0.75, "{} biased: {m:+.2} σ", PARAMETER_NAMES[i]);
    }
    assert!(coverage >= 0.9, "coverage {coverage}");
}

#[test]
fn a_csv_record_identifies_as_the_simulated_one() {
    let d = common::elbow();
    let sim = RecordSimulation::default();
    let data = sim.run(&d);
    let back = read_csv(&write_csv(&data), data.payload_moment).unwrap();
    assert_eq!(back.segments.len(), 2);
    let a = identify(&data, &IdentificationSettings::default()).unwrap();
    let b = identify(&back, &IdentificationSettings::default()).unwrap();
    for (x, y) in a.values.iter().zip(&b.values) {
        assert!((x - y).abs() <= 1e-9 * x.abs().max(1.0), "{x} vs {y}");
    }
}

fn message(data: &IdentificationData) -> String {
    identify(data, &IdentificationSettings::default())
        .unwrap_err()
        .to_string()
}

#[test]
fn bad_records_are_clear_errors() {
    let d = common::elbow();
    let data = RecordSimulation::default().run(&d);

    let mut nan = data.clone();
    nan.segments[1].current[1234] = f64::NAN;
    let m = message(&nan);
    assert!(
        m.contains("experiment 2") && m.contains("sample 1235") && m.contains("non-finite"),
        "{m}"
    );

    let mut backwards = data.clone();
    backwards.segments[0].t[50] = backwards.segments[0].t[48];
    let m = message(&backwards);
    assert!(
        m.contains("not increasing") && m.contains("sample 51"),
        "{m}"
    );

    let mut short = data.clone();
    let first = &mut short.segments[0];
    first.t.truncate(40);
    first.q.truncate(40);
    first.current.truncate(40);
    first.torque_sensor.truncate(40);
    let m = message(&short);
    assert!(m.contains("too few"), "{m}");

    let mut alone = data.clone();
    alone.segments.retain(|s| !s.payload);
    assert!(message(&alone).contains("payload"));

    // A constant-velocity sweep: q̈ ≡ 0 never excites the inertias.
    let model = d.model;
    let ramp = |payload: bool| {
        let mut s = Segment {
            payload,
            ..Segment::default()
        };
        let p = if payload {
            RecordSimulation::default().payload()
        } else {
            Default::default()
        };
        for k in 0..20000 {
            let t = k as f64 / 2000.0;
            let (q, v) = (-2.2 + 0.2 * t, 0.2);
            s.t.push(t);
            s.q.push(q);
            s.current
                .push(model.motor_torque(q, v, 0.0, 1.0, &p) / model.drive_gain);
            s.torque_sensor
                .push(model.joint_torque(q, v, 0.0, 1.0, &p) / model.torque_sensor_gain);
        }
        s
    };
    let flat = IdentificationData {
        segments: vec![ramp(false), ramp(true)],
        payload_moment: data.payload_moment,
    };
    let e = identify(&flat, &IdentificationSettings::default()).unwrap_err();
    println!("{e}");
    match e {
        ActuatorError::RankDeficient { cond, cause } => {
            assert!(cond > 1e8);
            assert!(cause.contains("does not excite"), "{cause}");
        }
        other => panic!("{other}"),
    }
}

#[test]
fn bad_csv_files_are_clear_errors() {
    let e = read_csv("t_s,q_rad,current_A\n0,0,0\n", 0.6)
        .unwrap_err()
        .to_string();
    assert!(e.contains("torque_sensor_Nm"), "{e}");
    let e = read_csv(
        "t_s,q_rad,current_A,torque_sensor_Nm,payload\n0,0,0,0,0\n0.1,x,0,0,0\n",
        0.6,
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("line 3") && e.contains("`x`"), "{e}");
    let e = read_csv(
        "t_s,q_rad,current_A,torque_sensor_Nm,payload\n0,0,0,0,0\n0.1,0,0,0,2\n",
        0.6,
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("payload must be 0 or 1"), "{e}");
    let e = read_csv(
        "t_s,q_rad,current_A,torque_sensor_Nm,payload\n0,0,0,0,0\n0.1,0,0,0,0\n0.05,0,0,0,0\n",
        0.6,
    )
    .unwrap_err()
    .to_string();
    assert!(
        e.contains("line 4") && e.contains("does not increase"),
        "{e}"
    );
}
