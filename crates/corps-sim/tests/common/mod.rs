//! Shared helpers of the simulator tests.
#![allow(dead_code)]

use corps_model::{
    build_model_from_urdf_file, build_model_from_urdf_str, load_reference_configurations, Model,
    RootJoint,
};
use corps_sim::*;
use nalgebra::DVector;
use std::sync::Arc;

pub fn repo(rel: &str) -> String {
    format!("{}/../../{}", env!("CARGO_MANIFEST_DIR"), rel)
}

/// TALOS with box feet and its SRDF reference configurations.
pub fn talos() -> Arc<Model> {
    let mut m = build_model_from_urdf_file(
        repo("robots/talos_data/robots/talos_reduced_box.urdf"),
        RootJoint::FreeFlyer,
    )
    .unwrap();
    load_reference_configurations(&mut m, repo("robots/talos_data/srdf/talos.srdf")).unwrap();
    Arc::new(m)
}

/// A single box body (free-flyer) of mass `m` and sides `size`.
pub fn box_body(m: f64, size: [f64; 3]) -> Arc<Model> {
    let [a, b, c] = size;
    let (ixx, iyy, izz) = (
        m * (b * b + c * c) / 12.0,
        m * (a * a + c * c) / 12.0,
        m * (a * a + b * b) / 12.0,
    );
    let urdf = format!(
        r#"<robot name="block"><link name="block"><inertial><mass value="{m}"/>
        <inertia ixx="{ixx}" iyy="{iyy}" izz="{izz}" ixy="0" ixz="0" iyz="0"/></inertial>
        <collision><geometry><box size="{a} {b} {c}"/></geometry></collision></link></robot>"#
    );
    Arc::new(build_model_from_urdf_str(&urdf, RootJoint::FreeFlyer).unwrap())
}

pub fn no_gains(model: &Model) -> ServoGains {
    let na = model.nv - first_actuated(model);
    ServoGains {
        kp: DVector::zeros(na),
        kd: DVector::zeros(na),
        integral: None,
    }
}

pub fn zero_torque(model: &Model) -> Command {
    Command::Torque(DVector::zeros(model.nv - first_actuated(model)))
}

/// Position command holding configuration `q`.
pub fn hold(model: &Model, q: &DVector<f64>) -> Command {
    Command::Position {
        q_ref: q.clone(),
        v_ref: DVector::zeros(model.nv - first_actuated(model)),
    }
}

/// TALOS in half-sitting placed on flat ground (μ 0.8), default settings, with the stiff
/// joint PD servo; returns the simulator and the configuration it holds.
pub fn standing_talos() -> (Simulator, DVector<f64>) {
    standing_talos_with(SimSettings::default())
}

/// TALOS in half-sitting on flat ground under the high-gain servo, with `settings`.
pub fn standing_talos_with(settings: SimSettings) -> (Simulator, DVector<f64>) {
    let model = talos();
    let mut q = model
        .reference_configuration("half_sitting")
        .unwrap()
        .clone();
    place_on_ground(&model, q.as_mut_slice(), 0.0).unwrap();
    let gains = ServoGains::high_gain(&model, q.as_slice(), 0.02, 1.0).unwrap();
    let s = Simulator::new(
        model,
        Terrain::preset(TerrainPreset::Flat, 0.8),
        settings,
        q.as_slice(),
        gains,
    )
    .unwrap();
    (s, q)
}

/// The walking runs' simulator: linearly implicit Euler at 1 ms with the stiff contact a
/// rigid-contact torque controller needs (4·10⁸ N/m per m², 10× the default).
#[allow(dead_code)]
pub fn implicit_stiff() -> SimSettings {
    let mut s = SimSettings {
        integrator: Integrator::ImplicitEuler,
        ..SimSettings::default()
    };
    s.contact.normal_stiffness = 4e8;
    s.contact.tangential_stiffness = 4e8;
    s
}

/// One test per integrator for a check taking the simulator settings: RK4 on the default
/// contact (`$rk4`) and implicit Euler on the walks' stiff contact (`$implicit`).
#[allow(unused_macros)]
macro_rules! under_both_integrators {
    ($check:ident: $rk4:ident, $implicit:ident) => {
        #[test]
        fn $rk4() {
            $check(SimSettings::default());
        }

        #[test]
        fn $implicit() {
            $check(implicit_stiff());
        }
    };
}
#[allow(unused_imports)]
pub(crate) use under_both_integrators;

/// Mass (kg) and arm (m) of [`pendulum`], and gravity.
pub const MASS: f64 = 2.0;
pub const ARM: f64 = 0.5;
pub const G: f64 = 9.81;

/// A point-like mass on a massless arm about the y axis, horizontal at q = 0 (fixed base,
/// no collision shape, so no contact).
pub fn pendulum() -> Arc<Model> {
    let urdf = format!(
        r#"<robot name="pendulum">
  <link name="base"/>
  <link name="arm"><inertial><origin xyz="{ARM} 0 0"/><mass value="{MASS}"/>
    <inertia ixx="1e-4" iyy="1e-4" izz="1e-4" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <joint name="hinge" type="revolute"><parent link="base"/><child link="arm"/>
    <axis xyz="0 1 0"/><limit lower="-3" upper="3" effort="1000" velocity="10"/></joint>
</robot>"#
    );
    Arc::new(build_model_from_urdf_str(&urdf, RootJoint::Fixed).unwrap())
}

/// The flexible-hip TALOS standing on the ground under implicit Euler, seen through its rigid
/// model: the plant, the description and the rigid standing configuration.
pub fn flexible_talos() -> (
    WithHiddenJoints<SimulatedRobot>,
    corps_robot::Robot,
    DVector<f64>,
) {
    let robot = corps_robot::Robot::built_in("talos_flexible_hip")
        .unwrap()
        .unwrap();
    let variant = robot.plant.clone().unwrap();
    let rigid = robot.model.clone();
    let map = HiddenJoints::new(&rigid, &variant.model).unwrap();
    let mut q0 = robot.posture.clone();
    place_on_ground(&rigid, q0.as_mut_slice(), 0.0).unwrap();
    let (q, _) = map.widen_state(q0.as_slice(), &vec![0.0; rigid.nv]);
    let model = variant.model.clone();
    let gains = ServoGains::high_gain(&model, q.as_slice(), 0.02, 1.0).unwrap();
    let settings = SimSettings {
        integrator: Integrator::ImplicitEuler,
        ..Default::default()
    };
    let terrain = Terrain::preset(TerrainPreset::Flat, 0.8);
    let mut sim = Simulator::new(model.clone(), terrain, settings, q.as_slice(), gains).unwrap();
    let passive: Vec<_> = (variant.passive.iter())
        .map(|p| (p.joint, p.stiffness, p.damping))
        .collect();
    sim.set_passive_joints(&passive).unwrap();
    let layout = SensorLayout::of(&robot, ForceTorqueModel::Contact);
    let sensors = Sensors::new(&model, &layout, SensorNoise::default(), 0).unwrap();
    let plant = WithHiddenJoints::new(SimulatedRobot::new(sim, sensors, Overlap::Never), map);
    (plant, robot, q0)
}
