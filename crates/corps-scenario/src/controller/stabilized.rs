//! A position-mode controller behind the balance stabilizer, as seed 000's controllers A and B
//! run (Fig 4.2, §3.4): pattern generator → DCM PI → CoM admittance → whole-body controller.
//! The stabilizer reads the measured CoM, CoM velocity, ZMP and foot wrenches and rewrites the
//! CoM target; the feet targets get the ankle admittance's roll/pitch offsets when its gain
//! is not zero (on every tick, swing included, so that the foot reference stays continuous
//! while the offset leaks out). The stabilizer's sway damping keeps its default
//! ([`StabilizerSettings::sway_damping`], 0.1 s): without it the loop excites the servo-held
//! robot's 1.3 Hz sway (see the `corps_control::stabilizer` module docs). For TSID in position
//! mode the damping offset comes filtered with its velocity and acceleration ([`ComTracking`]).

use super::{Measured, WholeBodyController};
use crate::gains::StabilizerGains;
use crate::targets::Targets;
use corps_control::stabilizer::{
    ContactPhase, Sole, Stabilizer, StabilizerInput, StabilizerOutput, StabilizerSettings,
};
use corps_control::{ControlError, FallbackReason};
use corps_sim::Command;
use nalgebra::{Vector2, Vector3};

pub struct Stabilized<C> {
    inner: C,
    stabilizer: Stabilizer,
    targets: Option<Targets>,
    /// The stabilizer's output of the last tick (None when it failed).
    output: Option<StabilizerOutput>,
    ankles: bool,
    gravity: f64,
}

/// How a whole-body controller behind the stabilizer tracks the CoM reference.
pub trait ComTracking {
    /// `Some(ω_f)` when the CoM task works at the acceleration level on the controller's own
    /// state, so the stabilizer's sway damping must come with its velocity and acceleration
    /// ([`StabilizerSettings::sway_damping_filter`]); `None` when the CoM position is tracked
    /// directly.
    fn sway_damping_filter(&self) -> Option<f64>;
}

impl ComTracking for super::IkController {
    fn sway_damping_filter(&self) -> Option<f64> {
        None
    }
}

/// Bandwidth of the sway damping filter for TSID in position mode [rad/s]: about five times
/// the servo-held sway's 8.4 rad/s (module docs of `corps_control::stabilizer`), i.e. ≈ 24° of
/// lag at the sway. The filter's acceleration feeds `ω_f² g_d ċ` of the measured CoM velocity
/// straight into the QP's CoM acceleration, which bounds it from above (120 rad/s made the
/// standing robot sway 9 mm; 30 and 60 rad/s held it within 1 mm).
pub const TSID_SWAY_DAMPING_FILTER: f64 = 40.0;

impl ComTracking for super::TsidController {
    /// TSID's CoM task is `c̈ = c̈* + K_p (c* − c) + K_d (ċ* − ċ)` on the integrated state:
    /// a position-only offset reaches that state through the PD alone (Kp 1000, Kd 300: a
    /// 0.3 s pole), too late to damp the sway.
    fn sway_damping_filter(&self) -> Option<f64> {
        Some(TSID_SWAY_DAMPING_FILTER)
    }
}

/// `inner`, behind the balance stabilizer when its gains file has one (`gains`).
pub fn behind_stabilizer<C: WholeBodyController + ComTracking + 'static>(
    inner: C,
    gains: Option<&StabilizerGains>,
    foot: &corps_robot::Foot,
    mass: f64,
    dt: f64,
) -> crate::Result<Box<dyn WholeBodyController>> {
    Ok(match gains {
        Some(g) => Box::new(Stabilized::new(inner, g, foot, mass, dt)?),
        None => Box::new(inner),
    })
}

impl<C: WholeBodyController + ComTracking> Stabilized<C> {
    /// `inner` behind a stabilizer with gains `g` for a robot of `mass` kg whose soles are
    /// `foot`'s, at period `dt`.
    pub fn new(
        inner: C,
        g: &StabilizerGains,
        foot: &corps_robot::Foot,
        mass: f64,
        dt: f64,
    ) -> crate::Result<Self> {
        let s = foot.sole;
        let sole = Sole::new(
            g.sole_half_length.unwrap_or(s.front.min(s.back)),
            g.sole_half_width.unwrap_or(s.left.min(s.right)),
            foot.ankle_height,
        );
        let mut s = StabilizerSettings::new(mass, sole);
        s.dt = dt;
        s.dcm.kp = g.dcm_kp;
        s.dcm.ki = g.dcm_ki;
        s.dcm.kz = g.dcm_kz;
        s.com_admittance.gain = g.com_admittance;
        s.ankle.gain = g.ankle_gain;
        if let Some(d) = g.sway_damping {
            s.sway_damping = d;
        }
        s.sway_damping_filter = inner.sway_damping_filter();
        Ok(Self {
            inner,
            gravity: s.gravity,
            stabilizer: Stabilizer::new(s)?,
            targets: None,
            output: None,
            ankles: g.ankle_gain > 0.0,
        })
    }
}

