//! One solve of the current-limiting iLQR (100 nodes of 1 ms, seed 000 §3.13) as the MPC runs
//! it at 1 kHz: warm-started from the previous tick, at most 10 iterations, at three moments
//! of the 30 kg swing (tracking, barrier engaging, arm held at the position barrier).
//! The thesis: 200 µs per solve on a laptop (i7-8850H), 300 µs on the robot.

use corps_actuator::mpc::{Mpc, MpcScenario};
use corps_actuator::ActuatorDescription;
use criterion::{criterion_group, criterion_main, BatchSize, Criterion};
use nalgebra::Vector2;

fn snapshot(ticks: usize) -> (Mpc, f64, Vector2<f64>) {
    let d =
        ActuatorDescription::from_toml(include_str!("../../../config/talos/actuators/elbow.toml"))
            .unwrap();
    let scenario = MpcScenario::default();
    let mut mpc = Mpc::new(&scenario, &d).unwrap();
    let mut plant = mpc.ocp;
    plant.dt = scenario.dt / 10.0;
    let mut x = Vector2::new(scenario.q_start, 0.0);
    for tick in 0..ticks {
        let (u, _) = mpc.command(tick as f64 * scenario.dt, &x).unwrap();
        for _ in 0..10 {
            x = plant.step(&x, u);
        }
    }
    (mpc, ticks as f64 * scenario.dt, x)
}

fn bench(c: &mut Criterion) {
    let mut group = c.benchmark_group("ilqr_mpc_tick");
    for (name, ticks) in [
        ("tracking_0.10s", 100),
        ("barrier_0.45s", 450),
        ("held_0.60s", 600),
    ] {
        let (mpc, t, x) = snapshot(ticks);
        let (_, iterations) = mpc.clone().command(t, &x).unwrap();
        println!("{name}: {iterations} iterations");
        group.bench_function(name, |b| {
            b.iter_batched_ref(
                || mpc.clone(),
                |m| m.command(t, &x).unwrap(),
                BatchSize::SmallInput,
            )
        });
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
