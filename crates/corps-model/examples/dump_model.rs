//! Prints corps' model of a URDF (free-flyer root) as JSON: every joint's kind, axis, parent,
//! placement and index ranges, every body's inertia, the gravity. Golden-data scripts read it
//! to compute reference answers on the model exactly as corps rounded it from the URDF
//! (`tools/golden/gen_aba_precision.py`):
//! `cargo run --release -p corps-model --example dump_model -- robot.urdf`.

use corps_model::*;
use serde_json::{json, Value};

fn matrix(m: &nalgebra::Matrix3<f64>) -> Value {
    json!((0..3)
        .map(|r| (0..3).map(|c| m[(r, c)]).collect::<Vec<_>>())
        .collect::<Vec<_>>())
}

fn main() {
    let Some(path) = std::env::args().nth(1) else {
        eprintln!("usage: dump_model <robot.urdf>");
        std::process::exit(2);
    };
    let model = match build_model_from_urdf_file(&path, RootJoint::FreeFlyer) {
        Ok(m) => m,
        Err(e) => {
            eprintln!("{path}: {e}");
            std::process::exit(1);
        }
    };
    let joints: Vec<Value> = model
        .joints
        .iter()
        .zip(&model.inertias)
        .map(|(j, y)| {
            let (kind, axis) = match j.kind {
                JointKind::FreeFlyer => ("free_flyer", None),
                JointKind::Revolute { axis } => ("revolute", Some(axis)),
                JointKind::RevoluteUnbounded { axis } => ("revolute_unbounded", Some(axis)),
                JointKind::Prismatic { axis } => ("prismatic", Some(axis)),
            };
            json!({
                "name": j.name,
                "kind": kind,
                "axis": axis.map(|a| vec![a.x, a.y, a.z]),
                "parent": j.parent,
                "rotation": matrix(&j.placement.rotation),
                "translation": [j.placement.translation.x, j.placement.translation.y, j.placement.translation.z],
                "idx_q": j.idx_q,
                "idx_v": j.idx_v,
                "nv": j.nv(),
                "mass": y.mass,
                "lever": [y.lever.x, y.lever.y, y.lever.z],
                "inertia": matrix(&y.inertia),
            })
        })
        .collect();
    let g = model.gravity;
    let out = json!({
        "name": model.name,
        "nq": model.nq,
        "nv": model.nv,
        "gravity": [g.x, g.y, g.z],
        "joints": joints,
    });
    println!("{out}");
}
