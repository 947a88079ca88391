//! Footstep plans: where and when each foot lands, the ZMP reference they imply and the
//! contact phase at any time.
//!
//! Timeline: an initial double support (the ZMP moves from the middle of the feet to the first
//! support foot), then for each step a single support (the step's foot swings to its new pose)
//! followed by a double support (the ZMP moves linearly to the foot that just landed); after the
//! last step a final double support brings the ZMP back to the middle of the feet, where it
//! stays. The ZMP reference is the support foot's centre in single support and moves linearly
//! in double support (Kajita 2003 §IV; the piecewise-linear reference of CCC's
//! `FootstepManager`).
//!
//! Footholds on uneven ground ([`FootstepPlan::on_ground`]): each footstep takes the height
//! and the tilt of the surface under its sole centre (the sole's normal is the surface's), the
//! swing foot interpolates to that tilt, and the ZMP reference stays the support sole's centre
//! (its projection on the horizontal plane, at the sole's height).

use crate::min_jerk::min_jerk;
use crate::pose::{FootPose, FootVelocity};
use crate::reference::ContactPhase;
use crate::swing_foot::{SwingTrajectory, DEFAULT_APEX_HEIGHT};
use crate::{Foot, WalkError};
use nalgebra::Vector3;

/// The ground under the footsteps: the top surface crossing the vertical line through a point.
pub trait Ground {
    /// Height of the top surface above `(x, y)` and its upward unit normal there, `None` where
    /// there is no surface.
    fn surface_at(&self, x: f64, y: f64) -> Option<(f64, Vector3<f64>)>;
}

/// One step: which foot moves and where it lands.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Footstep {
    /// The swinging foot.
    pub foot: Foot,
    /// Its landing pose.
    pub pose: FootPose,
}

/// Step timing.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StepTiming {
    /// Single-support (swing) duration (s).
    pub single_support: f64,
    /// Double-support duration between steps (s).
    pub double_support: f64,
    /// Initial double support, before the first lift-off (s).
    pub initial_double_support: f64,
    /// Final double support, after the last touch-down (s).
    pub final_double_support: f64,
}

impl StepTiming {
    /// SS / DS with initial and final double supports of one step period each (a slow first
    /// CoM shift, as in seed 000 S12 "first CoM shift quasi-static").
    pub fn new(single_support: f64, double_support: f64) -> Self {
        let period = single_support + double_support;
        Self {
            single_support,
            double_support,
            initial_double_support: period,
            final_double_support: period,
        }
    }

    /// Seed 000 §4 (L4681–L4686): SS 0.9 s, DS 0.115 s (20 cm and 60 cm walks).
    pub fn seed000_nominal() -> Self {
        Self::new(0.9, 0.115)
    }

    /// Seed 000 §4 faster walk: SS 0.711 s, DS 0.089 s.
    pub fn seed000_fast() -> Self {
        Self::new(0.711, 0.089)
    }

    /// Seed 002 §4.4: SS 1.0 s, DS 0.2 s (jrl-walkgen settings on Pyrène).
    pub fn seed002() -> Self {
        Self::new(1.0, 0.2)
    }

    fn validate(&self) -> Result<(), WalkError> {
        let ok = |v: f64| v.is_finite() && v > 0.0;
        if !ok(self.single_support) || !ok(self.double_support) {
            return Err(WalkError::InvalidParameter(
                "step durations must be finite and > 0",
            ));
        }
        if !ok(self.initial_double_support) || !ok(self.final_double_support) {
            return Err(WalkError::InvalidParameter(
                "initial and final double supports must be finite and > 0",
            ));
        }
        Ok(())
    }
}

/// What the plan prescribes at one instant.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlanSample {
    /// Contact phase.
    pub phase: ContactPhase,
    /// ZMP reference (x, y, and the ground height z under it).
    pub zmp: Vector3<f64>,
    /// Rate of change of the ZMP reference.
    pub zmp_vel: Vector3<f64>,
    /// Left foot pose.
    pub left: FootPose,
    /// Right foot pose.
    pub right: FootPose,
    /// Left foot velocity.
    pub left_vel: FootVelocity,
    /// Right foot velocity.
    pub right_vel: FootVelocity,
}