impl<C: WholeBodyController + ComTracking> WholeBodyController for Stabilized<C> {
    fn tick(
        &mut self,
        t: f64,
        q: &[f64],
        v: &[f64],
        targets: &Targets,
        measured: &Measured,
    ) -> Option<FallbackReason> {
        // The controller's contacts, not the plan's support: the distribution unloads the
        // leaving foot on the same early-release schedule as the whole-body controller. (With
        // the plan's support phase instead, the IK 20 cm walk's ZMP error peaks went from
        // 62.6 / 58.4 to 83.6 / 80.2 mm, x / y, and the x average from 9.2 to 12.1 mm.)
        let phase = match (targets.feet[0].in_contact, targets.feet[1].in_contact) {
            (true, false) => ContactPhase::LeftSupport,
            (false, true) => ContactPhase::RightSupport,
            _ => ContactPhase::Double,
        };
        let [px, py] = targets.reference_zmp(targets.contact_ground(), self.gravity);
        let zmp_ref = Vector2::new(px, py);
        let c = &targets.com;
        let v3 = |x: &nalgebra::DVector<f64>| Vector3::new(x[0], x[1], x[2]);
        let input = StabilizerInput {
            com_ref: v3(&c.pos),
            com_vel_ref: v3(&c.vel),
            com_acc_ref: v3(&c.acc),
            zmp_ref,
            com: measured.com,
            com_vel: measured.com_velocity,
            zmp: measured.zmp.unwrap_or(zmp_ref),
            feet: measured.feet,
            foot_wrenches: measured.foot_wrenches,
            phase,
        };
        let out = match self.stabilizer.tick(&input) {
            Ok(out) => {
                self.output = Some(out);
                out
            }
            Err(e) => {
                self.output = None;
                // Track the unstabilized references this tick and say why.
                let r = self.inner.tick(t, q, v, targets, measured);
                return r.or(Some(FallbackReason::Controller(e)));
            }
        };
        let stabilized = self.targets.get_or_insert_with(|| targets.clone());
        stabilized.clone_from(targets);
        for k in 0..3 {
            stabilized.com.pos[k] = out.com.pos[k];
            stabilized.com.vel[k] = out.com.vel[k];
            stabilized.com.acc[k] = out.com.acc[k];
        }
        if self.ankles {
            // Every tick, in contact or not: the admittance leaks a released foot's offset to
            // zero itself (`AnkleAdmittanceSettings::leak_time_constant`), so the reference
            // stays continuous. Dropping the offset when the plan releases the foot — a
            // `release` (the double support) before lift-off, while that foot still carries
            // most of the weight — stepped the priority-0 foot task by the whole offset in one
            // tick: at gain 0.01 on the stick walk, (0.043, −0.026) rad at t = 4.530 s, the
            // tick the hierarchical QP turned infeasible (the robot then fell).
            for (foot, ankle) in stabilized.feet.iter_mut().zip(&out.ankle) {
                let r = ankle.rotation().to_rotation_matrix();
                let m = &mut foot.reference.placement;
                m.rotation *= r.matrix();
            }
        }
        let r = self.inner.tick(t, q, v, stabilized, measured);
        if r.is_none() && !out.com.pos.iter().all(|x| x.is_finite()) {
            return Some(FallbackReason::Controller(ControlError::NonFinite(
                "stabilized CoM",
            )));
        }
        r
    }

    fn command(&self) -> &Command {
        self.inner.command()
    }

    fn controller_com(&self) -> Vector3<f64> {
        self.inner.controller_com()
    }

    fn stabilizer_output(&self) -> Option<&StabilizerOutput> {
        self.output.as_ref()
    }

    fn report(&self) -> Vec<crate::metrics::ReportLine> {
        self.inner.report()
    }

    fn teleop_metrics(&self) -> Option<crate::metrics::TeleopMetrics> {
        self.inner.teleop_metrics()
    }

    fn tracked_targets(&self) -> Option<&Targets> {
        self.inner.tracked_targets()
    }

    fn channels(&self) -> Vec<&'static str> {
        self.inner.channels()
    }

    fn push_channels(&self, row: &mut Vec<f64>) {
        self.inner.push_channels(row)
    }
}
