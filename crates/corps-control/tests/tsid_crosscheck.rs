//! The inverse-dynamics formulation against TSID 1.10 on TALOS: for 25 control ticks recorded
//! by TSID (state, gains, weights, references: tests/data/tsid_ticks.json, extracted by
//! tools/extract_tsid_ticks.py), rebuild the QP, compare every task's right-hand side with
//! TSID's, the assembled QP with the one eiquadprog received
//! (../corps-qp/tests/data/tsid_talos_double.json), and the solution with eiquadprog's:
//! joint accelerations to 1e-6, sole wrenches to 1e-3 N and N·m.

use corps_control::contacts::Contact6d;
use corps_control::formulation::InverseDynamics;
use corps_control::tasks::{AngularMomentumTask, ComTask, PostureTask, Reference, Se3Reference};
use corps_control::RobotState;
use corps_model::spatial::{Motion, Se3};
use corps_model::{build_model_from_urdf_file, Model, RootJoint};
use nalgebra::{DMatrix, DVector, Matrix3, Vector3, Vector6};
use serde_json::Value;

fn repo(rel: &str) -> String {
    format!("{}/../../{}", env!("CARGO_MANIFEST_DIR"), rel)
}

fn vecf(v: &Value) -> Vec<f64> {
    v.as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect()
}
fn dvec(v: &Value) -> DVector<f64> {
    DVector::from_vec(vecf(v))
}
fn v3(v: &Value) -> Vector3<f64> {
    Vector3::from_vec(vecf(v))
}
fn v6(v: &Value) -> Vector6<f64> {
    Vector6::from_vec(vecf(v))
}
fn mat(v: &Value) -> DMatrix<f64> {
    let rows: Vec<Vec<f64>> = v.as_array().unwrap().iter().map(vecf).collect();
    DMatrix::from_fn(rows.len(), rows[0].len(), |r, c| rows[r][c])
}

fn assert_close(what: &str, a: &[f64], b: &[f64], tol: f64) {
    assert_eq!(a.len(), b.len(), "{what}: sizes");
    let scale = b.iter().fold(1.0f64, |m, x| m.max(x.abs()));
    let err = a
        .iter()
        .zip(b)
        .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
    assert!(
        err <= tol * scale,
        "{what}: max error {err:.3e} > {tol:.0e} × {scale:.3e}"
    );
}

