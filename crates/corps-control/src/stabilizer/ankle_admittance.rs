//! Ankle (foot CoP) admittance (seed 002 §4.10, Eq 31, after Caron et al. 2019):
//!
//! `θ̇_raw = A · (τ_mes − p_d × f_mes)_{x,y}`,
//! `θ̇ = clamp(LPF(θ̇_raw), ±θ̇_max)`,  `θ ← clamp(θ + θ̇ dt, ±θ_max)`,
//!
//! for one foot, in its sole frame: `f_mes`, `τ_mes` = the measured contact wrench (ground on
//! foot, about the sole origin), `p_d` = desired CoP from the wrench distribution, `θ` =
//! (roll about sole x, pitch about sole y) offset of the foot's orientation reference, to be
//! composed as `R_ref · R_x(roll) R_y(pitch)`. Sign: a CoP behind its target (`p_mes,x <
//! p_d,x`) gives `τ_mes,y − τ_d,y = f_z (p_d,x − p_mes,x) > 0`, a positive pitch, i.e. toe
//! down, which moves the CoP forward on a stiff floor. That is the reference code's sign;
//! Eq 31 as printed has the opposite one (seed 002 §4.10, §8).
//!
//! When the foot is unloaded (`f_z` below `min_normal_force` or not in contact) the command is
//! zero and `θ` leaks to zero with time constant `leak_time_constant`; the caller keeps
//! applying `θ` meanwhile, so the foot reference stays continuous.
//!
//! Known limit (measured on the IK stick walk at `A = 0.01`): in single support the stance
//! CoP is the ZMP, which the CoM admittance also integrates, so `θ` drifts (the rate sits at
//! its clamp ≈ 8 % of the first 4.5 s, `|θ|` up to 0.05 rad) and the average lateral ZMP error
//! (12.8 mm) is above the run without the ankle admittance (11.8 mm).
//!
//! Why the filter (seed 002 §7 item 12): with a stiff floor and position servo the measured
//! moment answers the commanded tilt within one tick, `τ ≈ τ₀ − k θ`, so the unfiltered loop is
//! the discrete integrator `θ⁺ = θ − A k dt θ`, unstable at the Nyquist frequency (period 2 ticks,
//! the "≥ 1 kHz, instantaneous onset" oscillation) once `A k dt > 2`. The report's threshold
//! `A ≈ 0.001` then means `k ≈ 2·10⁶ N·m/rad` [derived].
//!
//! Why the lead (our design): a first-order filter at `ω_c` alone turns the loop into
//! `s² + ω_c s + A k ω_c` (continuous approximation): `ω_n = √(A k ω_c)`,
//! `ζ = ½ √(ω_c / (A k))`. It is stable far beyond `A k dt = 2`, but lightly damped: at
//! `A = 0.01`, `k = 10⁶`, 10 Hz, `ζ ≈ 0.04` at ≈ 130 Hz, and a lower cutoff is *less* damped.
//! Any kick that drives the CoP to a sole edge (where the moment saturates) then sustains a
//! ≈ 100 Hz limit cycle between the edges (the former `tests/stabilizer.rs` failure at 0.01,
//! in roll). Letting a fraction `β` of the raw rate bypass the filter,
//! `θ̇ = β θ̇_raw + (1 − β) LPF(θ̇_raw)`, i.e. the lag-lead `(β s + ω_c)/(s + ω_c)` with its zero
//! at `ω_c/β`, keeps the integral gain `A` and gives `s² + (ω_c + β A k) s + A k ω_c`:
//! `ζ = (ω_c + β A k) / (2 √(A k ω_c))`. The bypass is an unfiltered integrator of gain
//! `β A`, so the Nyquist bound becomes `β A k dt < 2` (exact discrete eigenvalues, 10 Hz, 1 kHz,
//! `β = 0.05`: `A k dt` = 0.035 / 0.35 / 3.5 / 10 / 20 give `ζ` ≈ 0.69 / 0.27 / 0.25 / 0.39 / 0.44,
//! unstable at 50). The default `β = 0.05` covers `A = 0.01` up to `k ≈ 2·10⁶ N·m/rad` (the
//! report's implied floor) and `A = 0.001` up to `2·10⁷`. The corps simulator's floor is far
//! softer: a 4·10⁷ N/m³ penalty contact on a 0.21 × 0.13 m sole has
//! `k = 4·10⁷ · b a³/12 ≈ 4·10³ N·m/rad` in pitch (1.5·10³ in roll), 10× that for the stiff
//! contact some scenarios use, where `A = 0.01` gives `A k dt ≤ 0.04` and the loop is
//! well damped either way. The clamp bounds what remains.

use super::contact::{Sole, Wrench};
use nalgebra::{UnitQuaternion, Vector2};

