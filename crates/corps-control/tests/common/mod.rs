//! A TSID-style standing controller for TALOS in the corps simulator, shared by the
//! closed-loop tests. Gains and weights from seed 000 Tables 5.1–5.2 (the thesis's TSID torque
//! controller): CoM weight 50, Kp 50, Kd 5; posture weight 0.1, Kp 80, Kd 2√Kp; angular
//! momentum weight 0.02, Kp 10; feet contacts Kp 30, Kd 2√Kp (hard constraints, as in ch. 4);
//! μ 0.3 and 1 ≤ Σfz ≤ 1000 N as in the TSID anchor harness.
#![allow(dead_code)]

use corps_control::contacts::Contact;
use corps_control::formulation::InverseDynamics;
use corps_control::tasks::{AngularMomentumTask, ComTask, PostureTask, Reference, Se3Reference};
use corps_control::RobotState;
use corps_model::spatial::Motion;
use corps_model::{build_model_from_urdf_file, load_reference_configurations, Model, RootJoint};
use corps_sim::*;
use nalgebra::{DVector, Vector3, Vector6};
use std::sync::Arc;

pub fn talos_box() -> Arc<Model> {
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/../../");
    let mut m = build_model_from_urdf_file(
        format!("{root}robots/talos_data/robots/talos_reduced_box.urdf"),
        RootJoint::FreeFlyer,
    )
    .unwrap();
    load_reference_configurations(&mut m, format!("{root}robots/talos_data/srdf/talos.srdf"))
        .unwrap();
    Arc::new(m)
}

/// Contact settings under which the torque loop is stable (see the crate docs): 10× the
/// default stiffness, 0.25 ms physics steps.
pub fn stiff_settings() -> SimSettings {
    let mut s = SimSettings {
        substeps: 4,
        ..SimSettings::default()
    };
    s.contact.normal_stiffness = 4e8;
    s.contact.tangential_stiffness = 4e8;
    s
}

/// The scenarios' contact (`scenarios/control/tsid_torque_*.toml`): 10× the default
/// stiffness under the linearly implicit Euler integrator, one physics step per 1 ms tick.
pub fn implicit_settings() -> SimSettings {
    let mut s = SimSettings {
        integrator: Integrator::ImplicitEuler,
        ..SimSettings::default()
    };
    s.contact.normal_stiffness = 4e8;
    s.contact.tangential_stiffness = 4e8;
    s
}

/// TALOS settled in half-sitting under the PD hold (0.5 s), and its initial configuration.
pub fn settled_talos(settings: SimSettings) -> (Simulator, DVector<f64>) {
    let model = talos_box();
    let mut q0 = model
        .reference_configuration("half_sitting")
        .unwrap()
        .clone();
    place_on_ground(&model, q0.as_mut_slice(), 0.0).unwrap();
    let gains = ServoGains::high_gain(&model, q0.as_slice(), 0.02, 1.0).unwrap();
    let mut sim = Simulator::new(
        model.clone(),
        Terrain::preset(TerrainPreset::Flat, 0.8),
        settings,
        q0.as_slice(),
        gains,
    )
    .unwrap();
    let hold = Command::Position {
        q_ref: q0.clone(),
        v_ref: DVector::zeros(model.nv - 6),
    };
    for _ in 0..500 {
        sim.step(&hold).unwrap();
    }
    (sim, q0)
}

