//! The current-limiting iLQR in closed loop at 1 kHz (seed 000 §4.1, Fig 3.7–3.10), on the
//! joint in corps-sim behind its drive and on the MPC's own model: with a 30 kg payload at
//! 5 cm the command stays under the 6 A limit and the arm stops before the −2.35 rad limit;
//! without the barriers the command exceeds the limit. A solve allocates nothing.

mod common;

use corps_actuator::ilqr::{Ilqr, IlqrSettings};
use corps_actuator::mpc::{MpcPlant, MpcScenario, MpcSeries};
use corps_testkit::{allocations_during, CountingAllocator};
use nalgebra::Vector2;

#[global_allocator]
static GLOBAL: CountingAllocator = CountingAllocator;

fn extremes(s: &MpcSeries) -> (f64, f64, f64) {
    let min_i = s.current.iter().copied().fold(f64::INFINITY, f64::min);
    let max_i = s.current.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let min_q = s.q.iter().copied().fold(f64::INFINITY, f64::min);
    (min_i, max_i, min_q)
}

#[test]
fn the_barrier_keeps_the_current_and_the_arm_inside_their_limits() {
    for plant in [MpcPlant::Simulator, MpcPlant::Model] {
        println!("{plant:?}:");
        limits_hold(plant);
    }
}

fn limits_hold(plant: MpcPlant) {
    let d = common::elbow();
    let with = MpcScenario {
        plant,
        ..MpcScenario::default()
    }
    .run(&d)
    .unwrap();
    let without = MpcScenario {
        barrier: false,
        plant,
        ..MpcScenario::default()
    }
    .run(&d)
    .unwrap();
    let (min_i, max_i, min_q) = extremes(&with);
    let (min_i_free, _, min_q_free) = extremes(&without);
    // The plateau: how long the command stays within 5 % of its most negative value.
    let plateau_ms = with.current.iter().filter(|&&i| i < 0.95 * min_i).count();
    println!(
        "with barriers: current {min_i:.2} … {max_i:.2} A (thesis: plateau ≈ −5.6 A under the \
         6 A limit), {plateau_ms} ms within 5 % of the minimum, lowest q {min_q:.3} rad \
         (limit −2.35); without: current down to {min_i_free:.2} A, q down to \
         {min_q_free:.3} rad"
    );
    let [lo, hi] = d.limits.current;
    assert!(min_i > lo && max_i < hi, "command {min_i} … {max_i}");
    assert!(min_q > d.limits.position[0], "q {min_q}");
    assert!(plateau_ms >= 100, "no plateau: {plateau_ms} ms");
    assert!(
        min_i_free < lo,
        "without barriers the command stays at {min_i_free}"
    );
    assert!(min_q_free < d.limits.position[0]);
    let mean_iterations =
        with.iterations.iter().sum::<usize>() as f64 / with.iterations.len() as f64;
    println!("iLQR iterations per tick: mean {mean_iterations:.2}");
}

#[test]
fn a_warm_started_solve_allocates_nothing() {
    let d = common::elbow();
    let scenario = MpcScenario::default();
    let ocp = scenario.ocp(&d);
    let mut solver = Ilqr::new(100, IlqrSettings::default());
    let reference: Vec<Vector2<f64>> = (0..=100)
        .map(|k| scenario.reference(k as f64 * 1e-3))
        .collect();
    let x = Vector2::new(scenario.q_start, 0.0);
    solver.solve(&ocp, &x, &reference).unwrap();
    let n = allocations_during(|| {
        for _ in 0..3 {
            solver.shift();
            solver.solve(&ocp, &x, &reference).unwrap();
        }
    });
    assert_eq!(n, 0);
}

#[test]
fn bad_scenarios_are_errors() {
    let d = common::elbow();
    let e = MpcScenario {
        payload_kg: -1.0,
        ..MpcScenario::default()
    }
    .run(&d)
    .unwrap_err();
    assert!(e.to_string().contains("payload"), "{e}");
    let e = MpcScenario {
        q_start: -3.0,
        ..MpcScenario::default()
    }
    .run(&d)
    .unwrap_err();
    assert!(e.to_string().contains("infeasible start"), "{e}");
}
