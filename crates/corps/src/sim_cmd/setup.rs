//! Builds the world of a scenario: the robot, its starting configuration, the terrain, the
//! simulator with its pushes, the sensors and the constant joint command. Everything that
//! needs the robot model is checked here; errors name the scenario key.

use super::scenario::{ActuationMode, Scenario};
use crate::default_robot::load_sim_model;
use anyhow::{anyhow, bail, Context, Result};
use corps_model::{forward_kinematics_placements, Data, Model};
use corps_sim::{
    first_actuated, place_on_ground, sample_contact_points, Command, SensorLayout, Sensors,
    ServoGains, Simulator, Surface, Terrain,
};
use nalgebra::DVector;
use std::path::Path;
use std::sync::Arc;

/// A foot: a force/torque sensor under it and the body carrying it.
#[derive(Clone, Debug)]
pub struct Foot {
    /// Label used in column and plot names ("left").
    pub label: String,
    /// Index of its force/torque sensor in the readings.
    pub sensor: usize,
    /// Frame of that sensor (TALOS: the sole frame).
    pub frame: usize,
    /// Joint whose body carries the sensor.
    pub joint: usize,
}

/// Everything a run needs.
pub struct Setup {
    pub model: Arc<Model>,
    pub sim: Simulator,
    pub sensors: Sensors,
    /// The command held for the whole run.
    pub command: Command,
    pub feet: Vec<Foot>,
    /// Frame of the IMU (None: the root body).
    pub imu_frame: Option<usize>,
    /// Number of control ticks to simulate.
    pub ticks: usize,
    /// Starting configuration (after placement).
    pub q0: DVector<f64>,
}

/// Builds the world of `scenario`; relative robot paths are resolved from `base_dir` (the
/// scenario file's directory).
pub fn build(scenario: &Scenario, base_dir: &Path) -> Result<Setup> {
    let urdf = scenario.robot.urdf.as_ref().map(|p| base_dir.join(p));
    let srdf = scenario.robot.srdf.as_ref().map(|p| base_dir.join(p));
    let default_robot = urdf.is_none();
    let model = Arc::new(load_sim_model(urdf.as_deref(), srdf.as_deref()).context("robot")?);

    let init = &scenario.initial;
    let mut q0 = model
        .reference_configuration(&init.configuration)
        .map_err(|e| anyhow!("initial.configuration: {e}"))?
        .clone();
    if let Some([x, y]) = init.base_xy {
        q0[0] = x;
        q0[1] = y;
    }
    if init.place_on_ground {
        place_on_ground(&model, q0.as_mut_slice(), 0.0)
            .map_err(|e| anyhow!("initial.place_on_ground: {e}"))?;
    }
    let terrain = Terrain::preset(scenario.terrain.preset, scenario.terrain.mu);
    check_clear_of_terrain(&model, &terrain, &q0, scenario.sim.contact.point_spacing)?;

    let act = &scenario.actuation;
    let gains = match &act.pid_gains {
        Some(path) => super::pid_gains::load(&model, &base_dir.join(path))
            .map_err(|e| anyhow!("actuation.pid_gains: {e}"))?,
        None => ServoGains::high_gain(
            &model,
            q0.as_slice(),
            act.saturation_angle,
            act.damping_ratio,
        )
        .map_err(|e| anyhow!("actuation: {e}"))?,
    };
    let na = model.nv - first_actuated(&model);
    let command = match act.mode {
        ActuationMode::Position => Command::Position {
            q_ref: q0.clone(),
            v_ref: DVector::zeros(na),
        },
        ActuationMode::Torque => Command::Torque(DVector::zeros(na)),
        ActuationMode::Velocity => Command::Velocity(DVector::zeros(na)),
    };

    let mut sim = Simulator::new(
        model.clone(),
        terrain,
        scenario.sim.clone(),
        q0.as_slice(),
        gains,
    )
    .map_err(|e| anyhow!("sim: {e}"))?;
    for (k, push) in scenario.pushes.iter().enumerate() {
        model
            .frame_id(&push.frame)
            .map_err(|e| anyhow!("push[{k}].frame: {e}"))?;
    }
    // A controller run adds its pushes at the handover (`corps run`), a plain simulation now.
    if scenario.controller.is_none() {
        let pushes = super::pushes::schedule(&scenario.pushes, 0.0, scenario.duration)
            .map_err(|e| anyhow!("{e}"))?;
        for push in pushes {
            sim.add_push(push).map_err(|e| anyhow!("push: {e}"))?;
        }
    }

    let (layout, feet) = sensor_layout(scenario, default_robot);
    let sensors = Sensors::new(&model, &layout, scenario.noise.clone(), scenario.seed)
        .map_err(|e| anyhow!("sensors: {e}"))?;
    let feet = feet
        .iter()
        .map(|(label, name)| {
            let sensor = layout
                .force_torque
                .iter()
                .position(|(n, _)| n == name)
                .ok_or_else(|| {
                    anyhow!("sensors.feet: '{name}' is not one of the force_torque sensors")
                })?;
            let frame = model.frame_id(&layout.force_torque[sensor].1)?;
            let joint = model.frames[frame]
                .parent_joint
                .ok_or_else(|| anyhow!("sensors.feet: '{name}' is fixed to the world"))?;
            Ok(Foot {
                label: label.clone(),
                sensor,
                frame,
                joint,
            })
        })
        .collect::<Result<Vec<_>>>()?;

    let imu_frame = layout
        .imu
        .as_deref()
        .map(|f| model.frame_id(f))
        .transpose()
        .map_err(|e| anyhow!("sensors.imu: {e}"))?;
    let ticks = (scenario.duration / scenario.sim.control_dt).round() as usize;
    Ok(Setup {
        model,
        sim,
        sensors,
        command,
        feet,
        imu_frame,
        ticks,
        q0,
    })
}

