//! A DDP solve in a workspace that has solved a horizon as long allocates nothing (counting
//! global allocator, per thread): the human walking OCP from a recorded-walk-like start, the
//! same horizon solved again from another start, and a shorter one.

use corps_ocp::human_walk::{HumanWalkEnd, HumanWalkStep, NU, NX};
use corps_ocp::{ActionModel, Ddp, DdpSettings, DdpWorkspace};
use corps_testkit::{allocations_during, CountingAllocator};
use nalgebra::Vector6;

#[global_allocator]
static GLOBAL: CountingAllocator = CountingAllocator;

#[test]
fn a_solve_in_a_used_workspace_does_not_allocate() {
    let goal = [0.0, 0.0, std::f64::consts::FRAC_PI_2];
    let (step, end) = (HumanWalkStep::new(goal), HumanWalkEnd::new(goal));
    let running: Vec<&dyn ActionModel<NX, NU>> = vec![&step; 50];
    let settings = DdpSettings::default();
    let mut workspace = DdpWorkspace::default();
    let x0 = Vector6::new(-1.0, -4.0, 1.2, 0.0, 0.0, 0.0);
    let first = workspace
        .solve(&x0, &running, &end, None, &settings)
        .unwrap();
    assert!(first.converged && first.iterations > 5, "{first:?}");
    let other = Vector6::new(2.0, -3.0, 2.0, 0.8, 0.1, 0.0);
    let mut outcomes = Vec::with_capacity(2);
    let n = allocations_during(|| {
        outcomes.push(workspace.solve(&other, &running, &end, None, &settings));
        outcomes.push(workspace.solve(&x0, &running[..30], &end, None, &settings));
    });
    for o in &outcomes {
        let o = o.as_ref().unwrap();
        assert!(o.iterations > 5, "{o:?}");
    }
    assert_eq!(workspace.xs().len(), 31);
    assert_eq!(n, 0, "{n} allocations in two solves");
}

/// A workspace reused across horizons of other lengths and starts (longer after shorter
/// included) gives what a fresh solve gives, to the bit, and an empty trajectory before any
/// solve.
#[test]
fn a_reused_workspace_solves_as_a_fresh_one() {
    let goal = [0.5, -0.3, 1.0];
    let (step, end) = (HumanWalkStep::new(goal), HumanWalkEnd::new(goal));
    let settings = DdpSettings::default();
    let mut workspace = DdpWorkspace::default();
    assert!(workspace.xs().is_empty() && workspace.us().is_empty());
    for (nodes, x0) in [
        (40, Vector6::new(-1.0, -4.0, 1.2, 0.0, 0.0, 0.0)),
        (20, Vector6::new(2.0, -3.0, 2.0, 0.8, 0.1, 0.0)),
        (60, Vector6::new(-3.0, 1.0, -0.5, 1.1, 0.0, 0.05)),
        (35, Vector6::new(1.0, 2.0, -2.0, 0.5, -0.2, 0.0)),
    ] {
        let running: Vec<&dyn ActionModel<NX, NU>> = vec![&step; nodes];
        let reused = workspace
            .solve(&x0, &running, &end, None, &settings)
            .unwrap();
        let fresh = Ddp::solve(&x0, &running, &end, None, &settings).unwrap();
        assert_eq!(
            (reused.cost, reused.iterations, reused.converged),
            (fresh.cost, fresh.iterations, fresh.converged),
            "{nodes} nodes"
        );
        assert_eq!(workspace.xs(), &fresh.xs[..]);
        assert_eq!(workspace.us(), &fresh.us[..]);
    }
    let bad = DdpSettings {
        mu_factor: 1.0,
        ..settings
    };
    let running: Vec<&dyn ActionModel<NX, NU>> = vec![&step; 10];
    let x0 = Vector6::zeros();
    assert!(workspace.solve(&x0, &running, &end, None, &bad).is_err());
    assert!(
        workspace.xs().is_empty(),
        "no trajectory after a refused solve"
    );
}