/// Where a time falls in a plan (see `FootstepPlan::locate`).
#[derive(Clone, Copy, Debug)]
enum PlanPhase {
    /// Before the plan, or a plan without steps.
    Standing,
    /// The initial double support, `fraction` of the way through.
    Initial { fraction: f64 },
    /// Step `step` swings, `local` s after its lift-off.
    Single { step: usize, local: f64 },
    /// The double support after step `step`, `elapsed` s after its touch-down.
    Double { step: usize, elapsed: f64 },
}

/// A timed sequence of footsteps from an initial stance.
#[derive(Debug, Clone, PartialEq)]
pub struct FootstepPlan {
    initial_left: FootPose,
    initial_right: FootPose,
    steps: Vec<Footstep>,
    /// Pose each step's foot leaves from.
    liftoff: Vec<FootPose>,
    timing: StepTiming,
    swing_height: f64,
    /// Each step's swing, built once (sampling runs every tick over the preview window).
    swings: Vec<SwingTrajectory>,
}

fn mid(a: &FootPose, b: &FootPose) -> Vector3<f64> {
    Vector3::new(0.5 * (a.x + b.x), 0.5 * (a.y + b.y), 0.5 * (a.z + b.z))
}

fn pos(a: &FootPose) -> Vector3<f64> {
    Vector3::new(a.x, a.y, a.z)
}

impl FootstepPlan {
    /// A plan from the initial feet and the steps (the swing apex height defaults to 5 cm).
    pub fn new(
        initial_left: FootPose,
        initial_right: FootPose,
        steps: Vec<Footstep>,
        timing: StepTiming,
    ) -> Result<Self, WalkError> {
        timing.validate()?;
        let (mut l, mut r) = (initial_left, initial_right);
        let mut liftoff = Vec::with_capacity(steps.len());
        for s in &steps {
            let p = s.pose;
            let coordinates = [p.x, p.y, p.z, p.yaw, p.roll, p.pitch];
            if !coordinates.iter().all(|c| c.is_finite()) {
                return Err(WalkError::InvalidParameter("footstep pose must be finite"));
            }
            match s.foot {
                Foot::Left => {
                    liftoff.push(l);
                    l = p;
                }
                Foot::Right => {
                    liftoff.push(r);
                    r = p;
                }
            }
        }
        Ok(Self {
            initial_left,
            initial_right,
            steps,
            liftoff,
            timing,
            swing_height: 0.0,
            swings: Vec::new(),
        }
        .with_swing_height(DEFAULT_APEX_HEIGHT))
    }

    /// The same plan with every footstep moved onto `ground`: its height becomes the surface's
    /// under the sole centre and its roll and pitch those that lay the sole on the surface
    /// ([`FootPose::on_surface`]); x, y, yaw and the timing are kept. The initial feet stay where
    /// they are (they are measured). Fails if a footstep has no surface under it or the surface
    /// is vertical.
    pub fn on_ground(self, ground: &impl Ground) -> Result<Self, WalkError> {
        let steps = self
            .steps
            .iter()
            .map(|s| {
                let p = s.pose;
                let (z, normal) = ground
                    .surface_at(p.x, p.y)
                    .ok_or(WalkError::InvalidParameter("no ground under a footstep"))?;
                let pose = FootPose::on_surface(p.x, p.y, z, p.yaw, &normal).ok_or(
                    WalkError::InvalidParameter("the ground under a footstep is not walkable"),
                )?;
                Ok(Footstep { foot: s.foot, pose })
            })
            .collect::<Result<Vec<_>, WalkError>>()?;
        Ok(
            Self::new(self.initial_left, self.initial_right, steps, self.timing)?
                .with_swing_height(self.swing_height),
        )
    }

    /// Sets the swing apex height (m).
    pub fn with_swing_height(mut self, height: f64) -> Self {
        self.swing_height = height;
        self.swings = self
            .liftoff
            .iter()
            .zip(&self.steps)
            .map(|(from, step)| {
                SwingTrajectory::new(from, &step.pose, self.timing.single_support, height)
            })
            .collect();
        self
    }

    /// Feet side by side at the origin, `feet_distance` apart, facing +x.
    pub fn initial_stance(feet_distance: f64) -> (FootPose, FootPose) {
        (
            FootPose::new(0.0, 0.5 * feet_distance, 0.0, 0.0),
            FootPose::new(0.0, -0.5 * feet_distance, 0.0, 0.0),
        )
    }

