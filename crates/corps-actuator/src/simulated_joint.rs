//! The drive of an actuator description as a plant in corps-sim: one revolute joint about y,
//! fixed base, whose link carries the description's first moments and link-side inertia
//! (`G(q) = g (M_Y sin q + M_X cos q)` is the generalised gravity: the link's mass `m` sits at
//! `(−M_X/m, 0, −M_Y/m)` in its frame) and the payload as a point mass at `(0, 0, −d)`,
//! driven through a corps-sim flexible drive with the description's motor inertia, friction
//! (motor and joint together, `tanh(1000 q̇)`), drive gain and current limit. The offsets
//! `Off_m + Off_j` act as a constant torque against the motor's. Assumed, as the robot
//! description's drives: stiffness 1.5e4 N·m/rad, 5 % of critical damping, a 500 Hz torque
//! loop, one control period of delay.

use crate::description::ActuatorDescription;
use crate::error::ActuatorError;
use corps_model::{build_model_from_urdf_str, RootJoint};
use corps_sim::{
    Command, FlexibleDrive, ServoGains, SimSettings, Simulator, Terrain, TerrainPreset,
};
use nalgebra::DVector;
use std::sync::Arc;

/// The link's mass, kg (upstream `pyreneActuator` M = 4.5667 kg; any mass whose CoM offset
/// leaves a positive central inertia serves).
const LINK_MASS: f64 = 4.5667;

/// The joint in the simulator.
pub struct SimulatedJoint {
    sim: Simulator,
    drive_gain: f64,
    offset: f64,
}

fn sim_error(e: corps_sim::SimError) -> ActuatorError {
    ActuatorError::Ilqr(format!("simulated joint: {e}"))
}

impl SimulatedJoint {
    /// The joint of `actuator` carrying `payload_kg` at `distance_m`, at rest at `q0`.
    pub fn new(
        actuator: &ActuatorDescription,
        payload_kg: f64,
        distance_m: f64,
        q0: f64,
    ) -> Result<Self, ActuatorError> {
        let m = &actuator.model;
        let (cx, cz) = (-m.m_x / LINK_MASS, -m.m_y / LINK_MASS);
        let central = m.i_j - LINK_MASS * (cx * cx + cz * cz);
        if central <= 0.0 {
            return Err(ActuatorError::Description(format!(
                "the link inertia I_j = {} is below its first moments' m c² at {LINK_MASS} kg",
                m.i_j
            )));
        }
        let urdf = format!(
            r#"<robot name="joint">
  <link name="base"/>
  <link name="link"><inertial><origin xyz="{cx} 0 {cz}"/><mass value="{LINK_MASS}"/>
    <inertia ixx="{central}" iyy="{central}" izz="{central}" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <link name="payload"><inertial><origin xyz="0 0 {pz}"/><mass value="{pm}"/>
    <inertia ixx="1e-9" iyy="1e-9" izz="1e-9" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <joint name="{name}" type="revolute"><parent link="base"/><child link="link"/>
    <axis xyz="0 1 0"/><limit lower="-10" upper="10" effort="1e9" velocity="100"/></joint>
  <joint name="payload_mount" type="fixed"><parent link="link"/><child link="payload"/></joint>
</robot>"#,
            pz = -distance_m,
            pm = payload_kg.max(1e-9),
            name = actuator.joint,
        );
        let model = build_model_from_urdf_str(&urdf, RootJoint::Fixed)
            .map_err(|e| ActuatorError::Description(format!("simulated joint: {e}")))?;
        let (fv, fs, offset) = m.friction();
        let stiffness = 1.5e4;
        let drive = FlexibleDrive {
            motor_inertia: m.i_m,
            stiffness,
            damping: 0.1 * (stiffness * m.i_m).sqrt(),
            viscous_friction: fv,
            dry_friction: fs,
            friction_velocity: 1e-3,
            drive_gain: m.drive_gain,
            current_limit: actuator.limits.current[1].max(-actuator.limits.current[0]),
            bandwidth_hz: 500.0,
            delay_periods: 1,
        };
        let gains = ServoGains {
            kp: DVector::zeros(1),
            kd: DVector::zeros(1),
            integral: None,
        };
        let settings = SimSettings {
            integrator: corps_sim::Integrator::ImplicitEuler,
            ..SimSettings::default()
        };
        let terrain = Terrain::preset(TerrainPreset::None, 0.8);
        let mut sim =
            Simulator::new(Arc::new(model), terrain, settings, &[q0], gains).map_err(sim_error)?;
        sim.set_drives(vec![Some(drive)]).map_err(sim_error)?;
        Ok(Self {
            sim,
            drive_gain: m.drive_gain,
            offset,
        })
    }

    /// `[q, q̇]`.
    pub fn state(&self) -> [f64; 2] {
        [self.sim.q()[0], self.sim.v()[0]]
    }

    /// One control period under the current command `current` (A).
    pub fn step(&mut self, current: f64) -> Result<(), ActuatorError> {
        let torque = self.drive_gain * current - self.offset;
        self.sim
            .step(&Command::Torque(DVector::from_element(1, torque)))
            .map_err(sim_error)
    }
}
