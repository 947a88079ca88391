//! The [τ; f] formulation against the [q̈; f] one: on TALOS standing with TSID's tasks (CoM,
//! posture, angular momentum, two 6D sole contacts), given the same objective (the [q̈; f]
//! formulation's 1e-8‖q̈‖² regularization added to the [τ; f] one as a task, its torque
//! regularization off), both minimize the same cost over the same dynamics, so their
//! answers agree to the solvers' precision; and the accelerations of the [τ; f] answer,
//! through the dynamics, meet the contacts' rows.

mod common;
use common::*;
use corps_control::formulation::TorqueForce;
use corps_control::formulation::HESSIAN_REGULARIZATION;
use corps_control::tasks::{ComTask, TaskRows};
use corps_control::{RobotState, Task, TaskLevel};
use corps_model::Model;
use corps_testkit::{allocations, CountingAllocator};
use nalgebra::{DVector, Vector3};

#[global_allocator]
static GLOBAL: CountingAllocator = CountingAllocator;

/// ‖q̈‖² as a task: identity rows, zero target.
struct AccelerationNorm(TaskRows);

impl Task for AccelerationNorm {
    fn level(&self) -> TaskLevel {
        TaskLevel::Acceleration
    }
    fn dim(&self) -> usize {
        self.0.rows()
    }
    fn compute(&mut self, _: &Model, _: &RobotState) -> corps_control::Result<&TaskRows> {
        Ok(&self.0)
    }
}

/// The [τ; f] formulation with the tasks and contacts of `standing_controller`.
fn torque_force(model: &Model, state: &RobotState, q: &DVector<f64>) -> TorqueForce {
    let (mut tf, id) = standing_torque_force(model, state, q);
    tf.contacts = id.contacts.clone();
    tf
}

#[test]
fn the_torque_force_optimum_is_the_acceleration_force_optimum() {
    let (model, q, _, _) = standing();
    let state = moving_state(&model, &q);
    let mut id = standing_controller(&model, &state, &q);
    let mut tf = torque_force(&model, &state, &q);
    // The same objective: [q̈; f]'s regularization of q̈, no torque regularization.
    tf.torque_weight = 0.0;
    let mut identity = TaskRows::new(model.nv, model.nv);
    identity.a.fill_with_identity();
    let norm = AccelerationNorm(identity);
    (tf.tasks)
        .add("acceleration_norm", norm, 1, HESSIAN_REGULARIZATION)
        .unwrap();
    for com in [
        id.tasks.task_mut::<ComTask>("com").unwrap(),
        tf.tasks.task_mut::<ComTask>("com").unwrap(),
    ] {
        com.reference.pos[1] += 0.02;
    }
    let a = id.compute(&model, &state).unwrap().clone();
    let b = tf.compute(&model, &state).unwrap().clone();
    let dtau = (&a.tau - &b.tau).amax();
    let df = (&a.forces - &b.forces).amax();
    let ddv = (&a.dv - &b.dv).amax();
    let (tau, f) = (a.tau.amax(), a.forces.amax());
    println!("|Δτ| {dtau:.2e} of {tau:.1} N·m, |Δf| {df:.2e} of {f:.1} N, |Δq̈| {ddv:.2e}");
    // Measured: 4.3e-7 N·m, 9.5e-5 N (of 254 N: the internal force between the feet is held
    // only by the 1e-8 regularization, the flattest direction of both problems), 1e-10.
    assert!(dtau < 1e-6 * tau, "torques differ by {dtau} N·m");
    assert!(df < 1e-6 * f, "forces differ by {df} N");
    assert!(ddv < 1e-8, "accelerations differ by {ddv}");
}

#[test]
fn its_accelerations_follow_the_dynamics_and_meet_the_contacts() {
    let (model, q, _, _) = standing();
    let state = moving_state(&model, &q);
    let mut tf = torque_force(&model, &state, &q);
    let out = tf.compute(&model, &state).unwrap().clone();
    // M q̈ + h = Sᵀτ + J_cᵀ f, from the model's own M and h.
    let mut rhs = -state.data.nle.clone();
    for k in 0..out.tau.len() {
        rhs[6 + k] += out.tau[k];
    }
    let mut o = 0;
    for c in &tf.contacts {
        rhs += c.jc.transpose() * out.forces.rows(o, c.n_force());
        o += c.n_force();
    }
    let residual = (&state.data.m * &out.dv - rhs).amax();
    assert!(residual < 1e-8, "dynamics residual {residual}");
    // The contacts' motion rows hold: J q̈ = a_des − J̇ v.
    for c in &tf.contacts {
        let rows = c.motion_rows();
        let m = c.n_motion();
        let e = (rows.a.rows(0, m) * &out.dv - rows.b.rows(0, m)).amax();
        assert!(e < 1e-8, "contact {}: rows off by {e}", c.name);
    }
}