    /// Straight walk: `n` steps of length `step_length` (each foot lands `step_length` ahead of
    /// the previous one, starting with `first`), then a closing step that brings the other foot
    /// beside the last one. Seed 000 S5: `straight(6, 0.2, …)` travels 1.2 m (SS 0.9, DS 0.115);
    /// S7: `straight(6, 0.6, …)`.
    pub fn straight(
        n: usize,
        step_length: f64,
        feet_distance: f64,
        first: Foot,
        timing: StepTiming,
    ) -> Result<Self, WalkError> {
        Self::stairs_like(n, step_length, 0.0, feet_distance, first, timing)
    }

    /// Stairs: `n` steps each `tread` forward and `rise` up, plus a closing step on the last
    /// stair (seed 000 S9: 6 stairs of 10 cm rise and 30 cm tread).
    pub fn stairs(
        n: usize,
        rise: f64,
        tread: f64,
        feet_distance: f64,
        first: Foot,
        timing: StepTiming,
    ) -> Result<Self, WalkError> {
        Self::stairs_like(n, tread, rise, feet_distance, first, timing)
    }

    /// Walking in place: `n` steps, each foot landing where it lifted off.
    pub fn in_place(
        n: usize,
        feet_distance: f64,
        first: Foot,
        timing: StepTiming,
    ) -> Result<Self, WalkError> {
        let (l, r) = Self::initial_stance(feet_distance);
        let mut foot = first;
        let steps = (0..n)
            .map(|_| {
                let s = Footstep {
                    foot,
                    pose: if foot == Foot::Left { l } else { r },
                };
                foot = foot.other();
                s
            })
            .collect();
        Self::new(l, r, steps, timing)
    }

    fn stairs_like(
        n: usize,
        dx: f64,
        dz: f64,
        feet_distance: f64,
        first: Foot,
        timing: StepTiming,
    ) -> Result<Self, WalkError> {
        if !(feet_distance.is_finite() && feet_distance > 0.0) {
            return Err(WalkError::InvalidParameter(
                "feet_distance must be finite and > 0",
            ));
        }
        let (l, r) = Self::initial_stance(feet_distance);
        let mut steps = Vec::with_capacity(n + 1);
        let mut foot = first;
        for k in 1..=n {
            let y = foot.side() * 0.5 * feet_distance;
            steps.push(Footstep {
                foot,
                pose: FootPose::new(k as f64 * dx, y, k as f64 * dz, 0.0),
            });
            foot = foot.other();
        }
        if n > 0 {
            let y = foot.side() * 0.5 * feet_distance;
            steps.push(Footstep {
                foot,
                pose: FootPose::new(n as f64 * dx, y, n as f64 * dz, 0.0),
            });
        }
        Self::new(l, r, steps, timing)
    }

    /// The steps.
    pub fn steps(&self) -> &[Footstep] {
        &self.steps
    }

    /// Step timing.
    pub fn timing(&self) -> &StepTiming {
        &self.timing
    }

    /// Initial left and right foot poses.
    pub fn initial_feet(&self) -> (FootPose, FootPose) {
        (self.initial_left, self.initial_right)
    }

    /// Final left and right foot poses.
    pub fn final_feet(&self) -> (FootPose, FootPose) {
        let (mut l, mut r) = (self.initial_left, self.initial_right);
        for s in &self.steps {
            match s.foot {
                Foot::Left => l = s.pose,
                Foot::Right => r = s.pose,
            }
        }
        (l, r)
    }

    /// Time of lift-off of step `i`.
    pub fn liftoff_time(&self, i: usize) -> f64 {
        let t = &self.timing;
        t.initial_double_support + i as f64 * (t.single_support + t.double_support)
    }

    /// Time of touch-down of step `i`.
    pub fn touchdown_time(&self, i: usize) -> f64 {
        self.liftoff_time(i) + self.timing.single_support
    }

    /// Time at which the ZMP reaches the middle of the final stance; the plan is static after.
    pub fn duration(&self) -> f64 {
        if self.steps.is_empty() {
            return 0.0;
        }
        self.touchdown_time(self.steps.len() - 1) + self.timing.final_double_support
    }

