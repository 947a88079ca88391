//! Controller A (seed 000 §3.7), the hierarchical velocity-level IK, integrated on its own:
//! a CoM step converges at the rate of its gain while both feet stay put. The closed-loop
//! scenarios of the IK on the simulated, position-controlled TALOS (stand, sinusoid, squat,
//! one foot, walks) run from their scenario files in `crates/corps/tests/`, as `corps run`
//! runs them.

mod common;
use common::*;
use corps_control::formulation::{IkGains, InverseKinematics, StackFrames};
use corps_control::tasks::velocity::ComVelocityTask;
use corps_control::tasks::Reference;
use corps_control::RobotState;
use nalgebra::{DVector, Vector3};

const DT: f64 = 1e-3;

/// The IK alone, integrated kinematically (its state is its own output): a CoM step
/// converges at the rate of its gain while both feet stay on their references.
#[test]
fn ik_kinematic_loop_converges() {
    let model = talos_box();
    let mut q = model
        .reference_configuration("half_sitting")
        .unwrap()
        .clone();
    corps_sim::place_on_ground(&model, q.as_mut_slice(), 0.0).unwrap();
    let mut state = RobotState::new(&model);
    let zero = DVector::zeros(model.nv);
    state.update(&model, q.as_slice(), zero.as_slice()).unwrap();
    let mut ik = InverseKinematics::standing_stack(
        &model,
        &state,
        DT,
        // TALOS' sole frames and waist.
        &StackFrames {
            left_foot: "leg_left_sole_fix_joint",
            right_foot: "leg_right_sole_fix_joint",
            waist: "base_link",
        },
        &IkGains::default(),
        &q,
    )
    .unwrap();
    let c0 = state.data.com;
    let target = c0 + Vector3::new(0.01, 0.02, -0.03);
    for name in ["com_height", "com_xy"] {
        ik.task_mut::<ComVelocityTask>(name).unwrap().reference =
            Reference::constant(DVector::from_column_slice(target.as_slice()));
    }
    let lf = model.frame_id("leg_left_sole_fix_joint").unwrap();
    let foot0 = state.frame_placement(&model, lf).unwrap();
    for _ in 0..100 {
        state.update(&model, q.as_slice(), zero.as_slice()).unwrap();
        let out = ik.compute(&model, &state, q.as_slice()).unwrap();
        q.copy_from(&out.q_des);
    }
    state.update(&model, q.as_slice(), zero.as_slice()).unwrap();
    let e = (state.data.com - target).norm();
    let foot = state.frame_placement(&model, lf).unwrap();
    let slip = (foot.translation - foot0.translation).norm();
    println!("kinematic: CoM error after 0.1 s {e:.3e} m, left foot moved {slip:.3e} m");
    // Unsaturated, the error would be exp(−100 · 0.1) of 3.7 cm = 1.7 µm; the first ticks
    // saturate 26 of the 38 joint-velocity bounds (the degenerate vertex of corps-qp's
    // `tests/data/ik_talos_degenerate.json`), which delays convergence (measured 9.8 µm).
    assert!(e < 1e-5 && slip < 1e-6);
}