#[test]
fn a_priority_zero_task_is_an_equality_and_a_tick_allocates_nothing() {
    let (model, q, _, _) = standing();
    let state = moving_state(&model, &q);
    let mut tf = torque_force(&model, &state, &q);
    tf.tasks.set_priority("com", 0).unwrap();
    let target = {
        let com = tf.tasks.task_mut::<ComTask>("com").unwrap();
        com.reference.acc = DVector::from_column_slice(&[0.3, -0.2, 0.0]);
        com.kp = Vector3::zeros();
        com.kd = Vector3::zeros();
        Vector3::new(0.3, -0.2, 0.0)
    };
    let out = tf.compute(&model, &state).unwrap().clone();
    // c̈ = J_com q̈ + drift.
    let c_acc = &state.data.jcom * &out.dv + state.com_drift;
    assert!((c_acc - target).amax() < 1e-8, "c̈ = {c_acc}");
    let v = state.v.clone();
    let mut st = RobotState::new(&model);
    let mut tau = DVector::zeros(model.nv - 6);
    assert!(tf
        .tick(
            &model,
            &mut st,
            0.0,
            q.as_slice(),
            v.as_slice(),
            5.0,
            &mut tau
        )
        .is_none());
    let before = allocations();
    for k in 1..20 {
        let r = tf.tick(
            &model,
            &mut st,
            k as f64 * 1e-3,
            q.as_slice(),
            v.as_slice(),
            5.0,
            &mut tau,
        );
        assert!(r.is_none(), "{r:?}");
    }
    assert_eq!(allocations() - before, 0);
}

/// The torque-rate bound of seed 001 Eq 2.43c, `|τ − τ₋₁| ≤ τ̇_max t_s`: starting from zero
/// torques, each tick's torques move at most the step from the last tick's, until they reach
/// the unbounded answer; without the bound the first tick jumps there at once.
#[test]
fn the_torque_rate_bound_limits_each_ticks_change() {
    let (model, q, _, _) = standing();
    let state = moving_state(&model, &q);
    let v = state.v.clone();
    let na = model.nv - 6;
    let mut free = torque_force(&model, &state, &q);
    let unbounded = free.compute(&model, &state).unwrap().tau.clone();
    let mut tf = torque_force(&model, &state, &q);
    tf.torque_step = Some(0.5);
    let mut st = RobotState::new(&model);
    let mut tau = DVector::zeros(na);
    let mut last = DVector::zeros(na);
    // The first tick has no previous command: unbounded.
    let r = tf.tick(
        &model,
        &mut st,
        0.0,
        q.as_slice(),
        v.as_slice(),
        5.0,
        &mut tau,
    );
    assert!(r.is_none());
    assert!((&tau - &unbounded).amax() < 1e-6);
    // Jump the state: the next answer is elsewhere, reached at 0.5 N·m per tick.
    let mut v2 = v.clone();
    for k in 6..model.nv {
        v2[k] = -v2[k] * 3.0;
    }
    let mut far = RobotState::new(&model);
    far.update(&model, q.as_slice(), v2.as_slice()).unwrap();
    let target = free.compute(&model, &far).unwrap().tau.clone();
    let gap = (&target - &tau).amax();
    println!("the answer moves by {gap:.2} N·m");
    assert!(gap > 2.0);
    last.copy_from(&tau);
    let mut ticks = 0;
    loop {
        ticks += 1;
        let r = tf.tick(
            &model,
            &mut st,
            0.001 * ticks as f64,
            q.as_slice(),
            v2.as_slice(),
            5.0,
            &mut tau,
        );
        assert!(r.is_none(), "{r:?}");
        assert!(
            (&tau - &last).amax() <= 0.5 + 1e-9,
            "moved {}",
            (&tau - &last).amax()
        );
        last.copy_from(&tau);
        if (&tau - &target).amax() < 1e-6 {
            break;
        }
        assert!(ticks < 100);
    }
    println!("reached in {ticks} ticks");
    assert!(ticks as f64 >= (gap / 0.5).floor());
}