/// The standing controller, with references taken at `state`.
pub fn standing_controller(
    model: &Model,
    state: &RobotState,
    q_posture: &DVector<f64>,
) -> InverseDynamics {
    let nv = model.nv;
    let na = nv - 6;
    let kd = |kp: f64| 2.0 * kp.sqrt();
    let mut id = InverseDynamics::new(model);
    let mut com = ComTask::new(nv, Vector3::repeat(50.0), Vector3::repeat(5.0));
    com.reference = Reference::constant(DVector::from_column_slice(state.data.com.as_slice()));
    id.tasks.add("com", com, 1, 50.0).unwrap();
    let posture = PostureTask::new(
        model,
        DVector::repeat(na, 80.0),
        DVector::repeat(na, kd(80.0)),
        q_posture.clone(),
    );
    id.tasks.add("posture", posture, 1, 0.1).unwrap();
    let am = AngularMomentumTask::new(nv, Vector3::repeat(10.0));
    id.tasks.add("angular_momentum", am, 1, 0.02).unwrap();
    for frame in ["leg_left_sole_fix_joint", "leg_right_sole_fix_joint"] {
        let fid = model.frame_id(frame).unwrap();
        let placement = state.frame_placement(model, fid).unwrap();
        let pts = [(0.1, 0.065), (0.1, -0.065), (-0.1, 0.065), (-0.1, -0.065)]
            .map(|(x, y)| Vector3::new(x, y, 0.0));
        let reference = Se3Reference {
            placement,
            velocity: Motion::zero(),
            acceleration: Motion::zero(),
        };
        id.contacts.push(Contact::new(
            model,
            frame,
            fid,
            pts,
            Vector3::z(),
            0.3,
            (1.0, 1000.0),
            Vector6::repeat(30.0),
            Vector6::repeat(kd(30.0)),
            reference,
        ));
    }
    id.actuation = Some((
        -model.effort_limit.rows(6, na).into_owned(),
        model.effort_limit.rows(6, na).into_owned(),
    ));
    id
}

/// TALOS standing still in half-sitting on the ground (no simulation): the model, the
/// configuration, the state and the standing controller with references taken there.
pub fn standing() -> (Arc<Model>, DVector<f64>, RobotState, InverseDynamics) {
    let model = talos_box();
    let mut q = model
        .reference_configuration("half_sitting")
        .unwrap()
        .clone();
    place_on_ground(&model, q.as_mut_slice(), 0.0).unwrap();
    let v = DVector::zeros(model.nv);
    let mut state = RobotState::new(&model);
    state.update(&model, q.as_slice(), v.as_slice()).unwrap();
    let id = standing_controller(&model, &state, &q);
    (model, q, state, id)
}

/// TALOS at `q` with the joints moving (0.05 sin(0.7 k) rad/s), the base still: a state off
/// equilibrium for the formulation tests.
pub fn moving_state(model: &Model, q: &DVector<f64>) -> RobotState {
    let mut v = DVector::zeros(model.nv);
    for k in 6..model.nv {
        v[k] = 0.05 * ((k as f64) * 0.7).sin();
    }
    let mut state = RobotState::new(model);
    state.update(model, q.as_slice(), v.as_slice()).unwrap();
    state
}

/// The standing controller's tasks (CoM, posture, angular momentum, at its weights) in the
/// [τ; f] formulation, no contact yet, and the controller itself (its contacts to copy).
pub fn standing_torque_force(
    model: &Model,
    state: &RobotState,
    q: &DVector<f64>,
) -> (corps_control::formulation::TorqueForce, InverseDynamics) {
    let id = standing_controller(model, state, q);
    let mut tf = corps_control::formulation::TorqueForce::new(model);
    for (name, w) in [("com", 50.0), ("posture", 0.1), ("angular_momentum", 0.02)] {
        assert_eq!(id.tasks.weight(name), Some(w));
    }
    let com = id.tasks.task::<ComTask>("com").unwrap().clone();
    let posture = id.tasks.task::<PostureTask>("posture").unwrap().clone();
    let am = (id.tasks.task::<AngularMomentumTask>("angular_momentum"))
        .unwrap()
        .clone();
    tf.tasks.add("com", com, 1, 50.0).unwrap();
    tf.tasks.add("posture", posture, 1, 0.1).unwrap();
    tf.tasks.add("angular_momentum", am, 1, 0.02).unwrap();
    (tf, id)
}
