//! The drilling scenario file (TOML): the arm, its tool, the plate, the cycle of Table 6.2,
//! the clamping bounds of Eq 6.2, the two loops, the weights of Table 6.1, the tank and the
//! sensors. Every key has a default but the arm's URDF and tool frame; `check` names the key
//! of every bad value.

use serde::Deserialize;

/// The most holes a cycle may drill between R1 and R2.
pub const MAX_HOLES: usize = 10_000;

/// A drilling scenario.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct DrillingScenario {
    /// Simulated time (s); default: the whole cycle and one second more.
    pub duration: Option<f64>,
    pub arm: ArmSection,
    #[serde(default)]
    pub tool: ToolSection,
    #[serde(default)]
    pub plate: PlateSection,
    #[serde(default)]
    pub cycle: CycleSection,
    #[serde(default)]
    pub clamp: ClampSection,
    #[serde(default)]
    pub loops: LoopSection,
    #[serde(default)]
    pub weights: WeightSection,
    #[serde(default)]
    pub gains: GainSection,
    #[serde(default)]
    pub tank: TankSection,
    #[serde(default)]
    pub sensors: SensorSection,
    #[serde(default)]
    pub sim: SimSection,
}

/// `[arm]`: a fixed-base arm from its URDF.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct ArmSection {
    /// The URDF (relative to the scenario file).
    pub urdf: String,
    /// The flange frame: the tool sticks out along its +z.
    pub tool_frame: String,
    /// The starting joint positions, one per joint in the URDF's order: degrees for a
    /// revolute joint, metres for a prismatic one; default all zero.
    #[serde(default)]
    pub q0: Vec<f64>,
}

/// `[tool]`: a cylinder on the flange (massless: its collision shape only).
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields, default)]
pub struct ToolSection {
    pub length: f64,
    pub radius: f64,
}

impl Default for ToolSection {
    fn default() -> Self {
        Self {
            length: 0.15,
            radius: 0.015,
        }
    }
}

/// `[plate]`: the work piece, a box whose top face is the drilled surface.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields, default)]
pub struct PlateSection {
    /// Centre of the top face (m, world).
    pub centre: [f64; 3],
    /// Orientation (roll, pitch, yaw; degrees): the top face's normal is the rotated +z.
    pub rpy_deg: [f64; 3],
    /// Size of the top face along the plate's x and y (m) and its thickness.
    pub size: [f64; 2],
    pub thickness: f64,
    /// Friction coefficient of the tool on the plate (the simulator's).
    pub mu: f64,
}

impl Default for PlateSection {
    fn default() -> Self {
        Self {
            centre: [0.45, 0.0, 0.1],
            rpy_deg: [0.0; 3],
            size: [0.5, 0.7],
            thickness: 0.02,
            mu: 0.8,
        }
    }
}

/// `[cycle]`: seed 000 Table 6.2 — the reference pre-holes R1 and R2 are clamped and checked,
/// `holes` holes are drilled between them, then R1 and R2 are drilled to their final
/// diameter. Positions are on the plate (m, plate x and y).
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields, default)]
pub struct CycleSection {
    pub r1: [f64; 2],
    pub r2: [f64; 2],
    pub holes: usize,
    /// Height of the approach point above each hole (m).
    pub standoff: f64,
    /// Durations (s): a move between approach points, the descent to the plate, the clamping
    /// force's rise and fall, a check at R1/R2 (step 1), a hole, and the retreat.
    pub move_time: f64,
    pub descent_time: f64,
    pub ramp_time: f64,
    pub check_time: f64,
    pub drill_time: f64,
    pub retreat_time: f64,
    /// The descent: a minimum-jerk motion over `descent_time` to `guard` above the surface
    /// (m), then a guarded approach at `touch_speed` (m/s) down to `descent_overshoot` below
    /// it (m): the tool touches on the way.
    pub guard: f64,
    pub touch_speed: f64,
    pub descent_overshoot: f64,
    /// The clamp load cell above this force (N) ends the descent: the contact is made.
    pub touch_force: f64,
    /// The drill's thrust on the tool while a hole is drilled (N, pushing the tool off the
    /// plate; the controller does not know it) and its rise time (s).
    pub thrust: f64,
    pub thrust_rise: f64,
}

