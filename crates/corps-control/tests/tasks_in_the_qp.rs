//! Joint bounds, contact-force tasks and point contacts inside the inverse-dynamics QP, on
//! TALOS standing in half-sitting, checked against identities: the look-ahead bounds hold,
//! the contact wrench follows the force task, and Newton's law holds for a point contact
//! (Σ f_z = m (g + c̈_z), with c̈ = Jcom q̈ + J̇com v).

mod common;
use common::*;
use corps_control::contacts::Contact;
use corps_control::tasks::{ContactForceTask, JointBoundsTask, PostureTask, Se3Reference};
use corps_model::spatial::Motion;
use nalgebra::{DVector, Vector3, Vector6};

#[test]
fn joint_bounds_keep_a_fast_joint_from_crossing_its_limit() {
    let (model, mut q, mut state, mut id) = standing();
    // Left elbow 1 mrad below its upper limit, moving up at 0.5 rad/s (stopping it within
    // h = 10 ms takes 80 rad/s², within its torque limit); the posture task pulls it 0.5 rad
    // beyond the limit.
    let elbow = model.joint_id("arm_left_4_joint").unwrap();
    let (iq, iv) = (model.joints[elbow].idx_q, model.joints[elbow].idx_v);
    let q_max = model.upper_position_limit[iq];
    q[iq] = q_max - 1e-3;
    let mut v = DVector::zeros(model.nv);
    v[iv] = 0.5;
    state.update(&model, q.as_slice(), v.as_slice()).unwrap();
    id.tasks.task_mut::<PostureTask>("posture").unwrap().q_ref[iq] = q_max + 0.5;
    let h = 0.01;
    id.joint_bounds = Some(JointBoundsTask::new(&model, h));
    let out = id.compute(&model, &state).unwrap();
    let a = out.dv[iv];
    let q_next = q[iq] + h * v[iv] + 0.5 * h * h * a;
    assert!(q_next <= q_max + 1e-9, "q reaches {q_next} > {q_max}");
    // The bound is active (it is what stops the joint).
    assert!((q_next - q_max).abs() < 1e-9, "{q_next} vs {q_max}");
    for k in 6..model.nv {
        let vk = v[k] + h * out.dv[k];
        assert!(
            vk.abs() <= model.velocity_limit[k] + 1e-9,
            "joint {k}: {vk} rad/s"
        );
    }
}

#[test]
fn the_contact_force_task_sets_the_load_on_one_foot() {
    let (model, _, state, mut id) = standing();
    let left = "leg_left_sole_fix_joint";
    let one = Vector6::repeat(1.0);
    let mut task = ContactForceTask::new(left, one * 10.0, one * 0.0, one * 5.0);
    task.reference = Vector6::new(0.0, 0.0, 600.0, 0.0, 0.0, 0.0);
    // The measured wrench equals the reference: f_ref = F*.
    task.update(&task.reference.clone(), &Vector6::zeros(), 1e-3);
    id.contact_forces.push((task, 1.0));
    id.compute(&model, &state).unwrap();
    let k = id.contact_index(left).unwrap();
    let fz = id.contact_wrench(k)[2];
    assert!((fz - 600.0).abs() < 1.0, "left foot carries {fz:.2} N");
    let total: f64 = (0..2).map(|k| id.normal_force(k)).sum();
    let weight = model.total_mass() * 9.81;
    assert!(
        (total - weight).abs() < 0.02 * weight,
        "{total} N vs {weight} N"
    );
}

#[test]
fn a_point_contact_carries_force_without_moment_and_newton_holds() {
    let (model, _, state, mut id) = standing();
    let left = "leg_left_sole_fix_joint";
    let k = id.contact_index(left).unwrap();
    let frame = id.contacts[k].frame;
    let reference = Se3Reference {
        placement: state.frame_placement(&model, frame).unwrap(),
        velocity: Motion::zero(),
        acceleration: Motion::zero(),
    };
    id.contacts[k] = Contact::point(
        &model,
        left,
        frame,
        Vector3::z(),
        0.3,
        (1.0, 1000.0),
        Vector3::repeat(30.0),
        Vector3::repeat(11.0),
        reference,
    );
    assert_eq!(id.dims(&model), (model.nv + 3 + 12, 6 + 3 + 6, 5 + 17 + 32));
    let out = id.compute(&model, &state).unwrap().clone();
    let w = id.contact_wrench(k);
    assert_eq!(
        w.fixed_rows::<3>(3).norm(),
        0.0,
        "a point carries no moment"
    );
    assert!(w[2] > 1.0, "the point carries load: {} N", w[2]);
    // Newton: Σ f_z (world) = m (g + c̈_z), the contact forces rotated from the sole frames.
    let com_acc = &state.data.jcom * &out.dv + state.com_drift;
    let fz: f64 = (0..2)
        .map(|c| {
            let r = state
                .frame_placement(&model, id.contacts[c].frame)
                .unwrap()
                .rotation;
            (r * id.contact_wrench(c).fixed_rows::<3>(0)).z
        })
        .sum();
    let expected = model.total_mass() * (9.81 + com_acc.z);
    assert!(
        (fz - expected).abs() < 1e-6 * expected,
        "{fz} vs {expected}"
    );
    // The point's linear acceleration constraint holds: rows 0..3 of its motion task.
    let rows = id.contacts[k].motion_rows();
    for r in 0..3 {
        let lhs: f64 = (0..model.nv).map(|c| rows.a[(r, c)] * out.dv[c]).sum();
        assert!(
            (lhs - rows.b[r]).abs() < 1e-8,
            "row {r}: {lhs} vs {}",
            rows.b[r]
        );
    }
}
