//! Joint drives: the flexible-joint model of seed 000 Eq 2.33 with a current-controlled motor,
//! per actuated joint, for torque commands.
//!
//! In link coordinates (gear ratio folded in: `θ` is the motor position over the ratio),
//! `B θ̈ = τ_m − τ_s − F_v θ̇ − F_s tanh(θ̇/ε)`, `τ_s = K (θ − q) + D (θ̇ − q̇)` is the torque the
//! harmonic drive passes to the link, and `τ_m = R K_m i` with the current following its
//! command through the torque loop, `i̇ = ω_c (i_cmd − i)`, `i_cmd = clamp(τ_cmd / (R K_m),
//! ±i_max)`, `τ_cmd` the controller's torque one control period late. Friction (Eq 2.34) is
//! lumped on the motor side (motor and joint friction in one term, as Eq 3.5 sums them): with
//! a stiff drive `θ̇ ≈ q̇` and the link then sees only the spring, whose stiffness `K` and
//! damping `D` the implicit integrator takes as it takes a servo's.
//!
//! The linearly implicit step solves link and motor together (the motor's implicit step is
//! affine in the link's new velocity, so the link sees the drive as a damper of known gain);
//! explicit steps move the motor on at its velocity while the link steps and must resolve the
//! spring on the lightest link (RK4: `√(K/I) h < 2.8`, substeps on light wrists). After each
//! physics step the motor advances to the link's new state: the current exactly (first
//! order), the motor by linearly implicit Euler (spring, damping and the friction's slope
//! implicit), stable at any step.

use crate::error::{Result, SimError};
use serde::{Deserialize, Serialize};

/// The longest command delay a drive takes, control periods.
pub const MAX_DELAY_PERIODS: usize = 1000;

/// One joint's drive parameters.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FlexibleDrive {
    /// Motor inertia through the gear ratio `B = r² I_rotor`, kg·m².
    pub motor_inertia: f64,
    /// Drive stiffness `K`, N·m/rad, and damping `D`, N·m·s/rad.
    pub stiffness: f64,
    pub damping: f64,
    /// Viscous and dry friction (motor and joint together), N·m·s/rad and N·m.
    pub viscous_friction: f64,
    pub dry_friction: f64,
    /// `ε` of `tanh(θ̇/ε)`, rad/s.
    pub friction_velocity: f64,
    /// `R K_m`, N·m/A.
    pub drive_gain: f64,
    /// `i_max`, A.
    pub current_limit: f64,
    /// Torque-loop bandwidth `ω_c / 2π`, Hz.
    pub bandwidth_hz: f64,
    /// Delay of the command, control periods.
    pub delay_periods: usize,
}

impl FlexibleDrive {
    /// Checks every value (`joint` names it in the message).
    pub fn validate(&self, joint: &str) -> Result<()> {
        let positive = [
            ("motor_inertia", self.motor_inertia),
            ("stiffness", self.stiffness),
            ("friction_velocity", self.friction_velocity),
            ("drive_gain", self.drive_gain),
            ("current_limit", self.current_limit),
            ("bandwidth_hz", self.bandwidth_hz),
        ];
        let non_negative = [
            ("damping", self.damping),
            ("viscous_friction", self.viscous_friction),
            ("dry_friction", self.dry_friction),
        ];
        for (name, v) in positive {
            if !(v.is_finite() && v > 0.0) {
                return Err(drive_error(joint, name, v, "positive"));
            }
        }
        for (name, v) in non_negative {
            if !(v.is_finite() && v >= 0.0) {
                return Err(drive_error(joint, name, v, "≥ 0"));
            }
        }
        if self.delay_periods > MAX_DELAY_PERIODS {
            return Err(SimError::Setting {
                name: format!("drive of {joint}: delay_periods"),
                reason: format!("{} (at most {MAX_DELAY_PERIODS})", self.delay_periods),
            });
        }
        Ok(())
    }

