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
