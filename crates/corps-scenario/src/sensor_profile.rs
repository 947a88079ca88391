//! A sensor profile: the `[noise]` tables of a scenario (and optionally its `seed` and
//! `force_torque_model`) in a file of their own, so that one set of sensor levels, stated once with its sources, applies to
//! every scenario (`corps run --noise FILE`; `scenarios/sensors/`).

use crate::error::{invalid, Result};
use crate::scenario::check_noise;
use corps_sim::{ForceTorqueModel, SensorNoise};
use serde::Deserialize;
use std::path::Path;

/// The file's contents: `seed` (optional) and the `[noise.<channel>]` tables of a scenario.
#[derive(Clone, Debug, Default, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SensorProfile {
    /// Where it came from (the file's name), for the run's report.
    #[serde(skip)]
    pub name: String,
    /// Replaces the scenario's noise seed when given.
    #[serde(default)]
    pub seed: Option<u64>,
    /// Replaces the scenario's `force_torque_model` when given.
    #[serde(default)]
    pub force_torque_model: Option<ForceTorqueModel>,
    /// Replaces the scenario's `[noise]` as a whole (channels left out are noiseless).
    #[serde(default)]
    pub noise: SensorNoise,
}

impl SensorProfile {
    /// Parses and checks a profile; the error is one line naming the key.
    pub fn parse(text: &str) -> Result<SensorProfile, String> {
        let profile: SensorProfile = corps_robot::toml_text::parse(text)?;
        check_noise(&profile.noise)?;
        Ok(profile)
    }

    /// Reads and checks the profile at `path`.
    pub fn read(path: &Path) -> Result<SensorProfile> {
        let text = std::fs::read_to_string(path)
            .map_err(|e| invalid!("{}: cannot read the sensor profile: {e}", path.display()))?;
        let mut profile =
            SensorProfile::parse(&text).map_err(|e| invalid!("{}: {e}", path.display()))?;
        profile.name = path.file_name().map_or_else(
            || path.display().to_string(),
            |n| n.to_string_lossy().into(),
        );
        Ok(profile)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_profile_sets_the_channels_it_names_and_refuses_what_a_scenario_refuses() {
        let p = SensorProfile::parse("seed = 7\n[noise.encoders]\nstd = 3.5e-6\n").unwrap();
        assert_eq!(p.seed, Some(7));
        assert_eq!(p.noise.encoders.std, 3.5e-6);
        assert_eq!(p.noise.force.std, 0.0);
        for (bad, key) in [
            ("[noise.encoders]\nstd = -1.0\n", "noise.encoders.std"),
            ("[noise.encoder]\nstd = 1.0\n", "unknown field"),
            ("duration = 1.0\n", "unknown field"),
            ("[noise.force]\nstd = 1e9\n", "noise.force.std"),
        ] {
            let e = SensorProfile::parse(bad).unwrap_err();
            assert!(e.contains(key) && !e.contains('\n'), "{bad}: {e}");
        }
    }

    #[test]
    fn the_shipped_profiles_parse() {
        let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenarios/sensors");
        let mut n = 0;
        for entry in std::fs::read_dir(dir).unwrap() {
            let path = entry.unwrap().path();
            SensorProfile::read(&path).unwrap();
            n += 1;
        }
        assert!(n >= 2, "the TALOS profiles are missing");
    }
}
