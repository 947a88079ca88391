//! Real-time discipline: once built, a simulation step and a sensor read allocate nothing
//! (counting global allocator, per thread).

mod common;
use common::*;
use corps_sim::*;
use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

struct Counting;

thread_local! {
    static ALLOCS: Cell<usize> = const { Cell::new(0) };
}

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, l: Layout) -> *mut u8 {
        let _ = ALLOCS.try_with(|c| c.set(c.get() + 1));
        System.alloc(l)
    }
    unsafe fn dealloc(&self, p: *mut u8, l: Layout) {
        System.dealloc(p, l)
    }
    unsafe fn realloc(&self, p: *mut u8, l: Layout, n: usize) -> *mut u8 {
        let _ = ALLOCS.try_with(|c| c.set(c.get() + 1));
        System.realloc(p, l, n)
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

#[test]
fn stepping_and_reading_sensors_do_not_allocate() {
    let model = talos();
    let mut q = model
        .reference_configuration("half_sitting")
        .unwrap()
        .clone();
    place_on_ground(&model, q.as_mut_slice(), 0.0).unwrap();
    let gains = ServoGains::high_gain(&model, q.as_slice(), 0.02, 1.0).unwrap();
    let mut sim = Simulator::new(
        model.clone(),
        Terrain::preset(TerrainPreset::Flat, 0.8),
        SimSettings::default(),
        q.as_slice(),
        gains,
    )
    .unwrap();
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
    let mut sensors = Sensors::new(&model, &SensorLayout::default(), noise, 7).unwrap();
    let cmd = hold(&model, &q);
    sim.step(&cmd).unwrap(); // the first step stores the command
    sensors.update(&sim);
    let before = ALLOCS.with(|c| c.get());
    for _ in 0..200 {
        sim.step(&cmd).unwrap();
        sensors.update(&sim);
    }
    let n = ALLOCS.with(|c| c.get()) - before;
    assert_eq!(n, 0, "{n} heap allocations in 200 steps");
    assert!(
        sensors.truth().force_torque[0][2] < -100.0 || sensors.truth().force_torque[0][2] > 100.0,
        "ankle F/T reads the weight"
    );
}