impl Default for CycleSection {
    fn default() -> Self {
        Self {
            r1: [0.0, -0.2],
            r2: [0.0, 0.2],
            holes: 10,
            standoff: 0.04,
            move_time: 1.5,
            descent_time: 1.0,
            ramp_time: 0.5,
            check_time: 0.5,
            drill_time: 2.0,
            retreat_time: 0.8,
            guard: 0.005,
            touch_speed: 0.01,
            descent_overshoot: 0.01,
            touch_force: 5.0,
            thrust: 20.0,
            thrust_rise: 0.2,
        }
    }
}

/// `[clamp]`: Eq 6.2's bounds — `F_min ≤ F⊥ ≤ F_max` while clamped and the tangential force
/// `|f_slip| ≤ slip_ratio · F⊥` — the clamping force held, and how far the tool may slide on
/// the plate from its touch to its release (mm) before the run fails.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields, default)]
pub struct ClampSection {
    pub force: f64,
    pub f_min: f64,
    pub f_max: f64,
    pub slip_ratio: f64,
    pub slide_limit_mm: f64,
}

impl Default for ClampSection {
    fn default() -> Self {
        Self {
            force: 60.0,
            f_min: 30.0,
            f_max: 100.0,
            slip_ratio: 1.0,
            slide_limit_mm: 0.1,
        }
    }
}

/// `[loops]`: the high-level QP at `qp_rate_hz` best effort, each update `U(−jitter, jitter)`
/// off its nominal time (seeded), and the local PD+ regulation at `local_rate_hz` around
/// the last update (seed 000 L6960–L6990).
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields, default)]
pub struct LoopSection {
    pub qp_rate_hz: f64,
    /// Jitter of each update (s).
    pub jitter: f64,
    pub local_rate_hz: f64,
    /// Bandwidth of the local PD+ (Hz): kp = M_ii ω², kd = 2 M_ii ω at the start posture.
    pub local_bandwidth_hz: f64,
    pub seed: u64,
}

impl Default for LoopSection {
    fn default() -> Self {
        Self {
            qp_rate_hz: 250.0,
            jitter: 0.002,
            local_rate_hz: 500.0,
            local_bandwidth_hz: 5.0,
            seed: 1,
        }
    }
}

/// `[weights]`: seed 000 Table 6.1 — end-effector contact 100, Cartesian force-contact 50,
/// posture 0.1.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields, default)]
pub struct WeightSection {
    pub end_effector: f64,
    pub force: f64,
    pub posture: f64,
}

impl Default for WeightSection {
    fn default() -> Self {
        Self {
            end_effector: 100.0,
            force: 50.0,
            posture: 0.1,
        }
    }
}

/// `[gains]` (D = 2√P where not given). Our choice for the arm, in the ranges of seed 000
/// Table 5.2 (end effector 100, contact 30, force Kp 10 with K_I = 0.5 Kp).
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields, default)]
pub struct GainSection {
    pub end_effector: f64,
    pub contact: f64,
    pub posture: f64,
    pub force_kp: f64,
    pub force_ki: f64,
    /// Cutoff of the low-pass on the clamp load cell the force task reads (Hz).
    pub force_lowpass_hz: f64,
    /// The joint bounds' look-ahead (s).
    pub bounds_horizon: f64,
    /// Joint damping of the safe command (N·m·s/rad).
    pub safe_damping: f64,
    /// How long a contact's force bound takes to appear or vanish (s).
    pub contact_transition: f64,
}

impl Default for GainSection {
    fn default() -> Self {
        Self {
            end_effector: 100.0,
            contact: 30.0,
            posture: 10.0,
            force_kp: 1.0,
            force_ki: 5.0,
            force_lowpass_hz: 10.0,
            bounds_horizon: 0.02,
            safe_damping: 2.0,
            contact_transition: 0.05,
        }
    }
}

