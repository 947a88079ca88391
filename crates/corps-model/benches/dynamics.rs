//! Per-algorithm timings on TALOS (talos_reduced, free-flyer, nv = 38) over a pool of random
//! states, cycled as Pinocchio's anchor harness (../shared/tools/anchors/pin_bench.cpp) does.
//! Run: `cargo bench -p corps-model --bench dynamics`; the Pinocchio side and the ratio table:
//! `bash tools/bench/compare_pinocchio.sh`.

use corps_model::*;
use criterion::{criterion_group, criterion_main, Criterion};
use nalgebra::DVector;
use rand::{Rng, SeedableRng};
use std::hint::black_box;

const POOL: usize = 1000;

fn talos() -> Model {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../robots/talos_data/robots/talos_reduced.urdf"
    );
    build_model_from_urdf_file(path, RootJoint::FreeFlyer).expect("TALOS loads")
}

type State = (DVector<f64>, DVector<f64>, DVector<f64>, DVector<f64>);

fn states(model: &Model) -> Vec<State> {
    let mut rng = rand::rngs::StdRng::seed_from_u64(42);
    (0..POOL)
        .map(|_| {
            let q = random_configuration(model, &mut rng);
            let mut r = || DVector::from_fn(model.nv, |_, _| rng.gen_range(-1.0..1.0));
            (q, r(), r(), r())
        })
        .collect()
}

fn bench(c: &mut Criterion) {
    let model = talos();
    let mut data = Data::new(&model);
    let pool = states(&model);
    let mut g = c.benchmark_group("talos");
    macro_rules! algo {
        ($name:literal, |$s:ident| $body:expr) => {
            let mut i = 0usize;
            g.bench_function($name, |b| {
                b.iter(|| {
                    i = (i + 1) % POOL;
                    let $s = &pool[i];
                    black_box($body)
                })
            });
        };
    }
    algo!("rnea", |s| rnea(
        &model,
        &mut data,
        s.0.as_slice(),
        s.1.as_slice(),
        s.2.as_slice()
    )
    .is_ok());
    algo!("nle", |s| nonlinear_effects(
        &model,
        &mut data,
        s.0.as_slice(),
        s.1.as_slice()
    )
    .is_ok());
    algo!("crba", |s| crba(&model, &mut data, s.0.as_slice()).is_ok());
    algo!("aba", |s| aba(
        &model,
        &mut data,
        s.0.as_slice(),
        s.1.as_slice(),
        s.3.as_slice()
    )
    .is_ok());
    algo!("joint_jacobians", |s| compute_joint_jacobians(
        &model,
        &mut data,
        s.0.as_slice()
    )
    .is_ok());
    algo!("ccrba", |s| compute_centroidal_momentum(
        &model,
        &mut data,
        s.0.as_slice(),
        s.1.as_slice()
    )
    .is_ok());
    algo!("all_terms", |s| compute_all_terms(
        &model,
        &mut data,
        s.0.as_slice(),
        s.1.as_slice()
    )
    .is_ok());
    algo!("fk_acc", |s| forward_kinematics(
        &model,
        &mut data,
        s.0.as_slice(),
        s.1.as_slice(),
        s.2.as_slice()
    )
    .is_ok());
    algo!("minv", |s| compute_minverse(
        &model,
        &mut data,
        s.0.as_slice()
    )
    .is_ok());
    algo!("coriolis", |s| coriolis_matrix(
        &model,
        &mut data,
        s.0.as_slice(),
        s.1.as_slice()
    )
    .is_ok());
    algo!("fd_crba_ltdl", |s| forward_dynamics_crba(
        &model,
        &mut data,
        s.0.as_slice(),
        s.1.as_slice(),
        s.3.as_slice()
    )
    .is_ok());
    g.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().warm_up_time(std::time::Duration::from_millis(500)).measurement_time(std::time::Duration::from_secs(2));
    targets = bench
}
criterion_main!(benches);
