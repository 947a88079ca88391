//! Balance stabilizer for position-controlled robots (seed 000 §3.3–3.4; seed 002 §4.7–4.11):
//! a DCM PI controller gives the desired ZMP ([`dcm`]), a wrench-distribution QP splits the
//! corresponding net wrench between the feet ([`wrench_distribution`]), a CoM admittance
//! turns the ZMP error into a CoM reference for the whole-body controller
//! ([`com_admittance`]), and per-foot ankle admittances turn each foot's CoP error into a
//! roll/pitch offset of its orientation reference ([`ankle_admittance`]).
//!
//! One [`Stabilizer::tick`] follows the signal flow of seed 002 §3.2: `ξ, ξ_ref → p*`
//! (clamped into the support polygon) `→` net wrench `(m ω²(c − p*), m(g + c̈_ref,z))` with
//! zero moment about `p*` (seed 002 Eq 28–29) `→` distribution (its ZMP feeds the CoM
//! admittance, seed 002 §4.8) `→` ankle admittances. Nothing allocates after [`Stabilizer::new`].
//!
//! # Sway damping (our addition)
//!
//! Eq 2.30–2.31 assume a stiff position-controlled robot whose CoM follows the CoM reference
//! `u` handed to the whole-body controller. A servo-held robot is an inverted pendulum on a
//! spring instead: `c̈ = ω²c − K_s(c − u) − D ċ`, with the measured ZMP `p = c − c̈/ω²`. In
//! the corps simulator TALOS sways at Ω ≈ 8.4 rad/s (1.33 Hz) with ζ ≈ 0.013 (≈ 8 % amplitude
//! loss per cycle, `ik_position_stand` without stabilizer), i.e. `K_s = Ω² + ω² ≈ 81 s⁻²`:
//! the servos' damping is set on each joint's own apparent inertia, not the whole body's.
//! Above Ω the response of `c` to `u` turns by 180°, so the DCM velocity term
//! `(1 + K_P/ω) ċ/ω` of `p*`, integrated twice by the admittance `δ̈ = K_adm(p − p*)`, feeds
//! `u` in phase with `ċ`: negative damping. Linearized (this model, Table 4.3 IK gains
//! K_P 8, K_I 1, K_Z 1, K_adm 15, a 10 ms IK lag), the sway poles are +3.4 ± 14.6j s⁻¹;
//! every `K_adm > 0` is unstable (K_adm 5: +1.9 ± 10.7j; K_adm 1: +0.5 ± 8.8j), and a stiffer
//! spring at the same ζ is worse, not better (Ω = 5 Hz: +8.4 ± 48j), as the IK lag adds phase. Subtracting `g_d (ċ − ċ*)` from the CoM reference adds the missing
//! damping (`K_s g_d` on the sway) without touching the LIPM design: on a robot whose CoM
//! follows its reference `ċ = ċ*` and the term is zero. Same model: `g_d = 0.05 s` gives
//! −2.2 ± 15.6j, `g_d = 0.1 s` gives −9.7 ± 14.2j (ζ ≈ 0.57), the DCM poles stay at
//! −2.8 ± 1.8j; hence the default 0.1 s ≈ `2 · 0.5 · Ω / K_s`.

pub mod ankle_admittance;
pub mod com_admittance;
pub mod contact;
pub mod dcm;
pub mod wrench_distribution;

pub use ankle_admittance::{AnkleAdmittance, AnkleAdmittanceSettings, AnkleCommand};
pub use com_admittance::{ComAdmittance, ComAdmittanceSettings, ComReference};
pub use contact::{
    zmp_from_feet, zmp_of, ContactPhase, Sole, Wrench, DEFAULT_FRICTION, LEFT, RIGHT,
};
pub use corps_model::support::ConvexPolygon;
pub use dcm::{DcmController, DcmGains, DcmOutput};
pub use wrench_distribution::{Distribution, DistributionSettings, WrenchDistribution};

use crate::error::{ControlError, Result};
use nalgebra::{Isometry3, Vector2, Vector3};