    /// The foot that carries the robot while step `i` swings.
    fn support_before(&self, i: usize) -> FootPose {
        let (l, r) = self.feet_before(i);
        if self.steps[i].foot == Foot::Left {
            r
        } else {
            l
        }
    }

    /// The feet before step `i` lifts off (after steps `0..i`).
    fn feet_before(&self, i: usize) -> (FootPose, FootPose) {
        // the foot that swings in step i is at liftoff[i]; the other one is where the last
        // step of that foot put it (or initial)
        let s = &self.steps[i];
        let other = if i > 0 && self.steps[i - 1].foot != s.foot {
            self.steps[i - 1].pose
        } else {
            // two steps of the same foot in a row, or the first step: search back
            let mut o = match s.foot {
                Foot::Left => self.initial_right,
                Foot::Right => self.initial_left,
            };
            for st in self.steps[..i].iter().rev() {
                if st.foot != s.foot {
                    o = st.pose;
                    break;
                }
            }
            o
        };
        match s.foot {
            Foot::Left => (self.liftoff[i], other),
            Foot::Right => (other, self.liftoff[i]),
        }
    }

    /// Where time `t` falls in the plan.
    fn locate(&self, t: f64) -> PlanPhase {
        let tm = &self.timing;
        let n = self.steps.len();
        if n == 0 || t <= 0.0 {
            return PlanPhase::Standing;
        }
        if t < tm.initial_double_support {
            return PlanPhase::Initial {
                fraction: t / tm.initial_double_support,
            };
        }
        let period = tm.single_support + tm.double_support;
        let tau = t - tm.initial_double_support;
        let step = ((tau / period).floor() as usize).min(n - 1);
        let local = tau - step as f64 * period;
        if local < tm.single_support {
            PlanPhase::Single { step, local }
        } else {
            PlanPhase::Double {
                step,
                elapsed: local - tm.single_support,
            }
        }
    }

    /// The ZMP reference and its rate at time `t`, without the feet (what a preview window
    /// samples hundreds of times per tick). [`FootstepPlan::sample`] gives the same values.
    pub fn zmp_at(&self, t: f64) -> (Vector3<f64>, Vector3<f64>) {
        self.zmp_in(self.locate(t))
    }

    /// The ZMP reference and its rate at a located time.
    fn zmp_in(&self, phase: PlanPhase) -> (Vector3<f64>, Vector3<f64>) {
        let tm = &self.timing;
        let still = Vector3::zeros();
        let initial_mid = mid(&self.initial_left, &self.initial_right);
        match phase {
            PlanPhase::Standing => (initial_mid, still),
            PlanPhase::Initial { fraction } => {
                let b = pos(&self.support_before(0));
                (
                    initial_mid + (b - initial_mid) * fraction,
                    (b - initial_mid) / tm.initial_double_support,
                )
            }
            PlanPhase::Single { step, .. } => (pos(&self.support_before(step)), still),
            PlanPhase::Double { step, elapsed } => {
                let a = pos(&self.support_before(step));
                let (b, dur) = if step + 1 < self.steps.len() {
                    (pos(&self.steps[step].pose), tm.double_support)
                } else {
                    let (l, r) = self.feet_after(step);
                    (mid(&l, &r), tm.final_double_support)
                };
                if elapsed >= dur {
                    (b, still)
                } else {
                    (a + (b - a) * (elapsed / dur), (b - a) / dur)
                }
            }
        }
    }

    /// The feet once step `i` has touched down.
    fn feet_after(&self, i: usize) -> (FootPose, FootPose) {
        let (l, r) = self.feet_before(i);
        let step = &self.steps[i];
        match step.foot {
            Foot::Left => (step.pose, r),
            Foot::Right => (l, step.pose),
        }
    }

