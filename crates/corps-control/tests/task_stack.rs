//! The generic task stack in the formulations: any `Task` (here one written in this test), at
//! priority 0 (an equality the solution meets exactly) or 1 (a weighted cost), named, and
//! re-weighted or removed at run time along a minimum-jerk ramp that keeps the torques
//! continuous, without a heap allocation in the ticks of a ramp.

mod common;
use common::*;
use corps_control::tasks::{ComTask, TaskRows};
use corps_control::{ControlError, RobotState, Task, TaskLevel, TaskStack};
use corps_model::Model;
use corps_testkit::{allocations, CountingAllocator};
use nalgebra::{DVector, Vector3};

#[global_allocator]
static GLOBAL: CountingAllocator = CountingAllocator;

/// A task of this test, unknown to corps-control: hold one joint's acceleration at `target`.
struct JointAcceleration {
    rows: TaskRows,
}

impl JointAcceleration {
    fn new(model: &Model, joint_v: usize, target: f64) -> Self {
        let mut rows = TaskRows::new(1, model.nv);
        rows.a[(0, joint_v)] = 1.0;
        rows.b[0] = target;
        Self { rows }
    }
}

impl Task for JointAcceleration {
    fn level(&self) -> TaskLevel {
        TaskLevel::Acceleration
    }
    fn dim(&self) -> usize {
        1
    }
    fn compute(&mut self, _: &Model, _: &RobotState) -> corps_control::Result<&TaskRows> {
        Ok(&self.rows)
    }
}

fn elbow(model: &Model) -> usize {
    let j = model.joint_id("arm_left_4_joint").unwrap();
    model.joints[j].idx_v
}

#[test]
fn a_task_of_the_users_at_priority_zero_is_met_exactly_and_at_priority_one_weighed() {
    let (model, _, state, mut id) = standing();
    let iv = elbow(&model);
    let free = id.compute(&model, &state).unwrap().dv[iv];
    // An equality: met to the solver's tolerance, whatever the posture task wants.
    (id.tasks)
        .add("elbow", JointAcceleration::new(&model, iv, 3.0), 0, 1.0)
        .unwrap();
    let hard = id.compute(&model, &state).unwrap().dv[iv];
    assert!((hard - 3.0).abs() < 1e-9, "q̈ = {hard}");
    // A cost: between the free value and the target, nearer the target as the weight grows.
    id.tasks.set_priority("elbow", 1).unwrap();
    let mut last = free;
    for w in [0.01, 0.1, 1.0, 100.0] {
        id.tasks.set_weight("elbow", w, 0.0, 0.0).unwrap();
        let a = id.compute(&model, &state).unwrap().dv[iv];
        assert!(a > last && a < 3.0, "w = {w}: q̈ = {a} (free {free})");
        last = a;
    }
    assert!((last - 3.0).abs() < 0.05, "w = 100: q̈ = {last}");
}

#[test]
fn the_stack_refuses_duplicates_wrong_levels_bad_weights_and_levels_the_formulation_lacks() {
    let (model, _, state, mut id) = standing();
    let iv = elbow(&model);
    let e = id
        .tasks
        .add("com", JointAcceleration::new(&model, iv, 0.0), 1, 1.0)
        .unwrap_err();
    assert!(e.to_string().contains("already"), "{e}");
    let mut velocity = TaskStack::new(TaskLevel::Velocity);
    let e = velocity
        .add("x", JointAcceleration::new(&model, iv, 0.0), 0, 1.0)
        .unwrap_err();
    assert!(e.to_string().contains("Acceleration-level task"), "{e}");
    let e = id.tasks.set_weight("com", f64::NAN, 0.0, 0.0).unwrap_err();
    assert!(matches!(e, ControlError::Config { .. }), "{e}");
    assert!(id.tasks.set_weight("nothing", 1.0, 0.0, 0.0).is_err());
    // The wrong type gives nothing rather than a wrong task.
    assert!(id.tasks.task_mut::<JointAcceleration>("com").is_none());
    assert!(id.tasks.task_mut::<ComTask>("com").is_some());
    // The weighted inverse dynamics solves priorities 0 and 1: a task beyond is refused when
    // it comes, not at the next tick.
    let e = id.tasks.set_priority("com", 2).unwrap_err().to_string();
    assert!(e.contains("priorities 0 to 1"), "{e}");
    let e = (id.tasks)
        .add("low", JointAcceleration::new(&model, iv, 0.0), 2, 1.0)
        .unwrap_err();
    assert!(e.to_string().contains("priority 2"), "{e}");
    // A ramp needs a finite time and duration; a refused smooth addition leaves nothing.
    assert!(id.tasks.remove_smoothly("com", 0.0, f64::NAN).is_err());
    assert!(id.tasks.set_weight("com", 1.0, f64::NAN, 0.1).is_err());
    let task = JointAcceleration::new(&model, iv, 0.0);
    assert!(id.tasks.add_smoothly("x", task, 1, -1.0, 0.0, 0.1).is_err());
    assert!(!id.tasks.contains("x"));
    id.tasks.update(f64::NAN);
    assert_eq!(id.tasks.weight("com"), Some(50.0));
    id.compute(&model, &state).unwrap();
}

