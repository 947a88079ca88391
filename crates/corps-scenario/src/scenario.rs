//! The scenario file of `corps sim`: its TOML schema (unknown keys are errors), parsing with
//! one-line errors that name the key, and the checks of values that need no robot model.

use crate::numbers::number;
use crate::pushes::PushSpec;
use corps_loop::verdict::{Criteria, Verdict};
use corps_sim::{ForceTorqueModel, SensorNoise, SimSettings, TerrainPreset};
use serde::Deserialize;
use std::path::PathBuf;

/// A simulation scenario. Every section is optional except `duration`.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scenario {
    /// Name of the run (default: the file name without extension); names the output directory.
    pub name: Option<String>,
    /// Simulated time (s).
    pub duration: f64,
    /// Seed of the sensor noise.
    #[serde(default)]
    pub seed: u64,
    /// The verdict the run should end with (a failure demonstration says `fell`); any other
    /// makes the command exit non-zero.
    #[serde(default = "completed")]
    pub expect: Verdict,
    /// When the run counts as fallen, diverged or its controller failed; replaces the robot
    /// description's `[fall]` (absent keys: corps' defaults).
    pub verdict: Option<Criteria>,
    #[serde(default)]
    pub robot: RobotSection,
    #[serde(default)]
    pub terrain: TerrainSection,
    #[serde(default)]
    pub initial: InitialSection,
    #[serde(default)]
    pub actuation: ActuationSection,
    /// Simulator settings (control period, substeps, integrator, contact, gravity).
    #[serde(default)]
    pub sim: SimSettings,
    /// Pushes, `[[push]]` tables.
    #[serde(default, rename = "push")]
    pub pushes: Vec<PushSpec>,
    /// Sensor noise per channel (none by default).
    #[serde(default)]
    pub noise: SensorNoise,
    /// What the F/T sensors read: `contact` (the contact wrench, as Gazebo's sensor: the
    /// default) or `transmitted` (as a real sensor: the foot's weight and inertia too; the
    /// estimator then removes the foot's weight).
    #[serde(default)]
    pub force_torque_model: ForceTorqueModel,
    /// Sensor layout; absent: TALOS' sensors for the default robot, none for another.
    pub sensors: Option<SensorsSection>,
    #[serde(default)]
    pub output: OutputSection,
    /// The whole-body controller driving the joints (`corps run`); absent: the constant
    /// `[actuation]` command (`corps sim`).
    pub controller: Option<crate::controller::ControllerSection>,
    /// What the controller is asked to do (`corps run`).
    #[serde(default)]
    pub motion: crate::motion::MotionSection,
    /// The documents' figures for this experiment, printed beside ours (`corps run`).
    pub thesis: Option<crate::metrics::ThesisFigures>,
    /// How the controller learns the robot's state from its sensors (`corps run`).
    #[serde(default)]
    pub estimator: crate::estimation::EstimatorSection,
    /// A tool in a hand pressing on a block (`corps run`, torque-mode TSID).
    pub press: Option<crate::press::PressSection>,
    /// A person the robot walks with (`corps run`, a velocity walk): co-navigation.
    pub human: Option<crate::conav::HumanSection>,
    /// `[mocap]`: the operator a teleoperation controller follows.
    pub mocap: Option<crate::mocap::MocapSection>,
    /// `[footsteps]`: steps a teleoperation controller walks on its own.
    pub footsteps: Option<crate::footsteps::FootstepsSection>,
}

fn completed() -> Verdict {
    Verdict::Completed
}

/// `[robot]`: a robot description — a built-in robot (`talos`, `talos_flexible_hip`, `icub`, `icub_backpacked`, `icub_parallel_legs`, `simple_humanoid`) or
/// a description file relative to the scenario — or, for `corps sim` only, a bare URDF (and
/// SRDF) relative to the scenario. Default: `description = "talos"`.
#[derive(Clone, Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RobotSection {
    pub description: Option<String>,
    pub urdf: Option<PathBuf>,
    pub srdf: Option<PathBuf>,
}

