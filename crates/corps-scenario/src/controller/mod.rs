//! The three whole-body controllers of seed 000 chapter 4 behind one interface:
//! - A, `ik_position`: hierarchical velocity IK, integrated once, joint position servos;
//! - B, `tsid_position`: TSID's inverse dynamics, integrated twice, joint position servos;
//! - C, `tsid_torque`: TSID's inverse dynamics at the measured state, joint torques;
//! - `passive_torque`: C under a global energy tank (seed 000 ch. 5), its gains file's `[tank]`;
//! - `soft_tasks`: seed 001's soft-tasks controller #2 on [τ; f] with its stepping state
//!   machine (§2.6c, §2.7).

mod hand_press;
mod ik;
pub mod soft_tasks;
mod stabilized;
pub mod teleop_velocity;
pub mod teleop_walk;
mod tsid;

pub use hand_press::HAND_CHANNELS;
pub use ik::IkController;
pub use soft_tasks::{SoftTasksConfig, SoftTasksController, SOFT_TASKS_CHANNELS};
pub use stabilized::{behind_stabilizer, Stabilized};
pub use tsid::{TsidController, TsidMode, POSTURE_CHANNELS, TANK_CHANNELS};

use super::targets::Targets;
use corps_control::flexibility::{
    planned_wrenches, CompensatedJoint, CompensationMode, FlexibilityCompensation,
};
use corps_control::stabilizer::{StabilizerOutput, Wrench};
use corps_control::FallbackReason;
use corps_estimation::EstimatedState;
use corps_loop::{Command, Controller};
use corps_model::spatial::Se3;
use nalgebra::{Isometry3, Vector2, Vector3};
use serde::Deserialize;
use std::path::PathBuf;

/// The robot's two feet, left then right, or an error: these controllers balance bipeds.
pub fn two_feet(robot: &corps_robot::Robot) -> crate::Result<[&corps_robot::Foot; 2]> {
    match robot.feet.as_slice() {
        [left, right] => Ok([left, right]),
        feet => crate::error::bail!(
            "robot '{}' has {} feet: the whole-body controllers of corps run balance a biped (two feet, left first)",
            robot.name,
            feet.len()
        ),
    }
}

/// `[controller]`.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct ControllerSection {
    pub kind: ControllerKind,
    /// Gains: a name of the robot description's `[gains]` (`tsid_torque_walk`) or a file
    /// relative to the scenario (absent: the robot's gains for the kind).
    pub gains: Option<PathBuf>,
    /// Time under the joint PD hold before the controller takes over (s).
    #[serde(default = "half_second")]
    pub settle: f64,
    /// Values replacing the gains file's, e.g. `posture.weight = 1e-3`.
    #[serde(default)]
    pub set: toml::Table,
    /// Compensation of the robot's passive joints in the position command (seed 000 App. 4).
    pub flexibility: Option<FlexibilitySection>,
}

/// `[controller.flexibility]`: offsets the position command of each joint a passive joint
/// of the robot description names in `compensated_by` (seed 000 Eq 6.3,
/// [`corps_control::flexibility`]).
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct FlexibilitySection {
    /// `fixed`: ±`offset` scaled by the leg's load share; `model`: the static torque over K.
    pub compensation: CompensationKind,
    /// The fixed offset, rad (default 0.021 = 20 N·m / 973 N·m/rad, seed 000 Eq 6.3, L5415).
    #[serde(default = "thesis_offset")]
    pub offset: f64,
    /// The model mode's low-pass time constant on the torque estimate, s.
    #[serde(default = "torque_filter")]
    pub filter: f64,
    /// Where the feet's wrenches come from: `planned` (the reference CoM and ZMP, no sensor:
    /// the default) or `measured` (the ankle F/T sensors).
    #[serde(default)]
    pub wrenches: WrenchSource,
    /// Stiffness the controller assumes for a passive joint (by name), N·m/rad, in place of
    /// the description's (an identification's estimate, say).
    #[serde(default)]
    pub stiffness: std::collections::BTreeMap<String, f64>,
}

/// `[controller.flexibility] compensation`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum CompensationKind {
    Fixed,
    Model,
}