#[test]
fn a_removal_ramps_the_weight_and_keeps_the_torques_continuous() {
    let (model, q, state, mut id) = standing();
    let iv = elbow(&model);
    (id.tasks)
        .add("elbow", JointAcceleration::new(&model, iv, 3.0), 1, 10.0)
        .unwrap();
    let mut tau = DVector::zeros(model.nv - 6);
    let (v, dt, duration) = (DVector::zeros(model.nv), 0.001, 0.1);
    let mut st = RobotState::new(&model);
    // Heap allocations inside the ticks (the test's own copies are not counted).
    let in_ticks = std::cell::Cell::new(0);
    let mut tick = |id: &mut corps_control::formulation::InverseDynamics, t: f64| {
        let before = allocations();
        let r = id.tick(
            &model,
            &mut st,
            t,
            q.as_slice(),
            v.as_slice(),
            5.0,
            &mut tau,
        );
        in_ticks.set(in_ticks.get() + allocations() - before);
        assert!(r.is_none(), "{r:?}");
        tau.clone()
    };
    // The first tick sizes the QP.
    let with = tick(&mut id, 0.0);
    in_ticks.set(0);
    id.tasks.remove_smoothly("elbow", 0.0, duration).unwrap();
    let (mut previous, mut largest_step) = (with.clone(), 0.0f64);
    let mut weights = Vec::with_capacity(120);
    for k in 1..=120 {
        let t = k as f64 * dt;
        let now = tick(&mut id, t);
        largest_step = largest_step.max((&now - &previous).amax());
        previous = now;
        if let Some(w) = id.tasks.weight("elbow") {
            weights.push(w);
        }
    }
    let without = previous;
    assert!(!id.tasks.contains("elbow"), "removed once its ramp ended");
    // The ramp is the minimum-jerk profile from 10 to 0 over 0.1 s.
    assert_eq!(weights.len(), 99);
    for (k, w) in weights.iter().enumerate() {
        let s = (k + 1) as f64 * dt / duration;
        let expected = 10.0 * (1.0 - s * s * s * (10.0 - 15.0 * s + 6.0 * s * s));
        assert!((w - expected).abs() < 1e-9, "t = {} ms: w = {w}", k + 1);
    }
    let jump = (&with - &without).amax();
    assert!(jump > 0.1, "the task moves the torques by {jump} N·m");
    // At once, one tick carries all of the change; along the ramp no tick carries a tenth of
    // it. (Measured: 7.7 %, at the end of the ramp, where the weight falls through the
    // posture's 0.1: a task's effect goes as w / (w + the others' weights), so a ramp linear
    // in the weight moves the torques most when the weight is small.)
    assert!(
        largest_step < 0.1 * jump,
        "a step of {largest_step} of {jump} N·m"
    );
    // The ramp's ticks allocate nothing; dropping the task at the end frees, not allocates.
    assert_eq!(in_ticks.get(), 0);
    let _ = state;
}