    /// Phase, ZMP reference and feet at time `t` (constant before 0 and after
    /// [`FootstepPlan::duration`]).
    pub fn sample(&self, t: f64) -> PlanSample {
        let still = FootVelocity::default();
        let phase = self.locate(t);
        let (zmp, zmp_vel) = self.zmp_in(phase);
        let mut out = PlanSample {
            phase: ContactPhase::Double,
            zmp,
            zmp_vel,
            left: self.initial_left,
            right: self.initial_right,
            left_vel: still,
            right_vel: still,
        };
        match phase {
            PlanPhase::Standing | PlanPhase::Initial { .. } => {}
            PlanPhase::Single { step, local } => {
                let (l, r) = self.feet_before(step);
                let (p, v) = self.swings[step].sample(local);
                match self.steps[step].foot {
                    Foot::Left => {
                        out.phase = ContactPhase::RightSupport;
                        (out.left, out.left_vel, out.right) = (p, v, r);
                    }
                    Foot::Right => {
                        out.phase = ContactPhase::LeftSupport;
                        (out.right, out.right_vel, out.left) = (p, v, l);
                    }
                }
            }
            PlanPhase::Double { step, .. } => (out.left, out.right) = self.feet_after(step),
        }
        out
    }

    /// The ground height the CoM rides above at `t`, with its first two derivatives: the
    /// support height, changed by a min-jerk transition over a whole step period from each
    /// touch-down (the double support and the next single support; the final double support
    /// for the closing step). The ZMP reference's height changes within the double support
    /// alone, a 10 cm stair in 0.115 s (seed 000 §4.2), which as a CoM height is a 0.87 m/s
    /// velocity step; spread over the period the peak rate is 1.875 Δz / T and the peak
    /// acceleration 5.77 Δz / T² (0.18 m/s and 0.56 m/s² for that stair at T = 1.015 s).
    pub fn com_ground(&self, t: f64) -> [f64; 3] {
        let n = self.steps.len();
        let start = mid(&self.initial_left, &self.initial_right).z;
        if n == 0 {
            return [start, 0.0, 0.0];
        }
        // The support height before step 0's touch-down: the first support foot's (the
        // initial double support moves the ZMP onto it).
        let mut z = self.support_before(0).z;
        if t < self.timing.initial_double_support {
            // Flat start in every plan corps builds; blend anyway if the feet differ.
            let lam = (t / self.timing.initial_double_support).clamp(0.0, 1.0);
            return min_jerk(start, z, lam, self.timing.initial_double_support);
        }
        for i in 0..n {
            let t0 = self.touchdown_time(i);
            if t < t0 {
                return [z, 0.0, 0.0];
            }
            let (to, dur) = if i + 1 < n {
                (
                    self.steps[i].pose.z,
                    self.timing.single_support + self.timing.double_support,
                )
            } else {
                let (l, r) = self.final_feet();
                (0.5 * (l.z + r.z), self.timing.final_double_support)
            };
            if t < t0 + dur {
                return min_jerk(z, to, (t - t0) / dur, dur);
            }
            z = to;
        }
        [z, 0.0, 0.0]
    }

