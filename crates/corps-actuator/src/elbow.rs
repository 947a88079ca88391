//! The single-joint drive of seed 000 Eq 3.1–3.5 (the TALOS elbow, harmonic drive taken
//! rigid, motor position = joint position):
//! `R K_m i = (I_m + I_j) q̈ + g (M_Y sin q + M_X cos q) + τ_fm + τ_fj` (motor side),
//! `K_j τ_js = I_j q̈ + g (M_Y sin q + M_X cos q) + τ_fj` (joint torque sensor),
//! `τ_f = F_v q̇ + F_s sign(q̇) + off` on each side (Eq 2.34 with an offset).
//! A payload on the link adds `I_L q̈ + g (L_Y sin q + L_X cos q)` to both sides (§3.13).

use crate::error::ActuatorError;
use serde::Deserialize;

/// Gravity, m/s².
pub const G: f64 = 9.81;

/// The inertial, friction and gain parameters of Eq 3.1–3.5.
#[derive(Clone, Copy, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ElbowParameters {
    /// First moments of the link, kg·m.
    pub m_x: f64,
    pub m_y: f64,
    /// Link-side inertia, kg·m², and its friction (N·m·s/rad, N·m) and offset (N·m).
    pub i_j: f64,
    pub f_sj: f64,
    pub f_vj: f64,
    pub off_j: f64,
    /// Motor-side inertia through the gear, friction and offset.
    pub i_m: f64,
    pub f_sm: f64,
    pub f_vm: f64,
    pub off_m: f64,
    /// `R K_m`, N·m per A of motor current.
    pub drive_gain: f64,
    /// `K_j`, the joint torque sensor's gain.
    pub torque_sensor_gain: f64,
}

/// A rigid payload on the link: its inertia about the joint axis and first moments.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Payload {
    pub inertia: f64,
    pub l_x: f64,
    pub l_y: f64,
}

impl Payload {
    /// A point mass `mass` kg at `distance` m from the joint along the link's Y axis
    /// (the forearm, as the thesis's "30 kg at 5 cm from the elbow").
    pub fn point_mass(mass: f64, distance: f64) -> Self {
        Self {
            inertia: mass * distance * distance,
            l_x: 0.0,
            l_y: mass * distance,
        }
    }
}

/// The box of admissible positions, velocities and currents.
#[derive(Clone, Copy, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Limits {
    pub position: [f64; 2],
    pub velocity: [f64; 2],
    pub current: [f64; 2],
}

impl ElbowParameters {
    /// Total inertia `I = I_m + I_j` (plus the payload's).
    pub fn inertia(&self, payload: &Payload) -> f64 {
        self.i_m + self.i_j + payload.inertia
    }

    /// Total viscous friction, dry friction and offset (Eq 3.5).
    pub fn friction(&self) -> (f64, f64, f64) {
        (
            self.f_vm + self.f_vj,
            self.f_sm + self.f_sj,
            self.off_m + self.off_j,
        )
    }

    /// Gravity torque `g (M_Y sin q + M_X cos q)` of link and payload.
    pub fn gravity(&self, q: f64, payload: &Payload) -> f64 {
        G * ((self.m_y + payload.l_y) * q.sin() + (self.m_x + payload.l_x) * q.cos())
    }

    /// Motor torque `R K_m i` the motion `(q, q̇, q̈)` needs (Eq 3.2), dry friction
    /// `sign(q̇)` as given by `sign`.
    pub fn motor_torque(&self, q: f64, v: f64, a: f64, sign: f64, payload: &Payload) -> f64 {
        let (fv, fs, off) = self.friction();
        self.inertia(payload) * a + self.gravity(q, payload) + fv * v + fs * sign + off
    }

    /// Link-side torque `τ_j` of Eq 3.3 (the sensor reads `τ_j / K_j`).
    pub fn joint_torque(&self, q: f64, v: f64, a: f64, sign: f64, payload: &Payload) -> f64 {
        (self.i_j + payload.inertia) * a
            + self.gravity(q, payload)
            + self.f_vj * v
            + self.f_sj * sign
            + self.off_j
    }

    /// Joint acceleration under motor current `current` (Eq 3.5), dry friction `sign(q̇)`
    /// as given by `sign`.
    pub fn acceleration(&self, q: f64, v: f64, current: f64, sign: f64, payload: &Payload) -> f64 {
        let (fv, fs, off) = self.friction();
        (self.drive_gain * current - fv * v - fs * sign - off - self.gravity(q, payload))
            / self.inertia(payload)
    }

    pub(crate) fn validate(&self) -> Result<(), ActuatorError> {
        let all = [
            self.m_x,
            self.m_y,
            self.i_j,
            self.f_sj,
            self.f_vj,
            self.off_j,
            self.i_m,
            self.f_sm,
            self.f_vm,
            self.off_m,
            self.drive_gain,
            self.torque_sensor_gain,
        ];
        if all.iter().any(|v| !v.is_finite()) {
            return Err(ActuatorError::Description(
                "a model value is not finite".into(),
            ));
        }
        if self.i_j + self.i_m <= 0.0 {
            return Err(ActuatorError::Description(format!(
                "the inertia I_m + I_j = {} must be positive",
                self.i_j + self.i_m
            )));
        }
        if self.drive_gain == 0.0 || self.torque_sensor_gain == 0.0 {
            return Err(ActuatorError::Description(
                "drive_gain and torque_sensor_gain must not be zero".into(),
            ));
        }
        Ok(())
    }
}

impl Limits {
    pub(crate) fn validate(&self) -> Result<(), ActuatorError> {
        for (name, [lo, hi]) in [
            ("position", self.position),
            ("velocity", self.velocity),
            ("current", self.current),
        ] {
            if !(lo.is_finite() && hi.is_finite() && lo < hi) {
                return Err(ActuatorError::Description(format!(
                    "{name} limits [{lo}, {hi}] must be finite with lower < upper"
                )));
            }
        }
        for (name, [lo, hi]) in [("velocity", self.velocity), ("current", self.current)] {
            if !(lo < 0.0 && hi > 0.0) {
                return Err(ActuatorError::Description(format!(
                    "{name} limits [{lo}, {hi}] must hold zero inside"
                )));
            }
        }
        Ok(())
    }
}
