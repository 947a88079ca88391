//! Reading a scenario file with what its caller replaces (the command's `--duration`,
//! `--robot`, `--estimator`, `--noise`, `--max-log-mb`; the same keywords from Python), so
//! that every front end reports the same one-line errors.

use crate::estimation::EstimatorKind;
use crate::scenario::{RobotSection, Scenario};
use crate::sensor_profile::SensorProfile;
use std::path::Path;

/// What replaces the scenario's own settings.
#[derive(Clone, Debug, Default)]
pub struct Overrides {
    /// Controlled time (s).
    pub duration: Option<f64>,
    /// Size cap of the log (MB).
    pub max_log_mb: Option<f64>,
    /// A built-in robot's name or a description file (relative to the working directory).
    pub robot: Option<String>,
    /// What feeds the controller.
    pub estimator: Option<EstimatorKind>,
    /// Sensor noise (and its seed, and the F/T model, where the profile gives them).
    pub noise: Option<SensorProfile>,
}

/// The text of the scenario file at `path`; the error names the file.
pub fn read_file(path: &Path) -> Result<String, String> {
    let shown = path.display();
    match std::fs::read_to_string(path) {
        Ok(t) => Ok(t),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
            Err(format!("{shown}: no such scenario file"))
        }
        Err(e) => Err(format!("{shown}: cannot read the scenario file: {e}")),
    }
}

impl Scenario {
    /// Parses scenario `text` read from `path` and applies `overrides`; errors start with
    /// the path.
    pub fn parse_with(text: &str, path: &Path, overrides: &Overrides) -> Result<Scenario, String> {
        let shown = path.display();
        let mut scenario = Scenario::parse(text).map_err(|e| format!("{shown}: {e}"))?;
        if let Some(d) = overrides.duration {
            scenario = scenario
                .with_duration(d)
                .map_err(|e| format!("{shown}: {e}"))?;
        }
        if let Some(mb) = overrides.max_log_mb {
            scenario = scenario
                .with_max_log_mb(mb)
                .map_err(|e| format!("{shown}: {e}"))?;
        }
        if let Some(robot) = &overrides.robot {
            scenario.robot = RobotSection::from_argument(robot);
        }
        if let Some(kind) = overrides.estimator {
            scenario.estimator.kind = kind;
        }
        if let Some(profile) = &overrides.noise {
            scenario.noise = profile.noise.clone();
            scenario.seed = profile.seed.unwrap_or(scenario.seed);
            scenario.force_torque_model = profile
                .force_torque_model
                .unwrap_or(scenario.force_torque_model);
        }
        Ok(scenario)
    }
}
