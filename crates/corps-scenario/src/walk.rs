//! The walking motions of a run, sampled at the control period and anchored at the robot's
//! soles at the handover (plan x/y origin = the soles' midpoint, plan z = 0 = the soles'
//! height, feet yaw relative to their starting orientation):
//! - a footstep plan (corps-walk) turned by Kajita's preview control into CoM, ZMP and feet
//!   references ([`WalkSection`]); with `on_terrain` each footstep takes the height and tilt
//!   of the scenario's terrain under it (the tilted platforms);
//! - velocity commands (v_x, v_y, ω) that change at given times, turned into footsteps and CoM
//!   by the velocity-driven MPC of seed 002 §4.4, re-planned every control period
//!   ([`VelocitySection`]; steered live by [`crate::velocity_walk`]).

use crate::error::{Context, Result};
use crate::targets::{positive, FootTarget, Side, Targets};
use crate::velocity_walk::VelocityGenerator;
use corps_control::trajectories::MinJerk;
use corps_model::spatial::{Motion, Se3};
use corps_sim::Terrain;
use corps_walk::mpc::VelocityCommand;
use corps_walk::preview_control::PreviewParams;
use corps_walk::preview_walk::PreviewWalk;
use corps_walk::{
    Foot, FootPose, FootVelocity, FootstepPlan, Ground, Lipm, StepTiming, WalkingReference,
};
use nalgebra::DVector;
use nalgebra::Vector3;

/// `[motion] kind = "walk"`: the parameters of a straight walk or a staircase.
#[derive(Clone, Debug, PartialEq, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WalkSection {
    /// Number of steps before the closing step.
    pub steps: usize,
    /// Step length (m): each foot lands this far ahead of the previous footstep.
    pub step_length: f64,
    /// Step height (m): > 0 climbs stairs.
    #[serde(default)]
    pub step_height: f64,
    /// Footsteps on the terrain: each takes the height of the scenario's terrain under its
    /// sole centre and the tilt that lays the sole on it (then `step_height` must be 0).
    #[serde(default)]
    pub on_terrain: bool,
    /// Single- and double-support durations (s); default seed 000 §4.2: 0.9 / 0.115.
    #[serde(default = "single_support")]
    pub single_support: f64,
    #[serde(default = "double_support")]
    pub double_support: f64,
    /// Swing apex height (m), default 5 cm (issue: "height setting, default 5 cm").
    #[serde(default = "swing_height")]
    pub swing_height: f64,
    /// The foot that steps first.
    #[serde(default = "first_foot")]
    pub first: Side,
    /// The contact of a foot about to swing is released this long before lift-off (its force
    /// ramps to zero over the controller's contact transition); default: the double support.
    pub release: Option<f64>,
    /// CoM height above the soles while walking (m); default: the height at the handover. Long
    /// steps need it lower (the stance leg would otherwise reach full extension): the CoM
    /// moves there (min-jerk) while the robot stands before the plan starts.
    pub com_height: Option<f64>,
    /// Run the dynamic filter (seed 002 §2.2.2) on the plan before the run: a kinematic IK
    /// replay measures the whole body's ZMP and one preview-control pass corrects the CoM
    /// (`crate::dynamic_filter`). Default off.
    #[serde(default)]
    pub dynamic_filter: bool,
}

fn single_support() -> f64 {
    0.9
}
fn double_support() -> f64 {
    0.115
}
fn swing_height() -> f64 {
    0.05
}
fn first_foot() -> Side {
    Side::Right
}

impl WalkSection {
    pub fn check(&self) -> Result<(), String> {
        positive("single_support", self.single_support)?;
        positive("double_support", self.double_support)?;
        if !(self.step_length.is_finite() && self.step_height.is_finite()) {
            return Err("motion.step_length and step_height: must be finite".into());
        }
        if self.on_terrain && self.step_height != 0.0 {
            return Err(
                "motion.step_height: must be 0 with on_terrain (the terrain gives the heights)"
                    .into(),
            );
        }
        if !(self.swing_height >= 0.0 && self.swing_height.is_finite()) {
            return Err("motion.swing_height: must be ≥ 0".into());
        }
        check_release(self.release)?;
        if let Some(h) = self.com_height {
            if !(h > 0.0 && h.is_finite()) {
                return Err("motion.com_height: must be positive".into());
            }
        }
        Ok(())
    }
}

