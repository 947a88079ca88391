//! Closed-loop scenarios: the inverse-dynamics controller in torque mode drives TALOS in the
//! corps simulator.

mod common;
use common::*;
use corps_control::formulation::InverseDynamics;
use corps_control::tasks::{Reference, Se3Reference, Se3Task};
use corps_control::trajectories::{MinJerk, Sinusoid};
use corps_control::{FallbackReason, RobotState};
use corps_model::spatial::Motion;
use corps_sim::{Command, Push, Simulator};
use nalgebra::{DVector, Vector3, Vector6};

/// Runs the torque loop for `seconds`; `script(t, id, state)` updates references each tick
/// (t counts from the handover). Returns the worst CoM tracking error (m).
fn run(
    sim: &mut Simulator,
    id: &mut InverseDynamics,
    state: &mut RobotState,
    t0: f64,
    seconds: f64,
    mut script: impl FnMut(f64, &mut InverseDynamics, &RobotState),
) -> f64 {
    let model = sim.model().clone();
    let mut tau = DVector::zeros(model.nv - 6);
    let mut worst = 0.0f64;
    let steps = (seconds * 1000.0).round() as usize;
    for _ in 0..steps {
        let t = sim.time() - t0;
        script(t, id, state);
        let (q, v) = (sim.q().clone_owned(), sim.v().clone_owned());
        if let Some(reason) = id.tick(&model, state, t, q.as_slice(), v.as_slice(), 5.0, &mut tau) {
            panic!("t = {t:.3} s: fell back to the safe command: {reason}");
        }
        if let Some((com, _)) = &id.com {
            worst = worst.max((state.data.com - com.reference.pos.fixed_rows::<3>(0)).norm());
        }
        sim.step(&Command::Torque(tau.clone())).unwrap();
    }
    worst
}

fn sole(sim: &Simulator, frame: &str) -> Vector3<f64> {
    let m = sim.model();
    let fid = m.frame_id(frame).unwrap();
    corps_model::frame_placement(m, sim.data(), fid)
        .unwrap()
        .translation
}

fn start() -> (Simulator, RobotState, InverseDynamics, f64) {
    let (sim, q0) = settled_talos(stiff_settings());
    let model = sim.model().clone();
    let mut state = RobotState::new(&model);
    state
        .update(&model, sim.q().as_slice(), sim.v().as_slice())
        .unwrap();
    let id = standing_controller(&model, &state, &q0);
    let t0 = sim.time();
    (sim, state, id, t0)
}

#[test]
fn com_tracks_a_lateral_sinusoid() {
    // 3 cm amplitude at 0.5 Hz (issue: peak CoM tracking error < 5 mm). The amplitude ramps in
    // over the first second (smoothstep) so the reference starts at rest, as the robot does.
    let (mut sim, mut state, mut id, t0) = start();
    let c0 = DVector::from_column_slice(state.data.com.as_slice());
    let sine = Sinusoid {
        center: c0.clone(),
        amplitude: DVector::from_vec(vec![0.0, 0.03, 0.0]),
        frequency: 0.5,
    };
    let ramp = MinJerk {
        start: DVector::zeros(1),
        end: DVector::from_vec(vec![1.0]),
        t0: 0.0,
        duration: 1.0,
    };
    let worst = run(&mut sim, &mut id, &mut state, t0, 5.0, |t, id, _| {
        let (s, r) = (sine.sample(t), ramp.sample(t));
        let (k, dk, ddk) = (r.pos[0], r.vel[0], r.acc[0]);
        // c = c0 + k(t) (s − c0): product rule for the derivatives.
        let d = &s.pos - &c0;
        id.com.as_mut().unwrap().0.reference = Reference {
            pos: &c0 + &d * k,
            vel: &s.vel * k + &d * dk,
            acc: &s.acc * k + &s.vel * (2.0 * dk) + &d * ddk,
        };
    });
    assert!(worst < 5e-3, "CoM tracking error peak {worst:.4} m");
}