/// `[tank]`: seed 000 L6396–L6401 (E_max 5 J, E_min 0.1 J, P_low −0.5 W), started at 3 J.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields, default)]
pub struct TankSection {
    pub e_max: f64,
    pub e_min: f64,
    pub p_low: f64,
    pub initial: f64,
}

impl Default for TankSection {
    fn default() -> Self {
        Self {
            e_max: 5.0,
            e_min: 0.1,
            p_low: -0.5,
            initial: 3.0,
        }
    }
}

/// `[sensors]`: white noise (standard deviations) on the encoders, the joint velocities and
/// the clamp load cell, seeded by `[loops] seed`.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields, default)]
pub struct SensorSection {
    pub encoder: f64,
    pub velocity: f64,
    pub load_cell: f64,
}

impl Default for SensorSection {
    fn default() -> Self {
        Self {
            encoder: 1e-5,
            velocity: 1e-3,
            load_cell: 0.5,
        }
    }
}

/// `[sim]`: the physics step (s; the local period is split into whole steps of at most
/// this) and the contact's stiffness per area.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields, default)]
pub struct SimSection {
    pub step: f64,
    pub normal_stiffness: f64,
    pub tangential_stiffness: f64,
}

impl Default for SimSection {
    fn default() -> Self {
        Self {
            step: 0.001,
            normal_stiffness: 4e8,
            tangential_stiffness: 4e8,
        }
    }
}

impl DrillingScenario {
    /// Parses and checks a scenario's text.
    pub fn parse(text: &str) -> Result<Self, String> {
        let s: DrillingScenario = corps_robot::toml_text::parse(text)?;
        s.check()?;
        Ok(s)
    }

