//! The teleoperation controller's tick — the operator's pose, its retargeting, the tasks'
//! references, the two-layer HQP and its integration — allocates nothing once set up
//! (counting global allocator, per thread): iCub following a shared clip of a person (read in
//! place), the feet loaded, for the whole clip.

use corps_control::stabilizer::Wrench;
use corps_scenario::controller::teleop_velocity::{TeleopVelocityConfig, TeleopVelocityController};
use corps_scenario::controller::{Measured, WholeBodyController};
use corps_scenario::scenario::Scenario;
use corps_scenario::targets::Targets;
use corps_testkit::{allocations, CountingAllocator};
use nalgebra::{Isometry3, Vector3};
use std::path::PathBuf;

#[global_allocator]
static GLOBAL: CountingAllocator = CountingAllocator;

fn repo(rel: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../..")
        .join(rel)
}

#[test]
fn a_teleoperation_tick_does_not_allocate() {
    let path = repo("scenarios/teleop/icub_raise_hands.toml");
    let scenario = Scenario::parse(&std::fs::read_to_string(&path).unwrap()).unwrap();
    let dir = path.parent().unwrap();
    let operator = scenario.mocap.as_ref().unwrap().open(dir).unwrap();
    let robot = operator.mapping.robot().unwrap();
    let config: TeleopVelocityConfig =
        toml::from_str(&std::fs::read_to_string(repo("config/teleop/velocity_hqp.toml")).unwrap())
            .unwrap();
    let dt = 0.01;
    let frames = operator.clip.frames();
    let frame_time = operator.clip.frame_time;
    let q = robot.posture.clone();
    let mut c = TeleopVelocityController::new(&robot, config, dt, &q, operator).unwrap();
    let mut weight = Wrench::default();
    weight.force.z = 150.0;
    let measured = Measured {
        com: Vector3::zeros(),
        com_velocity: Vector3::zeros(),
        zmp: None,
        hands: &[],
        feet: [Isometry3::identity(); 2],
        foot_wrenches: [weight; 2],
    };
    let feet = [corps_model::spatial::Se3::identity(); 2];
    let targets = Targets::at_rest(&Vector3::zeros(), &feet);
    let v = vec![0.0; robot.model.nv];
    // The first ticks size the QP.
    for k in 0..3 {
        assert!(c
            .tick(k as f64 * dt, q.as_slice(), &v, &targets, &measured)
            .is_none());
    }
    let ticks = (frames as f64 * frame_time / dt) as usize;
    let before = allocations();
    for k in 3..ticks {
        let r = c.tick(k as f64 * dt, q.as_slice(), &v, &targets, &measured);
        assert!(r.is_none(), "{r:?}");
    }
    let n = allocations() - before;
    assert_eq!(n, 0, "{n} heap allocations in {} ticks", ticks - 3);
}