/// Settings of the [`Stabilizer`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StabilizerSettings {
    /// Total mass [kg], from the one shared robot model (seed 002 §7 item 6).
    pub mass: f64,
    /// Gravity [m/s²]. Default 9.81 (seed 000 §3.3).
    pub gravity: f64,
    /// Control period [s]. Default 1 ms (seed 002 §2: 1 kHz).
    pub dt: f64,
    pub dcm: DcmGains,
    pub com_admittance: ComAdmittanceSettings,
    pub distribution: DistributionSettings,
    pub ankle: AnkleAdmittanceSettings,
    pub sole: Sole,
    /// Sway damping `g_d` [s]: the CoM reference's position becomes `c* − g_d (ċ − ċ*)`
    /// (x, y; `ċ` measured, `c*`, `ċ*` the admittance's output). Default 0.1 s (our addition,
    /// see "Sway damping" in the module docs); 0 gives seed 000 Eq 2.30–2.31 alone.
    pub sway_damping: f64,
    /// How the sway damping offset `d = −g_d (ċ − ċ*)` reaches the CoM reference. `None`
    /// (default): added to the position only, for a whole-body controller that tracks the CoM
    /// position directly (the IK). `Some(ω_f)` [rad/s]: `d` goes through a critically damped
    /// second-order low-pass at `ω_f` whose output, velocity and acceleration are added to
    /// the reference's position, velocity and acceleration, for a controller whose CoM task
    /// works at the acceleration level on its own state (TSID in position mode): there a
    /// position-only offset is followed through the CoM task's PD alone (Table 4.3 TSID-position
    /// Kp 1000, Kd 300: poles −3.4 and −297 s⁻¹), i.e. at the sway frequency it arrives ≈ 70°
    /// late at a third of its size and no longer damps (see "Sway damping" above).
    pub sway_damping_filter: Option<f64>,
}

impl StabilizerSettings {
    /// The settings for a robot of `mass` kg standing on `sole`s (both from its
    /// description), with the documents' defaults for everything else.
    pub fn new(mass: f64, sole: Sole) -> Self {
        Self {
            mass,
            gravity: corps_model::STANDARD_GRAVITY,
            dt: 1e-3,
            dcm: DcmGains::default(),
            com_admittance: ComAdmittanceSettings {
                max_offset: sole.half_length / 2.0,
                ..ComAdmittanceSettings::default()
            },
            distribution: DistributionSettings::default(),
            ankle: AnkleAdmittanceSettings::default(),
            sole,
            sway_damping: 0.1,
            sway_damping_filter: None,
        }
    }
}

/// Inputs of one tick (world frame unless stated).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StabilizerInput {
    /// CoM reference position, velocity, acceleration (from the pattern generator).
    pub com_ref: Vector3<f64>,
    pub com_vel_ref: Vector3<f64>,
    pub com_acc_ref: Vector3<f64>,
    /// ZMP reference `p_ref` (x, y).
    pub zmp_ref: Vector2<f64>,
    /// Measured (estimated) CoM and CoM velocity; the DCM is `c + ċ/ω`.
    pub com: Vector3<f64>,
    pub com_vel: Vector3<f64>,
    /// Measured ZMP (e.g. [`zmp_from_feet`] of the F/T wrenches).
    pub zmp: Vector2<f64>,
    /// Sole frames (origin on the sole surface, z = contact normal), left then right.
    pub feet: [Isometry3<f64>; 2],
    /// Measured contact wrenches, ground on foot, in each sole frame about its origin.
    pub foot_wrenches: [Wrench; 2],
    pub phase: ContactPhase,
}

/// Outputs of one tick.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StabilizerOutput {
    /// CoM reference for the whole-body controller's CoM task.
    pub com: ComReference,
    /// Desired ZMP `p*` of the DCM controller (inside the support polygon).
    pub zmp_des: Vector2<f64>,
    /// ZMP of the distributed foot wrenches (what the CoM admittance tracks).
    pub zmp_distributed: Vector2<f64>,
    /// Measured and reference DCM (x, y) and ω.
    pub dcm: Vector2<f64>,
    pub dcm_ref: Vector2<f64>,
    pub omega: f64,
    /// Desired per-foot wrenches (sole frame, about the sole origin) and CoPs (sole frame).
    pub foot_wrenches: [Wrench; 2],
    pub foot_cops: [Vector2<f64>; 2],
    /// Per-foot ankle orientation offsets (roll, pitch) and rates.
    pub ankle: [AnkleCommand; 2],
    /// Support polygon used for the clamp.
    pub support: ConvexPolygon,
}