/// The longest early contact release (s): ten seconds is far beyond any step.
const MAX_RELEASE: f64 = 10.0;

fn check_release(release: Option<f64>) -> Result<(), String> {
    match release {
        Some(r) if !(0.0..=MAX_RELEASE).contains(&r) => Err(format!(
            "motion.release = {r}: must be between 0 and {MAX_RELEASE} s"
        )),
        _ => Ok(()),
    }
}

/// A velocity command from time `t` on (robot frame, REP-103: +y left, +ω counter-clockwise).
#[derive(Clone, Debug, PartialEq, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CommandAt {
    pub t: f64,
    pub vx: f64,
    #[serde(default)]
    pub vy: f64,
    #[serde(default)]
    pub yaw_rate: f64,
}

/// `[motion] kind = "velocity"`: velocity commands through the MPC pattern generator, with
/// seed 002's timing (single support 1.0 s, double support 0.2 s).
#[derive(Clone, Debug, PartialEq, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct VelocitySection {
    /// `[[motion.commands]]`, in time order; before the first, and after a zero command, the
    /// robot stands. Empty for a walk steered live ([`crate::run::ScenarioRun::steered`]).
    #[serde(default)]
    pub commands: Vec<CommandAt>,
    /// Early contact release before lift-off (s); default: the double support.
    pub release: Option<f64>,
}

impl VelocitySection {
    pub fn check(&self) -> Result<(), String> {
        let mut last = f64::NEG_INFINITY;
        for (k, c) in self.commands.iter().enumerate() {
            if ![c.t, c.vx, c.vy, c.yaw_rate].iter().all(|x| x.is_finite()) || c.t < last {
                return Err(format!(
                    "motion.commands[{k}]: values must be finite and times non-decreasing"
                ));
            }
            last = c.t;
        }
        check_release(self.release)
    }

    /// The command in force at `t`.
    pub fn at(&self, t: f64) -> VelocityCommand {
        self.commands
            .iter()
            .rev()
            .find(|c| c.t <= t)
            .map(|c| VelocityCommand::new(c.vx, c.vy, c.yaw_rate))
            .unwrap_or_default()
    }
}

/// The terrain seen from the plan's frame: x, y from the soles' midpoint at the handover,
/// heights from the ground under the starting soles (plan z = 0 is where the soles rest, a few
/// millimetres above the surface they stand on: the sole frame rests at that height above any
/// surface).
struct PlanGround<'a> {
    terrain: &'a Terrain,
    origin: Vector3<f64>,
    /// Mean height of the terrain under the starting soles.
    ground0: f64,
}

impl<'a> PlanGround<'a> {
    /// The terrain seen from the plan of a walk starting from the soles `feet0`.
    fn new(terrain: &'a Terrain, feet0: &[Se3; 2]) -> Result<Self> {
        let under = |p: &Se3| {
            let (z, _) = terrain
                .surface_at(p.translation.x, p.translation.y)
                .context("motion.on_terrain: no terrain under the starting feet")?;
            Ok::<_, crate::ScenarioError>(z)
        };
        let ground0 = (under(&feet0[0])? + under(&feet0[1])?) / 2.0;
        let origin = (feet0[0].translation + feet0[1].translation) / 2.0;
        Ok(Self {
            terrain,
            origin,
            ground0,
        })
    }
}

impl Ground for PlanGround<'_> {
    fn surface_at(&self, x: f64, y: f64) -> Option<(f64, Vector3<f64>)> {
        let o = self.origin;
        let (z, n) = self.terrain.surface_at(x + o.x, y + o.y)?;
        Some((z - self.ground0, n))
    }
}

/// The walk, sampled once per control period for the whole run.
pub struct WalkMotion {
    samples: Vec<WalkingReference>,
    /// Contact flags with the early release applied, per sample.
    contact: Vec<[bool; 2]>,
    /// The dynamic filter's correction per sample (empty without it).
    com_correction: Vec<[[f64; 2]; 2]>,
    frame: PlanFrame,
    /// When the plan starts (s after the handover): the preview window.
    pub lead_time: f64,
    /// The preview control that planned a footstep-list walk (None for the MPC's).
    preview: Option<PreviewParams>,
}

