//! Builds the world of a scenario: the robot, its starting configuration, the terrain, the
//! simulator with its pushes, the sensors and the constant joint command. Everything that
//! needs the robot model is checked here; errors name the scenario key.

use crate::error::{bail, invalid, Context, Result};
use crate::foot::Foot;
use crate::scenario::{ActuationMode, Scenario};
use corps_loop::verdict::Criteria;
use corps_model::{forward_kinematics_placements, Data, Model};
use corps_robot::Robot;
use corps_sim::{
    first_actuated, place_on_ground, sample_contact_points, Command, HiddenJoints, SensorLayout,
    Sensors, ServoGains, Simulator, Surface, Terrain,
};
use nalgebra::DVector;
use std::path::Path;
use std::sync::Arc;

/// Everything a run needs.
pub struct Setup {
    /// The robot's description (None for a bare URDF).
    pub robot: Option<Robot>,
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
    /// When the run counts as failed: the scenario's `[verdict]`, else the robot's `[fall]`.
    pub criteria: Criteria,
    /// The tool and block of `[press]`, if any.
    pub press: Option<crate::press::PressWorld>,
    /// When the robot has passive joints its description keeps from the controllers
    /// ([`corps_robot::PlantVariant`]): the maps between `model` and the simulator's model.
    /// `sim`, `sensors` and `command` are then of the simulator's model, everything else of
    /// `model`.
    pub hidden: Option<HiddenJoints>,
}

/// The scenario's robot: its description (default: TALOS), or a bare URDF for `corps sim`.
pub fn load_robot(scenario: &Scenario, base_dir: &Path) -> Result<(Option<Robot>, Arc<Model>)> {
    let section = &scenario.robot;
    if let Some(urdf) = &section.urdf {
        let srdf = section.srdf.as_ref().map(|s| base_dir.join(s));
        let model =
            crate::default_robot::load_model(Some(&base_dir.join(urdf)), srdf.as_deref(), false)
                .context("robot")?;
        return Ok((None, Arc::new(model)));
    }
    let name = section.description.as_deref().unwrap_or("talos");
    let robot = Robot::resolve(name, base_dir).map_err(|e| invalid!("robot: {e}"))?;
    let model = robot.model.clone();
    Ok((Some(robot), model))
}