/// `[controller.flexibility] wrenches`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum WrenchSource {
    #[default]
    Planned,
    Measured,
}

fn thesis_offset() -> f64 {
    0.021
}

fn torque_filter() -> f64 {
    0.02
}

impl FlexibilitySection {
    /// The compensation of `robot`'s passive joints for the rigid model, `posture` standing.
    pub fn build(
        &self,
        robot: &corps_robot::Robot,
        posture: &[f64],
        gravity: f64,
    ) -> crate::Result<FlexibilityCompensation> {
        let Some(plant) = &robot.plant else {
            crate::error::bail!(
                "controller.flexibility: robot '{}' has no passive joints to compensate",
                robot.name
            );
        };
        for (name, k) in &self.stiffness {
            if !plant.passive.iter().any(|p| &p.name == name) {
                crate::error::bail!(
                    "controller.flexibility.stiffness: '{name}' is not a passive joint of robot '{}'",
                    robot.name
                );
            }
            if !(k.is_finite() && *k > 0.0) {
                crate::error::bail!(
                    "controller.flexibility.stiffness.{name}: must be a finite number > 0 (N·m/rad), got {k}"
                );
            }
        }
        let joints: Vec<CompensatedJoint> = (plant.passive.iter())
            .filter_map(|p| {
                Some(CompensatedJoint {
                    joint: p.compensated_by?,
                    stiffness: *self.stiffness.get(&p.name).unwrap_or(&p.stiffness),
                })
            })
            .collect();
        if joints.is_empty() {
            crate::error::bail!(
                "controller.flexibility: no passive joint of robot '{}' names the joint that compensates it (compensated_by)",
                robot.name
            );
        }
        let mode = match self.compensation {
            CompensationKind::Fixed => CompensationMode::Fixed {
                offset: self.offset,
            },
            CompensationKind::Model => CompensationMode::Model {
                filter: self.filter,
            },
        };
        let feet: Vec<usize> = robot.feet.iter().map(|f| f.frame).collect();
        FlexibilityCompensation::new(&robot.model, &joints, &feet, posture, mode, gravity)
            .map_err(|e| crate::error::invalid!("controller.flexibility: {e}"))
    }
}

/// Longest settling time under the joint PD hold before the controller takes over (s).
pub const MAX_SETTLE: f64 = 600.0;

fn half_second() -> f64 {
    0.5
}

impl ControllerSection {
    pub fn check(&self) -> Result<(), String> {
        if !(self.settle >= 0.0 && self.settle <= MAX_SETTLE) {
            return Err(format!(
                "controller.settle: must be a time in [0, {MAX_SETTLE}] s, got {}",
                crate::numbers::number(self.settle)
            ));
        }
        Ok(())
    }
}

/// `[controller] kind`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ControllerKind {
    IkPosition,
    TsidPosition,
    TsidTorque,
    PassiveTorque,
    SoftTasks,
    TeleopVelocity,
}

impl ControllerKind {
    /// The name in scenario files and of the robot description's gains (`tsid_torque`).
    pub fn name(self) -> &'static str {
        match self {
            ControllerKind::IkPosition => "ik_position",
            ControllerKind::TsidPosition => "tsid_position",
            ControllerKind::TsidTorque => "tsid_torque",
            ControllerKind::PassiveTorque => "passive_torque",
            ControllerKind::SoftTasks => "soft_tasks",
            ControllerKind::TeleopVelocity => "teleop_velocity",
        }
    }

    pub fn label(self) -> &'static str {
        match self {
            ControllerKind::IkPosition => "IK (position)",
            ControllerKind::TsidPosition => "TSID (position)",
            ControllerKind::TsidTorque => "TSID (torque)",
            ControllerKind::PassiveTorque => "passive TSID (torque, energy tank)",
            ControllerKind::SoftTasks => "soft tasks on [τ; f] (seed 001), stepping state machine",
            ControllerKind::TeleopVelocity => {
                "teleoperation: two-layer velocity HQP (seed 001 §6.1.3), position mode"
            }
        }
    }
}