    /// The torque the drive can deliver, `R K_m i_max`, N·m.
    pub fn torque_limit(&self) -> f64 {
        self.drive_gain * self.current_limit
    }
}

fn drive_error(joint: &str, name: &str, v: f64, what: &str) -> SimError {
    SimError::Setting {
        name: format!("drive of {joint}: {name}"),
        reason: format!("{v} (must be {what})"),
    }
}

/// One drive's state.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct DriveState {
    /// Motor position and velocity in link coordinates, rad and rad/s.
    pub theta: f64,
    pub theta_dot: f64,
    /// Motor current, A.
    pub current: f64,
}

/// The drives of the actuated joints (None: ideal torque).
#[derive(Clone, Debug)]
pub struct Drives {
    params: Vec<Option<FlexibleDrive>>,
    state: Vec<DriveState>,
    /// Per joint, the last `delay_periods` commands (a ring read and written at `head`),
    /// and the command the drive is applying.
    queued: Vec<Vec<f64>>,
    head: usize,
    applied: Vec<f64>,
    started: bool,
}

impl Drives {
    /// Drives for `params` (one entry per actuated joint), each validated.
    pub fn new(params: Vec<Option<FlexibleDrive>>, names: &[String]) -> Result<Self> {
        for (p, name) in params.iter().zip(names) {
            if let Some(p) = p {
                p.validate(name)?;
            }
        }
        let n = params.len();
        let queued = params
            .iter()
            .map(|p| vec![0.0; p.map_or(0, |p| p.delay_periods)])
            .collect();
        Ok(Self {
            params,
            state: vec![DriveState::default(); n],
            queued,
            head: 0,
            applied: vec![0.0; n],
            started: false,
        })
    }

    pub fn len(&self) -> usize {
        self.params.len()
    }

    pub fn is_empty(&self) -> bool {
        self.params.is_empty()
    }

    /// The drive of actuated joint `k`, if flexible.
    pub fn drive(&self, k: usize) -> Option<&FlexibleDrive> {
        self.params[k].as_ref()
    }

    pub fn state(&self, k: usize) -> &DriveState {
        &self.state[k]
    }

    /// Forgets the motors' state: the next period starts them at rest on the link, the
    /// spring loaded with the command.
    pub fn restart(&mut self) {
        self.started = false;
    }

    /// Takes a control period's torque command `tau` (actuated joints) at link state
    /// `(q, v)`: each drive applies the command of `delay_periods` periods ago. The first
    /// period starts each motor on its link with the spring loaded by the command (and the
    /// delay line full of it), so that a run begins without a transient.
    pub fn begin_period(&mut self, tau: &[f64], q: &[f64], v: &[f64]) {
        for (k, p) in self.params.iter().enumerate() {
            let Some(p) = p else { continue };
            let line = &mut self.queued[k];
            if !self.started {
                let t = tau[k].clamp(-p.torque_limit(), p.torque_limit());
                self.state[k] = DriveState {
                    theta: q[k] + t / p.stiffness,
                    theta_dot: v[k],
                    current: t / p.drive_gain,
                };
                line.fill(tau[k]);
            }
            if line.is_empty() {
                self.applied[k] = tau[k];
            } else {
                let slot = self.head % line.len();
                self.applied[k] = line[slot];
                line[slot] = tau[k];
            }
        }
        self.head = self.head.wrapping_add(1);
        self.started = true;
    }

    /// The torque drive `k` passes to its link at `(q, v)`, `lead` s into the physics step:
    /// `K (θ + lead θ̇ − q) + D (θ̇ − q̇)`. The motor moves on at its velocity while the link
    /// steps (held still, it would brake the link by `K h q̇`, a spurious damping).
    pub fn link_torque(&self, k: usize, q: f64, v: f64, lead: f64) -> Option<f64> {
        let p = self.params[k].as_ref()?;
        let s = &self.state[k];
        Some(p.stiffness * (s.theta + lead * s.theta_dot - q) + p.damping * (s.theta_dot - v))
    }

