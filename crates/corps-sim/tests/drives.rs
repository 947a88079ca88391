//! Flexible joint drives (seed 000 Eq 2.33) on a pendulum: a drive close to ideal (light,
//! stiff, fast, no friction or delay) moves the link as an ideal torque does under every
//! integrator; the elbow's drive delivers the torque command a period late, within its
//! current limit, and its friction resists motion.

mod common;
use common::{pendulum, ARM, G, MASS};
use corps_sim::*;
use nalgebra::DVector;

fn near_ideal() -> FlexibleDrive {
    FlexibleDrive {
        motor_inertia: 1e-4,
        stiffness: 1e5,
        damping: 1.0,
        viscous_friction: 0.0,
        dry_friction: 0.0,
        friction_velocity: 0.001,
        drive_gain: 10.0,
        current_limit: 1e3,
        bandwidth_hz: 1e5,
        delay_periods: 0,
    }
}

/// q(t) every control period for 2 s of a PD holding the arm at 0.3 rad from rest at 0.
fn swing(drive: Option<FlexibleDrive>, integrator: Integrator, substeps: usize) -> Vec<f64> {
    let model = pendulum();
    let terrain = Terrain::preset(TerrainPreset::Flat, 0.8);
    let settings = SimSettings {
        integrator,
        substeps,
        ..SimSettings::default()
    };
    let gains = ServoGains {
        kp: DVector::zeros(1),
        kd: DVector::zeros(1),
        integral: None,
    };
    let mut sim = Simulator::new(model, terrain, settings, &[0.0], gains).unwrap();
    if drive.is_some() {
        sim.set_drives(vec![drive]).unwrap();
    }
    let mut out = Vec::new();
    for _ in 0..2000 {
        let (q, v) = (sim.q()[0], sim.v()[0]);
        // Gravity turns the arm about +y by m g l cos q (x forward, z up): compensate it.
        let tau = -MASS * G * ARM * q.cos() + 100.0 * (0.3 - q) - 10.0 * v;
        sim.step(&Command::Torque(DVector::from_element(1, tau)))
            .unwrap();
        out.push(sim.q()[0]);
    }
    out
}

#[test]
fn a_near_ideal_drive_moves_the_link_as_an_ideal_torque() {
    // The implicit step solves link and motor together; the explicit ones move the motor on
    // at its velocity during the link's step, a first-order splitting that wants substeps.
    for (integrator, substeps, tolerance) in [
        (Integrator::ImplicitEuler, 1, 1e-4),
        (Integrator::Rk4, 10, 1e-3),
        (Integrator::SemiImplicitEuler, 10, 1e-3),
    ] {
        let ideal = swing(None, integrator, substeps);
        let driven = swing(Some(near_ideal()), integrator, substeps);
        let worst = ideal
            .iter()
            .zip(&driven)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        println!(
            "{integrator:?}: final {:.5} vs {:.5}, largest difference {worst:.2e} rad",
            ideal[1999], driven[1999]
        );
        assert!((ideal[1999] - 0.3).abs() < 1e-3, "{}", ideal[1999]);
        assert!(worst < tolerance, "{integrator:?}: {worst}");
    }
}

#[test]
fn an_explicit_step_too_long_for_a_drive_is_refused() {
    let model = pendulum();
    let terrain = Terrain::preset(TerrainPreset::Flat, 0.8);
    let gains = ServoGains {
        kp: DVector::zeros(1),
        kd: DVector::zeros(1),
        integral: None,
    };
    let mut stiff = near_ideal();
    stiff.stiffness = 1e9;
    // The arm's inertia about the hinge is 0.5 kg·m²: √(1e9/0.5) · 1 ms = 44.7 > 2.8.
    let mut sim = Simulator::new(
        model.clone(),
        terrain.clone(),
        SimSettings::default(),
        &[0.0],
        gains.clone(),
    )
    .unwrap();
    let e = sim.set_drives(vec![Some(stiff)]).unwrap_err().to_string();
    assert!(e.contains("hinge") && e.contains("substeps"), "{e}");
    let implicit = SimSettings {
        integrator: Integrator::ImplicitEuler,
        ..SimSettings::default()
    };
    let mut sim = Simulator::new(model, terrain, implicit, &[0.0], gains).unwrap();
    sim.set_drives(vec![Some(stiff)]).unwrap();
}
