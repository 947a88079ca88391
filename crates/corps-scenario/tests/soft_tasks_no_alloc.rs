//! The soft-tasks controller's tick allocates nothing while the contacts stay as they are
//! (a contact added or removed resizes the QP once): iCub standing at half-sitting under
//! `config/icub/soft_tasks.toml`, 150 ticks of FSM #2's first state (two feet, 2 s), and
//! under `config/icub/soft_tasks_fsm1.toml` 300 ticks through FSM #1's switch from its first
//! state to its second (new gains blending in, the posture heading to Table A.7's set-point),
//! after one tick of warm-up.

use corps_control::stabilizer::Wrench;
use corps_robot::Robot;
use corps_scenario::controller::{
    Measured, SoftTasksConfig, SoftTasksController, WholeBodyController,
};
use corps_scenario::gains::{self, GainsSource};
use corps_scenario::targets::Targets;
use corps_testkit::{allocations, CountingAllocator};
use nalgebra::{DVector, Isometry3, Translation3, UnitQuaternion, Vector3};

#[global_allocator]
static GLOBAL: CountingAllocator = CountingAllocator;

#[test]
fn a_tick_between_contact_changes_allocates_nothing() {
    let state = ticks_allocate_nothing("icub", "soft_tasks", 150);
    assert_eq!(state, 0.0, "still in the first state");
}

#[test]
fn a_state_switch_of_fsm1_allocates_nothing() {
    let state = ticks_allocate_nothing("icub_parallel_legs", "soft_tasks_fsm1", 300);
    assert_eq!(state, 1.0, "in FSM #1's second state");
}

/// `ticks` ticks of robot `name` under its gains file `gains`, the robot held where it
/// stands, after one tick of warm-up; returns the state machine's state at the end.
fn ticks_allocate_nothing(name: &str, gains: &str, ticks: usize) -> f64 {
    let robot = Robot::built_in(name).unwrap().unwrap();
    let model = robot.model.clone();
    let source = GainsSource::resolve(
        Some(std::path::Path::new(gains)),
        "soft_tasks",
        &robot,
        std::path::Path::new("."),
    )
    .unwrap();
    let config: SoftTasksConfig = gains::load(&source, &toml::Table::new()).unwrap();
    let q = robot.posture.clone();
    let v = DVector::zeros(model.nv);
    let mut controller = SoftTasksController::new(&robot, config, 0.01, &q, &v).unwrap();
    let mut data = corps_model::Data::new(&model);
    corps_model::forward_kinematics_placements(&model, &mut data, q.as_slice()).unwrap();
    let (com, _) = corps_model::com_at_placements(&model, &data);
    let feet = [0, 1].map(|k| {
        let p = corps_model::frame_placement(&model, &data, robot.feet[k].frame).unwrap();
        let r = nalgebra::Rotation3::from_matrix_unchecked(p.rotation);
        Isometry3::from_parts(
            Translation3::from(p.translation),
            UnitQuaternion::from_rotation_matrix(&r),
        )
    });
    let half = model.total_mass() * corps_model::STANDARD_GRAVITY / 2.0;
    let measured = Measured {
        com,
        com_velocity: Vector3::zeros(),
        zmp: None,
        feet,
        foot_wrenches: [0, 1].map(|_| Wrench::new(Vector3::new(0.0, 0.0, half), Vector3::zeros())),
        hands: &[],
    };
    let targets = Targets::at_rest(
        &com,
        &[0, 1].map(|k| corps_model::frame_placement(&model, &data, robot.feet[k].frame).unwrap()),
    );
    let tick = |c: &mut SoftTasksController, k: usize| {
        let r = c.tick(
            0.01 * k as f64,
            q.as_slice(),
            v.as_slice(),
            &targets,
            &measured,
        );
        assert!(r.is_none(), "{r:?}");
    };
    tick(&mut controller, 0);
    let before = allocations();
    for k in 1..ticks {
        tick(&mut controller, k);
    }
    assert_eq!(
        allocations() - before,
        0,
        "allocations in {} ticks",
        ticks - 1
    );
    let mut row = Vec::new();
    controller.push_channels(&mut row);
    row[0]
}
