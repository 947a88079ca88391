//! The thermal model (seed 000 Eq 3.6–3.8): identification on a simulated heating and
//! cooling record, the holding case of §4.1, and bad records.

mod common;

use corps_actuator::thermal::{identify_thermal, HeatingRecord, HeatingSimulation};
use corps_actuator::ActuatorError;

#[test]
fn a_heating_record_gives_back_the_thermal_parameters() {
    let truth = common::elbow().thermal;
    let record = HeatingSimulation::default().run(&truth);
    let fit = identify_thermal(&record, &truth).unwrap();
    let pairs = [
        (
            "C_th",
            fit.heat_capacity_j_per_k,
            truth.heat_capacity_j_per_k,
            fit.sigma_percent[0],
        ),
        (
            "R_th",
            fit.thermal_resistance_k_per_w,
            truth.thermal_resistance_k_per_w,
            fit.sigma_percent[1],
        ),
        (
            "P_0",
            fit.idle_power_w,
            truth.idle_power(),
            fit.sigma_percent[2],
        ),
    ];
    for (name, value, expected, sigma) in pairs {
        let z = (value - expected).abs() / (sigma / 100.0 * value.abs());
        println!("{name}: {value:.4} (truth {expected:.4}), σ {sigma:.3} %, {z:.2} σ off");
        assert!(z < 3.0, "{name}: {value} vs {expected} ({z:.1} σ)");
        assert!(
            (value / expected - 1.0).abs() < 0.02,
            "{name}: {value} vs {expected}"
        );
    }
    // The simulated model's temperature follows the record to the sensor's noise (0.1 °C).
    println!("temperature RMSD {:.3} K", fit.rmsd_k);
    assert!(fit.rmsd_k < 0.2, "{}", fit.rmsd_k);
}

#[test]
fn holding_20_kg_at_5_cm_from_the_elbow_is_thermally_safe() {
    let d = common::elbow();
    // Worst posture: the forearm horizontal, link and payload moments adding up.
    let torque = corps_actuator::elbow::G * (d.model.m_y + 20.0 * 0.05);
    let current = torque / d.model.drive_gain;
    let steady = d
        .thermal
        .steady_state(current)
        .expect("an equilibrium exists");
    let after_hour = d.thermal.predict(d.thermal.idle_c, current, 3600.0);
    println!(
        "holding 20 kg at 5 cm: {current:.2} A, {after_hour:.1} °C after an hour, \
         {steady:.1} °C at equilibrium, limit {} °C",
        d.thermal.max_temperature_c
    );
    assert!(after_hour <= steady + 1e-9 && steady < d.thermal.max_temperature_c);
    // The continuous current the limit allows is well above it.
    let mut i = current;
    while d
        .thermal
        .steady_state(i)
        .is_some_and(|t| t < d.thermal.max_temperature_c)
    {
        i += 0.01;
    }
    println!("continuous current at the limit: {i:.2} A");
    assert!(i > current);
}

#[test]
fn bad_records_are_errors() {
    let truth = common::elbow().thermal;
    let good = HeatingSimulation::default().run(&truth);
    let mut nan = good.clone();
    nan.temperature[7] = f64::NAN;
    let e = identify_thermal(&nan, &truth).unwrap_err();
    assert!(e.to_string().contains("row 8"), "{e}");
    let mut backwards = good.clone();
    backwards.t[5] = backwards.t[3];
    let e = identify_thermal(&backwards, &truth).unwrap_err();
    assert!(e.to_string().contains("does not increase"), "{e}");
    let short = HeatingRecord {
        t: good.t[..5].to_vec(),
        current: good.current[..5].to_vec(),
        temperature: good.temperature[..5].to_vec(),
    };
    assert!(matches!(
        identify_thermal(&short, &truth),
        Err(ActuatorError::Data(_))
    ));
    // No current, constant temperature: nothing to separate.
    let flat = HeatingRecord {
        t: good.t.clone(),
        current: vec![0.0; good.t.len()],
        temperature: vec![truth.idle_c; good.t.len()],
    };
    let e = identify_thermal(&flat, &truth).unwrap_err();
    assert!(matches!(e, ActuatorError::RankDeficient { .. }), "{e}");
}

#[test]
fn bad_descriptions_are_errors() {
    let text = include_str!("../../../config/talos/actuators/elbow.toml");
    for (from, to, needle) in [
        (
            "velocity = [-4.58, 4.58]",
            "velocity = [0.5, 4.58]",
            "velocity limits",
        ),
        (
            "current = [-6.0, 6.0]",
            "current = [6.0, -6.0]",
            "current limits",
        ),
        ("i_m = 0.45", "i_m = -0.33", "inertia"),
        ("ambient_c = 26.0", "ambient_c = 50.0", "ambient"),
        ("joint = ", "jiont = ", "unknown field"),
    ] {
        assert!(text.contains(from), "{from}");
        let e = corps_actuator::ActuatorDescription::from_toml(&text.replace(from, to))
            .unwrap_err()
            .to_string();
        assert!(e.contains(needle), "{to}: {e}");
    }
}
