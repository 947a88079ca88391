use corps_actuator::ActuatorDescription;

/// The TALOS elbow's description, as shipped.
pub fn elbow() -> ActuatorDescription {
    ActuatorDescription::from_toml(include_str!(
        "../../../../config/talos/actuators/elbow.toml"
    ))
    .expect("the shipped description parses")
}