    /// The current after a step of `h` towards the applied command, A.
    fn next_current(&self, k: usize, p: &FlexibleDrive, h: f64) -> f64 {
        let target = (self.applied[k] / p.drive_gain).clamp(-p.current_limit, p.current_limit);
        let decay = (-std::f64::consts::TAU * p.bandwidth_hz * h).exp();
        target + (self.state[k].current - target) * decay
    }

    /// The motor's implicit step over `h` from link position `q` as an affine function of
    /// the link's velocity at the step's end: `θ̇⁺ = a + b q̇⁺` (with `q⁺ = q + h q̇⁺`):
    /// `(B + h(hK + D + F_v + F_s s)) θ̇⁺ = B θ̇ + h (τ_m − K(θ − q) − F_s tanh(θ̇/ε) + F_s s θ̇)
    /// + h (hK + D) q̇⁺`, `s` the slope of `tanh(θ̇/ε)`.
    fn motor_step(&self, k: usize, p: &FlexibleDrive, h: f64, q: f64) -> (f64, f64) {
        let s = &self.state[k];
        let torque = p.drive_gain * self.next_current(k, p, h);
        let eps = p.friction_velocity;
        let tanh = (s.theta_dot / eps).tanh();
        let slope = p.dry_friction * (1.0 - tanh * tanh) / eps;
        let coupling = h * p.stiffness + p.damping;
        let lhs = p.motor_inertia + h * (coupling + p.viscous_friction + slope);
        let free = p.motor_inertia * s.theta_dot
            + h * (torque - p.stiffness * (s.theta - q) - p.dry_friction * tanh
                + slope * s.theta_dot);
        (free / lhs, h * coupling / lhs)
    }

    /// For a linearly implicit step of `h` from link state `(q, v)`: the drive's torque on
    /// its link at the step's end as `τ₀ − c (q̇⁺ − q̇)`, returned as `(τ₀, c)`. The link and
    /// the motor are solved together: `τ⁺ = K(θ − q) + (hK + D)(θ̇⁺ − q̇⁺)`.
    pub fn implicit_link_torque(&self, k: usize, h: f64, q: f64, v: f64) -> Option<(f64, f64)> {
        let p = self.params[k].as_ref()?;
        let (a, b) = self.motor_step(k, p, h, q);
        let coupling = h * p.stiffness + p.damping;
        let c = coupling * (1.0 - b);
        let tau0 = p.stiffness * (self.state[k].theta - q) + coupling * (a + (b - 1.0) * v);
        Some((tau0, c))
    }

