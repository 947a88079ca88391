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
