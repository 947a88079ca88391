//! Simulation speed: TALOS (box feet) standing on flat ground under the joint PD hold of
//! half-sitting, one 1 ms control period per iteration: RK4 (4 + 1 dynamics evaluations),
//! semi-implicit Euler, and linearly implicit Euler, the latter also with the walking runs'
//! stiff contact (the torque walks' RK4 alternative is 4 RK4 substeps: 4× the RK4 figure).
//! Real-time factor = 1 ms / median step time. Run: `cargo bench -p corps-sim --bench simulation`.

use corps_model::{build_model_from_urdf_file, load_reference_configurations, RootJoint};
use corps_sim::*;
use criterion::{criterion_group, criterion_main, Criterion};
use nalgebra::DVector;
use std::sync::Arc;

fn standing_talos(integrator: Integrator, stiffness: f64) -> (Simulator, Command) {
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/../../");
    let mut m = build_model_from_urdf_file(
        format!("{root}robots/talos_data/robots/talos_reduced_box.urdf"),
        RootJoint::FreeFlyer,
    )
    .expect("TALOS loads");
    load_reference_configurations(&mut m, format!("{root}robots/talos_data/srdf/talos.srdf"))
        .expect("SRDF loads");
    let model = Arc::new(m);
    let mut q = model
        .reference_configuration("half_sitting")
        .expect("half_sitting")
        .clone();
    place_on_ground(&model, q.as_mut_slice(), 0.0).expect("placed");
    let gains = ServoGains::high_gain(&model, q.as_slice(), 0.02, 1.0).expect("gains");
    let mut settings = SimSettings {
        integrator,
        ..SimSettings::default()
    };
    settings.contact.normal_stiffness = stiffness;
    settings.contact.tangential_stiffness = stiffness;
    let mut sim = Simulator::new(
        model.clone(),
        Terrain::preset(TerrainPreset::Flat, 0.8),
        settings,
        q.as_slice(),
        gains,
    )
    .expect("sim");
    let cmd = Command::Position {
        q_ref: q,
        v_ref: DVector::zeros(model.nv - 6),
    };
    // Settle into contact first, so the benchmark measures steady standing.
    for _ in 0..500 {
        sim.step(&cmd).expect("step");
    }
    (sim, cmd)
}

fn bench(c: &mut Criterion) {
    let mut g = c.benchmark_group("talos_standing");
    let default = ContactParams::default().normal_stiffness;
    for (name, integrator, stiffness) in [
        ("rk4_1ms", Integrator::Rk4, default),
        (
            "semi_implicit_euler_1ms",
            Integrator::SemiImplicitEuler,
            default,
        ),
        ("implicit_euler_1ms", Integrator::ImplicitEuler, default),
        ("implicit_euler_1ms_stiff", Integrator::ImplicitEuler, 4e8),
    ] {
        let (mut sim, cmd) = standing_talos(integrator, stiffness);
        g.bench_function(name, |b| b.iter(|| sim.step(&cmd).expect("step")));
    }
    g.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().warm_up_time(std::time::Duration::from_millis(500)).measurement_time(std::time::Duration::from_secs(3));
    targets = bench
}
criterion_main!(benches);
