//! The PID position servo (Gazebo's joint position controller law) on a pendulum held
//! horizontal against gravity: a PD servo settles with the error load / kp; the integral term
//! takes the load off the proportional one up to its clamp, and the torque clamp caps the
//! whole command.

mod common;
use common::{pendulum, ARM, G, MASS};
use corps_sim::*;
use nalgebra::DVector;

/// The joint angle after `seconds` of holding q = 0 under `gains`.
fn settle(gains: ServoGains, seconds: f64) -> f64 {
    let model = pendulum();
    let q0 = DVector::zeros(1);
    let terrain = Terrain::preset(TerrainPreset::Flat, 0.8);
    let mut sim =
        Simulator::new(model, terrain, SimSettings::default(), q0.as_slice(), gains).unwrap();
    let cmd = Command::Position {
        q_ref: q0.clone(),
        v_ref: DVector::zeros(1),
    };
    let steps = (seconds / sim.settings().control_dt).round() as usize;
    for _ in 0..steps {
        sim.step(&cmd).unwrap();
    }
    sim.q()[0]
}

fn gains(kp: f64, kd: f64, integral: Option<(f64, f64, f64)>) -> ServoGains {
    ServoGains {
        kp: DVector::from_element(1, kp),
        kd: DVector::from_element(1, kd),
        integral: integral.map(|(ki, i_clamp, torque_clamp)| IntegralTerm {
            ki: DVector::from_element(1, ki),
            i_clamp: DVector::from_element(1, i_clamp),
            torque_clamp: DVector::from_element(1, torque_clamp),
        }),
    }
}

#[test]
fn the_integral_term_removes_the_steady_error_up_to_its_clamp() {
    let load = MASS * G * ARM; // 9.81 N·m about the hinge
    let (kp, kd) = (500.0, 20.0);
    // PD: kp e = load (the pendulum sags: a positive rotation about y lowers +x).
    let pd = settle(gains(kp, kd, None), 3.0);
    assert!((pd - load / kp).abs() < 1e-3 * load / kp, "{pd}");
    // PID with room in its clamp: the error goes to zero.
    let pid = settle(gains(kp, kd, Some((2000.0, 2.0 * load, 1e3))), 10.0);
    assert!(pid.abs() < 1e-3 * load / kp, "{pid}");
    // PID clamped at half the load: the proportional term carries the other half.
    let half = settle(gains(kp, kd, Some((2000.0, 0.5 * load, 1e3))), 10.0);
    assert!((half - 0.5 * load / kp).abs() < 1e-3 * load / kp, "{half}");
}

#[test]
fn the_torque_clamp_caps_the_servo() {
    // The servo may give at most half the load: the pendulum falls through q = 0.5 rad.
    let load = MASS * G * ARM;
    let q = settle(gains(500.0, 20.0, Some((0.0, 0.0, 0.5 * load))), 1.0);
    assert!(q > 0.5, "{q}");
}