#[test]
fn squat_down_ten_centimetres_and_back() {
    // CoM height −10 cm in 2 s and back in 2 s (min-jerk). Bound: peak error < 1 cm.
    let (mut sim, mut state, mut id, t0) = start();
    // Seed 000 gives no squat gains; its posture weight (0.1, Table 5.1) holds the half-sitting
    // knees against a 10 cm squat, so the posture only regularizes here (weight 1e-3).
    id.posture.as_mut().unwrap().1 = 1e-3;
    let c0 = DVector::from_column_slice(state.data.com.as_slice());
    let mut low = c0.clone();
    low[2] -= 0.10;
    let down = MinJerk {
        start: c0.clone(),
        end: low.clone(),
        t0: 0.0,
        duration: 2.0,
    };
    let up = MinJerk {
        start: low,
        end: c0,
        t0: 2.0,
        duration: 2.0,
    };
    let mut min_z = f64::INFINITY;
    let worst = run(&mut sim, &mut id, &mut state, t0, 4.5, |t, id, s| {
        id.com.as_mut().unwrap().0.reference = if t < 2.0 {
            down.sample(t)
        } else {
            up.sample(t)
        };
        min_z = min_z.min(s.data.com.z);
    });
    let c_end = state.data.com;
    assert!(worst < 1e-2, "CoM tracking error peak {worst:.4} m");
    assert!(
        (min_z - (down.start[2] - 0.10)).abs() < 1e-2,
        "lowest CoM {min_z:.4} m"
    );
    assert!(
        (c_end.z - down.start[2]).abs() < 5e-3,
        "back up at {:.4} m",
        c_end.z
    );
}

#[test]
fn balance_on_the_left_foot_with_the_right_foot_lifted() {
    // Shift the CoM over the left sole (2 s), release the right contact (0.3 s force ramp),
    // lift the right foot 5 cm (1 s) and hold it for 5 s.
    let (mut sim, mut state, mut id, t0) = start();
    let model = sim.model().clone();
    let left0 = sole(&sim, "leg_left_sole_fix_joint");
    let c0 = DVector::from_column_slice(state.data.com.as_slice());
    let mut over_left = c0.clone();
    over_left[0] = left0.x;
    over_left[1] = left0.y;
    let shift = MinJerk {
        start: c0,
        end: over_left,
        t0: 0.0,
        duration: 2.0,
    };
    let right = model.frame_id("leg_right_sole_fix_joint").unwrap();
    let right0 = state.frame_placement(&model, right).unwrap();
    let mut raised = right0;
    raised.translation.z += 0.05;
    let lift = MinJerk {
        start: DVector::from_column_slice(right0.translation.as_slice()),
        end: DVector::from_column_slice(raised.translation.as_slice()),
        t0: 2.3,
        duration: 1.0,
    };
    let mut released = false;
    let mut min_base = f64::INFINITY;
    run(&mut sim, &mut id, &mut state, t0, 8.3, |t, id, s| {
        id.com.as_mut().unwrap().0.reference = shift.sample(t);
        if t >= 2.0 && !released {
            id.remove_contact("leg_right_sole_fix_joint", t, 0.3)
                .unwrap();
            let reference = Se3Reference {
                placement: right0,
                velocity: Motion::zero(),
                acceleration: Motion::zero(),
            };
            // Foot motion gains and weight of seed 000 Tables 5.2–5.3: Kp 100, Kd 5, weight 100.
            id.frames.push((
                Se3Task::new(
                    model.nv,
                    right,
                    Vector6::repeat(100.0),
                    Vector6::repeat(5.0),
                    reference,
                ),
                100.0,
            ));
            released = true;
        }
        if released {
            let r: Reference = lift.sample(t);
            let task = &mut id.frames[0].0;
            task.reference.placement.translation = Vector3::new(r.pos[0], r.pos[1], r.pos[2]);
            task.reference.velocity =
                Motion::new(Vector3::new(r.vel[0], r.vel[1], r.vel[2]), Vector3::zeros());
            task.reference.acceleration =
                Motion::new(Vector3::new(r.acc[0], r.acc[1], r.acc[2]), Vector3::zeros());
        }
        min_base = min_base.min(s.q[2]);
    });
    assert_eq!(id.contacts.len(), 1, "the right contact is gone");
    assert!(min_base > 0.8, "base height fell to {min_base:.3} m");
    let slip = (sole(&sim, "leg_left_sole_fix_joint") - left0).xy().norm();
    assert!(slip < 1e-2, "left foot slipped {slip:.4} m");
    let lifted = sole(&sim, "leg_right_sole_fix_joint").z - right0.translation.z;
    assert!(
        (lifted - 0.05).abs() < 1e-2,
        "right foot lifted {lifted:.4} m"
    );
    let fz_right: f64 = sim.contact().body_wrenches[model.joint_id("leg_right_6_joint").unwrap()]
        .linear
        .z;
    assert!(
        fz_right.abs() < 1e-9,
        "the right foot still touches: {fz_right:.2} N"
    );
}

