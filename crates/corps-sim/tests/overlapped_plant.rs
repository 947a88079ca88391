//! The simulated robot stepped on its worker thread (the overlap) reads, steps and ends
//! exactly as on the caller's thread: every tick's readings and true state, and the final
//! state, bit for bit, whichever ticks overlap and whichever thread runs the loop.

mod common;
use common::*;
use corps_loop::{Command, Plant, Sensed};
use corps_sim::*;
use corps_testkit::{allocations, CountingAllocator};
use nalgebra::DVector;

#[global_allocator]
static GLOBAL: CountingAllocator = CountingAllocator;

const TICKS: usize = 400;

fn noisy_sensors(model: &corps_model::Model) -> Sensors {
    let talos = corps_robot::Robot::built_in("talos").unwrap().unwrap();
    let layout = SensorLayout::of(&talos, ForceTorqueModel::Contact);
    let noise = SensorNoise {
        encoders: Noise {
            std: 1e-4,
            bias: 0.0,
        },
        joint_velocities: Noise {
            std: 1e-2,
            bias: 0.0,
        },
        force: Noise {
            std: 2.0,
            bias: 0.0,
        },
        ..Default::default()
    };
    Sensors::new(model, &layout, noise, 11).unwrap()
}

/// Standing TALOS under implicit Euler with noisy sensors, and the configuration it holds.
fn plant(overlap: Overlap) -> (SimulatedRobot, DVector<f64>) {
    let (sim, q0) = standing_talos_with(implicit_stiff());
    let sensors = noisy_sensors(sim.model());
    (SimulatedRobot::new(sim, sensors, overlap), q0)
}

/// A command that depends on what was sensed (its noise included): the servo holds `q0` and
/// damps the measured joint velocities.
fn command(q0: &DVector<f64>, sensed: &Sensed) -> Command {
    Command::Position {
        q_ref: q0.clone(),
        v_ref: -0.5 * &sensed.readings.joint_velocities,
    }
}

/// One tick as the closed loop runs it: sense, prepare, complete, step.
fn tick(plant: &mut SimulatedRobot, sensed: &mut Sensed, q0: &DVector<f64>) {
    plant.sense(sensed).unwrap();
    plant.prepare();
    plant.complete(sensed).unwrap();
    plant.step(&command(q0, sensed)).unwrap();
}

#[test]
fn a_plant_stepped_on_its_worker_is_the_serial_plant() {
    for overlap in [Overlap::Always, Overlap::Adaptive] {
        let (mut serial, q0) = plant(Overlap::Never);
        let (mut overlapped, _) = plant(overlap);
        let (mut a, mut b) = (serial.sensed(), overlapped.sensed());
        // Half the run on this thread, half on another: the worker wakes whichever thread
        // runs the loop.
        for k in 0..TICKS / 2 {
            tick(&mut serial, &mut a, &q0);
            tick(&mut overlapped, &mut b, &q0);
            assert_eq!(a, b, "{overlap:?}, tick {k}");
        }
        std::thread::scope(|s| {
            s.spawn(|| {
                for k in TICKS / 2..TICKS {
                    tick(&mut serial, &mut a, &q0);
                    tick(&mut overlapped, &mut b, &q0);
                    assert_eq!(a, b, "{overlap:?}, tick {k} (another thread)");
                }
            });
        });
        assert!(
            a.truth.as_ref().is_some_and(|t| !t.contacts.is_empty()),
            "the feet carry the robot"
        );
        let (ticks_overlapped, _) = overlapped.overlap_counts();
        if overlap == Overlap::Always {
            assert_eq!(ticks_overlapped, TICKS as u64);
        }
        let (sim_a, sim_b) = (
            serial.into_simulator().unwrap(),
            overlapped.into_simulator().unwrap(),
        );
        assert_eq!(sim_a.q(), sim_b.q(), "{overlap:?}");
        assert_eq!(sim_a.v(), sim_b.v(), "{overlap:?}");
        assert_eq!(sim_a.time(), sim_b.time());
    }
}

#[test]
fn a_caller_that_skips_complete_still_gets_every_tick_s_readings() {
    // Only the true state waits for `complete`: a loop that never reads it (a real robot's
    // loop has none) gets the same readings.
    let (mut serial, q0) = plant(Overlap::Never);
    let (mut overlapped, _) = plant(Overlap::Always);
    let (mut a, mut b) = (serial.sensed(), overlapped.sensed());
    for k in 0..100 {
        serial.sense(&mut a).unwrap();
        overlapped.sense(&mut b).unwrap();
        overlapped.prepare();
        assert_eq!(a.readings, b.readings, "tick {k}");
        assert_eq!(a.time, b.time);
        serial.step(&command(&q0, &a)).unwrap();
        overlapped.step(&command(&q0, &b)).unwrap();
    }
}

#[test]
fn an_overlapped_tick_allocates_nothing_on_the_loop_s_thread() {
    let (mut plant, q0) = plant(Overlap::Always);
    let mut sensed = plant.sensed();
    let mut cmd = command(&q0, &sensed);
    for _ in 0..5 {
        tick(&mut plant, &mut sensed, &q0);
    }
    let before = allocations();
    for _ in 0..100 {
        plant.sense(&mut sensed).unwrap();
        plant.prepare();
        plant.complete(&mut sensed).unwrap();
        if let Command::Position { v_ref, .. } = &mut cmd {
            for (v, w) in v_ref
                .iter_mut()
                .zip(sensed.readings.joint_velocities.iter())
            {
                *v = -0.5 * w;
            }
        }
        plant.step(&cmd).unwrap();
    }
    let n = allocations() - before;
    assert_eq!(n, 0, "{n} heap allocations in 100 overlapped ticks");
    assert_eq!(plant.overlap_counts().0, 105);
}