/// The stabilizer: DCM PI + wrench distribution + CoM admittance + ankle admittances.
#[derive(Clone, Debug)]
pub struct Stabilizer {
    pub settings: StabilizerSettings,
    dcm: DcmController,
    distribution: WrenchDistribution,
    com: ComAdmittance,
    ankles: [AnkleAdmittance; 2],
    /// State of the sway damping filter (x, y): offset and its rate.
    sway: Vector2<f64>,
    sway_rate: Vector2<f64>,
}

fn check(name: &str, ok: bool, reason: &str) -> Result<()> {
    if ok {
        Ok(())
    } else {
        Err(ControlError::Config {
            name: name.into(),
            reason: reason.into(),
        })
    }
}

impl Stabilizer {
    pub fn new(settings: StabilizerSettings) -> Result<Self> {
        let s = &settings;
        let pos = |x: f64| x.is_finite() && x > 0.0;
        let nonneg = |x: f64| !x.is_nan() && x >= 0.0;
        check("mass", pos(s.mass), "must be positive")?;
        check("gravity", pos(s.gravity), "must be positive")?;
        check("dt", pos(s.dt), "must be positive")?;
        check(
            "dcm gains",
            s.dcm.kp.is_finite()
                && s.dcm.ki.is_finite()
                && s.dcm.kz.is_finite()
                && s.dcm.kp >= 0.0
                && s.dcm.ki >= 0.0
                && s.dcm.kz >= 0.0,
            "must be finite and ≥ 0",
        )?;
        check(
            "dcm integral",
            pos(s.dcm.integral_time_constant) || s.dcm.integral_time_constant == f64::INFINITY,
            "time constant must be > 0",
        )?;
        check(
            "dcm integral limit",
            nonneg(s.dcm.integral_limit),
            "must be ≥ 0",
        )?;
        check(
            "com admittance",
            nonneg(s.com_admittance.gain) && nonneg(s.com_admittance.max_offset),
            "must be ≥ 0",
        )?;
        check(
            "sway damping",
            nonneg(s.sway_damping) && s.sway_damping.is_finite(),
            "must be finite and ≥ 0",
        )?;
        check(
            "sway damping filter",
            s.sway_damping_filter.is_none_or(pos),
            "must be positive",
        )?;
        let d = &s.distribution;
        check(
            "distribution weights",
            pos(d.weight_net_wrench)
                && pos(d.weight_ankle)
                && nonneg(d.weight_ratio)
                && d.ankle_component_weights.iter().all(|w| pos(*w)),
            "must be positive",
        )?;
        check(
            "min normal force",
            nonneg(d.min_normal_force) && d.min_normal_force.is_finite(),
            "must be finite and ≥ 0",
        )?;
        check(
            "sole",
            pos(s.sole.half_length)
                && pos(s.sole.half_width)
                && pos(s.sole.friction)
                && nonneg(s.sole.ankle_height),
            "sizes and friction must be positive",
        )?;
        let a = &s.ankle;
        check(
            "ankle",
            nonneg(a.gain)
                && nonneg(a.max_velocity)
                && nonneg(a.max_offset)
                && pos(a.leak_time_constant)
                && (0.0..=1.0).contains(&a.lead_fraction)
                && (pos(a.filter_cutoff_hz) || a.filter_cutoff_hz == f64::INFINITY),
            "gains ≥ 0, cutoff and leak > 0, lead fraction in [0, 1]",
        )?;
        Ok(Self {
            settings,
            dcm: DcmController::new(settings.dcm),
            distribution: WrenchDistribution::new(settings.distribution, settings.sole),
            com: ComAdmittance::new(settings.com_admittance),
            ankles: [
                AnkleAdmittance::new(settings.ankle),
                AnkleAdmittance::new(settings.ankle),
            ],
            sway: Vector2::zeros(),
            sway_rate: Vector2::zeros(),
        })
    }

    /// Zero the DCM integral, the CoM offset and the ankle offsets.
    pub fn reset(&mut self) {
        self.dcm.reset();
        self.com.reset();
        self.sway = Vector2::zeros();
        self.sway_rate = Vector2::zeros();
        for a in &mut self.ankles {
            a.reset();
        }
    }

    /// Current CoM offset `c* − c_ref` (x, y).
    pub fn com_offset(&self) -> Vector2<f64> {
        self.com.offset()
    }

    /// DCM integral.
    pub fn dcm_integral(&self) -> Vector2<f64> {
        self.dcm.integral()
    }

