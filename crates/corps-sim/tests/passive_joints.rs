//! Passive spring-damper joints (seed 000 Eq 6.4) and the plant whose model has joints the
//! controllers' lacks: a pendulum on a spring settles where `k θ = m g l cos θ` whatever the
//! command says; the flexible-hip TALOS' encoders never show its hip joints.

mod common;
use common::{pendulum, ARM, G, MASS};
use corps_loop::Plant;
use corps_sim::*;
use nalgebra::DVector;

/// `k θ = m g l cos θ` by Newton's method.
fn equilibrium(k: f64) -> f64 {
    let mut th = 0.0;
    for _ in 0..50 {
        let f = k * th - MASS * G * ARM * f64::cos(th);
        let df = k + MASS * G * ARM * f64::sin(th);
        th -= f / df;
    }
    th
}

fn settle(integrator: Integrator, cmd: &Command, k: f64, d: f64) -> (f64, f64) {
    let model = pendulum();
    let q0 = DVector::zeros(1);
    let gains = ServoGains::from_bandwidth(&model, q0.as_slice(), 20.0).unwrap();
    let settings = SimSettings {
        integrator,
        ..Default::default()
    };
    let terrain = Terrain::preset(TerrainPreset::Flat, 0.8);
    let mut sim = Simulator::new(model, terrain, settings, q0.as_slice(), gains).unwrap();
    sim.set_passive_joints(&[(0, k, d)]).unwrap();
    for _ in 0..5000 {
        sim.step(cmd).unwrap();
    }
    (sim.q()[0], sim.applied_torques()[0])
}

#[test]
fn a_passive_pendulum_settles_where_its_spring_holds_gravity() {
    let (k, d) = (300.0, 5.0);
    let expected = equilibrium(k);
    // A position command holding 0 and a torque command: the joint takes neither.
    let hold = Command::Position {
        q_ref: DVector::zeros(1),
        v_ref: DVector::zeros(1),
    };
    let push = Command::Torque(DVector::from_element(1, 50.0));
    for integrator in [
        Integrator::ImplicitEuler,
        Integrator::Rk4,
        Integrator::SemiImplicitEuler,
    ] {
        for cmd in [&hold, &push] {
            let (theta, tau) = settle(integrator, cmd, k, d);
            assert!(
                (theta - expected).abs() < 1e-6 * expected.abs().max(1.0),
                "{integrator:?}: θ = {theta}, k θ = m g l cos θ gives {expected}"
            );
            assert!((tau + k * theta).abs() < 1e-3, "{integrator:?}: τ = {tau}");
        }
    }
}

#[test]
fn bad_passive_joints_are_refused() {
    let model = pendulum();
    let q0 = DVector::zeros(1);
    let gains = ServoGains::from_bandwidth(&model, q0.as_slice(), 20.0).unwrap();
    let terrain = Terrain::preset(TerrainPreset::Flat, 0.8);
    let mut sim =
        Simulator::new(model, terrain, SimSettings::default(), q0.as_slice(), gains).unwrap();
    for (joint, k, d, expected) in [
        (0, 0.0, 1.0, "stiffness"),
        (0, -3.0, 1.0, "stiffness"),
        (0, f64::NAN, 1.0, "stiffness"),
        (0, f64::INFINITY, 1.0, "stiffness"),
        (0, 10.0, -1.0, "damping"),
        (0, 10.0, f64::NAN, "damping"),
        (7, 10.0, 1.0, "no joint"),
    ] {
        let err = sim
            .set_passive_joints(&[(joint, k, d)])
            .unwrap_err()
            .to_string();
        assert!(err.contains(expected), "{joint} {k} {d}: {err}");
    }
}

/// The flexible-hip TALOS standing under a position hold, seen through the rigid model.
#[test]
fn hidden_joints_never_reach_the_readings() {
    let robot = corps_robot::Robot::built_in("talos_flexible_hip")
        .unwrap()
        .unwrap();
    let variant = robot.plant.clone().unwrap();
    let rigid = &robot.model;
    let map = HiddenJoints::new(rigid, &variant.model).unwrap();
    let mut q0 = robot.posture.clone();
    place_on_ground(rigid, q0.as_mut_slice(), 0.0).unwrap();
    let (q, v) = map.widen_state(q0.as_slice(), &vec![0.0; rigid.nv]);
    assert!(v.iter().all(|x| *x == 0.0));
    let mut back = DVector::zeros(rigid.nq);
    map.narrow_q(q.as_slice(), back.as_mut_slice());
    assert_eq!(back, q0, "widen then narrow is the identity");

    let (mut plant, _, _) = common::flexible_talos();
    let mut sensed = plant.sensed();
    let na = rigid.nv - rigid.first_actuated();
    assert_eq!(sensed.readings.joint_positions.len(), na);
    // The rigid model's command, holding its posture.
    let hold = Command::Position {
        q_ref: q0.clone(),
        v_ref: DVector::zeros(na),
    };
    for _ in 0..1000 {
        plant.step(&hold).unwrap();
    }
    plant.sense(&mut sensed).unwrap();
    plant.complete(&mut sensed).unwrap();
    let truth = sensed.truth.as_ref().unwrap();
    assert_eq!(truth.q.len(), rigid.nq);
    assert_eq!(truth.joint_placements.len(), rigid.joints.len());
    // The encoders read the actuated joints' own angles, rates and torques (the plant's
    // without the hidden joints), not the legs' true orientation.
    let sim = plant.into_inner().into_simulator().unwrap();
    let (plant_q, plant_v, plant_tau) = (
        sim.q().clone(),
        sim.v().clone(),
        sim.applied_torques().clone(),
    );
    for (j, joint) in rigid.joints.iter().enumerate().skip(1) {
        let k = joint.idx_v - rigid.first_actuated();
        let p = &variant.model.joints[variant.model.joint_id(&joint.name).unwrap()];
        let r = &sensed.readings;
        assert!(
            (r.joint_positions[k] - plant_q[p.idx_q]).abs() < 1e-12,
            "joint {j}"
        );
        assert!(
            (r.joint_velocities[k] - plant_v[p.idx_v]).abs() < 1e-12,
            "joint {j}"
        );
        assert!(
            (r.joint_torques[k] - plant_tau[p.idx_v]).abs() < 1e-12,
            "joint {j}"
        );
        assert_eq!(
            r.contact_wrenches[j], truth.readings.contact_wrenches[j],
            "joint {j}"
        );
    }
    // Each sole's contact wrench is its body's in the plant.
    for f in &robot.feet {
        let w = sensed.readings.contact_wrenches[f.joint];
        assert!(w[2] > 100.0, "{}: {w:?}", f.label);
    }
    // The hips bent under the robot's weight: the plant has it, the readings cannot.
    let bent: Vec<f64> = (variant.passive.iter())
        .map(|p| plant_q[variant.model.joints[p.joint].idx_q])
        .collect();
    assert!(bent.iter().any(|b| b.abs() > 1e-4), "{bent:?}");
    // The true placements are the plant's: the soles where the plant has them.
    for f in &robot.feet {
        let sole = truth.frame_placement(rigid, f.frame).translation;
        assert!(sole.z.abs() < 5e-3, "{}: {sole}", f.label);
    }
}