/// Settings of [`AnkleAdmittance`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AnkleAdmittanceSettings {
    /// `A` [rad/(N·m·s)]. Default 0.001: the reference script's default and the largest value
    /// the report found stable without a filter (seed 002 §4.10, R L928); 0.01 is the
    /// "expected" value (R L857).
    pub gain: f64,
    /// Clamp of the angular-velocity command [rad/s]. Default 0.1 (seed 002 §4.10, R L969).
    pub max_velocity: f64,
    /// Cutoff of the first-order low-pass filter on the command [Hz]; `f64::INFINITY`
    /// disables it. The report gives none (seed 002 §4.10, §11); default 10 Hz (module docs).
    pub filter_cutoff_hz: f64,
    /// Fraction `β` ∈ [0, 1] of the raw rate that bypasses the filter (the lead, module docs):
    /// 0 = filter only, 1 = no filter. Default 0.05 (our design, module docs).
    pub lead_fraction: f64,
    /// Clamp of each offset angle [rad]. Default 10° (seed 002 R L1023: such stabilizers aim
    /// at slopes up to 10°).
    pub max_offset: f64,
    /// Leak time constant of the offset when the foot is unloaded [s]. Default 0.1 s (our
    /// choice: the offset is gone, e^-8, within a 0.8 s swing, seed 000 §4.2 / anchors §4.4).
    pub leak_time_constant: f64,
    /// Normal force below which the foot counts as unloaded [N]. Default 15 (the distribution's
    /// minimum pressure, seed 002 §4.9).
    pub min_normal_force: f64,
}

impl Default for AnkleAdmittanceSettings {
    fn default() -> Self {
        Self {
            gain: 0.001,
            max_velocity: 0.1,
            filter_cutoff_hz: 10.0,
            lead_fraction: 0.05,
            max_offset: 10f64.to_radians(),
            leak_time_constant: 0.1,
            min_normal_force: 15.0,
        }
    }
}

/// Command of one ankle.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct AnkleCommand {
    /// (roll, pitch) offset of the foot orientation reference in the sole frame [rad].
    pub offset: Vector2<f64>,
    /// Filtered and clamped (roll, pitch) rate [rad/s].
    pub velocity: Vector2<f64>,
}

impl AnkleCommand {
    /// The offset as a rotation, `R_x(roll) R_y(pitch)`, to right-multiply the foot's
    /// reference orientation.
    pub fn rotation(&self) -> UnitQuaternion<f64> {
        UnitQuaternion::from_axis_angle(&nalgebra::Vector3::x_axis(), self.offset.x)
            * UnitQuaternion::from_axis_angle(&nalgebra::Vector3::y_axis(), self.offset.y)
    }
}

/// Admittance of one ankle.
#[derive(Clone, Debug)]
pub struct AnkleAdmittance {
    pub settings: AnkleAdmittanceSettings,
    filtered: Vector2<f64>,
    command: AnkleCommand,
}

impl AnkleAdmittance {
    pub fn new(settings: AnkleAdmittanceSettings) -> Self {
        Self {
            settings,
            filtered: Vector2::zeros(),
            command: AnkleCommand::default(),
        }
    }

    pub fn reset(&mut self) {
        self.filtered = Vector2::zeros();
        self.command = AnkleCommand::default();
    }

    pub fn command(&self) -> AnkleCommand {
        self.command
    }

    /// Moment error `(τ_mes − p_d × f_mes)_{x,y}` in the sole frame [N·m].
    pub fn moment_error(measured: &Wrench, desired_cop: &Vector2<f64>) -> Vector2<f64> {
        let f = &measured.force;
        // p_d × f with p_d = (x, y, 0): (y f_z, −x f_z, x f_y − y f_x).
        Vector2::new(
            measured.torque.x - desired_cop.y * f.z,
            measured.torque.y + desired_cop.x * f.z,
        )
    }