    /// One control tick.
    pub fn tick(&mut self, i: &StabilizerInput) -> Result<StabilizerOutput> {
        let finite = i
            .com_ref
            .iter()
            .chain(i.com_vel_ref.iter())
            .chain(i.com_acc_ref.iter())
            .chain(i.zmp_ref.iter())
            .chain(i.com.iter())
            .chain(i.com_vel.iter())
            .chain(i.zmp.iter())
            .chain(
                i.foot_wrenches
                    .iter()
                    .flat_map(|w| w.force.iter().chain(w.torque.iter())),
            )
            .all(|x| x.is_finite())
            && i.feet.iter().all(|f| {
                f.translation
                    .vector
                    .iter()
                    .chain(f.rotation.coords.iter())
                    .all(|x| x.is_finite())
            });
        if !finite {
            return Err(ControlError::NonFinite("stabilizer input"));
        }
        let s = self.settings;
        // Sync settings edited through the public field.
        self.dcm.gains = s.dcm;
        self.com.settings = s.com_admittance;
        self.distribution.settings = s.distribution;
        self.distribution.sole = s.sole;
        for a in &mut self.ankles {
            a.settings = s.ankle;
        }

        // Support: soles in contact; ground height = their mean height.
        let mut corners = [Vector2::zeros(); 8];
        let (mut n, mut ground, mut m) = (0, 0.0, 0.0);
        for f in 0..2 {
            if i.phase.in_contact(f) {
                corners[n..n + 4].copy_from_slice(&s.sole.corners(&i.feet[f]));
                n += 4;
                ground += i.feet[f].translation.vector.z;
                m += 1.0;
            }
        }
        let support = ConvexPolygon::hull(&corners[..n]);
        let ground = ground / m;
        let height = i.com_ref.z - ground;
        if height <= 1e-3 {
            return Err(ControlError::NonFinite(
                "ω: CoM reference not above the support",
            ));
        }
        // ω = √(g / c_z) (seed 000 Eq 2.23–2.27).
        let omega = (s.gravity / height).sqrt();
        let dcm_ref = i.com_ref.xy() + i.com_vel_ref.xy() / omega;
        let dcm = i.com.xy() + i.com_vel.xy() / omega;
        let d = self
            .dcm
            .update(omega, &dcm_ref, &dcm, &i.zmp_ref, &i.zmp, &support, s.dt);

        // Net wrench of the LIPM at p* (seed 002 Eq 28–29): zero moment about p*.
        let point = Vector3::new(d.zmp.x, d.zmp.y, ground);
        let acc = (i.com.xy() - d.zmp) * (omega * omega);
        let desired = Wrench::new(
            Vector3::new(
                s.mass * acc.x,
                s.mass * acc.y,
                s.mass * (s.gravity + i.com_acc_ref.z),
            ),
            Vector3::zeros(),
        );
        let dist = self
            .distribution
            .solve(&desired, &point, &i.feet, i.phase)?;

        let mut com = self.com.update(
            &i.com_ref,
            &i.com_vel_ref,
            &i.com_acc_ref,
            &i.zmp,
            &dist.zmp,
            s.dt,
        );
        // Sway damping (module docs): zero when the measured CoM moves with its reference.
        for k in 0..2 {
            let d = -s.sway_damping * (i.com_vel[k] - com.vel[k]);
            match s.sway_damping_filter {
                None => com.pos[k] += d,
                Some(w) => {
                    let acc = w * w * (d - self.sway[k]) - 2.0 * w * self.sway_rate[k];
                    self.sway_rate[k] += acc * s.dt;
                    self.sway[k] += self.sway_rate[k] * s.dt;
                    com.pos[k] += self.sway[k];
                    com.vel[k] += self.sway_rate[k];
                    com.acc[k] += acc;
                }
            }
        }
        let mut ankle = [AnkleCommand::default(); 2];
        #[allow(clippy::needless_range_loop)] // per-foot arrays in step
        for f in 0..2 {
            ankle[f] = self.ankles[f].update(
                &i.foot_wrenches[f],
                &dist.cops[f],
                i.phase.in_contact(f),
                &s.sole,
                s.dt,
            );
        }
        Ok(StabilizerOutput {
            com,
            zmp_des: d.zmp,
            zmp_distributed: dist.zmp,
            dcm,
            dcm_ref,
            omega,
            foot_wrenches: dist.wrenches,
            foot_cops: dist.cops,
            ankle,
            support,
        })
    }
}