impl WalkMotion {
    /// Plans the walk from the soles `feet0` and the CoM `com0` (at rest), for `duration` s
    /// at period `dt`; with `on_terrain` the footsteps land on `terrain`.
    pub fn new(
        w: &WalkSection,
        feet0: &[Se3; 2],
        com0: &Vector3<f64>,
        dt: f64,
        duration: f64,
        terrain: &Terrain,
    ) -> Result<Self> {
        let (l, r) = (feet0[0].translation, feet0[1].translation);
        let origin = (l + r) / 2.0;
        let com_height = com0.z - origin.z;
        let feet_distance = (l - r).xy().norm();
        let first = match w.first {
            Side::Left => Foot::Left,
            Side::Right => Foot::Right,
        };
        let timing = StepTiming::new(w.single_support, w.double_support);
        let plan = FootstepPlan::stairs(
            w.steps,
            w.step_height,
            w.step_length,
            feet_distance,
            first,
            timing,
        )
        .context("motion: footstep plan")?
        .with_swing_height(w.swing_height);
        let plan = if w.on_terrain {
            plan.on_ground(&PlanGround::new(terrain, feet0)?)
                .context("motion.on_terrain: footsteps on the terrain")?
        } else {
            plan
        };
        let walking_height = w.com_height.unwrap_or(com_height);
        let mut params = PreviewParams::kajita2003();
        params.period = dt;
        params.lipm =
            Lipm::new(walking_height, corps_walk::lipm::GRAVITY).context("motion: LIPM")?;
        params.horizon = (1.6 / dt).round() as usize;
        let mut walk = PreviewWalk::new(plan, params)
            .context("motion: preview control")?
            .starting_at(com0.x - origin.x, com0.y - origin.y);
        let lead_time = walk.lead_time();
        let n = (duration / dt).round() as usize + 1;
        let mut samples = Vec::with_capacity(n);
        // From the starting height to the walking height (min-jerk) during the lead time.
        let lower = MinJerk {
            start: DVector::from_element(1, com_height - walking_height),
            end: DVector::zeros(1),
            t0: 0.0,
            duration: lead_time,
        };
        for k in 0..n {
            let mut r = walk.step().context("motion: preview control")?;
            let dz = lower.sample(k as f64 * dt);
            r.com.z += dz.pos[0];
            r.com_vel.z += dz.vel[0];
            r.com_acc.z += dz.acc[0];
            samples.push(r);
        }
        let release = w.release.unwrap_or(w.double_support);
        let mut motion = Self::from_samples(samples, release, dt, feet0, lead_time);
        motion.preview = Some(params);
        Ok(motion)
    }

    /// The preview control's parameters (period, LIPM, horizon) of a footstep-list walk.
    pub fn preview_params(&self) -> Option<&PreviewParams> {
        self.preview.as_ref()
    }

    /// Runs the MPC on the commands of `v` for `duration` s, re-planning every `dt`, from the
    /// soles `feet0` with the CoM at height `com_height` above them.
    pub fn velocity(
        robot: &corps_robot::Robot,
        v: &VelocitySection,
        feet0: &[Se3; 2],
        com_height: f64,
        dt: f64,
        duration: f64,
    ) -> Result<Self> {
        let mut generator =
            VelocityGenerator::new(robot, Box::new(v.clone()), feet0, com_height, dt)?;
        let release = v.release.unwrap_or(generator.double_support());
        let n = (duration / dt).round() as usize + 1;
        let mut samples = Vec::with_capacity(n);
        for _ in 0..n {
            let t = generator.next_time();
            let r = generator
                .next()
                .with_context(|| format!("motion: MPC at t = {t:.3} s"))?;
            samples.push(r);
        }
        Ok(Self::from_samples(samples, release, dt, feet0, 0.0))
    }

