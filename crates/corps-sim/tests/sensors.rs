//! Sensors read the physics correctly and noise is reproducible from the seed.

mod common;
use common::*;
use corps_sim::*;

fn standing(noise: SensorNoise, seed: u64, seconds: f64) -> (Simulator, Sensors) {
    standing_with(noise, seed, seconds, ForceTorqueModel::Contact)
}

fn standing_with(
    noise: SensorNoise,
    seed: u64,
    seconds: f64,
    force_torque_model: ForceTorqueModel,
) -> (Simulator, Sensors) {
    let (mut sim, q) = standing_talos();
    let model = sim.model().clone();
    let layout = SensorLayout {
        force_torque_model,
        ..talos_layout()
    };
    let mut sensors = Sensors::new(&model, &layout, noise, seed).unwrap();
    let cmd = hold(&model, &q);
    for _ in 0..(seconds * 1000.0) as usize {
        sim.step(&cmd).unwrap();
        sensors.update(&sim);
    }
    (sim, sensors)
}

#[test]
fn contact_sensors_read_the_contact_wrench_alone() {
    // Gazebo's contact sensor: the ankles carry the whole weight, the wrists nothing.
    let (sim, sensors) = standing(SensorNoise::default(), 0, 2.0);
    let t = sensors.truth();
    let weight = sim.model().total_mass() * 9.81;
    let fz = t.force_torque[0][2] + t.force_torque[1][2];
    assert!(
        (fz - weight).abs() < 1e-3 * weight,
        "{fz} N, weight {weight} N"
    );
    assert_eq!(t.force_torque[2], [0.0; 6]);
}

#[test]
fn standing_robot_sensors_read_gravity_and_weight() {
    let (sim, sensors) = standing_with(
        SensorNoise::default(),
        0,
        2.0,
        ForceTorqueModel::Transmitted,
    );
    let t = sensors.truth();
    // IMU at rest: specific force of magnitude g, pointing up in the world.
    let a = nalgebra::Vector3::from(t.imu.linear_acceleration);
    assert!((a.norm() - 9.81).abs() < 0.05, "IMU specific force {a:?}");
    let [x, y, z, w] = t.imu.orientation;
    let r = corps_model::spatial::rotation::quat_to_matrix(x, y, z, w);
    assert!(
        ((r * a).z - 9.81).abs() < 0.05,
        "IMU specific force in the world {:?}",
        r * a
    );
    assert!(nalgebra::Vector3::from(t.imu.angular_velocity).norm() < 0.05);
    // Each sensor carries what hangs below it: the mass of its body and that body's subtree.
    let model = sim.model();
    let below = |frame: &str| -> f64 {
        let j = model.frames[model.frame_id(frame).unwrap()]
            .parent_joint
            .unwrap();
        model
            .subtree_joints(j)
            .map(|k| model.inertias[k].mass)
            .sum()
    };
    let feet = below("leg_left_sole_fix_joint") + below("leg_right_sole_fix_joint");
    assert!(feet > 2.0, "the feet weigh {feet} kg");
    // Ankle F/T sensors (sole frames, upright) carry the weight above the feet between them.
    let weight = model.total_mass() * 9.81;
    let fz = t.force_torque[0][2] + t.force_torque[1][2];
    let above_feet = weight - feet * 9.81;
    assert!(
        (fz - above_feet).abs() < 1e-3 * weight,
        "ankle sensors {fz:.2} N, weight above the feet {above_feet:.2} N"
    );
    assert!(
        t.force_torque[0][2] > 0.3 * weight && t.force_torque[1][2] > 0.3 * weight,
        "both feet loaded"
    );
    // Wrists touch nothing: each holds the hand's weight (frames rotated with the arm, so
    // the force's norm; the servo-held arm sways a little).
    let hand = below("wrist_left_ft_link") * 9.81;
    let f = nalgebra::Vector3::from_row_slice(&t.force_torque[2][..3]);
    assert!(
        (f.norm() - hand).abs() < 1e-2 * hand,
        "left wrist {:.3} N, hand {hand:.3} N",
        f.norm()
    );
    // Measured = truth without noise.
    assert_eq!(sensors.measured(), t);
}

#[test]
fn noise_is_reproducible_from_the_seed_and_has_its_statistics() {
    let noise = SensorNoise {
        encoders: Noise {
            std: 1e-3,
            bias: 2e-3,
        },
        force: Noise {
            std: 5.0,
            bias: 0.0,
        },
        ..Default::default()
    };
    let (_, a) = standing(noise.clone(), 42, 0.05);
    let (_, b) = standing(noise.clone(), 42, 0.05);
    let (_, c) = standing(noise, 43, 0.05);
    assert_eq!(a.measured(), b.measured(), "same seed, same readings");
    assert_ne!(
        a.measured().joint_positions,
        c.measured().joint_positions,
        "another seed, other noise"
    );
    let err = a.measured().joint_positions.clone() - &a.truth().joint_positions;
    let mean = err.mean();
    let std = (err.map(|e| (e - mean) * (e - mean)).sum() / (err.len() - 1) as f64).sqrt();
    assert!((mean - 2e-3).abs() < 1e-3, "bias {mean:.2e}");
    assert!(std > 0.5e-3 && std < 1.6e-3, "std {std:.2e}");
}

#[test]
fn unknown_sensor_frames_are_named_in_the_error() {
    let model = talos();
    let layout = SensorLayout {
        force_torque: vec![("left".into(), "no_such_frame".into())],
        imu: None,
        ..talos_layout()
    };
    let e = Sensors::new(&model, &layout, SensorNoise::default(), 0)
        .err()
        .expect("rejected")
        .to_string();
    assert!(e.contains("left") && e.contains("no_such_frame"), "{e}");
}

#[test]
fn every_noise_channel_is_validated() {
    let model = talos();
    let noise = SensorNoise {
        base_angular_velocity: Noise {
            std: -1.0,
            bias: 0.0,
        },
        ..Default::default()
    };
    let e = Sensors::new(&model, &talos_layout(), noise, 0)
        .err()
        .expect("rejected")
        .to_string();
    assert!(e.contains("noise.base_angular_velocity"), "{e}");
}

/// TALOS' sensors, from its description.
fn talos_layout() -> SensorLayout {
    let talos = corps_robot::Robot::built_in("talos").unwrap().unwrap();
    SensorLayout::of(&talos, corps_sim::ForceTorqueModel::Contact)
}