impl RobotSection {
    /// The robot of `--robot`: a built-in name, or a description path from the current
    /// directory.
    pub fn from_argument(robot: &str) -> Self {
        let path = std::path::Path::new(robot);
        let description = if path.extension().is_some() && path.is_relative() {
            std::env::current_dir()
                .map(|d| d.join(path).display().to_string())
                .unwrap_or_else(|_| robot.to_string())
        } else {
            robot.to_string()
        };
        Self {
            description: Some(description),
            urdf: None,
            srdf: None,
        }
    }
}

/// `[terrain]`: a preset and its friction coefficient.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct TerrainSection {
    pub preset: TerrainPreset,
    pub mu: f64,
}

impl Default for TerrainSection {
    fn default() -> Self {
        Self {
            preset: TerrainPreset::Flat,
            mu: 0.8,
        }
    }
}

/// `[initial]`: the starting configuration.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct InitialSection {
    /// A reference configuration of the SRDF (default: the robot's posture, else
    /// `half_sitting`).
    pub configuration: Option<String>,
    /// Lower or lift the base so the lowest contact point touches z = 0.
    pub place_on_ground: bool,
    /// Horizontal base position (m), replacing the configuration's.
    pub base_xy: Option<[f64; 2]>,
}

impl Default for InitialSection {
    fn default() -> Self {
        Self {
            configuration: None,
            place_on_ground: true,
            base_xy: None,
        }
    }
}

/// What the joints are commanded to do for the whole run.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ActuationMode {
    /// Joint PD servo holding the initial configuration.
    Position,
    /// Zero joint torque (the robot collapses).
    Torque,
    /// Joint velocity servo holding zero velocity.
    Velocity,
}

/// `[actuation]`: the mode and the servo gains of `corps_sim::ServoGains::high_gain`.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct ActuationSection {
    pub mode: ActuationMode,
    /// Joint error (rad) at which the servo reaches the effort limit.
    pub saturation_angle: f64,
    /// Damping ratio of each joint on its own inertia.
    pub damping_ratio: f64,
    /// A PID gains file (relative to the scenario) replacing the high-gain PD servo, e.g.
    /// Gazebo's TALOS position controllers (`config/talos/gazebo_pid.toml`).
    pub pid_gains: Option<PathBuf>,
    /// Simulate the robot description's joint drives (`[drives]`: flexible joints, current-
    /// controlled motors, delay) under torque commands; default false: ideal torques.
    pub drives: bool,
    /// `[actuation.drive]`: values replacing the description's drive parameters in this run
    /// (to test what an actuator effect does).
    pub drive: DriveOverrides,
}

/// Drive parameters a scenario replaces (absent: the robot description's).
#[derive(Clone, Debug, Default, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct DriveOverrides {
    pub motor_inertia: Option<f64>,
    pub stiffness: Option<f64>,
    pub damping: Option<f64>,
    pub viscous_friction: Option<f64>,
    pub dry_friction: Option<f64>,
    pub friction_velocity: Option<f64>,
    pub drive_gain: Option<f64>,
    pub current_limit: Option<f64>,
    pub bandwidth_hz: Option<f64>,
    pub delay_periods: Option<usize>,
}

impl Default for ActuationSection {
    fn default() -> Self {
        Self {
            mode: ActuationMode::Position,
            saturation_angle: 0.02,
            damping_ratio: 1.0,
            pid_gains: None,
            drives: false,
            drive: DriveOverrides::default(),
        }
    }
}

/// `[sensors]`: force/torque sensors as `[name, frame]` pairs, the IMU frame (absent: the root
/// body) and the feet as `[label, force/torque sensor]` pairs (for contact forces, CoP, slip).
#[derive(Clone, Debug, Default, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct SensorsSection {
    pub force_torque: Vec<(String, String)>,
    pub imu: Option<String>,
    pub feet: Vec<(String, String)>,
}

/// Log file formats.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum LogFormat {
    /// Comma-separated values, one row per control tick.
    #[default]
    Csv,
}

/// Default size cap of a log (`[output] max_log_mb`).
pub const DEFAULT_MAX_LOG_MB: f64 = 1024.0;

/// `[output]`: where and what to write.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct OutputSection {
    /// Output directory, relative to the current directory (default `out/<name>`).
    pub directory: Option<PathBuf>,
    pub format: LogFormat,
    /// Write the PNG plots.
    pub plots: bool,
    /// Log one control tick in this many (1: every tick).
    pub log_every: usize,
    /// Size cap of the log (MB): a run whose log would be larger is refused before it starts.
    pub max_log_mb: f64,
}

