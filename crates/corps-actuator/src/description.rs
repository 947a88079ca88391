//! An actuator description file (TOML): the joint it drives, the drive model of
//! [`crate::elbow`], its limits and its thermal model.

use crate::elbow::{ElbowParameters, Limits};
use crate::error::ActuatorError;
use crate::thermal::ThermalParameters;
use serde::Deserialize;

/// One actuator: model, limits and thermal parameters.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ActuatorDescription {
    /// The joint of the robot description it drives.
    pub joint: String,
    pub model: ElbowParameters,
    pub limits: Limits,
    pub thermal: ThermalParameters,
}

impl ActuatorDescription {
    /// Parses and checks a description.
    pub fn from_toml(text: &str) -> Result<Self, ActuatorError> {
        let d: Self = toml::from_str(text)
            .map_err(|e| ActuatorError::Description(e.message().to_string()))?;
        d.model.validate()?;
        d.limits.validate()?;
        d.thermal.validate()?;
        Ok(d)
    }
}
