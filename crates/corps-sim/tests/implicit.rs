//! The implicit-Euler step's pieces: the servo linearization it solves with, and the model
//! terms it carries from one step to the next.

mod common;
use common::*;
use corps_sim::*;
use nalgebra::DVector;

/// ∂τ/∂q = −k_p and ∂τ/∂q̇ = −k_d for a position command (central differences of the servo
/// law), −k_d alone for a velocity command, nothing for torques, and nothing on a joint held
/// at its effort limit.
#[test]
fn servo_linearization_matches_finite_differences_and_the_clamp() {
    let model = talos();
    let q0 = model
        .reference_configuration("half_sitting")
        .unwrap()
        .clone();
    let gains = ServoGains::high_gain(&model, q0.as_slice(), 0.02, 1.0).unwrap();
    let mut act = Actuators::new(&model, gains.clone());
    let (nv, first) = (model.nv, first_actuated(&model));
    let na = nv - first;
    // A small error on every joint, and a large one on joint 3 that saturates it.
    let mut q_ref = q0.clone();
    for k in 0..na {
        q_ref[7 + k] += 1e-3 * (k as f64 + 1.0).sin();
    }
    q_ref[7 + 3] += 0.5;
    let v = DVector::from_fn(nv, |i, _| 1e-2 * (i as f64).cos());
    let cmd = Command::Position {
        q_ref,
        v_ref: DVector::zeros(na),
    };
    let torques = |act: &mut Actuators, q: &DVector<f64>, v: &DVector<f64>| {
        let mut t = vec![0.0; nv];
        act.torques(&model, &cmd, q.as_slice(), v.as_slice(), &mut t);
        t
    };
    let tau = torques(&mut act, &q0, &v);
    let (mut kp, mut kd) = (vec![0.0; na], vec![0.0; na]);
    act.linearization(&model, &cmd, &tau, &mut kp, &mut kd);
    let h = 1e-7;
    for k in 0..na {
        let (mut qa, mut qb) = (q0.clone(), q0.clone());
        qa[7 + k] += h;
        qb[7 + k] -= h;
        let dq = (torques(&mut act, &qa, &v)[first + k] - torques(&mut act, &qb, &v)[first + k])
            / (2.0 * h);
        let (mut va, mut vb) = (v.clone(), v.clone());
        va[first + k] += h;
        vb[first + k] -= h;
        let dv = (torques(&mut act, &q0, &va)[first + k] - torques(&mut act, &q0, &vb)[first + k])
            / (2.0 * h);
        assert!(
            (dq + kp[k]).abs() <= 1e-6 * gains.kp[k].max(1.0),
            "joint {k}: ∂τ/∂q {dq} vs −{}",
            kp[k]
        );
        assert!(
            (dv + kd[k]).abs() <= 1e-6 * gains.kd[k].max(1.0),
            "joint {k}: ∂τ/∂q̇ {dv} vs −{}",
            kd[k]
        );
    }
    assert_eq!(
        (kp[3], kd[3]),
        (0.0, 0.0),
        "the saturated joint has no gain"
    );
    assert!(kp[0] > 0.0 && kd[0] > 0.0);

    let vel = Command::Velocity(DVector::zeros(na));
    let mut t = vec![0.0; nv];
    act.torques(&model, &vel, q0.as_slice(), v.as_slice(), &mut t);
    act.linearization(&model, &vel, &t, &mut kp, &mut kd);
    assert!(kp.iter().all(|x| *x == 0.0));
    assert_eq!(kd[0], gains.kd[0]);
    let torque = Command::Torque(DVector::zeros(na));
    act.linearization(&model, &torque, &vec![0.0; nv], &mut kp, &mut kd);
    assert!(kp.iter().chain(&kd).all(|x| *x == 0.0));
}

/// Each step reuses M, the Jacobians and the twists the previous one left; a simulator made
/// to recompute them every step (`energy()` clears them) must follow bit for bit.
#[test]
fn carried_model_terms_give_the_same_steps_as_recomputed_ones() {
    let (mut carried, q) = standing_talos_with(implicit_stiff());
    let (mut recomputed, _) = standing_talos_with(implicit_stiff());
    let cmd = hold(&carried.model().clone(), &q);
    for _ in 0..300 {
        carried.step(&cmd).unwrap();
        recomputed.energy().unwrap();
        recomputed.step(&cmd).unwrap();
    }
    assert_eq!(carried.q(), recomputed.q());
    assert_eq!(carried.v(), recomputed.v());
}

/// `prepare_step` (the state-only part, done ahead, e.g. on another thread) leaves every
/// reading alone and gives the same steps bit for bit: under a position hold (servo terms in
/// A), after switching to torques (A redone for the new servo linearization), and with a push
/// added between a preparation and its step (the preparation is dropped).
#[test]
fn prepared_steps_are_the_steps() {
    let (mut prepared, q) = standing_talos_with(implicit_stiff());
    let (mut plain, _) = standing_talos_with(implicit_stiff());
    let model = prepared.model().clone();
    let position = hold(&model, &q);
    let mut torque = position.clone();
    let push = Push {
        frame: "base_link".into(),
        start: 0.0,
        duration: 0.02,
        force: [80.0, -40.0, 0.0],
        torque: [0.0; 3],
    };
    for k in 0..400 {
        if k == 200 {
            // The hold's last torques, as a torque command.
            torque = Command::Torque(plain.applied_torques().rows(6, model.nv - 6).into_owned());
        }
        let cmd = &torque;
        let readings = (
            prepared.q().clone(),
            prepared.v().clone(),
            prepared.applied_torques().clone(),
            prepared.contact().point_forces.clone(),
            prepared.contact().point_positions.clone(),
        );
        prepared.prepare_step();
        assert_eq!(prepared.q(), &readings.0);
        assert_eq!(prepared.v(), &readings.1);
        assert_eq!(prepared.applied_torques(), &readings.2);
        assert_eq!(prepared.contact().point_forces, readings.3);
        assert_eq!(prepared.contact().point_positions, readings.4);
        if k == 250 {
            let push = Push {
                start: plain.time(),
                ..push.clone()
            };
            prepared.add_push(push.clone()).unwrap();
            plain.add_push(push).unwrap();
        }
        prepared.step(cmd).unwrap();
        plain.step(cmd).unwrap();
        assert_eq!(prepared.q(), plain.q(), "step {k}");
        assert_eq!(prepared.v(), plain.v(), "step {k}");
        assert_eq!(
            prepared.contact().point_forces,
            plain.contact().point_forces
        );
    }
    assert!(
        plain.contact().point_forces.iter().any(|f| f.z > 1.0),
        "in contact"
    );
}