impl OutputSection {
    /// The log's size cap in bytes.
    pub fn max_log_bytes(&self) -> u64 {
        (self.max_log_mb * 1e6) as u64
    }
}

impl Default for OutputSection {
    fn default() -> Self {
        Self {
            directory: None,
            format: LogFormat::Csv,
            plots: true,
            log_every: 1,
            max_log_mb: DEFAULT_MAX_LOG_MB,
        }
    }
}

impl Scenario {
    /// Parses and checks a scenario. The error is one line: `line N: key.path: message`.
    pub fn parse(text: &str) -> Result<Scenario, String> {
        let scenario: Scenario = corps_robot::toml_text::parse(text)?;
        scenario.check()?;
        Ok(scenario)
    }

    /// Replaces the duration (command-line override) and checks again.
    pub fn with_duration(mut self, duration: f64) -> Result<Scenario, String> {
        self.duration = duration;
        self.check().map_err(|e| format!("--duration: {e}"))?;
        Ok(self)
    }

    /// Replaces the log's size cap (command-line override) and checks again.
    pub fn with_max_log_mb(mut self, mb: f64) -> Result<Scenario, String> {
        self.output.max_log_mb = mb;
        self.check().map_err(|e| format!("--max-log-mb: {e}"))?;
        Ok(self)
    }

    /// Checks the values that need no robot model; the error names the key.
    fn check(&self) -> Result<(), String> {
        let positive = |key: &str, x: f64, unit: &str| {
            if x > 0.0 && x.is_finite() {
                Ok(())
            } else {
                Err(format!(
                    "{key}: must be a positive number of {unit}, got {x}"
                ))
            }
        };
        positive("duration", self.duration, "seconds")?;
        if self.duration > MAX_DURATION {
            return Err(format!(
                "duration: {} s is over the limit of {MAX_DURATION:e} s (11.6 simulated days)",
                number(self.duration)
            ));
        }
        if self.sim.control_dt < MIN_CONTROL_DT {
            return Err(format!(
                "sim.control_dt: {} s is under the limit of {MIN_CONTROL_DT:e} s",
                number(self.sim.control_dt)
            ));
        }
        let ticks = self.duration / self.sim.control_dt;
        if ticks > MAX_TICKS {
            return Err(format!(
                "duration: {} s at sim.control_dt = {} s is {ticks:.3e} control ticks, over the limit of {MAX_TICKS:.0e}",
                self.duration, self.sim.control_dt
            ));
        }
        if self.output.log_every == 0 {
            return Err("output.log_every: must be at least 1".into());
        }
        if let Some(c) = &self.controller {
            c.check()?;
        }
        self.motion.check()?;
        if let Some(p) = &self.press {
            p.check()?;
        }
        if let Some(h) = &self.human {
            h.check()?;
        }
        if let Some(name) = &self.name {
            if name.is_empty() || name.contains(['/', '\\']) || name == "." || name == ".." {
                return Err(format!(
                    "name: '{name}' cannot name a directory (empty, or holds a path separator)"
                ));
            }
        }
        if self.robot.description.is_some()
            && (self.robot.urdf.is_some() || self.robot.srdf.is_some())
        {
            return Err("robot: give either a description or a urdf (and srdf), not both".into());
        }
        if !(self.terrain.mu >= 0.0 && self.terrain.mu.is_finite()) {
            return Err(format!(
                "terrain.mu: must be a finite number ≥ 0, got {}",
                self.terrain.mu
            ));
        }
        if let Some([x, y]) = self.initial.base_xy {
            if !(x.is_finite() && y.is_finite()) {
                return Err("initial.base_xy: must be finite".into());
            }
        }
        positive(
            "actuation.saturation_angle",
            self.actuation.saturation_angle,
            "radians",
        )?;
        if !(self.actuation.damping_ratio >= 0.0 && self.actuation.damping_ratio.is_finite()) {
            return Err(format!(
                "actuation.damping_ratio: must be a finite number ≥ 0, got {}",
                self.actuation.damping_ratio
            ));
        }
        self.sim.validate().map_err(|e| match e {
            corps_sim::SimError::Setting { name, reason } => format!("sim.{name}: {reason}"),
            other => format!("sim: {other}"),
        })?;
        if self.duration < self.sim.control_dt {
            return Err(format!(
                "duration: {} s is shorter than one control period ({} s)",
                self.duration, self.sim.control_dt
            ));
        }
        if !(self.output.max_log_mb > 0.0 && self.output.max_log_mb.is_finite()) {
            return Err(format!(
                "output.max_log_mb: must be a positive number of MB, got {}",
                self.output.max_log_mb
            ));
        }
        for (k, p) in self.pushes.iter().enumerate() {
            p.check(k)?;
        }
        if let Some(v) = &self.verdict {
            v.check().map_err(|e| format!("verdict.{e}"))?;
        }
        crate::pushes::schedule(&self.pushes, 0.0, self.duration, None)?;
        check_noise(&self.noise)
    }