fn pushed(force: [f64; 3]) -> (f64, f64) {
    let (mut sim, mut state, mut id, t0) = start();
    let feet0 = [
        sole(&sim, "leg_left_sole_fix_joint"),
        sole(&sim, "leg_right_sole_fix_joint"),
    ];
    sim.add_push(Push {
        frame: "base_link".into(),
        start: sim.time() + 0.5,
        duration: 0.1,
        force,
        torque: [0.0; 3],
    })
    .unwrap();
    let mut min_base = f64::INFINITY;
    run(&mut sim, &mut id, &mut state, t0, 3.0, |_, _, s| {
        min_base = min_base.min(s.q[2])
    });
    let feet = [
        sole(&sim, "leg_left_sole_fix_joint"),
        sole(&sim, "leg_right_sole_fix_joint"),
    ];
    let slip = (0..2)
        .map(|k| (feet[k] - feet0[k]).xy().norm())
        .fold(0.0, f64::max);
    (min_base, slip)
}

#[test]
fn recovers_from_a_100_newton_push_from_the_front() {
    let (min_base, slip) = pushed([100.0, 0.0, 0.0]);
    assert!(min_base > 0.8, "base fell to {min_base:.3} m");
    assert!(slip < 1e-2, "foot slip {slip:.4} m");
}

#[test]
fn recovers_from_a_100_newton_push_from_the_side() {
    let (min_base, slip) = pushed([0.0, 100.0, 0.0]);
    assert!(min_base > 0.8, "base fell to {min_base:.3} m");
    assert!(slip < 1e-2, "foot slip {slip:.4} m");
}

#[test]
fn a_failing_qp_or_a_nan_sensor_gives_the_safe_command_and_a_reason() {
    let (sim, mut state, mut id, _) = start();
    let model = sim.model().clone();
    let mut tau = DVector::zeros(model.nv - 6);
    let (q, mut v) = (sim.q().clone_owned(), sim.v().clone_owned());
    // A NaN in the velocity: no controller output, damping-free gravity compensation.
    v[10] = f64::NAN;
    let r = id.tick(
        &model,
        &mut state,
        0.0,
        q.as_slice(),
        v.as_slice(),
        5.0,
        &mut tau,
    );
    assert!(matches!(r, Some(FallbackReason::BadState(_))), "{r:?}");
    assert!(
        tau.iter().all(|t| t.is_finite()) && tau.amax() > 1.0,
        "gravity compensation, finite: {tau}"
    );
    // An infeasible QP: both feet must push at least 1000 N, which the actuators cannot give.
    v[10] = 0.0;
    for c in &mut id.contacts {
        c.fmin = 5000.0;
        c.fmax = 6000.0;
    }
    let r = id.tick(
        &model,
        &mut state,
        0.0,
        q.as_slice(),
        v.as_slice(),
        5.0,
        &mut tau,
    );
    assert!(matches!(r, Some(FallbackReason::Controller(_))), "{r:?}");
    for k in 0..tau.len() {
        assert!(tau[k].abs() <= model.effort_limit[6 + k] + 1e-12);
    }
}

#[test]
fn torque_controlled_talos_stands_ten_seconds() {
    let (mut sim, q0) = settled_talos(stiff_settings());
    let model = sim.model().clone();
    let mut state = RobotState::new(&model);
    state
        .update(&model, sim.q().as_slice(), sim.v().as_slice())
        .unwrap();
    let mut id = standing_controller(&model, &state, &q0);
    let com_ref = state.data.com;
    let base0 = sim.q().fixed_rows::<3>(0).into_owned();
    let mut cmd = Command::Torque(DVector::zeros(model.nv - 6));
    let mut worst_com = 0.0f64;
    for _ in 0..10_000 {
        state
            .update(&model, sim.q().as_slice(), sim.v().as_slice())
            .unwrap();
        let out = id
            .compute(&model, &state)
            .expect("the QP solves at every tick");
        if let Command::Torque(t) = &mut cmd {
            t.copy_from(&out.tau);
        }
        sim.step(&cmd).unwrap();
        worst_com = worst_com.max((state.data.com - com_ref).norm());
    }
    let drift = (sim.q().fixed_rows::<3>(0) - base0).norm();
    assert!(drift < 1e-3, "base drift {drift:.3e} m over 10 s");
    assert!(worst_com < 5e-3, "CoM error peak {worst_com:.3e} m");
    assert!(
        sim.v().amax() < 0.05,
        "still moving: {:.3e}",
        sim.v().amax()
    );
}
