//! The teleoperation controller's tick — the operator's pose, its retargeting, the tasks'
//! references, the two-layer HQP and its integration — allocates nothing once set up
//! (counting global allocator, per thread): iCub following shared clips of a person (read in
//! place) — raising the hands, and walking (its steps queued for the walking state machine
//! inside the tick) — the feet loaded, for the whole clip.

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
    for clip in ["icub_raise_hands", "icub_walk"] {
        ticks_without_allocation(&format!("scenarios/teleop/{clip}.toml"));
    }
}

fn ticks_without_allocation(file: &str) {
    let path = repo(file);
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
    let mut c = TeleopVelocityController::new(&robot, config, dt, &q, Some(operator), &[]).unwrap();
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
    assert_eq!(n, 0, "{file}: {n} heap allocations in {} ticks", ticks - 3);
    if file.contains("walk") {
        let steps = c.teleop_metrics().unwrap().operator_steps;
        assert!(
            steps > 0,
            "{file}: the operator's steps were queued in the tick"
        );
    }
}

/// The walking state machine (Fig 6.6) through every state of 30 steps, on a robot that follows
/// its references: no allocation after it is made (its step queue and step record are fixed).
#[test]
fn the_walking_state_machine_does_not_allocate() {
    use corps_scenario::controller::teleop_walk::{PlannedStep, TeleopWalk};
    use nalgebra::Vector2;
    let text = std::fs::read_to_string(repo("config/teleop/velocity_hqp.toml")).unwrap();
    let spec = toml::from_str::<TeleopVelocityConfig>(&text)
        .unwrap()
        .walking;
    let feet = [Vector3::new(0.0, 0.07, 0.0), Vector3::new(0.0, -0.07, 0.0)];
    let mut walk = TeleopWalk::new(spec, feet, Vector3::zeros());
    let before = allocations();
    for k in 0..30 {
        walk.push(PlannedStep {
            foot: k % 2,
            travel: Vector2::new(0.05, 0.0),
            height: 0.03,
            // Every third step turns its sole.
            turn: if k % 3 == 0 { 0.1 } else { 0.0 },
        });
    }
    let mut r = walk.references(0.0);
    let dt = 0.01;
    for k in 0..60_000 {
        let t = k as f64 * dt;
        let soles = r.feet.map(|p| Isometry3::translation(p.x, p.y, p.z));
        let forces = r.feet.map(|p| if p.z < 1e-3 { 150.0 } else { 0.0 });
        r = walk.update(t, &r.com, &soles, forces);
    }
    let n = allocations() - before;
    assert_eq!(walk.steps_done, 30, "steps walked");
    assert_eq!(n, 0, "{n} heap allocations");
}
