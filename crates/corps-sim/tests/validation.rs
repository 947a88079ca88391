//! The simulator's validation cases (issue "Built-in physics simulator", item 8), each with
//! its bound.

mod common;
use common::*;
use corps_model::spatial::rotation::rpy_to_matrix;
use corps_model::{neutral, Model};
use corps_sim::*;
use nalgebra::{DVector, Vector3};
use std::sync::Arc;

fn sim(model: Arc<Model>, terrain: Terrain, settings: SimSettings, q: &DVector<f64>) -> Simulator {
    let gains = no_gains(&model);
    Simulator::new(model, terrain, settings, q.as_slice(), gains).unwrap()
}

fn run(s: &mut Simulator, cmd: &Command, seconds: f64) {
    let n = (seconds / s.settings().control_dt).round() as usize;
    for _ in 0..n {
        s.step(cmd).unwrap();
    }
}

#[test]
fn energy_is_conserved_without_contact_or_damping() {
    // TALOS falling freely with its joints swinging (no terrain, zero torques), 5 s at 1 ms.
    let model = talos();
    let q0 = model
        .reference_configuration("half_sitting")
        .unwrap()
        .clone();
    let mut s = sim(
        model.clone(),
        Terrain::preset(TerrainPreset::None, 0.0),
        SimSettings::default(),
        &q0,
    );
    let v0 = DVector::from_fn(model.nv, |k, _| 0.5 * ((k as f64) * 0.7).sin());
    s.set_state(q0.as_slice(), v0.as_slice()).unwrap();
    let e0 = s.energy().unwrap();
    let ke0 = corps_model::kinetic_energy(
        &model,
        &mut corps_model::Data::new(&model),
        q0.as_slice(),
        v0.as_slice(),
    )
    .unwrap();
    let cmd = zero_torque(&model);
    let mut worst = 0.0f64;
    for _ in 0..5 {
        run(&mut s, &cmd, 1.0);
        worst = worst.max((s.energy().unwrap() - e0).abs());
    }
    // Relative to the energy in motion at the end (kinetic, dominated by the 5 s fall).
    let scale = corps_model::kinetic_energy(
        &model,
        &mut corps_model::Data::new(&model),
        s.q().as_slice(),
        s.v().as_slice(),
    )
    .unwrap();
    assert!(ke0 > 1.0, "the joints must be moving");
    assert!(
        worst / scale < 1e-4,
        "energy drift {worst:.3e} J over a kinetic energy of {scale:.1} J"
    );
}

#[test]
fn energy_is_conserved_for_a_swinging_fixed_base_robot() {
    // simple_humanoid welded to the world, limbs swinging under gravity for 5 s.
    let model = Arc::new(
        corps_model::build_model_from_urdf_file(
            repo("robots/simple_humanoid_description/urdf/simple_humanoid.urdf"),
            corps_model::RootJoint::Fixed,
        )
        .unwrap(),
    );
    let q0 = neutral(&model);
    let mut s = sim(
        model.clone(),
        Terrain::preset(TerrainPreset::None, 0.0),
        SimSettings::default(),
        &q0,
    );
    let v0 = DVector::from_fn(model.nv, |k, _| ((k as f64) * 1.3).cos());
    s.set_state(q0.as_slice(), v0.as_slice()).unwrap();
    let e0 = s.energy().unwrap();
    let ke0 = corps_model::kinetic_energy(
        &model,
        &mut corps_model::Data::new(&model),
        q0.as_slice(),
        v0.as_slice(),
    )
    .unwrap();
    let cmd = zero_torque(&model);
    let mut worst = 0.0f64;
    for _ in 0..50 {
        run(&mut s, &cmd, 0.1);
        worst = worst.max((s.energy().unwrap() - e0).abs());
    }
    assert!(
        worst / ke0 < 1e-4,
        "energy drift {worst:.3e} J for {ke0:.2} J of initial kinetic energy"
    );
}

fn box_rests(settings: SimSettings) {
    let (m, g) = (2.0, 9.81);
    let model = box_body(m, [0.2, 0.15, 0.1]);
    let mut q = neutral(&model);
    q[2] = 0.05; // touching
    let mut s = sim(
        model.clone(),
        Terrain::preset(TerrainPreset::Flat, 0.8),
        settings.clone(),
        &q,
    );
    let cmd = zero_torque(&model);
    run(&mut s, &cmd, 1.0);
    let start = s.q().clone_owned();
    run(&mut s, &cmd, 10.0);
    let fz: f64 = s.contact().point_forces.iter().map(|f| f.z).sum();
    assert!(
        (fz - m * g).abs() <= 0.005 * m * g,
        "normal force {fz:.4} N, weight {:.4} N",
        m * g
    );
    let drift = (s.q().fixed_rows::<3>(0) - start.fixed_rows::<3>(0)).norm();
    assert!(drift < 1e-5, "drift {drift:.3e} m over 10 s");
}

