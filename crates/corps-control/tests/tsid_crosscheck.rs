//! The inverse-dynamics formulation against TSID 1.10 on TALOS: for 25 control ticks recorded
//! by TSID (state, gains, weights, references: tests/data/tsid_ticks.json, extracted by
//! tools/extract_tsid_ticks.py), rebuild the QP, compare every task's right-hand side with
//! TSID's, the assembled QP with the one eiquadprog received
//! (../corps-qp/tests/data/tsid_talos_double.json), both to 1e-10 of their largest entry, and
//! the solution with eiquadprog's: joint accelerations to 1e-6, sole wrenches to 1e-3 N and
//! N·m. The same on 8 single-support ticks (one sole, a swing-foot task) through the task
//! stack.

#[path = "common/tsid.rs"]
mod tsid;
use corps_control::tasks::{AngularMomentumTask, ComTask, PostureTask, Se3Task};
use corps_control::RobotState;
use corps_model::{build_model_from_urdf_file, RootJoint};
use corps_testkit::assert_close;
use serde_json::Value;
use tsid::*;

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
        check_tick(&model, &mut state, tick, qp);
    }
}

/// TSID in single support (the anchor harness's `single` scenario: the left sole in contact,
/// the right sole lifted 5 cm by a TaskSE3Equality at priority 1, weight 1): each recorded
/// tick (tests/data/tsid_ticks_single.json, extracted with its QP by
/// tools/extract_tsid_ticks.py --single) rebuilt through the task stack, checked as above.
#[test]
fn inverse_dynamics_reproduces_tsid_in_single_support() {
    let model = build_model_from_urdf_file(
        repo("robots/talos_data/robots/talos_reduced.urdf"),
        RootJoint::FreeFlyer,
    )
    .unwrap();
    let data: Value = serde_json::from_str(
        &std::fs::read_to_string(repo(
            "crates/corps-control/tests/data/tsid_ticks_single.json",
        ))
        .unwrap(),
    )
    .unwrap();
    let ticks = data["ticks"].as_array().unwrap();
    assert!(ticks.len() >= 5, "{} single-support ticks", ticks.len());
    let mut state = RobotState::new(&model);
    for tick in ticks {
        assert_eq!(tick["contacts"].as_array().unwrap().len(), 1);
        assert_eq!(tick["se3_tasks"].as_array().unwrap().len(), 1);
        check_tick(&model, &mut state, tick, &tick["qp"]);
    }
}

/// Rebuilds the QP of one recorded tick, compares every task's right-hand side, the assembled
/// QP (1e-10) and the solution (joint accelerations 1e-6, sole wrenches 1e-3 N and N·m).
fn check_tick(model: &corps_model::Model, state: &mut RobotState, tick: &Value, qp: &Value) {
    let n = tick["tick"].as_u64().unwrap();
    let ctx = |w: &str| format!("tick {n} {w}");
    state
        .update(model, &vecf(&tick["q"]), &vecf(&tick["v"]))
        .unwrap();
    let mut id = configure(model, tick);
    id.build(model, state).unwrap();
    // Task by task.
    let com = id.tasks.task_mut::<ComTask>("com").unwrap();
    assert_close(
        &ctx("CoM rhs"),
        com.compute(state).b.as_slice(),
        &vecf(&tick["com"]["computed"]["rhs"]),
        1e-10,
    );
    let post = id.tasks.task_mut::<PostureTask>("posture").unwrap();
    assert_close(
        &ctx("posture rhs"),
        post.compute(model, state).unwrap().b.as_slice(),
        &vecf(&tick["posture"]["computed"]["rhs"]),
        1e-10,
    );
    let am = (id.tasks)
        .task_mut::<AngularMomentumTask>("angular_momentum")
        .unwrap();
    assert_close(
        &ctx("AM rhs"),
        am.compute(state).b.as_slice(),
        &vecf(&tick["am"]["computed"]["rhs"]),
        1e-10,
    );
    for (k, c) in tick["contacts"].as_array().unwrap().iter().enumerate() {
        assert_close(
            &ctx("contact rhs"),
            id.contacts[k].motion_rows().b.as_slice(),
            &vecf(&c["motion"]["computed"]["rhs"]),
            1e-10,
        );
    }
    for t in tick["se3_tasks"].as_array().into_iter().flatten() {
        let name = format!("se3 {}", t["frame"].as_str().unwrap());
        let task = id.tasks.task_mut::<Se3Task>(&name).unwrap();
        let ours = task.compute(model, state).unwrap().b.clone();
        assert_close(
            &ctx("SE3 task rhs"),
            ours.as_slice(),
            &vecf(&t["computed"]["rhs"]),
            1e-10,
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
            1e-10,
        );
    }
    for (name, ours, theirs) in [
        ("g", &p.g, "g"),
        ("b", &p.b, "b"),
        ("l", &p.l, "l"),
        ("u", &p.u, "u"),
    ] {
        assert_close(&ctx(name), ours.as_slice(), &vecf(&qp[theirs]), 1e-10);
    }
    // The solution.
    id.compute(model, state).unwrap();
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