/// Builds the world of `scenario`; relative robot paths are resolved from `base_dir` (the
/// scenario file's directory).
pub fn build(scenario: &Scenario, base_dir: &Path) -> Result<Setup> {
    let (mut robot, mut model) = load_robot(scenario, base_dir)?;
    let init = &scenario.initial;
    let configuration = (init.configuration.as_deref())
        .or(robot.as_ref().map(|r| r.posture_name.as_str()))
        .unwrap_or("half_sitting");
    let mut q0 = model
        .reference_configuration(configuration)
        .map_err(|e| invalid!("initial.configuration: {e}"))?
        .clone();
    if let Some([x, y]) = init.base_xy {
        q0[0] = x;
        q0[1] = y;
    }
    if init.place_on_ground {
        place_on_ground(&model, q0.as_mut_slice(), 0.0)
            .map_err(|e| invalid!("initial.place_on_ground: {e}"))?;
    }
    let mut terrain = Terrain::preset(scenario.terrain.preset, scenario.terrain.mu);
    let mut press = None;
    if let Some(section) = &scenario.press {
        let Some(r) = robot.as_mut() else {
            bail!("press: needs a robot description with hands, not a bare URDF");
        };
        let (block, tip_frame, sensor) = crate::press::equip(r, section, &q0, scenario.terrain.mu)?;
        model = r.model.clone();
        terrain.surfaces.push(block);
        press = Some((
            section,
            tip_frame,
            r.force_torque[sensor].0.clone(),
            terrain.surfaces.len() - 1,
        ));
    }
    check_clear_of_terrain(&model, &terrain, &q0, scenario.sim.contact.point_spacing)?;

    // The simulator's model: the rigid one, or its variant with passive joints.
    let variant = robot.as_ref().and_then(|r| r.plant.clone());
    let act = &scenario.actuation;
    let (sim_model, sim_q0, hidden) = match &variant {
        Some(v) => {
            if press.is_some() {
                bail!("press: not available on a robot with passive joints");
            }
            if act.drives {
                bail!("actuation.drives: not available on a robot with passive joints");
            }
            let map = HiddenJoints::new(&model, &v.model).map_err(|e| invalid!("robot: {e}"))?;
            let (q, _) = map.widen_state(q0.as_slice(), &vec![0.0; model.nv]);
            (v.model.clone(), q, Some(map))
        }
        None => (model.clone(), q0.clone(), None),
    };
    let gains = match &act.pid_gains {
        // Gains name the robot's joints: read on the rigid model, the hidden joints get none.
        Some(path) => {
            let gains = crate::pid_gains::load(&model, &base_dir.join(path))
                .map_err(|e| invalid!("actuation.pid_gains: {e}"))?;
            match &hidden {
                Some(map) => map.widen_gains(&gains),
                None => gains,
            }
        }
        None => ServoGains::high_gain(
            &sim_model,
            sim_q0.as_slice(),
            act.saturation_angle,
            act.damping_ratio,
        )
        .map_err(|e| invalid!("actuation: {e}"))?,
    };
    let na = sim_model.nv - first_actuated(&sim_model);
    let command = match act.mode {
        ActuationMode::Position => Command::Position {
            q_ref: sim_q0.clone(),
            v_ref: DVector::zeros(na),
        },
        ActuationMode::Torque => Command::Torque(DVector::zeros(na)),
        ActuationMode::Velocity => Command::Velocity(DVector::zeros(na)),
    };

    let mut sim = Simulator::new(
        sim_model.clone(),
        terrain,
        scenario.sim.clone(),
        sim_q0.as_slice(),
        gains,
    )
    .map_err(|e| invalid!("sim: {e}"))?;
    if let Some(v) = &variant {
        let passive: Vec<_> = (v.passive.iter())
            .map(|p| (p.joint, p.stiffness, p.damping))
            .collect();
        sim.set_passive_joints(&passive)
            .map_err(|e| invalid!("robot: {e}"))?;
    }
    if act.drives {
        let drives = crate::drives::for_model(&model, robot.as_ref(), &act.drive)?;
        sim.set_drives(drives)
            .map_err(|e| invalid!("actuation.drives: {e}"))?;
    }
    for (k, push) in scenario.pushes.iter().enumerate() {
        model
            .frame_id(&push.frame)
            .map_err(|e| invalid!("push[{k}].frame: {e}"))?;
    }
    // A controller run adds its pushes at the handover (`corps run`), a plain simulation now.
    if scenario.controller.is_none() {
        let pushes = crate::pushes::schedule(
            &scenario.pushes,
            0.0,
            scenario.duration,
            Some(model.total_mass()),
        )
        .map_err(|e| invalid!("{e}"))?;
        for push in pushes {
            sim.add_push(push).map_err(|e| invalid!("push: {e}"))?;
        }
    }

    let (layout, feet) = sensor_layout(scenario, robot.as_ref());
    let sensors = Sensors::new(&sim_model, &layout, scenario.noise.clone(), scenario.seed)
        .map_err(|e| invalid!("sensors: {e}"))?;
    let feet = feet
        .iter()
        .map(|(label, name)| {
            let sensor = layout
                .force_torque
                .iter()
                .position(|(n, _)| n == name)
                .ok_or_else(|| {
                    invalid!("sensors.feet: '{name}' is not one of the force_torque sensors")
                })?;
            let frame = model.frame_id(&layout.force_torque[sensor].1)?;
            let joint = model.frames[frame]
                .parent_joint
                .ok_or_else(|| invalid!("sensors.feet: '{name}' is fixed to the world"))?;
            Ok(Foot {
                label: label.clone(),
                sensor,
                frame,
                joint,
            })
        })
        .collect::<Result<Vec<_>>>()?;

    let press = match press {
        Some((section, tip_frame, sensor, block_surface)) => {
            let hand_sensor = (layout.force_torque.iter())
                .position(|(n, _)| *n == sensor)
                .ok_or_else(|| {
                    invalid!(
                        "press.hand: its sensor '{sensor}' is not one of the force_torque sensors"
                    )
                })?;
            let sensor_frame = model.frame_id(&layout.force_torque[hand_sensor].1)?;
            Some(crate::press::PressWorld {
                tip_frame,
                hand_sensor,
                sensor_frame,
                block_surface,
                section: section.clone(),
            })
        }
        None => None,
    };
    let imu_frame = layout
        .imu
        .as_deref()
        .map(|f| model.frame_id(f))
        .transpose()
        .map_err(|e| invalid!("sensors.imu: {e}"))?;
    let ticks = (scenario.duration / scenario.sim.control_dt).round() as usize;
    let criteria = scenario
        .verdict
        .unwrap_or_else(|| robot.as_ref().map_or_else(Criteria::default, |r| r.fall));
    Ok(Setup {
        robot,
        criteria,
        model,
        sim,
        sensors,
        command,
        feet,
        imu_frame,
        ticks,
        q0,
        press,
        hidden,
    })
}

/// The sensor layout and the feet: the scenario's `[sensors]`, else the robot description's,
/// else (a bare URDF) only an IMU on the root body.
fn sensor_layout(
    scenario: &Scenario,
    robot: Option<&Robot>,
) -> (SensorLayout, Vec<(String, String)>) {
    let model = scenario.force_torque_model;
    match (&scenario.sensors, robot) {
        (Some(s), _) => (
            SensorLayout {
                force_torque: s.force_torque.clone(),
                force_torque_model: model,
                imu: s.imu.clone(),
            },
            s.feet.clone(),
        ),
        (None, Some(robot)) => {
            let feet = (robot.feet.iter())
                .filter_map(|f| {
                    let sensor = &robot.force_torque[f.force_torque?].0;
                    Some((f.label.clone(), sensor.clone()))
                })
                .collect();
            (SensorLayout::of(robot, model), feet)
        }
        (None, None) => (
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