    /// The motion from references sampled every `dt` from the handover.
    fn from_samples(
        samples: Vec<WalkingReference>,
        release: f64,
        dt: f64,
        feet0: &[Se3; 2],
        lead_time: f64,
    ) -> Self {
        let n = samples.len();
        let lead = lead_samples(release, dt);
        let contact = (0..n)
            .map(|i| held_contact(&samples[i], &samples[(i + lead).min(n - 1)]))
            .collect();
        Self {
            samples,
            contact,
            com_correction: Vec::new(),
            frame: PlanFrame::new(feet0, dt),
            lead_time,
            preview: None,
        }
    }

    /// Adds the dynamic filter's correction `[Δc, Δċ, Δc̈]` (x, then y; one per sample from
    /// the handover) to the planned CoM; the reference ZMP stays the plan's
    /// ([`Targets::com_correction`]).
    pub fn correct_com(&mut self, dx: &[Vector3<f64>], dy: &[Vector3<f64>]) {
        self.com_correction = dx
            .iter()
            .zip(dy)
            .map(|(cx, cy)| [[cx[0], cy[0]], [cx[2], cy[2]]])
            .collect();
        for ((s, cx), cy) in self.samples.iter_mut().zip(dx).zip(dy) {
            s.com.x += cx[0];
            s.com_vel.x += cx[1];
            s.com_acc.x += cx[2];
            s.com.y += cy[0];
            s.com_vel.y += cy[1];
            s.com_acc.y += cy[2];
        }
    }

    /// The walk proper, in seconds after the handover: from the first lift-off of a foot to
    /// the last touchdown (the standing before and after left out); None when no foot ever
    /// leaves the ground.
    pub fn walking_window(&self) -> Option<(f64, f64)> {
        let stepping =
            |r: &WalkingReference| !(r.phase.left_in_contact() && r.phase.right_in_contact());
        let first = self.samples.iter().position(stepping)?;
        let last = self.samples.iter().rposition(stepping)?;
        let dt = self.frame.dt;
        Some((first as f64 * dt, (last + 1) as f64 * dt))
    }

    /// The planned CoM and feet at the end of the run (world).
    pub fn final_reference(&self) -> &WalkingReference {
        self.samples.last().unwrap_or_else(|| unreachable!("n ≥ 1"))
    }

    /// A plan point in the world.
    pub fn world(&self, p: Vector3<f64>) -> Vector3<f64> {
        p + self.frame.origin
    }

    /// Writes the targets at `t` into `out`.
    pub fn sample(&self, t: f64, out: &mut Targets) {
        let i = ((t / self.frame.dt).round() as usize).min(self.samples.len() - 1);
        let correction = self.com_correction.get(i).copied().unwrap_or([[0.0; 2]; 2]);
        self.frame.write(
            &self.samples[i],
            &self.samples[i.saturating_sub(1)],
            self.contact[i],
            correction,
            out,
        );
    }
}

/// Samples of the release time `release` at period `dt`: how far ahead of a sample the
/// controller's contact flags look.
pub(crate) fn lead_samples(release: f64, dt: f64) -> usize {
    (release / dt).round() as usize
}

/// The controller's contact of each foot (left, right) at sample `now`: held while the foot
/// supports now and still supports at sample `ahead` (the release time later), so that its
/// force ramps to zero before the lift-off.
pub(crate) fn held_contact(now: &WalkingReference, ahead: &WalkingReference) -> [bool; 2] {
    let (now, ahead) = (now.phase, ahead.phase);
    [
        now.left_in_contact() && ahead.left_in_contact(),
        now.right_in_contact() && ahead.right_in_contact(),
    ]
}

/// Where a walk plan sits in the world: plan x, y from the soles' midpoint at the handover,
/// plan z from their height, feet orientations relative to the starting ones.
#[derive(Clone, Debug)]
pub(crate) struct PlanFrame {
    pub(crate) dt: f64,
    origin: Vector3<f64>,
    feet_rotation0: [nalgebra::Matrix3<f64>; 2],
}

impl PlanFrame {
    /// The frame of a plan starting from the soles `feet0`, sampled every `dt`.
    pub(crate) fn new(feet0: &[Se3; 2], dt: f64) -> Self {
        Self {
            dt,
            origin: (feet0[0].translation + feet0[1].translation) / 2.0,
            feet_rotation0: [feet0[0].rotation, feet0[1].rotation],
        }
    }

