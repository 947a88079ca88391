//! Leg odometry against the simulator's exact state: TALOS standing under its joint PD hold,
//! pushed at the pelvis (150 N for 0.1 s) so that the base sways on the ankles, then swaying
//! its hips by a joint motion. The estimator reads only encoders, joint velocities, the IMU
//! and the ankle F/T sensors.

use corps_estimation::{
    BaseSource, Estimator, EstimatorSettings, FootSensor, KinematicEstimator, Readings,
};
use corps_model::{build_model_from_urdf_file, load_reference_configurations, Model, RootJoint};
use corps_sim::{
    place_on_ground, Command, ForceTorqueModel, Integrator, Push, SensorLayout, SensorNoise,
    Sensors, ServoGains, SimSettings, Simulator, Terrain, TerrainPreset,
};
use nalgebra::{DVector, Vector3};
use std::sync::Arc;

fn repo(rel: &str) -> String {
    format!("{}/../../{}", env!("CARGO_MANIFEST_DIR"), rel)
}

fn talos() -> Arc<Model> {
    let mut m = build_model_from_urdf_file(
        repo("robots/talos_data/robots/talos_reduced_box.urdf"),
        RootJoint::FreeFlyer,
    )
    .unwrap();
    load_reference_configurations(&mut m, repo("robots/talos_data/srdf/talos.srdf")).unwrap();
    Arc::new(m)
}

struct Bench {
    model: Arc<Model>,
    sim: Simulator,
    sensors: Sensors,
    q0: DVector<f64>,
}

fn standing(noise: SensorNoise) -> Bench {
    standing_with(noise, ForceTorqueModel::Contact)
}

fn standing_with(noise: SensorNoise, force_torque_model: ForceTorqueModel) -> Bench {
    let model = talos();
    let mut q = model
        .reference_configuration("half_sitting")
        .unwrap()
        .clone();
    place_on_ground(&model, q.as_mut_slice(), 0.0).unwrap();
    let gains = ServoGains::high_gain(&model, q.as_slice(), 0.02, 1.0).unwrap();
    let mut settings = SimSettings {
        integrator: Integrator::ImplicitEuler,
        ..SimSettings::default()
    };
    settings.contact.normal_stiffness = 4e8;
    settings.contact.tangential_stiffness = 4e8;
    let sim = Simulator::new(
        model.clone(),
        Terrain::preset(TerrainPreset::Flat, 0.8),
        settings,
        q.as_slice(),
        gains,
    )
    .unwrap();
    let layout = SensorLayout {
        force_torque_model,
        ..talos_layout()
    };
    let sensors = Sensors::new(&model, &layout, noise, 7).unwrap();
    Bench {
        model,
        sim,
        sensors,
        q0: q,
    }
}

fn estimator(model: &Arc<Model>, base: BaseSource) -> KinematicEstimator {
    estimator_with(model, base, false)
}

fn estimator_with(
    model: &Arc<Model>,
    base: BaseSource,
    calibrate_foot_weight: bool,
) -> KinematicEstimator {
    let sole = |name: &str| model.frame_id(name).unwrap();
    let feet = ["leg_left_sole_fix_joint", "leg_right_sole_fix_joint"]
        .iter()
        .enumerate()
        .map(|(k, f)| FootSensor {
            sensor: k,
            sensor_frame: sole(f),
            sole_frame: sole(f),
        })
        .collect();
    let settings = EstimatorSettings {
        base,
        calibrate_foot_weight,
        ..Default::default()
    };
    KinematicEstimator::new(model.clone(), feet, sole("imu_link"), settings).unwrap()
}

/// Largest errors over the run: base position (m), base orientation (rad), base linear
/// velocity (m/s), CoM (m).
#[derive(Debug, Default)]
struct Errors {
    position: f64,
    orientation: f64,
    velocity: f64,
    com: f64,
    /// Largest displacement of a sole origin from its start, and its largest speed: how far
    /// the simulated feet break the odometry's assumption.
    sole_displacement: f64,
    sole_speed: f64,
}