/// The sensor layout and the feet: the scenario's `[sensors]`, else TALOS' (ankle F/T at the
/// soles, wrist F/T, IMU) for the default robot and only an IMU on the root body for another.
fn sensor_layout(
    scenario: &Scenario,
    default_robot: bool,
) -> (SensorLayout, Vec<(String, String)>) {
    let model = scenario.force_torque_model;
    match &scenario.sensors {
        Some(s) => (
            SensorLayout {
                force_torque: s.force_torque.clone(),
                force_torque_model: model,
                imu: s.imu.clone(),
            },
            s.feet.clone(),
        ),
        None if default_robot => (
            SensorLayout {
                force_torque_model: model,
                ..SensorLayout::default()
            },
            vec![
                ("left".into(), "left_ankle".into()),
                ("right".into(), "right_ankle".into()),
            ],
        ),
        None => (
            SensorLayout {
                force_torque: vec![],
                force_torque_model: model,
                imu: None,
            },
            vec![],
        ),
    }
}

/// Fails when a contact point of the robot at `q` starts more than 2 mm inside a terrain
/// surface (the contact springs would launch it): the robot must start beside obstacles.
fn check_clear_of_terrain(
    model: &Model,
    terrain: &Terrain,
    q: &DVector<f64>,
    spacing: f64,
) -> Result<()> {
    let mut data = Data::new(model);
    forward_kinematics_placements(model, &mut data, q.as_slice())?;
    let (points, _) = sample_contact_points(model, spacing);
    for p in &points {
        let world = data.o_m_i[p.joint].act_point(&p.local);
        for (k, surface) in terrain.surfaces.iter().enumerate() {
            let probe = world - surface.up() * p.radius;
            if let Some(pen) = surface.penetration(&probe) {
                if pen.depth > 2e-3 {
                    let what = match surface {
                        Surface::Plane { .. } => format!("terrain surface {k} (a plane)"),
                        Surface::Box { .. } => format!("terrain surface {k} (a box)"),
                    };
                    bail!(
                        "initial: the robot starts {:.0} mm inside {what} (link '{}'); \
                         move it with initial.base_xy or set initial.place_on_ground",
                        pen.depth * 1e3,
                        model.collisions[p.shape].link
                    );
                }
            }
        }
    }
    Ok(())
}
