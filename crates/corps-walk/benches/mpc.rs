//! Criterion benchmarks: one MPC re-plan while walking (goal ≤ 0.5 ms; seed 002: a new
//! horizon every 5 ms) and one preview-control step (both axes, N = 320).
//!
//! Run: `cargo bench -p corps-walk --bench mpc -- --warm-up-time 1 --measurement-time 3`.

#[path = "../tests/common/talos.rs"]
pub mod talos;
mod common {
    pub use crate::talos;
}

use corps_walk::mpc::{VelocityCommand, WalkingMpc};
use corps_walk::preview_control::{PreviewAxis, PreviewController};
use criterion::{black_box, criterion_group, criterion_main, Criterion};

fn bench(c: &mut Criterion) {
    let mut mpc = WalkingMpc::new(common::talos::talos_mpc(), 0.0, 0.0, 0.0).unwrap();
    let cmd = VelocityCommand::new(0.1, 0.0, 0.05);
    // reach the steady gait first
    for _ in 0..1000 {
        mpc.tick(cmd).unwrap();
    }
    c.bench_function("mpc_replan_walking", |b| {
        b.iter(|| black_box(mpc.tick(black_box(cmd)).unwrap()))
    });

    let ctrl = PreviewController::with_integral(&common::talos::talos_preview()).unwrap();
    let window: Vec<f64> = (0..=ctrl.horizon()).map(|j| 0.001 * j as f64).collect();
    let (mut x, mut y) = (PreviewAxis::default(), PreviewAxis::default());
    c.bench_function("preview_control_step_xy", |b| {
        b.iter(|| {
            ctrl.step(&mut x, black_box(&window)).unwrap();
            ctrl.step(&mut y, black_box(&window)).unwrap();
            x = PreviewAxis::default();
            y = PreviewAxis::default();
        })
    });
}

criterion_group!(benches, bench);
criterion_main!(benches);
