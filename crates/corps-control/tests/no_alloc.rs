//! A control tick (model terms, QP assembly, solve, torques) allocates nothing once the
//! controller is set up: counting global allocator, per thread.

#[path = "common/tsid.rs"]
mod tsid;
use corps_control::RobotState;
use nalgebra::DVector;
use tsid::*;

use corps_testkit::{allocations, CountingAllocator};

#[global_allocator]
static GLOBAL: CountingAllocator = CountingAllocator;

#[test]
fn a_control_tick_does_not_allocate() {
    let (model, mut id, states) = anchor_problem();
    let mut state = RobotState::new(&model);
    let mut tau = DVector::zeros(model.nv - 6);
    // First tick sizes the QP.
    assert!(id
        .tick(
            &model,
            &mut state,
            0.0,
            &states[0].0,
            &states[0].1,
            5.0,
            &mut tau
        )
        .is_none());
    let before = allocations();
    for (q, v) in &states {
        let r = id.tick(&model, &mut state, 0.001, q, v, 5.0, &mut tau);
        assert!(r.is_none(), "{r:?}");
    }
    let n = allocations() - before;
    assert_eq!(n, 0, "{n} heap allocations in {} ticks", states.len());
}

#[test]
fn a_passive_tick_does_not_allocate() {
    use corps_control::formulation::PassiveInverseDynamics;
    use corps_control::passivity::{EnergyTank, TankParams};
    let (model, mut id, states) = anchor_problem();
    let mut state = RobotState::new(&model);
    let mut tau = DVector::zeros(model.nv - 6);
    let tank = EnergyTank::new(TankParams::default(), 3.0).unwrap();
    let mut passive = PassiveInverseDynamics::new(&model, tank, 1e-3).unwrap();
    let (q0, v0) = &states[0];
    // The first ticks size the QP (with its power row) and the stacked energy.
    for _ in 0..2 {
        let r = passive.tick(&mut id, &model, &mut state, 0.0, q0, v0, 5.0, &mut tau);
        assert!(r.is_none(), "{r:?}");
    }
    let before = allocations();
    for (q, v) in &states {
        let r = passive.tick(&mut id, &model, &mut state, 0.001, q, v, 5.0, &mut tau);
        assert!(r.is_none(), "{r:?}");
    }
    let n = allocations() - before;
    assert_eq!(
        n,
        0,
        "{n} heap allocations in {} passive ticks",
        states.len()
    );
}