    /// Checks every value that needs no model; the error names the key.
    pub fn check(&self) -> Result<(), String> {
        let positive = |key: &str, x: f64| {
            if x > 0.0 && x.is_finite() {
                Ok(())
            } else {
                Err(format!("{key}: must be finite and > 0, got {x}"))
            }
        };
        let non_negative = |key: &str, x: f64| {
            if x >= 0.0 && x.is_finite() {
                Ok(())
            } else {
                Err(format!("{key}: must be finite and ≥ 0, got {x}"))
            }
        };
        if let Some(d) = self.duration {
            positive("duration", d)?;
        }
        if self.arm.q0.iter().any(|x| !x.is_finite()) {
            return Err("arm.q0: a non-finite position".into());
        }
        positive("tool.length", self.tool.length)?;
        positive("tool.radius", self.tool.radius)?;
        let p = &self.plate;
        if p.centre.iter().chain(&p.rpy_deg).any(|x| !x.is_finite()) {
            return Err("plate: non-finite centre or rpy_deg".into());
        }
        positive("plate.size[0]", p.size[0])?;
        positive("plate.size[1]", p.size[1])?;
        positive("plate.thickness", p.thickness)?;
        non_negative("plate.mu", p.mu)?;
        let c = &self.cycle;
        for (key, xy) in [("cycle.r1", c.r1), ("cycle.r2", c.r2)] {
            if xy.iter().any(|x| !x.is_finite()) {
                return Err(format!("{key}: non-finite"));
            }
            if xy[0].abs() > p.size[0] / 2.0 || xy[1].abs() > p.size[1] / 2.0 {
                return Err(format!(
                    "{key}: ({}, {}) m is off the plate (±{} × ±{} m)",
                    xy[0],
                    xy[1],
                    p.size[0] / 2.0,
                    p.size[1] / 2.0
                ));
            }
        }
        if c.r1 == c.r2 {
            return Err("cycle.r2: the same point as cycle.r1".into());
        }
        positive("cycle.standoff", c.standoff)?;
        for (key, x) in [
            ("cycle.move_time", c.move_time),
            ("cycle.descent_time", c.descent_time),
            ("cycle.ramp_time", c.ramp_time),
            ("cycle.retreat_time", c.retreat_time),
        ] {
            positive(key, x)?;
        }
        non_negative("cycle.check_time", c.check_time)?;
        non_negative("cycle.drill_time", c.drill_time)?;
        non_negative("cycle.descent_overshoot", c.descent_overshoot)?;
        non_negative("cycle.guard", c.guard)?;
        positive("cycle.touch_speed", c.touch_speed)?;
        if c.guard >= c.standoff {
            return Err(format!(
                "cycle.guard: {} m is not below the standoff ({} m)",
                c.guard, c.standoff
            ));
        }
        positive("cycle.touch_force", c.touch_force)?;
        non_negative("cycle.thrust", c.thrust)?;
        positive("cycle.thrust_rise", c.thrust_rise)?;
        if c.thrust > 0.0 && c.drill_time > 0.0 && c.thrust_rise > c.drill_time {
            return Err(format!(
                "cycle.thrust_rise: {} s is longer than cycle.drill_time ({} s)",
                c.thrust_rise, c.drill_time
            ));
        }
        if c.holes > MAX_HOLES {
            return Err(format!("cycle.holes: {} is more than {MAX_HOLES}", c.holes));
        }
        let k = &self.clamp;
        non_negative("clamp.f_min", k.f_min)?;
        positive("clamp.f_max", k.f_max)?;
        positive("clamp.slip_ratio", k.slip_ratio)?;
        positive("clamp.slide_limit_mm", k.slide_limit_mm)?;
        if !(k.f_min < k.force && k.force < k.f_max) {
            return Err(format!(
                "clamp.force: {} N is not inside (f_min, f_max) = ({}, {}) N",
                k.force, k.f_min, k.f_max
            ));
        }
        if c.touch_force >= k.force {
            return Err(format!(
                "cycle.touch_force: {} N is not below clamp.force ({} N)",
                c.touch_force, k.force
            ));
        }
        let l = &self.loops;
        positive("loops.qp_rate_hz", l.qp_rate_hz)?;
        positive("loops.local_rate_hz", l.local_rate_hz)?;
        positive("loops.local_bandwidth_hz", l.local_bandwidth_hz)?;
        non_negative("loops.jitter", l.jitter)?;
        if l.qp_rate_hz > l.local_rate_hz {
            return Err(format!(
                "loops.qp_rate_hz: {} Hz is faster than the local loop ({} Hz)",
                l.qp_rate_hz, l.local_rate_hz
            ));
        }
        if l.jitter >= 1.0 / l.qp_rate_hz {
            return Err(format!(
                "loops.jitter: {} s is not shorter than the QP's period ({} s)",
                l.jitter,
                1.0 / l.qp_rate_hz
            ));
        }
        let w = &self.weights;
        positive("weights.end_effector", w.end_effector)?;
        positive("weights.force", w.force)?;
        positive("weights.posture", w.posture)?;
        let g = &self.gains;
        positive("gains.end_effector", g.end_effector)?;
        positive("gains.contact", g.contact)?;
        positive("gains.posture", g.posture)?;
        non_negative("gains.force_kp", g.force_kp)?;
        non_negative("gains.force_ki", g.force_ki)?;
        positive("gains.force_lowpass_hz", g.force_lowpass_hz)?;
        positive("gains.bounds_horizon", g.bounds_horizon)?;
        non_negative("gains.safe_damping", g.safe_damping)?;
        positive("gains.contact_transition", g.contact_transition)?;
        non_negative("tank.initial", self.tank.initial)?;
        let s = &self.sensors;
        non_negative("sensors.encoder", s.encoder)?;
        non_negative("sensors.velocity", s.velocity)?;
        non_negative("sensors.load_cell", s.load_cell)?;
        positive("sim.step", self.sim.step)?;
        if self.sim.step > 1.0 / l.local_rate_hz {
            return Err(format!(
                "sim.step: {} s is longer than the local loop's period ({} s)",
                self.sim.step,
                1.0 / l.local_rate_hz
            ));
        }
        if self.sim.step < 1e-3 / l.local_rate_hz {
            return Err(format!(
                "sim.step: {} s is more than a thousand steps per local period",
                self.sim.step
            ));
        }
        positive("sim.normal_stiffness", self.sim.normal_stiffness)?;
        non_negative("sim.tangential_stiffness", self.sim.tangential_stiffness)?;
        Ok(())
    }
}