    /// Advances every motor by `h` to the links' new state `(q, v)` (actuated joints): the
    /// same implicit step, `q` being `q⁺`.
    pub fn advance(&mut self, h: f64, q: &[f64], v: &[f64]) {
        for k in 0..self.params.len() {
            let Some(p) = self.params[k] else { continue };
            // motor_step takes the step's starting q: q⁺ − h q̇⁺.
            let (a, b) = self.motor_step(k, &p, h, q[k] - h * v[k]);
            let current = self.next_current(k, &p, h);
            let s = &mut self.state[k];
            s.current = current;
            s.theta_dot = a + b * v[k];
            s.theta += h * s.theta_dot;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn elbow() -> FlexibleDrive {
        FlexibleDrive {
            motor_inertia: 0.45,
            stiffness: 1.5e4,
            damping: 8.0,
            viscous_friction: 5.57,
            dry_friction: 4.55,
            friction_velocity: 0.01,
            drive_gain: 10.6,
            current_limit: 6.0,
            bandwidth_hz: 500.0,
            delay_periods: 1,
        }
    }

    #[test]
    fn a_blocked_link_receives_the_delayed_command_at_steady_state() {
        let mut d = Drives::new(vec![Some(elbow())], &["j".into()]).unwrap();
        let (q, v) = ([0.3], [0.0]);
        d.begin_period(&[0.0], &q, &v);
        assert_eq!(d.link_torque(0, q[0], v[0], 0.0), Some(0.0));
        d.begin_period(&[20.0], &q, &v);
        for _ in 0..10 {
            d.advance(1e-4, &q, &v);
        }
        // One period of delay: the spring still holds the previous command.
        assert!(d.link_torque(0, q[0], v[0], 0.0).unwrap().abs() < 1e-9);
        for _ in 0..2000 {
            d.begin_period(&[20.0], &q, &v);
            for _ in 0..10 {
                d.advance(1e-4, &q, &v);
            }
        }
        let t = d.link_torque(0, q[0], v[0], 0.0).unwrap();
        assert!((t - 20.0).abs() < 1e-6, "{t}");
        // Beyond the current limit the torque saturates at R K_m i_max.
        for _ in 0..2000 {
            d.begin_period(&[500.0], &q, &v);
            for _ in 0..10 {
                d.advance(1e-4, &q, &v);
            }
        }
        let t = d.link_torque(0, q[0], v[0], 0.0).unwrap();
        assert!((t - 63.6).abs() < 1e-6, "{t}");
    }

    #[test]
    fn a_command_arrives_after_its_delay() {
        let mut p = elbow();
        p.delay_periods = 3;
        p.bandwidth_hz = 1e9;
        let mut d = Drives::new(vec![Some(p)], &["j".into()]).unwrap();
        let (q, v) = ([0.0], [0.0]);
        let mut seen = Vec::new();
        for tau in [1.0, 2.0, 3.0, 4.0, 5.0, 6.0] {
            d.begin_period(&[tau], &q, &v);
            seen.push(d.applied[0]);
        }
        // The first command fills the line; each later one arrives three periods on.
        assert_eq!(seen, vec![1.0, 1.0, 1.0, 1.0, 2.0, 3.0]);
        let mut bad = elbow();
        bad.delay_periods = MAX_DELAY_PERIODS + 1;
        assert!(Drives::new(vec![Some(bad)], &["j".into()]).is_err());
        bad = elbow();
        bad.stiffness = -1.0;
        let e = Drives::new(vec![Some(bad)], &["knee".into()]).unwrap_err();
        assert!(
            e.to_string().contains("knee") && e.to_string().contains("stiffness"),
            "{e}"
        );
    }

    #[test]
    fn the_motor_step_is_stable_at_a_millisecond_and_rings_at_the_drive_frequency() {
        let mut p = elbow();
        p.dry_friction = 0.0;
        p.viscous_friction = 0.0;
        p.damping = 0.0;
        let mut d = Drives::new(vec![Some(p)], &["j".into()]).unwrap();
        let (q, v) = ([0.0], [0.0]);
        d.begin_period(&[0.0], &q, &v);
        d.state[0].theta = 0.01;
        // Implicit Euler: the free oscillation decays and never grows, even at h = 1 ms
        // (ω = √(K/B) = 183 rad/s, ω h = 0.18).
        for _ in 0..1000 {
            d.advance(1e-3, &q, &v);
            assert!(d.state[0].theta.abs() <= 0.0100001);
        }
        assert!(d.state[0].theta.abs() < 0.005);
        // A fine step follows the undamped period 2π √(B/K).
        let mut d = Drives::new(vec![Some(p)], &["j".into()]).unwrap();
        d.begin_period(&[0.0], &q, &v);
        d.state[0].theta = 0.01;
        let h = 1e-6;
        let period = std::f64::consts::TAU * (p.motor_inertia / p.stiffness).sqrt();
        let steps = (period / h).round() as usize;
        let mut crossings = 0;
        let mut last = d.state[0].theta;
        for _ in 0..steps {
            d.advance(h, &q, &v);
            if (d.state[0].theta > 0.0) != (last > 0.0) {
                crossings += 1;
            }
            last = d.state[0].theta;
        }
        assert_eq!(crossings, 2);
        assert!(
            (d.state[0].theta - 0.01).abs() < 1e-4,
            "{}",
            d.state[0].theta
        );
    }
}