fn run(b: &mut Bench, est: &mut dyn Estimator, seconds: f64, measured: bool) -> Errors {
    let mut e = Errors::default();
    let nv = b.model.nv;
    let mut data = corps_model::Data::new(&b.model);
    let zeros = vec![0.0; nv];
    // After 1 s: the hips sway ±4 cm sideways through the hip roll joints at 0.5 Hz.
    let rolls = [
        "leg_left_2_joint",
        "leg_right_2_joint",
        "leg_left_6_joint",
        "leg_right_6_joint",
    ]
    .map(|n| b.model.joints[b.model.joint_id(n).unwrap()].idx_q);
    let q_ref0 = b.q0.clone();
    let soles = ["leg_left_sole_fix_joint", "leg_right_sole_fix_joint"]
        .map(|n| b.model.frame_id(n).unwrap());
    let sole_positions = |sim: &Simulator| {
        soles.map(|f| {
            corps_model::frame_placement(sim.model(), sim.data(), f)
                .unwrap()
                .translation
        })
    };
    // The simulator's kinematics are current after a step.
    let (mut start, mut last) = ([Vector3::zeros(); 2], [Vector3::zeros(); 2]);
    let ticks = (seconds / 1e-3) as usize;
    for tick in 0..ticks {
        let t = tick as f64 * 1e-3;
        let mut q_ref = q_ref0.clone();
        if t > 1.0 {
            let a = 0.04 * (std::f64::consts::PI * (t - 1.0)).sin();
            for (k, j) in rolls.iter().enumerate() {
                q_ref[*j] += if k < 2 { a } else { -a };
            }
        }
        let cmd = Command::Position {
            q_ref,
            v_ref: DVector::zeros(nv - 6),
        };
        b.sim.step(&cmd).unwrap();
        b.sensors.update(&b.sim);
        let now = sole_positions(&b.sim);
        if tick == 0 {
            (start, last) = (now, now);
        }
        for k in 0..2 {
            e.sole_displacement = e.sole_displacement.max((now[k] - start[k]).norm());
            e.sole_speed = e.sole_speed.max((now[k] - last[k]).norm() / 1e-3);
        }
        last = now;
        let r: &Readings = if measured {
            b.sensors.measured()
        } else {
            b.sensors.truth()
        };
        est.update(r).unwrap();
        let s = est.state();
        let (q, v) = (b.sim.q(), b.sim.v());
        e.position = e
            .position
            .max((Vector3::new(q[0], q[1], q[2]) - Vector3::new(s.q[0], s.q[1], s.q[2])).norm());
        let dot = (0..4)
            .map(|k| q[3 + k] * s.q[3 + k])
            .sum::<f64>()
            .abs()
            .min(1.0);
        e.orientation = e.orientation.max(2.0 * dot.acos());
        // Linear velocities in world axes.
        let world = |q: &[f64], v: &[f64]| {
            corps_model::spatial::rotation::quat_to_matrix(q[3], q[4], q[5], q[6])
                * Vector3::new(v[0], v[1], v[2])
        };
        let dv = world(q.as_slice(), v.as_slice()) - world(s.q.as_slice(), s.v.as_slice());
        e.velocity = e.velocity.max(dv.norm());
        let com =
            corps_model::center_of_mass(&b.model, &mut data, q.as_slice(), v.as_slice(), &zeros)
                .unwrap();
        e.com = e.com.max((com - s.com).norm());
    }
    e
}

#[test]
fn leg_odometry_follows_the_base_of_a_pushed_swaying_robot() {
    let mut b = standing(SensorNoise::default());
    b.sim
        .add_push(Push {
            frame: "base_link".into(),
            start: 0.3,
            duration: 0.1,
            force: [150.0, 0.0, 0.0],
            torque: [0.0; 3],
        })
        .unwrap();
    let mut est = estimator(&b.model, BaseSource::LegOdometry);
    est.reset(b.q0.as_slice(), &vec![0.0; b.model.nv]).unwrap();
    let e = run(&mut b, &mut est, 3.0, true);
    // Leg odometry assumes that a foot in contact does not move. On the compliant floor the
    // soles sink, shear and roll a little: the estimate may be off by what they moved, no
    // more (the anchors are weighted means of the soles' start points).
    assert!(e.position <= e.sole_displacement + 1e-9, "{e:?}");
    assert!(e.velocity <= e.sole_speed + 1e-9, "{e:?}");
    assert!(e.com <= e.sole_displacement + 1e-9, "{e:?}");
    // The IMU's orientation, exact here, passes through the kinematics unchanged.
    assert!(e.orientation < 1e-9, "{e:?}");
    // What the soles did on this floor, and so the odometry's error: about a millimetre.
    assert!(e.sole_displacement < 2e-3, "{e:?}");
    eprintln!("{e:?}");
}

#[test]
fn the_direct_base_on_exact_readings_is_the_simulator_state() {
    let mut b = standing(SensorNoise::default());
    let mut est = estimator(&b.model, BaseSource::Direct);
    est.reset(b.q0.as_slice(), &vec![0.0; b.model.nv]).unwrap();
    let e = run(&mut b, &mut est, 1.5, false);
    assert!(
        e.position < 1e-12 && e.velocity < 1e-12 && e.com < 1e-12,
        "{e:?}"
    );
}