#[test]
fn a_task_added_smoothly_enters_from_zero_weight() {
    let (model, _, state, mut id) = standing();
    let mut com = ComTask::new(model.nv, Vector3::repeat(10.0), Vector3::repeat(1.0));
    com.reference
        .pos
        .copy_from(&DVector::from_column_slice(state.data.com.as_slice()));
    id.tasks.remove("com").unwrap();
    id.tasks
        .add_smoothly("com", com, 1, 50.0, 1.0, 0.2)
        .unwrap();
    assert_eq!(id.tasks.weight("com"), Some(0.0));
    id.update_transitions(1.1);
    assert!((id.tasks.weight("com").unwrap() - 25.0).abs() < 1e-9);
    id.update_transitions(1.3);
    assert_eq!(id.tasks.weight("com"), Some(50.0));
    id.compute(&model, &state).unwrap();
}

/// The velocity IK holds a weight ramp in its levels' weights: the ticks of a ramp rebuild
/// nothing and allocate nothing, and two tasks sharing a level trade places as the weights
/// move.
#[test]
fn an_ik_weight_ramp_needs_no_rebuild() {
    use corps_control::formulation::{IkGains, InverseKinematics, StackFrames};
    use corps_control::tasks::velocity::PostureVelocityTask;
    let (model, q, state, _) = standing();
    let frames = StackFrames {
        left_foot: "leg_left_sole_fix_joint",
        right_foot: "leg_right_sole_fix_joint",
        waist: "base_link",
    };
    let mut ik =
        InverseKinematics::standing_stack(&model, &state, 1e-3, &frames, &IkGains::default(), &q)
            .unwrap();
    // A second posture at the posture's level, towards the elbow bent by 0.5 rad.
    let iv = elbow(&model);
    let iq = model.joints[model.joint_id("arm_left_4_joint").unwrap()].idx_q;
    let mut bent = q.clone();
    bent[iq] -= 0.5;
    let na = model.nv - 6;
    let other = PostureVelocityTask::new(&model, DVector::repeat(na, 100.0), bent).unwrap();
    ik.add_task("bent_posture", 4, 0.01, other).unwrap();
    let v_at = |ik: &mut InverseKinematics| ik.compute(&model, &state, q.as_slice()).unwrap().v[iv];
    let before_ramp = v_at(&mut ik);
    ik.tasks
        .set_weight("bent_posture", 100.0, 0.0, 0.1)
        .unwrap();
    let start = allocations();
    for k in 1..=100 {
        ik.update_transitions(k as f64 * 1e-3);
        v_at(&mut ik);
    }
    assert_eq!(allocations() - start, 0, "a ramp rebuilt the levels");
    let after_ramp = v_at(&mut ik);
    // Two postures in one level: the elbow's velocity is their weighted mean, the reference
    // posture's 0 (it is there) and the bent one's −K·0.5 rad = −50 rad/s, clamped at the
    // joint's velocity limit.
    let limit = model.velocity_limit[iv];
    let mean = |w: f64| (-50.0 * w / (1.0 + w)).max(-limit);
    println!("elbow: {before_ramp} → {after_ramp} rad/s (limit {limit})");
    // Measured: −0.492 against −0.495 before the ramp (the levels above hold the CoM, which
    // the arm moves, so the mean is not exact), the limit after it.
    assert!(
        (before_ramp - mean(0.01)).abs() < 0.05 * mean(0.01).abs(),
        "{before_ramp}"
    );
    assert!((after_ramp - mean(100.0)).abs() < 1e-6, "{after_ramp}");
}

/// A posture reference that is not a configuration of the model, or gains of the wrong size,
/// are errors of the tick, not a stale error or a panic.
#[test]
fn a_bad_posture_reference_or_gain_size_is_an_error() {
    use corps_control::tasks::PostureTask;
    let (model, q, state, _) = standing();
    let na = model.nv - 6;
    let mut bad_ref = q.clone();
    bad_ref[3] = f64::NAN; // the base quaternion
    let mut task = PostureTask::new(
        &model,
        DVector::repeat(na, 1.0),
        DVector::repeat(na, 1.0),
        bad_ref,
    );
    assert!(task.compute(&model, &state).is_err());
    let mut task = PostureTask::new(
        &model,
        DVector::repeat(na - 1, 1.0),
        DVector::repeat(na, 1.0),
        q.clone(),
    );
    let e = task.compute(&model, &state).unwrap_err().to_string();
    assert!(e.contains("kp"), "{e}");
}