    /// The run's name: `name`, or the file stem of `path`.
    pub fn run_name(&self, path: &std::path::Path) -> String {
        self.name.clone().unwrap_or_else(|| {
            path.file_stem()
                .map(|s| s.to_string_lossy().into_owned())
                .unwrap_or_else(|| "scenario".into())
        })
    }
}

/// Longest simulated time of a run (s).
pub const MAX_DURATION: f64 = 1e6;
/// Shortest control period (s).
pub const MIN_CONTROL_DT: f64 = 1e-6;
/// Most control ticks in a run.
pub const MAX_TICKS: f64 = 1e9;
/// Largest noise standard deviation or bias of a channel, in its unit (larger values
/// overflow the readings to infinity and the log to NaN).
pub const MAX_NOISE: f64 = 1e6;

/// Every noise channel needs a finite standard deviation ≥ 0 and a finite bias, both at most
/// [`MAX_NOISE`] in magnitude.
pub(crate) fn check_noise(noise: &SensorNoise) -> Result<(), String> {
    for (channel, n) in noise.channels() {
        for (key, x) in [("std", n.std), ("bias", n.bias)] {
            if x.abs() > MAX_NOISE {
                return Err(format!(
                    "noise.{channel}.{key}: {} is over the limit of {MAX_NOISE:.0e} in magnitude",
                    number(x)
                ));
            }
        }
        if !(n.std >= 0.0 && n.std.is_finite()) {
            let got = if n.std.is_finite() {
                n.std.to_string()
            } else {
                "non-finite".into()
            };
            return Err(format!(
                "noise.{channel}.std: must be a finite number ≥ 0, got {got}"
            ));
        }
        if !n.bias.is_finite() {
            return Err(format!("noise.{channel}.bias: must be finite"));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_fill_a_minimal_file() {
        let s = Scenario::parse("duration = 1.5").unwrap();
        assert_eq!(s.duration, 1.5);
        assert_eq!(s.terrain.preset, TerrainPreset::Flat);
        assert_eq!(s.terrain.mu, 0.8);
        assert_eq!(s.initial.configuration, None);
        assert!(s.initial.place_on_ground && s.output.plots);
        assert_eq!(s.actuation.mode, ActuationMode::Position);
        assert_eq!(s.sim, SimSettings::default());
    }

    #[test]
    fn errors_are_one_line_naming_the_key() {
        let cases = [
            ("duraton = 1", "unknown field `duraton`"),
            ("duration = 1\n[terrain]\npreset = \"moon\"", "terrain.preset"),
            ("duration = -1", "duration: must be a positive"),
            ("duration = 1\n[sim]\ncontrol_dt = 0", "sim.control_dt"),
            ("duration = 1\n[noise.force]\nstd = -1", "noise.force.std"),
            (
                "duration = 1\n[[push]]\nframe = \"x\"\nstart = -1\nduration = 0.1\nforce = [1, 0, 0]",
                "push[0].start",
            ),
            ("duration = 1\n[sim]\nintegrator = \"leapfrog\"", "sim.integrator"),
            ("duration = ", "line 1"),
            ("duration = 1\nduration = 2", "line 2: duplicate key `duration`"),
        ];
        for (text, expected) in cases {
            let e = Scenario::parse(text).unwrap_err();
            assert!(e.contains(expected), "{text:?}: {e}");
            assert!(!e.contains('\n'), "{text:?}: {e}");
        }
    }
}
