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
    id.tasks.set_priority("com", 2).unwrap();
    let e = id.compute(&model, &state).unwrap_err().to_string();
    assert!(e.contains("two levels"), "{e}");
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