/// What the robot's sensors tell the controllers besides (q, v): the quantities a base
/// estimator and the feet's and hands' force/torque sensors give.
#[derive(Clone, Debug, PartialEq)]
pub struct Measured<'a> {
    pub com: Vector3<f64>,
    pub com_velocity: Vector3<f64>,
    /// ZMP on the contact plane (world x, y); None in the air.
    pub zmp: Option<Vector2<f64>>,
    /// Sole frames, left then right.
    pub feet: [Isometry3<f64>; 2],
    /// Ground-on-foot wrenches in each sole frame, about its origin.
    pub foot_wrenches: [Wrench; 2],
    /// The hands the estimator reads (a `[press]` tool's), their wrenches in their contact
    /// frames.
    pub hands: &'a [corps_estimation::FootEstimate],
}

/// A whole-body controller of a scenario.
pub trait WholeBodyController: Send {
    /// Computes the joint command at `t` (s since the handover) from the measured state and
    /// the targets. Returns why the safe command was used instead, if it was.
    fn tick(
        &mut self,
        t: f64,
        q: &[f64],
        v: &[f64],
        targets: &Targets,
        measured: &Measured<'_>,
    ) -> Option<FallbackReason>;
    /// The command of the last tick.
    fn command(&self) -> &Command;
    /// The CoM of the state the controller works on (measured in torque mode, its own
    /// integrated state in position mode), after the last tick.
    fn controller_com(&self) -> Vector3<f64>;
    /// The balance stabilizer's output of the last tick, for the log; `None` without one (or
    /// when its last tick failed).
    fn stabilizer_output(&self) -> Option<&StabilizerOutput> {
        None
    }
    /// The references the controller chose itself this tick (a state machine's), which the
    /// log and the metrics then compare with instead of the motion's; `None`: it tracks the
    /// motion's.
    fn tracked_targets(&self) -> Option<&Targets> {
        None
    }
    /// The controller's own figures of the run so far, for the metrics.
    fn report(&self) -> Vec<crate::metrics::ReportLine> {
        Vec::new()
    }
    /// Names of the controller's own log columns (the energy tank's signals, say).
    fn channels(&self) -> Vec<&'static str> {
        Vec::new()
    }
    /// Appends the values of [`Self::channels`] for the last tick to `row`.
    fn push_channels(&self, _row: &mut Vec<f64>) {}
    /// A teleoperation controller's figures of the run so far.
    fn teleop_metrics(&self) -> Option<crate::metrics::TeleopMetrics> {
        None
    }
}

/// A scenario's controller as the loop's [`Controller`]: it reads the estimator's state and
/// hands the controller (q, v) and what the sensors measured.
pub struct ScenarioController {
    inner: Box<dyn WholeBodyController>,
    /// The passive joints' compensation, the model, the control period and the compensated
    /// command.
    compensation: Option<Compensated>,
}

struct Compensated {
    compensation: FlexibilityCompensation,
    model: std::sync::Arc<corps_model::Model>,
    dt: f64,
    command: Command,
    wrenches: WrenchSource,
    /// Mass (kg) and gravity (m/s², > 0) for the planned wrenches.
    mass: f64,
    gravity: f64,
}

impl ScenarioController {
    pub fn new(inner: Box<dyn WholeBodyController>) -> Self {
        Self {
            inner,
            compensation: None,
        }
    }

    /// Offsets the inner controller's position commands by `compensation`.
    pub fn with_compensation(
        mut self,
        compensation: FlexibilityCompensation,
        wrenches: WrenchSource,
        model: std::sync::Arc<corps_model::Model>,
        gravity: f64,
        dt: f64,
    ) -> Self {
        let command = self.inner.command().clone();
        self.compensation = Some(Compensated {
            compensation,
            mass: model.total_mass(),
            model,
            dt,
            command,
            wrenches,
            gravity,
        });
        self
    }

    /// The balance stabilizer's output of the last tick, if there is a stabilizer.
    pub fn stabilizer_output(&self) -> Option<&StabilizerOutput> {
        self.inner.stabilizer_output()
    }

