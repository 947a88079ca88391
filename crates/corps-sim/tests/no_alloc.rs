//! Real-time discipline: once built, a simulation step and a sensor read allocate nothing
//! (counting global allocator, per thread).

mod common;
use common::*;
use corps_sim::*;
use corps_testkit::{allocations, CountingAllocator};

#[global_allocator]
static GLOBAL: CountingAllocator = CountingAllocator;

under_both_integrators!(
    steps_without_allocating:
    stepping_and_reading_sensors_do_not_allocate,
    implicit_euler_steps_do_not_allocate
);

fn steps_without_allocating(settings: SimSettings) {
    let (mut sim, q) = standing_talos_with(settings);
    let model = sim.model().clone();
    sim.add_push(Push {
        frame: "base_link".into(),
        start: 0.05,
        duration: 0.05,
        force: [50.0, 0.0, 0.0],
        torque: [0.0; 3],
    })
    .unwrap();
    let noise = SensorNoise {
        encoders: Noise {
            std: 1e-4,
            bias: 0.0,
        },
        imu_orientation: Noise {
            std: 1e-3,
            bias: 0.0,
        },
        ..Default::default()
    };
    let mut sensors = Sensors::new(&model, &talos_layout(), noise, 7).unwrap();
    let cmd = hold(&model, &q);
    sim.step(&cmd).unwrap(); // the first step stores the command
    sensors.update(&sim);
    let before = allocations();
    for k in 0..200 {
        // Half the steps prepared ahead (as `corps run` does on its second thread).
        if k % 2 == 0 {
            sim.prepare_step();
        }
        sim.step(&cmd).unwrap();
        sensors.update(&sim);
    }
    let n = allocations() - before;
    assert_eq!(n, 0, "{n} heap allocations in 200 steps");
    assert!(
        sensors.truth().force_torque[0][2] < -100.0 || sensors.truth().force_torque[0][2] > 100.0,
        "ankle F/T reads the weight"
    );
}

/// TALOS' sensors, from its description.
fn talos_layout() -> SensorLayout {
    let talos = corps_robot::Robot::built_in("talos").unwrap().unwrap();
    SensorLayout::of(&talos, corps_sim::ForceTorqueModel::Contact)
}

under_both_integrators!(
    drives_step_without_allocating:
    steps_through_joint_drives_do_not_allocate,
    implicit_steps_through_joint_drives_do_not_allocate
);

/// Torque commands through flexible drives on every joint (delay line, motor states). An
/// explicit step must resolve the drive's spring on the lightest link (RK4: ten substeps).
fn drives_step_without_allocating(mut settings: SimSettings) {
    if settings.integrator == Integrator::Rk4 {
        settings.substeps = 10;
    }
    let (mut sim, _) = standing_talos_with(settings);
    let na = sim.model().nv - first_actuated(sim.model());
    let drive = FlexibleDrive {
        motor_inertia: 0.45,
        stiffness: 1.5e4,
        damping: 8.0,
        viscous_friction: 5.57,
        dry_friction: 4.55,
        friction_velocity: 0.001,
        drive_gain: 10.6,
        current_limit: 10.0,
        bandwidth_hz: 500.0,
        delay_periods: 3,
    };
    sim.set_drives(vec![Some(drive); na]).unwrap();
    let cmd = Command::Torque(nalgebra::DVector::from_element(na, 1.0));
    sim.step(&cmd).unwrap();
    let before = allocations();
    for k in 0..50 {
        if k % 2 == 0 {
            sim.prepare_step();
        }
        sim.step(&cmd).unwrap();
    }
    let n = allocations() - before;
    assert_eq!(n, 0, "{n} heap allocations in 50 steps");
    assert!(sim.drives().is_some_and(|d| d.state(0).current != 0.0));
}

/// The flexible-hip TALOS seen through its rigid model: widening the commands and narrowing
/// the readings and the true state allocate nothing once sized.
#[test]
fn a_plant_with_hidden_joints_steps_and_reads_without_allocating() {
    use corps_loop::Plant;
    let (mut plant, robot, q0) = flexible_talos();
    let rigid = robot.model.clone();
    let mut sensed = plant.sensed();
    let cmd = hold(&rigid, &q0);
    plant.step(&cmd).unwrap(); // the first step sizes the widened command
    plant.sense(&mut sensed).unwrap();
    plant.complete(&mut sensed).unwrap();
    let before = allocations();
    for _ in 0..100 {
        plant.step(&cmd).unwrap();
        plant.sense(&mut sensed).unwrap();
        plant.complete(&mut sensed).unwrap();
    }
    let n = allocations() - before;
    assert_eq!(n, 0, "{n} heap allocations in 100 ticks");
    assert!(sensed
        .truth
        .as_ref()
        .is_some_and(|t| !t.contacts.is_empty()));
}