    /// Contact phase at time `t`.
    pub fn phase_at(&self, t: f64) -> ContactPhase {
        match self.locate(t) {
            PlanPhase::Single { step, .. } => match self.steps[step].foot {
                Foot::Left => ContactPhase::RightSupport,
                Foot::Right => ContactPhase::LeftSupport,
            },
            _ => ContactPhase::Double,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn com_ground_climbs_each_stair_smoothly_over_a_step_period() {
        let timing = StepTiming::seed000_nominal();
        let plan = FootstepPlan::stairs(4, 0.1, 0.3, 0.17, Foot::Right, timing).unwrap();
        let period = timing.single_support + timing.double_support;
        let dt = 1e-4;
        let (mut prev, mut max_rate) = (plan.com_ground(0.0), 0.0f64);
        let mut t = dt;
        while t < plan.duration() + 0.5 {
            let g = plan.com_ground(t);
            // Continuous, and the rates are the derivatives (central differences).
            assert!((g[0] - prev[0]).abs() < 0.2 * dt + 1e-12, "jump at {t}");
            let (a, b) = (plan.com_ground(t - dt), plan.com_ground(t + dt));
            assert!((b[0] - a[0]) / (2.0 * dt) - g[1] < 1e-5, "rate at {t}");
            assert!(
                ((b[1] - a[1]) / (2.0 * dt) - g[2]).abs() < 1e-3,
                "acc at {t}"
            );
            max_rate = max_rate.max(g[1].abs());
            prev = g;
            t += dt;
        }
        // One stair per step period: the min-jerk peak rate 1.875 Δz / T.
        assert!((max_rate - 1.875 * 0.1 / period).abs() < 1e-3, "{max_rate}");
        // On each tread by the next touch-down, and at the top at the end.
        for i in 0..3 {
            let g = plan.com_ground(plan.touchdown_time(i) + period);
            assert!((g[0] - plan.steps()[i].pose.z).abs() < 1e-12);
        }
        assert!((plan.com_ground(plan.duration() + 1.0)[0] - 0.4).abs() < 1e-12);
    }

    #[test]
    fn seed000_straight_walk() {
        let plan = FootstepPlan::straight(6, 0.2, 0.17, Foot::Left, StepTiming::seed000_nominal())
            .unwrap();
        assert_eq!(plan.steps().len(), 7);
        let (l, r) = plan.final_feet();
        assert!(
            (l.x - 1.2).abs() < 1e-12 && (r.x - 1.2).abs() < 1e-12,
            "1.2 m travelled"
        );
        // alternating feet, each landing 0.2 m ahead of the previous footprint
        for w in plan.steps()[..6].windows(2) {
            assert_ne!(w[0].foot, w[1].foot);
            assert!((w[1].pose.x - w[0].pose.x - 0.2).abs() < 1e-12);
        }
        let t = plan.timing();
        let d = plan.duration();
        let expected = t.initial_double_support + 6.0 * 1.015 + 0.9 + t.final_double_support;
        assert!((d - expected).abs() < 1e-12);
    }

    #[test]
    fn phases_and_zmp_reference() {
        let timing = StepTiming::seed000_fast();
        let plan = FootstepPlan::straight(3, 0.2, 0.2, Foot::Right, timing).unwrap();
        let ti = timing.initial_double_support;
        assert_eq!(plan.phase_at(0.5 * ti), ContactPhase::Double);
        // first step: the right foot swings, the ZMP sits on the left foot (0, 0.1)
        let s = plan.sample(ti + 0.3);
        assert_eq!(s.phase, ContactPhase::LeftSupport);
        assert_eq!(s.phase.code(), 1);
        assert!((s.zmp - Vector3::new(0.0, 0.1, 0.0)).norm() < 1e-12);
        assert!(s.right.z > 0.0 && s.left == plan.initial_feet().0);
        // mid double support after the first step: halfway between (0, 0.1) and (0.2, −0.1)
        let s = plan.sample(ti + 0.711 + 0.0445);
        assert_eq!(s.phase, ContactPhase::Double);
        assert!((s.zmp - Vector3::new(0.1, 0.0, 0.0)).norm() < 1e-12);
        assert!((s.right.x - 0.2).abs() < 1e-12 && s.right.z == 0.0);
        // second step: the left swings, right support, code −1
        assert_eq!(plan.phase_at(ti + 0.8 + 0.1).code(), -1);
        // the ZMP reference is continuous and always inside the support polygon of the phase
        let g = crate::test_fixtures::TALOS_SOLE;
        let mut prev = plan.sample(0.0).zmp;
        let mut t = 0.0;
        while t < plan.duration() + 1.0 {
            let s = plan.sample(t);
            // fastest ZMP motion: 0.2 m forward and 0.2 m across in one 0.089 s double support
            assert!(
                (s.zmp - prev).norm() <= 0.2 * 2f64.sqrt() * 0.001 / 0.089 + 1e-9,
                "jump at {t}"
            );
            prev = s.zmp;
            let poly = match s.phase {
                ContactPhase::Double => g.double_support(&s.left, &s.right),
                ContactPhase::LeftSupport => g.sole_polygon(&s.left),
                ContactPhase::RightSupport => g.sole_polygon(&s.right),
            };
            assert!(poly.contains(&s.zmp.xy(), 1e-12), "t = {t}");
            t += 0.001;
        }
        // ends between the feet
        let s = plan.sample(plan.duration() + 5.0);
        let (l, r) = plan.final_feet();
        assert!((s.zmp - mid(&l, &r)).norm() < 1e-12);
    }

    /// Two platforms beside each other for x in [0.3, 1.2], rolled ±10° (a valley: each rises
    /// outwards), 3.5 cm high at y = ±0.085; flat ground elsewhere.
    struct Platforms;

    impl Ground for Platforms {
        fn surface_at(&self, x: f64, y: f64) -> Option<(f64, Vector3<f64>)> {
            if !(0.3..=1.2).contains(&x) || y.abs() > 0.3 {
                return Some((0.0, Vector3::z()));
            }
            let t = 10f64.to_radians().tan();
            let z = 0.035 + t * (y.abs() - 0.085);
            Some((z, Vector3::new(0.0, -t * y.signum(), 1.0).normalize()))
        }
    }

    #[test]
    fn footsteps_on_tilted_platforms_lie_on_the_surface() {
        let timing = StepTiming::seed000_nominal();
        let plan = FootstepPlan::straight(6, 0.25, 0.17, Foot::Right, timing)
            .unwrap()
            .on_ground(&Platforms)
            .unwrap();
        assert_eq!(plan.steps().len(), 7);
        let mut tilted = 0;
        for s in plan.steps() {
            let p = s.pose;
            let (z, n) = Platforms.surface_at(p.x, p.y).unwrap();
            assert!((p.z - z).abs() < 1e-12);
            // the sole's normal is the surface normal, the heading is kept
            assert!((p.sole_normal() - n).norm() < 1e-12, "{p:?}");
            assert!(p.yaw.abs() < 1e-12 && p.pitch.abs() < 1e-12);
            if n.z < 1.0 {
                tilted += 1;
                // the left sole's normal leans to −y (a positive roll), the right's to +y
                assert!((p.roll.abs() - 10f64.to_radians()).abs() < 1e-12);
                assert_eq!(p.roll.signum(), s.foot.side());
            }
        }
        assert_eq!(tilted, 3, "left at 0.5 and 1.0, right at 0.75");
        // every swing lands at rest on its foothold: the sample at touch-down is the footstep
        for (i, s) in plan.steps().iter().enumerate() {
            let at = plan.sample(plan.touchdown_time(i) - 1e-9);
            let (pose, vel) = match s.foot {
                Foot::Left => (at.left, at.left_vel),
                Foot::Right => (at.right, at.right_vel),
            };
            assert!((pose.position() - s.pose.position()).norm() < 1e-9);
            assert!((pose.sole_normal() - s.pose.sole_normal()).norm() < 1e-9);
            assert!(vel.linear().norm() < 1e-6 && vel.angular(&pose).norm() < 1e-6);
        }
        // the ZMP reference follows the support sole's height
        let s = plan.sample(plan.touchdown_time(2) - 0.1);
        assert_eq!(s.phase, ContactPhase::LeftSupport);
        assert!((s.zmp.z - 0.035).abs() < 1e-12);
        // a footstep off the ground is an error, not a panic
        struct Cliff;
        impl Ground for Cliff {
            fn surface_at(&self, x: f64, _: f64) -> Option<(f64, Vector3<f64>)> {
                (x < 0.5).then_some((0.0, Vector3::z()))
            }
        }
        let plan = FootstepPlan::straight(6, 0.25, 0.17, Foot::Right, timing).unwrap();
        assert!(plan.on_ground(&Cliff).is_err());
    }

    #[test]
    fn stairs_and_in_place() {
        let plan =
            FootstepPlan::stairs(6, 0.1, 0.3, 0.2, Foot::Left, StepTiming::seed000_nominal())
                .unwrap();
        let (l, r) = plan.final_feet();
        assert!(
            (l.z - 0.6).abs() < 1e-12 && (r.z - 0.6).abs() < 1e-12 && (l.x - 1.8).abs() < 1e-12
        );
        // ZMP height follows the support foot (step 2 stands on step 1's stair, z = 0.2)
        let s = plan.sample(plan.touchdown_time(2) - 0.1);
        assert!((s.zmp.z - 0.2).abs() < 1e-12);
        // step 1 (right foot, z 0 → 0.2) passes 5 cm above the upper stair at mid-swing
        let mid_swing = plan.sample(plan.liftoff_time(1) + 0.45);
        assert!((mid_swing.right.z - 0.25).abs() < 1e-12);

        let plan = FootstepPlan::in_place(4, 0.2, Foot::Left, StepTiming::seed002()).unwrap();
        let (l0, r0) = plan.initial_feet();
        assert_eq!(plan.final_feet(), (l0, r0));
        assert_eq!(
            plan.phase_at(plan.liftoff_time(0) + 0.5),
            ContactPhase::RightSupport
        );
        assert!(
            FootstepPlan::straight(2, 0.2, 0.2, Foot::Left, StepTiming::new(0.0, 0.1)).is_err()
        );
    }
}
