//! Shared helpers of the integration tests.
#![allow(dead_code)]

use corps_model::{build_model_from_urdf_file, random_configuration, Model, RootJoint};
use nalgebra::DVector;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::path::PathBuf;

/// Path of a file under the repository root.
pub fn repo_path(rel: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../..")
        .join(rel)
}

pub const TALOS: &str = "robots/talos_data/robots/talos_reduced.urdf";
pub const ICUB: &str = "robots/icub_description/robots/icub_reduced.urdf";
pub const SIMPLE: &str = "robots/simple_humanoid_description/urdf/simple_humanoid.urdf";
pub const MIXED: &str = "crates/corps-model/tests/data/mixed_joints.urdf";

pub fn load(rel: &str, root: RootJoint) -> Model {
    build_model_from_urdf_file(repo_path(rel), root).expect("model loads")
}

/// Robots exercised by the identity tests.
pub fn robots() -> Vec<(&'static str, Model)> {
    vec![
        ("talos", load(TALOS, RootJoint::FreeFlyer)),
        ("icub", load(ICUB, RootJoint::FreeFlyer)),
        ("simple_humanoid_fixed", load(SIMPLE, RootJoint::Fixed)),
        ("mixed_joints", load(MIXED, RootJoint::FreeFlyer)),
    ]
}

/// A reproducible random state (q, v, a, τ).
pub fn random_state(
    model: &Model,
    seed: u64,
) -> (DVector<f64>, DVector<f64>, DVector<f64>, DVector<f64>) {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let q = random_configuration(model, &mut rng);
    let mut r = || DVector::from_fn(model.nv, |_, _| rng.gen_range(-1.0..1.0));
    let v = r();
    let a = r();
    let t = r() * 10.0;
    (q, v, a, t)
}

#[allow(unused_imports)] // not every test binary that includes this module compares vectors
pub use corps_testkit::assert_close;