under_both_integrators!(
    box_rests:
    a_box_rests_on_a_plane_with_its_weight_and_does_not_drift,
    implicit_euler_box_rests_on_a_plane_with_its_weight_and_does_not_drift
);

/// A block on a plane inclined by `theta` about y, friction `mu`: returns its displacement
/// along the slope over `seconds`, sampled each control period.
fn incline(settings: SimSettings, theta: f64, mu: f64, seconds: f64) -> Vec<(f64, f64)> {
    let model = box_body(1.0, [0.1, 0.1, 0.05]);
    let n = rpy_to_matrix(0.0, -theta, 0.0) * Vector3::z();
    let terrain = Terrain {
        surfaces: vec![Surface::Plane {
            point: Vector3::zeros(),
            normal: n,
            mu,
        }],
    };
    let mut q = neutral(&model);
    // Block aligned with the slope, resting on it.
    let r = rpy_to_matrix(0.0, -theta, 0.0);
    let quat = corps_model::spatial::rotation::matrix_to_quat(&r);
    q.as_mut_slice()[3..7].copy_from_slice(&quat);
    let c = n * 0.025;
    q.as_mut_slice()[..3].copy_from_slice(c.as_slice());
    let mut s = sim(model.clone(), terrain, settings, &q);
    let down = rpy_to_matrix(0.0, -theta, 0.0) * Vector3::x(); // along the slope (descending: -x side)
    let cmd = zero_torque(&model);
    let mut out = vec![];
    let p0 = Vector3::new(q[0], q[1], q[2]);
    for k in 0..(seconds / 1e-3) as usize {
        s.step(&cmd).unwrap();
        let p = Vector3::new(s.q()[0], s.q()[1], s.q()[2]);
        out.push(((k + 1) as f64 * 1e-3, -(p - p0).dot(&down)));
    }
    out
}

fn block_stays(settings: SimSettings) {
    // μ = 0.5: friction angle 26.6°; at 20° the block holds.
    let track = incline(settings, 20f64.to_radians(), 0.5, 5.0);
    let slip = track.iter().map(|(_, s)| s.abs()).fold(0.0, f64::max);
    assert!(slip < 1e-3, "slipped {slip:.3e} m in 5 s");
}

under_both_integrators!(
    block_stays:
    a_block_below_the_friction_angle_stays,
    implicit_euler_block_below_the_friction_angle_stays
);

fn block_slides(settings: SimSettings) {
    let (theta, mu, g) = (35f64.to_radians(), 0.5, 9.81);
    let expected = g * (theta.sin() - mu * theta.cos());
    let track = incline(settings, theta, mu, 1.5);
    // Least-squares fit s = s0 + v0 t + a t²/2 over 0.5–1.5 s.
    let pts: Vec<_> = track.into_iter().filter(|(t, _)| *t >= 0.5).collect();
    let a = fit_acceleration(&pts);
    assert!(
        (a - expected).abs() <= 0.02 * expected,
        "acceleration {a:.4} m/s², analytic {expected:.4}"
    );
}

under_both_integrators!(
    block_slides:
    a_block_above_the_friction_angle_slides_with_the_coulomb_acceleration,
    implicit_euler_block_above_the_friction_angle_slides_with_the_coulomb_acceleration
);

fn fit_acceleration(pts: &[(f64, f64)]) -> f64 {
    let mut ata = nalgebra::Matrix3::<f64>::zeros();
    let mut atb = Vector3::zeros();
    for (t, s) in pts {
        let row = Vector3::new(1.0, *t, t * t / 2.0);
        ata += row * row.transpose();
        atb += row * *s;
    }
    (ata.try_inverse().unwrap() * atb)[2]
}

fn dropped_box_settles(settings: SimSettings) {
    let model = box_body(1.5, [0.1, 0.1, 0.1]);
    let mut q = neutral(&model);
    q[2] = 0.4;
    // Tilted so that it lands on a corner.
    let quat = corps_model::spatial::rotation::matrix_to_quat(&rpy_to_matrix(0.3, 0.2, 0.1));
    q.as_mut_slice()[3..7].copy_from_slice(&quat);
    let mut s = sim(
        model.clone(),
        Terrain::preset(TerrainPreset::Flat, 0.8),
        settings.clone(),
        &q,
    );
    let e0 = s.energy().unwrap();
    let cmd = zero_torque(&model);
    let mut max_e = f64::NEG_INFINITY;
    for _ in 0..3000 {
        s.step(&cmd).unwrap();
        max_e = max_e.max(s.energy().unwrap());
    }
    assert!(
        max_e <= e0 + 1e-6 * e0.abs().max(1.0),
        "energy rose from {e0:.6} to {max_e:.6} J"
    );
    assert!(
        s.v().amax() < 1e-3,
        "still moving after 3 s: {:.3e}",
        s.v().amax()
    );
    assert!(
        (s.q()[2] - 0.05).abs() < 2e-3,
        "rests at z = {:.4}",
        s.q()[2]
    );
}

