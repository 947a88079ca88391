//! The safe fallback in the loop: the inverse-dynamics controller, taking over a settled TALOS
//! in the corps simulator, answers a NaN sensor or an infeasible QP with the safe command and
//! its reason. The closed-loop scenarios themselves (stand, sinusoid, squat, one foot, pushes,
//! for the three controllers) run from their scenario files in `crates/corps/tests/
//! control_scenarios.rs`, as `corps run` runs them.

mod common;
use common::*;
use corps_control::formulation::InverseDynamics;
use corps_control::{FallbackReason, RobotState};
use corps_sim::Simulator;
use nalgebra::DVector;

fn start() -> (Simulator, RobotState, InverseDynamics, f64) {
    let (sim, q0) = settled_talos(stiff_settings());
    let model = sim.model().clone();
    let mut state = RobotState::new(&model);
    state
        .update(&model, sim.q().as_slice(), sim.v().as_slice())
        .unwrap();
    let id = standing_controller(&model, &state, &q0);
    let t0 = sim.time();
    (sim, state, id, t0)
}

#[test]
fn a_failing_qp_or_a_nan_sensor_gives_the_safe_command_and_a_reason() {
    let (sim, mut state, mut id, _) = start();
    let model = sim.model().clone();
    let mut tau = DVector::zeros(model.nv - 6);
    let (q, mut v) = (sim.q().clone_owned(), sim.v().clone_owned());
    // A NaN in the velocity: no controller output, damping-free gravity compensation.
    v[10] = f64::NAN;
    let r = id.tick(
        &model,
        &mut state,
        0.0,
        q.as_slice(),
        v.as_slice(),
        5.0,
        &mut tau,
    );
    assert!(matches!(r, Some(FallbackReason::BadState(_))), "{r:?}");
    assert!(
        tau.iter().all(|t| t.is_finite()) && tau.amax() > 1.0,
        "gravity compensation, finite: {tau}"
    );
    // An infeasible QP: both feet must push at least 1000 N, which the actuators cannot give.
    v[10] = 0.0;
    for c in &mut id.contacts {
        c.fmin = 5000.0;
        c.fmax = 6000.0;
    }
    let r = id.tick(
        &model,
        &mut state,
        0.0,
        q.as_slice(),
        v.as_slice(),
        5.0,
        &mut tau,
    );
    assert!(matches!(r, Some(FallbackReason::Controller(_))), "{r:?}");
    for k in 0..tau.len() {
        assert!(tau[k].abs() <= model.effort_limit[6 + k] + 1e-12);
    }
}