    /// One tick. `in_contact` is the contact phase's view of this foot; `desired_cop` is
    /// clamped into the sole.
    pub fn update(
        &mut self,
        measured: &Wrench,
        desired_cop: &Vector2<f64>,
        in_contact: bool,
        sole: &Sole,
        dt: f64,
    ) -> AnkleCommand {
        let s = &self.settings;
        let loaded = in_contact && measured.force.z >= s.min_normal_force;
        if loaded {
            let raw = Self::moment_error(measured, &sole.clamp_cop(desired_cop)) * s.gain;
            let alpha = if s.filter_cutoff_hz.is_finite() {
                1.0 - (-2.0 * std::f64::consts::PI * s.filter_cutoff_hz * dt).exp()
            } else {
                1.0
            };
            self.filtered += (raw - self.filtered) * alpha;
            let beta = s.lead_fraction;
            let v = (raw * beta + self.filtered * (1.0 - beta))
                .map(|x| x.clamp(-s.max_velocity, s.max_velocity));
            self.command.velocity = v;
            self.command.offset =
                (self.command.offset + v * dt).map(|x| x.clamp(-s.max_offset, s.max_offset));
        } else {
            self.filtered = Vector2::zeros();
            self.command.velocity = Vector2::zeros();
            self.command.offset *= (-dt / s.leak_time_constant).exp();
        }
        self.command
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Vector3;

    /// Foot on a floor whose moment answers the tilt (one tick later): τ = τ₀ − k θ, f_z fixed.
    fn run(
        settings: AnkleAdmittanceSettings,
        k: f64,
        ticks: usize,
    ) -> (AnkleAdmittance, Vec<Vector2<f64>>) {
        let sole = Sole::new(0.10, 0.06, 0.107);
        let fz = 450.0;
        // Body loads the foot at CoP (−2 cm, +1 cm); the distribution wants (+1 cm, 0).
        let tau0 = Vector3::new(0.01 * fz, 0.02 * fz, 0.0);
        let target = Vector2::new(0.01, 0.0);
        let mut a = AnkleAdmittance::new(settings);
        let mut cops = Vec::with_capacity(ticks);
        let mut theta = Vector2::zeros();
        for _ in 0..ticks {
            // τ_x = p_y f_z falls with roll; τ_y = −p_x f_z falls with pitch.
            let w = Wrench::new(
                Vector3::new(0.0, 0.0, fz),
                tau0 - Vector3::new(k * theta.x, k * theta.y, 0.0),
            );
            let w = Wrench::new(
                w.force,
                Vector3::new(
                    w.torque.x.clamp(-0.06 * fz, 0.06 * fz),
                    w.torque.y.clamp(-0.1 * fz, 0.1 * fz),
                    0.0,
                ),
            );
            cops.push(w.cop());
            theta = a.update(&w, &target, true, &sole, 1e-3).offset;
        }
        (a, cops)
    }

    #[test]
    fn the_cop_converges_to_its_target() {
        // Soft floor (k = 3200 N·m/rad: a 4·10⁷ N/m³ penalty contact on a 0.2 × 0.12 sole).
        let s = AnkleAdmittanceSettings {
            gain: 0.01,
            ..Default::default()
        };
        let (_, cops) = run(s, 3200.0, 5000);
        let last = cops.last().unwrap();
        println!("soft floor: final cop {last:?}");
        assert!((last - Vector2::new(0.01, 0.0)).norm() < 1e-4, "{last}");
    }

    #[test]
    fn velocity_is_clamped_and_the_offset_leaks_when_unloaded() {
        let sole = Sole::new(0.10, 0.06, 0.107);
        let mut a = AnkleAdmittance::new(AnkleAdmittanceSettings {
            gain: 1.0,
            filter_cutoff_hz: f64::INFINITY,
            ..Default::default()
        });
        let w = Wrench::new(
            Vector3::new(0.0, 0.0, 400.0),
            Vector3::new(50.0, -50.0, 0.0),
        );
        let mut c = AnkleCommand::default();
        for _ in 0..100 {
            c = a.update(&w, &Vector2::zeros(), true, &sole, 1e-3);
        }
        assert_eq!(c.velocity, Vector2::new(0.1, -0.1));
        assert!((c.offset - Vector2::new(0.01, -0.01)).norm() < 1e-12);
        // Lifted: 1 s of leak at 0.1 s.
        for _ in 0..1000 {
            c = a.update(&Wrench::default(), &Vector2::zeros(), true, &sole, 1e-3);
        }
        assert!(
            c.offset.norm() < 0.0142 * (-10f64).exp() * 1.01,
            "{}",
            c.offset
        );
        assert_eq!(c.velocity, Vector2::zeros());
    }

    #[test]
    fn stiff_floor_chatters_without_the_filter_and_settles_with_it() {
        // k = 10⁶ N·m/rad, A = 0.01: A k dt = 10 > 2.
        let stiff = 1e6;
        let unfiltered = AnkleAdmittanceSettings {
            gain: 0.01,
            filter_cutoff_hz: f64::INFINITY,
            ..Default::default()
        };
        let (_, cops) = run(unfiltered, stiff, 3000);
        let tail = &cops[2000..];
        let flips = tail
            .windows(3)
            .filter(|w| (w[1].x - w[0].x) * (w[2].x - w[1].x) < 0.0)
            .count();
        let amp = tail.iter().map(|c| c.x).fold(f64::NEG_INFINITY, f64::max)
            - tail.iter().map(|c| c.x).fold(f64::INFINITY, f64::min);
        println!("unfiltered: {flips} direction changes in 1000 ticks, p-p {amp:.4} m");
        assert!(flips > 900 && amp > 0.01);
        let (_, cops) = run(
            AnkleAdmittanceSettings {
                gain: 0.01,
                ..Default::default()
            },
            stiff,
            3000,
        );
        let tail = &cops[2000..];
        let amp = tail.iter().map(|c| c.x).fold(f64::NEG_INFINITY, f64::max)
            - tail.iter().map(|c| c.x).fold(f64::INFINITY, f64::min);
        let last = cops.last().unwrap();
        println!("filtered: p-p {amp:.2e} m, final cop {last:?}");
        assert!(amp < 1e-6);
        assert!((last - Vector2::new(0.01, 0.0)).norm() < 1e-6);
    }
}
