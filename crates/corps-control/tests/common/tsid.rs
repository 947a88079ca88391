//! Loading TSID's recorded ticks (tests/data/tsid_ticks.json) and configuring the
//! inverse-dynamics formulation exactly as TSID was at a tick. Shared by the TSID cross-check
//! test and the tick benchmark.
#![allow(dead_code)]

use corps_control::contacts::Contact;
use corps_control::formulation::InverseDynamics;
use corps_control::tasks::{
    AngularMomentumTask, ComTask, PostureTask, Reference, Se3Reference, Se3Task,
};
use corps_model::spatial::{Motion, Se3};
use corps_model::Model;
use nalgebra::{DMatrix, DVector, Matrix3, Vector3, Vector6};
use serde_json::Value;

pub fn repo(rel: &str) -> String {
    format!("{}/../../{}", env!("CARGO_MANIFEST_DIR"), rel)
}

pub fn vecf(v: &Value) -> Vec<f64> {
    v.as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect()
}
pub fn dvec(v: &Value) -> DVector<f64> {
    DVector::from_vec(vecf(v))
}
pub fn v3(v: &Value) -> Vector3<f64> {
    Vector3::from_vec(vecf(v))
}
pub fn v6(v: &Value) -> Vector6<f64> {
    Vector6::from_vec(vecf(v))
}
pub fn mat(v: &Value) -> DMatrix<f64> {
    let rows: Vec<Vec<f64>> = v.as_array().unwrap().iter().map(vecf).collect();
    DMatrix::from_fn(rows.len(), rows[0].len(), |r, c| rows[r][c])
}

/// Configures the formulation as TSID was at this tick.
pub fn configure(model: &Model, tick: &Value) -> InverseDynamics {
    let mut id = InverseDynamics::new(model);
    let com = &tick["com"];
    let mut c = ComTask::new(model.nv, v3(&com["Kp"]), v3(&com["Kd"]));
    c.reference = Reference {
        pos: dvec(&com["ref"]["pos"]),
        vel: dvec(&com["ref"]["vel"]),
        acc: dvec(&com["ref"]["acc"]),
    };
    id.tasks
        .add("com", c, 1, com["weight"].as_f64().unwrap())
        .unwrap();
    let post = &tick["posture"];
    let mut q_ref = dvec(&tick["q"]);
    q_ref
        .rows_mut(7, model.nq - 7)
        .copy_from(&dvec(&post["ref"]["q"]));
    let mut p = PostureTask::new(model, dvec(&post["Kp"]), dvec(&post["Kd"]), q_ref);
    p.v_ref = dvec(&post["ref"]["v"]);
    p.a_ref = dvec(&post["ref"]["a"]);
    id.tasks
        .add("posture", p, 1, post["weight"].as_f64().unwrap())
        .unwrap();
    let am = &tick["am"];
    let mut a = AngularMomentumTask::new(model.nv, v3(&am["Kp"]));
    a.reference = v3(&am["ref"]["value"]);
    a.reference_derivative = v3(&am["ref"]["derivative"]);
    id.tasks
        .add("angular_momentum", a, 1, am["weight"].as_f64().unwrap())
        .unwrap();
    for c in tick["contacts"].as_array().unwrap() {
        let frame = model.frame_id(c["frame"].as_str().unwrap()).unwrap();
        let pts: Vec<Vector3<f64>> = c["contact_points"]
            .as_array()
            .unwrap()
            .iter()
            .map(v3)
            .collect();
        let r = &c["motion"]["ref"];
        let rot = mat(&r["rotation"]);
        let reference = Se3Reference {
            placement: Se3::new(Matrix3::from_fn(|i, j| rot[(i, j)]), v3(&r["translation"])),
            velocity: Motion::from_slice(&vecf(&r["vel"])),
            acceleration: Motion::from_slice(&vecf(&r["acc"])),
        };
        let mut contact = Contact::new(
            model,
            &format!("c_{}", c["frame"].as_str().unwrap()),
            frame,
            [pts[0], pts[1], pts[2], pts[3]],
            v3(&c["normal"]),
            c["mu"].as_f64().unwrap(),
            (c["fmin"].as_f64().unwrap(), c["fmax"].as_f64().unwrap()),
            v6(&c["motion"]["Kp"]),
            v6(&c["motion"]["Kd"]),
            reference,
        );
        contact.force_reg_weight = c["force_reg"]["weight"].as_f64().unwrap();
        contact.force_reg_components = v6(&c["force_reg"]["component_weights"]);
        contact.force_reference = v6(&c["force_reg"]["f_ref"]);
        id.contacts.push(contact);
    }
    for t in tick["se3_tasks"].as_array().into_iter().flatten() {
        let name = t["frame"].as_str().unwrap();
        let r = &t["ref"];
        let rot = mat(&r["rotation"]);
        let reference = Se3Reference {
            placement: Se3::new(Matrix3::from_fn(|i, j| rot[(i, j)]), v3(&r["translation"])),
            velocity: Motion::from_slice(&vecf(&r["vel"])),
            acceleration: Motion::from_slice(&vecf(&r["acc"])),
        };
        let frame = model.frame_id(name).unwrap();
        let mut task = Se3Task::new(model.nv, frame, v6(&t["Kp"]), v6(&t["Kd"]), reference);
        task.mask = v6(&t["mask"]);
        let priority = t["priority"].as_u64().unwrap() as usize;
        let weight = t["weight"].as_f64().unwrap();
        (id.tasks)
            .add(&format!("se3 {name}"), task, priority, weight)
            .unwrap();
    }
    id.actuation = Some((
        dvec(&tick["actuation"]["lower"]),
        dvec(&tick["actuation"]["upper"]),
    ));
    id
}

/// The recorded ticks.
pub fn ticks() -> Vec<Value> {
    let text =
        std::fs::read_to_string(repo("crates/corps-control/tests/data/tsid_ticks.json")).unwrap();
    let v: Value = serde_json::from_str(&text).unwrap();
    v["ticks"].as_array().unwrap().clone()
}

/// Recorded states (q, v).
pub type States = Vec<(Vec<f64>, Vec<f64>)>;

/// TSID's TALOS anchor problem: the model (`talos_reduced.urdf`, free-flyer), the controller
/// configured as at the first recorded tick, and the 25 recorded states (q, v).
#[allow(dead_code)]
pub fn anchor_problem() -> (Model, InverseDynamics, States) {
    let model = corps_model::build_model_from_urdf_file(
        repo("robots/talos_data/robots/talos_reduced.urdf"),
        corps_model::RootJoint::FreeFlyer,
    )
    .expect("TALOS");
    let ticks = ticks();
    let states = ticks
        .iter()
        .map(|t| (vecf(&t["q"]), vecf(&t["v"])))
        .collect();
    let id = configure(&model, &ticks[0]);
    (model, id, states)
}