#[test]
fn the_zmp_from_the_calibrated_ankle_sensors_is_the_simulators_and_the_feet_carry_the_weight() {
    // Sensors that read the wrench passed through them (the feet hang below), calibrated.
    let mut b = standing_with(SensorNoise::default(), ForceTorqueModel::Transmitted);
    let mut est = estimator_with(&b.model, BaseSource::LegOdometry, true);
    est.reset(b.q0.as_slice(), &vec![0.0; b.model.nv]).unwrap();
    run(&mut b, &mut est, 0.5, true);
    let s = est.state();
    let r = b.sensors.truth();
    // The simulator's ZMP on z = 0 from the exact contact wrenches (world, about the origin).
    let (mut f, mut m) = (Vector3::zeros(), Vector3::zeros());
    for w in &r.contact_wrenches {
        f += Vector3::new(w[0], w[1], w[2]);
        m += Vector3::new(w[3], w[4], w[5]);
    }
    let exact = nalgebra::Vector2::new(-m.y / f.z, m.x / f.z);
    let zmp = s.zmp.expect("both feet loaded");
    assert!(s.feet.iter().all(|f| f.in_contact));
    // The same point up to the plane: the estimator's is at the soles' height (the sole
    // frames sit 0.1 mm under the floor here), the exact one at z = 0; the forces are within
    // 2° of vertical, so the two differ by less than 0.1 mm.
    assert!((zmp - exact).norm() < 1e-4, "zmp {zmp}, exact {exact}");
    // The sensors read the weight above the feet (each foot hangs below its sensor, 1.6 kg on
    // TALOS); calibrated, the feet's wrenches carry the whole robot.
    let total: f64 = s.feet.iter().map(|f| f.wrench[2]).sum();
    let weight = b.model.total_mass() * 9.81;
    assert!(
        (total - weight).abs() < 2e-3 * weight,
        "{total} N vs {weight} N"
    );
    let read: f64 = r.force_torque[..2].iter().map(|w| w[2]).sum();
    assert!(
        weight - read > 30.0,
        "the sensors read {read} N of {weight} N"
    );
}

/// A hand's sensor is read as the feet's: the calibrated wrench in the contact frame. Reading
/// the left ankle's sensor as a "hand" expressed at the left sole gives the left foot's
/// wrench, in another frame the same wrench moved there, and a contact frame on another body
/// than the sensor's is refused.
#[test]
fn a_hand_sensor_reads_as_a_foot_in_its_contact_frame() {
    let mut b = standing_with(SensorNoise::default(), ForceTorqueModel::Transmitted);
    let model = b.model.clone();
    let frame = |name: &str| model.frame_id(name).unwrap();
    let (sole, ankle) = (frame("leg_left_sole_fix_joint"), frame("leg_left_6_link"));
    let hands = [
        FootSensor {
            sensor: 0,
            sensor_frame: sole,
            sole_frame: sole,
        },
        FootSensor {
            sensor: 0,
            sensor_frame: sole,
            sole_frame: ankle,
        },
    ];
    let mut est = estimator_with(&b.model, BaseSource::LegOdometry, true)
        .with_hands(&hands)
        .unwrap();
    est.reset(b.q0.as_slice(), &vec![0.0; b.model.nv]).unwrap();
    run(&mut b, &mut est, 0.2, true);
    let s = est.state();
    assert_eq!(s.hands.len(), 2);
    assert!((s.hands[0].wrench - s.feet[0].wrench).norm() < 1e-9);
    // The same wrench about the ankle frame: its force rotated, its moment moved.
    let (foot, at_ankle) = (&s.feet[0], &s.hands[1]);
    let world_force = foot.placement.rotation * foot.wrench.fixed_rows::<3>(0);
    let world_moment = foot.placement.rotation * foot.wrench.fixed_rows::<3>(3)
        + (foot.placement.translation - at_ankle.placement.translation).cross(&world_force);
    let r = at_ankle.placement.rotation;
    assert!((r * at_ankle.wrench.fixed_rows::<3>(0) - world_force).norm() < 1e-6);
    assert!((r * at_ankle.wrench.fixed_rows::<3>(3) - world_moment).norm() < 1e-6);
    let other_body = FootSensor {
        sensor: 0,
        sensor_frame: sole,
        sole_frame: frame("imu_link"),
    };
    let e = estimator(&b.model, BaseSource::LegOdometry)
        .with_hands(&[other_body])
        .err()
        .expect("refused")
        .to_string();
    assert!(e.contains("not on one body"), "{e}");
}

#[test]
fn non_finite_readings_are_refused_and_the_estimate_is_held() {
    let mut b = standing(SensorNoise::default());
    let mut est = estimator(&b.model, BaseSource::LegOdometry);
    est.reset(b.q0.as_slice(), &vec![0.0; b.model.nv]).unwrap();
    b.sim
        .step(&Command::Torque(DVector::zeros(b.model.nv - 6)))
        .unwrap();
    b.sensors.update(&b.sim);
    let mut r = b.sensors.measured().clone();
    let before = est.state().clone();
    r.joint_velocities[3] = f64::NAN;
    let e = est.update(&r).unwrap_err().to_string();
    assert!(e.contains("joint_velocities"), "{e}");
    assert_eq!(est.state(), &before);
    r.joint_velocities = DVector::zeros(3);
    assert!(est.update(&r).is_err());
}

/// TALOS' sensors, from its description.
fn talos_layout() -> SensorLayout {
    let talos = corps_robot::Robot::built_in("talos").unwrap().unwrap();
    SensorLayout::of(&talos, corps_sim::ForceTorqueModel::Contact)
}