    /// Writes the targets of plan sample `r` (after `prev`, one period earlier) into `out`,
    /// with the controller's contact flags `contact` and the dynamic filter's `correction`.
    pub(crate) fn write(
        &self,
        r: &WalkingReference,
        prev: &WalkingReference,
        contact: [bool; 2],
        correction: [[f64; 2]; 2],
        out: &mut Targets,
    ) {
        let o = self.origin;
        for k in 0..3 {
            out.com.pos[k] = r.com[k] + if k == 2 { o.z } else { o[k] };
            out.com.vel[k] = r.com_vel[k];
            out.com.acc[k] = r.com_acc[k];
        }
        let feet = [
            (
                (&r.left_foot, &r.left_foot_vel),
                (&prev.left_foot, &prev.left_foot_vel),
            ),
            (
                (&r.right_foot, &r.right_foot_vel),
                (&prev.right_foot, &prev.right_foot_vel),
            ),
        ];
        out.waist_yaw = r.waist_yaw;
        out.com_correction = correction;
        for (k, (now, before)) in feet.into_iter().enumerate() {
            write_foot(
                &mut out.feet[k],
                now,
                before,
                self.dt,
                o,
                &self.feet_rotation0[k],
            );
            out.feet[k].in_contact = contact[k];
            out.feet[k].supporting = [r.phase.left_in_contact(), r.phase.right_in_contact()][k];
        }
    }
}

/// A foot target from a plan pose and velocity `now` (and those of the previous sample,
/// `before`): position + origin, orientation `R_z(yaw) R_y(pitch) R_x(roll) R₀` (the plan's
/// heading and tilt applied to the starting orientation `R₀`), world angular velocity from
/// the Euler rates ([`FootVelocity::angular`]); accelerations by backward differences.
fn write_foot(
    out: &mut FootTarget,
    now: (&FootPose, &FootVelocity),
    before: (&FootPose, &FootVelocity),
    dt: f64,
    origin: Vector3<f64>,
    rotation0: &nalgebra::Matrix3<f64>,
) {
    let ((pose, vel), (prev_pose, prev_vel)) = (now, before);
    out.reference.placement = Se3::new(
        pose.rotation().matrix() * rotation0,
        pose.position() + origin,
    );
    let omega = vel.angular(pose);
    out.reference.velocity = Motion::new(vel.linear(), omega);
    out.reference.acceleration = Motion::new(
        (vel.linear() - prev_vel.linear()) / dt,
        (omega - prev_vel.angular(prev_pose)) / dt,
    );
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Matrix3;

    fn section() -> WalkSection {
        toml::from_str("steps = 2\nstep_length = 0.2").unwrap()
    }

    /// The controller's contact of the leaving foot is released over the double support, the
    /// plan's support keeps it until lift-off; both agree in single support.
    #[test]
    fn contact_is_released_before_lift_off_while_support_lasts_until_it() {
        let dt = 1e-3;
        let feet0 = [
            Se3::new(Matrix3::identity(), Vector3::new(0.0, 0.085, 0.0)),
            Se3::new(Matrix3::identity(), Vector3::new(0.0, -0.085, 0.0)),
        ];
        let w = WalkMotion::new(
            &section(),
            &feet0,
            &Vector3::new(0.0, 0.0, 0.87),
            dt,
            6.0,
            &corps_sim::Terrain::default(),
        )
        .unwrap();
        let mut out = Targets::at_rest(&Vector3::zeros(), &feet0);
        let (mut released_but_supporting, mut single) = (0, 0);
        for k in 0..6000 {
            w.sample(k as f64 * dt, &mut out);
            for f in &out.feet {
                // A held contact is always a supporting foot.
                assert!(!f.in_contact || f.supporting, "t = {}", k as f64 * dt);
                if f.supporting && !f.in_contact {
                    released_but_supporting += 1;
                }
            }
            if out.feet[0].supporting != out.feet[1].supporting {
                single += 1;
                assert_eq!(out.feet[0].in_contact, out.feet[0].supporting);
            }
        }
        // Three lift-offs (two steps and the closing step), each released 0.115 s early.
        assert_eq!(released_but_supporting, 3 * 115);
        assert!(single > 2 * 900, "{single} single-support ticks");
    }
}