/// Configures the formulation as TSID was at this tick.
fn configure(model: &Model, tick: &Value) -> InverseDynamics {
    let mut id = InverseDynamics::new(model);
    let com = &tick["com"];
    let mut c = ComTask::new(model.nv, v3(&com["Kp"]), v3(&com["Kd"]));
    c.reference = Reference {
        pos: dvec(&com["ref"]["pos"]),
        vel: dvec(&com["ref"]["vel"]),
        acc: dvec(&com["ref"]["acc"]),
    };
    id.com = Some((c, com["weight"].as_f64().unwrap()));
    let post = &tick["posture"];
    let mut q_ref = dvec(&tick["q"]);
    q_ref
        .rows_mut(7, model.nq - 7)
        .copy_from(&dvec(&post["ref"]["q"]));
    let mut p = PostureTask::new(model, dvec(&post["Kp"]), dvec(&post["Kd"]), q_ref);
    p.v_ref = dvec(&post["ref"]["v"]);
    p.a_ref = dvec(&post["ref"]["a"]);
    id.posture = Some((p, post["weight"].as_f64().unwrap()));
    let am = &tick["am"];
    let mut a = AngularMomentumTask::new(model.nv, v3(&am["Kp"]));
    a.reference = v3(&am["ref"]["value"]);
    a.reference_derivative = v3(&am["ref"]["derivative"]);
    id.angular_momentum = Some((a, am["weight"].as_f64().unwrap()));
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
        let mut contact = Contact6d::new(
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
    id.actuation = Some((
        dvec(&tick["actuation"]["lower"]),
        dvec(&tick["actuation"]["upper"]),
    ));
    id
}

#[test]
fn inverse_dynamics_reproduces_tsid_on_talos() {
    let model = build_model_from_urdf_file(
        repo("robots/talos_data/robots/talos_reduced.urdf"),
        RootJoint::FreeFlyer,
    )
    .unwrap();
    let ticks: Value = serde_json::from_str(
        &std::fs::read_to_string(repo("crates/corps-control/tests/data/tsid_ticks.json")).unwrap(),
    )
    .unwrap();
    let qps: Value = serde_json::from_str(
        &std::fs::read_to_string(repo("crates/corps-qp/tests/data/tsid_talos_double.json"))
            .unwrap(),
    )
    .unwrap();
    let ticks = ticks["ticks"].as_array().unwrap();
    let qps = qps["qps"].as_array().unwrap();
    assert_eq!(ticks.len(), 25);
    let mut state = RobotState::new(&model);
    for tick in ticks {
        let n = tick["tick"].as_u64().unwrap();
        let qp = qps
            .iter()
            .find(|p| p["tick"].as_u64() == Some(n))
            .expect("QP of the tick");
        let ctx = |w: &str| format!("tick {n} {w}");
        state
            .update(&model, &vecf(&tick["q"]), &vecf(&tick["v"]))
            .unwrap();
        let mut id = configure(&model, tick);
        id.build(&model, &state).unwrap();
        // Task by task.
        let (com, _) = id.com.as_mut().unwrap();
        assert_close(
            &ctx("CoM rhs"),
            com.compute(&state).b.as_slice(),
            &vecf(&tick["com"]["computed"]["rhs"]),
            1e-9,
        );
        let (post, _) = id.posture.as_mut().unwrap();
        assert_close(
            &ctx("posture rhs"),
            post.compute(&model, &state).b.as_slice(),
            &vecf(&tick["posture"]["computed"]["rhs"]),
            1e-9,
        );
        let (am, _) = id.angular_momentum.as_mut().unwrap();
        assert_close(
            &ctx("AM rhs"),
            am.compute(&state).b.as_slice(),
            &vecf(&tick["am"]["computed"]["rhs"]),
            1e-9,
        );
        for (k, c) in tick["contacts"].as_array().unwrap().iter().enumerate() {
            assert_close(
                &ctx("contact rhs"),
                id.contacts[k].motion_rows().b.as_slice(),
                &vecf(&c["motion"]["computed"]["rhs"]),
                1e-9,
            );
        }
        // The assembled QP.
        let p = &id.problem;
        for (name, ours, theirs) in [("H", &p.h, "H"), ("A", &p.a, "A"), ("C", &p.c, "C")] {
            let t = mat(&qp[theirs]);
            assert_close(
                &ctx(name),
                ours.transpose().as_slice(),
                t.transpose().as_slice(),
                1e-9,
            );
        }
        for (name, ours, theirs) in [
            ("g", &p.g, "g"),
            ("b", &p.b, "b"),
            ("l", &p.l, "l"),
            ("u", &p.u, "u"),
        ] {
            assert_close(&ctx(name), ours.as_slice(), &vecf(&qp[theirs]), 1e-9);
        }
        // The solution.
        id.compute(&model, &state).unwrap();
        let x = vecf(&tick["x"]);
        assert_close(
            &ctx("joint accelerations"),
            id.output.dv.as_slice(),
            &x[..38],
            1e-6,
        );
        for (k, contact) in id.contacts.iter().enumerate() {
            let ours = contact.wrench(&id.output.forces.as_slice()[12 * k..12 * k + 12]);
            let theirs = contact.wrench(&x[38 + 12 * k..50 + 12 * k]);
            let err = (ours - theirs).amax();
            assert!(err < 1e-3, "tick {n} sole {k} wrench error {err:.3e}");
        }
    }
}
