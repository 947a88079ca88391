//! One control tick of the inverse-dynamics controller on TALOS standing on two 6D contacts
//! with CoM, posture, angular-momentum and actuation-bound tasks: exactly TSID's anchor problem
//! (62 variables, 18 equalities, 66 inequalities), cycling over the 25 states TSID recorded.
//! Split as TSID's harness splits it: problem data (model terms), QP assembly, QP solve, and the
//! whole tick. Run: `cargo bench -p corps-control --bench tick`; TSID side:
//! `bash tools/bench/run_tsid_bench.sh`. `passive_tick` is the whole tick under the energy
//! tank (seed 000 ch. 5: stage 1's stacked task energy and valves, the scaled references and
//! the passivity row), beside `plain_tick`, the same tick without it, through the same
//! torque-tick path.

#[path = "../tests/common/tsid.rs"]
mod tsid;
use corps_control::formulation::PassiveInverseDynamics;
use corps_control::passivity::{EnergyTank, TankParams};
use corps_control::RobotState;
use criterion::{criterion_group, criterion_main, Criterion};
use nalgebra::DVector;
use std::hint::black_box;
use tsid::*;

fn bench(c: &mut Criterion) {
    let (model, mut id, states) = anchor_problem();
    let mut state = RobotState::new(&model);
    let mut g = c.benchmark_group("talos_id_tick");
    let mut k = 0usize;
    g.bench_function("problem_data", |b| {
        b.iter(|| {
            k = (k + 1) % states.len();
            black_box(state.update(&model, &states[k].0, &states[k].1)).expect("state")
        })
    });
    state
        .update(&model, &states[0].0, &states[0].1)
        .expect("state");
    g.bench_function("qp_assembly", |b| {
        b.iter(|| black_box(id.build(&model, &state)).expect("build"))
    });
    let mut solver = corps_qp::ActiveSetSolver::new(62, 18, 66);
    g.bench_function("qp_solve", |b| {
        b.iter(|| black_box(solver.solve(&id.problem).map(|s| s.x[0])).expect("solve"))
    });
    g.bench_function("whole_tick", |b| {
        b.iter(|| {
            k = (k + 1) % states.len();
            state
                .update(&model, &states[k].0, &states[k].1)
                .expect("state");
            black_box(id.compute(&model, &state).map(|o| o.tau[0])).expect("tick")
        })
    });
    let na = model.nv - 6;
    let mut tau = DVector::zeros(na);
    let mut plain = id;
    g.bench_function("plain_tick", |b| {
        b.iter(|| {
            k = (k + 1) % states.len();
            let (q, v) = &states[k];
            black_box(plain.tick(&model, &mut state, 0.0, q, v, 5.0, &mut tau))
        })
    });
    let (_, mut id, _) = anchor_problem();
    // The 25 states are unrelated, so each tick's spring energy jumps: a tank far larger than
    // any jump keeps the valves open, the regime of a controller whose tank is not empty.
    let params = TankParams {
        e_max: 1e9,
        ..TankParams::default()
    };
    let tank = EnergyTank::new(params, 1e8).expect("tank");
    let mut passive = PassiveInverseDynamics::new(&model, tank, 1e-3).expect("passive");
    g.bench_function("passive_tick", |b| {
        b.iter(|| {
            k = (k + 1) % states.len();
            let (q, v) = &states[k];
            black_box(passive.tick(&mut id, &model, &mut state, 0.0, q, v, 5.0, &mut tau))
        })
    });
    g.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().warm_up_time(std::time::Duration::from_millis(500)).measurement_time(std::time::Duration::from_secs(3));
    targets = bench
}
criterion_main!(benches);