    /// The references the controller chose itself, if it did ([`WholeBodyController::tracked_targets`]).
    pub fn tracked_targets(&self) -> Option<&Targets> {
        self.inner.tracked_targets()
    }

    /// The CoM of the state the controller works on ([`WholeBodyController::controller_com`]).
    pub fn controller_com(&self) -> Vector3<f64> {
        self.inner.controller_com()
    }

    /// The controller's own figures of the run.
    pub fn report(&self) -> Vec<crate::metrics::ReportLine> {
        self.inner.report()
    }

    pub fn teleop_metrics(&self) -> Option<crate::metrics::TeleopMetrics> {
        self.inner.teleop_metrics()
    }

    /// The controller's own log columns.
    pub fn channels(&self) -> Vec<&'static str> {
        self.inner.channels()
    }

    /// Their values at the last tick.
    pub fn push_channels(&self, row: &mut Vec<f64>) {
        self.inner.push_channels(row)
    }
}

impl Controller for ScenarioController {
    type References = Targets;
    type Fallback = FallbackReason;

    fn tick(&mut self, t: f64, est: &EstimatedState, targets: &Targets) -> Option<FallbackReason> {
        let measured = Measured {
            com: est.com,
            com_velocity: est.com_velocity,
            zmp: est.zmp,
            feet: [0, 1].map(|k| isometry(&est.feet[k].placement)),
            foot_wrenches: [0, 1].map(|k| {
                let w = &est.feet[k].wrench;
                Wrench::new(
                    Vector3::new(w[0], w[1], w[2]),
                    Vector3::new(w[3], w[4], w[5]),
                )
            }),
            hands: &est.hands,
        };
        let fallback = self
            .inner
            .tick(t, est.q.as_slice(), est.v.as_slice(), targets, &measured);
        if let Some(c) = &mut self.compensation {
            let cmd = self.inner.command();
            match (&mut c.command, cmd) {
                (
                    Command::Position { q_ref, v_ref },
                    Command::Position {
                        q_ref: q_in,
                        v_ref: v_in,
                    },
                ) if q_ref.len() == q_in.len() && v_ref.len() == v_in.len() => {
                    q_ref.copy_from(q_in);
                    v_ref.copy_from(v_in);
                }
                (slot, cmd) => *slot = cmd.clone(),
            }
            // Measured: the estimated state with the F/T wrenches; planned: the state the
            // controller commands (before the offsets) with the reference's feet and wrenches,
            // one consistent world.
            if let Command::Position { q_ref, .. } = &c.command {
                let result = match c.wrenches {
                    WrenchSource::Measured => c.compensation.update(
                        &c.model,
                        est.q.as_slice(),
                        &measured.feet,
                        &measured.foot_wrenches,
                        c.dt,
                    ),
                    WrenchSource::Planned => {
                        let feet = [0, 1].map(|k| isometry(&targets.feet[k].reference.placement));
                        let supporting = [0, 1].map(|k| targets.feet[k].supporting);
                        let zmp = targets.reference_zmp(targets.contact_ground(), c.gravity);
                        let acc = Vector3::from_column_slice(targets.com.acc.as_slice());
                        let wrenches =
                            planned_wrenches(c.mass, c.gravity, &acc, zmp, &feet, supporting);
                        c.compensation
                            .update(&c.model, q_ref.as_slice(), &feet, &wrenches, c.dt)
                    }
                };
                // A failed update (a non-finite state) keeps the last offsets.
                let _ = result;
            }
            if let Command::Position { q_ref, .. } = &mut c.command {
                c.compensation.apply(q_ref.as_mut_slice());
            }
        }
        fallback
    }

    fn command(&self) -> &Command {
        match &self.compensation {
            Some(c) => &c.command,
            None => self.inner.command(),
        }
    }
}

/// An `Se3` as a nalgebra isometry.
fn isometry(m: &Se3) -> nalgebra::Isometry3<f64> {
    let r = nalgebra::Rotation3::from_matrix_unchecked(m.rotation);
    nalgebra::Isometry3::from_parts(
        nalgebra::Translation3::from(m.translation),
        nalgebra::UnitQuaternion::from_rotation_matrix(&r),
    )
}
