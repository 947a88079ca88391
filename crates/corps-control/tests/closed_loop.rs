//! Closed-loop scenarios: the inverse-dynamics controller in torque mode drives TALOS in the
//! corps simulator.

mod common;
use common::*;
use corps_control::RobotState;
use corps_sim::Command;
use nalgebra::DVector;

#[test]
fn torque_controlled_talos_stands_ten_seconds() {
    let (mut sim, q0) = settled_talos(stiff_settings());
    let model = sim.model().clone();
    let mut state = RobotState::new(&model);
    state
        .update(&model, sim.q().as_slice(), sim.v().as_slice())
        .unwrap();
    let mut id = standing_controller(&model, &state, &q0);
    let com_ref = state.data.com;
    let base0 = sim.q().fixed_rows::<3>(0).into_owned();
    let mut cmd = Command::Torque(DVector::zeros(model.nv - 6));
    let mut worst_com = 0.0f64;
    for _ in 0..10_000 {
        state
            .update(&model, sim.q().as_slice(), sim.v().as_slice())
            .unwrap();
        let out = id
            .compute(&model, &state)
            .expect("the QP solves at every tick");
        if let Command::Torque(t) = &mut cmd {
            t.copy_from(&out.tau);
        }
        sim.step(&cmd).unwrap();
        worst_com = worst_com.max((state.data.com - com_ref).norm());
    }
    let drift = (sim.q().fixed_rows::<3>(0) - base0).norm();
    assert!(drift < 1e-3, "base drift {drift:.3e} m over 10 s");
    assert!(worst_com < 5e-3, "CoM error peak {worst_com:.3e} m");
    assert!(
        sim.v().amax() < 0.05,
        "still moving: {:.3e}",
        sim.v().amax()
    );
}