under_both_integrators!(
    dropped_box_settles:
    a_dropped_box_settles_without_gaining_energy,
    implicit_euler_dropped_box_settles_without_gaining_energy
);

fn sole_positions(s: &Simulator) -> [Vector3<f64>; 2] {
    let m = s.model();
    ["leg_left_sole_fix_joint", "leg_right_sole_fix_joint"].map(|f| {
        let fid = m.frame_id(f).unwrap();
        corps_model::frame_placement(m, s.data(), fid)
            .unwrap()
            .translation
    })
}

fn talos_stands(settings: SimSettings) {
    let (mut s, q) = standing_talos_with(settings);
    let model = s.model().clone();
    let cmd = hold(&model, &q);
    s.step(&cmd).unwrap();
    let feet0 = sole_positions(&s);
    run(&mut s, &cmd, 10.0);
    let weight = model.total_mass() * 9.81;
    let fz: f64 = s.contact().point_forces.iter().map(|f| f.z).sum();
    assert!(
        (fz - weight).abs() <= 0.01 * weight,
        "vertical contact force {fz:.2} N for a weight of {weight:.2} N"
    );
    let feet = sole_positions(&s);
    for k in 0..2 {
        let slip = (feet[k] - feet0[k]).xy().norm();
        assert!(slip < 1e-3, "foot {k} slipped {slip:.3e} m");
    }
    assert!(s.q()[2] > 0.9, "base height {:.3}", s.q()[2]);
    // Standing still: no joint drifting at a spurious speed (an integrator-stability symptom).
    assert!(
        s.v().amax() < 0.05,
        "largest velocity {:.3e} while standing",
        s.v().amax()
    );
}

under_both_integrators!(
    talos_stands:
    talos_stands_under_the_pd_hold,
    implicit_euler_talos_stands_under_the_pd_hold
);

/// The placements and world twists `Simulator::data` hands out (to sensors and metrics) are
/// those of the current state, as a fresh kinematic pass computes them.
fn kinematics_are_current(s: &Simulator) {
    let model = s.model();
    let mut fresh = corps_model::Data::new(model);
    let zero = DVector::zeros(model.nv);
    corps_model::forward_kinematics(
        model,
        &mut fresh,
        s.q().as_slice(),
        s.v().as_slice(),
        zero.as_slice(),
    )
    .unwrap();
    let data = s.data();
    for i in 0..model.njoints() {
        let (m, f) = (&data.o_m_i[i], &fresh.o_m_i[i]);
        let ov = f.act_motion(&fresh.v[i]);
        let err = [
            (m.translation - f.translation).amax(),
            (m.rotation - f.rotation).amax(),
            (data.ov[i].linear - ov.linear).amax(),
            (data.ov[i].angular - ov.angular).amax(),
        ];
        assert!(
            err.iter().all(|e| *e < 1e-9),
            "joint {i}: placement / twist off by {err:?}"
        );
    }
}

fn push_moves_robot(settings: SimSettings) {
    let (mut s, q) = standing_talos_with(settings);
    let model = s.model().clone();
    let cmd = hold(&model, &q);
    run(&mut s, &cmd, 1.0);
    let x0 = s.q()[0];
    s.add_push(Push {
        frame: "base_link".into(),
        start: 1.0,
        duration: 0.1,
        force: [100.0, 0.0, 0.0],
        torque: [0.0; 3],
    })
    .unwrap();
    run(&mut s, &cmd, 0.3);
    kinematics_are_current(&s);
    let dx = s.q()[0] - x0;
    let dy = s.q()[1];
    assert!(dx > 1e-3, "base moved {dx:.4} m along the push");
    assert!(
        dx > 5.0 * dy.abs(),
        "base moved {dy:.4} m sideways for {dx:.4} m forward"
    );
}

under_both_integrators!(
    push_moves_robot:
    a_push_moves_the_standing_robot_in_the_push_direction,
    implicit_euler_push_moves_the_standing_robot_in_the_push_direction
);
