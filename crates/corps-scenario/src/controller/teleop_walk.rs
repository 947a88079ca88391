//! The teleoperation walking state machine (seed 001 §6.1.2, Fig 6.6, state 2b): each of the
//! operator's steps becomes one robot step.
//!
//! - i. walking double support: the CoM's ground projection goes to mid-feet; with a step
//!   pending, once the measured CoM is within `e_com` of its target, → ii;
//! - ii. liftoff: the CoM goes over the stance sole; once within `e_com`, the swing foot rises
//!   to the step's height and half its length; reached (within `e_foot`) and seen unloaded
//!   (below `f_contact`: off the ground), → iii;
//! - iii. touchdown: the swing foot goes down to its target; once it touches (loaded past
//!   `f_contact`; ours, where the thesis waits for `e_foot`), the CoM goes back to mid-feet;
//!   with the CoM within `e_com`, the foot within `e_foot` of where it touched and its sole
//!   loaded past `f_touchdown`, the feet swap roles → i.
//!
//! A step may turn its sole by `turn` about the vertical (autonomous walking's turning steps;
//! the operator's steps do not turn): its landing point is its start swung about the stance
//! sole by the robot's change of heading (the heading is the mean of the soles' turns, so half
//! the step's turn), plus its travel, taken in the robot's heading at the step's start; the
//! sole's yaw reference follows a minimum-jerk profile over twice `swing_time` from the moment
//! the rise is commanded (the rise and the descent when the sole leaves the ground at once).
//! Turns are meant for alternating feet: nothing bounds the yaw between the two soles.
//!
//! With no step pending, i ends in the teleoperation double support (2a). Every reference moves
//! along a minimum-jerk profile; the waist goes `waist_drop` lower during the liftoff and
//! touchdown of a short step (Table 6.2 and L8072–L8080). Thresholds are checked on the
//! estimator's CoM and feet and on the feet's F/T sensors, as the robot's own FSM reads them.

use corps_model::min_jerk::min_jerk_between;
use nalgebra::{Isometry3, Vector2, Vector3};
use serde::Deserialize;

/// `[walking]` of the teleoperation gains file.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct WalkingSpec {
    /// Table 6.2's e_CoM (m): the measured CoM's ground projection this close to its target.
    pub e_com: f64,
    /// Table 6.2's e_foot (m): the measured swing sole this close to its target.
    pub e_foot: f64,
    /// Table 6.2's F_touchdown (N): the landed sole's vertical force.
    pub f_touchdown: f64,
    /// A descending sole loaded past this (N) has touched the ground: its reference stops
    /// there (a stiff position servo pressing further lifts the robot off its stance foot).
    pub f_contact: f64,
    /// How fast (m/s) and how far below the landing point (m) a sole that has not touched the
    /// ground is lowered.
    pub search_speed: f64,
    pub search_depth: f64,
    /// Duration of a CoM transfer (s).
    pub com_time: f64,
    /// Duration of the swing foot's rise, and of its descent (s).
    pub swing_time: f64,
    /// A step no longer than this (m) is short: the waist drops during its swing.
    pub short_step: f64,
    /// How much lower the waist goes during a short step (m).
    pub waist_drop: f64,
}

impl WalkingSpec {
    pub fn check(&self) -> Result<(), String> {
        for (name, v) in [
            ("walking.e_com", self.e_com),
            ("walking.e_foot", self.e_foot),
            ("walking.f_touchdown", self.f_touchdown),
            ("walking.f_contact", self.f_contact),
            ("walking.search_speed", self.search_speed),
            ("walking.search_depth", self.search_depth),
            ("walking.com_time", self.com_time),
            ("walking.swing_time", self.swing_time),
            ("walking.short_step", self.short_step),
            ("walking.waist_drop", self.waist_drop),
        ] {
            if !(v.is_finite() && v >= 0.0) {
                return Err(format!("{name}: must be a finite number ≥ 0"));
            }
        }
        for (name, v) in [
            ("walking.e_com", self.e_com),
            ("walking.e_foot", self.e_foot),
            ("walking.com_time", self.com_time),
            ("walking.swing_time", self.swing_time),
        ] {
            if v == 0.0 {
                return Err(format!("{name}: must be > 0"));
            }
        }
        Ok(())
    }
}

/// One robot step to make: which foot, its horizontal travel in the world at the start of the
/// walk (m; turned with the robot's heading when the step begins), the height its sole rises
/// to (m) and how much the sole turns about the vertical (rad, counter-clockwise).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlannedStep {
    /// 0 left, 1 right.
    pub foot: usize,
    pub travel: Vector2<f64>,
    pub height: f64,
    pub turn: f64,
}

/// The states of Fig 6.6's branch 2.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum WalkState {
    /// 2a: teleoperation double support, no step pending.
    DoubleSupport,
    /// 2b-i.
    WalkingDoubleSupport,
    /// 2b-ii, the CoM going over the stance sole.
    ShiftToStance,
    /// 2b-ii, the swing foot rising.
    Liftoff,
    /// 2b-iii, the swing foot going down.
    Touchdown,
    /// 2b-iii, the CoM going back to mid-feet, the foot landed.
    Landing,
}

impl WalkState {
    /// A number per state for the run log (0 = 2a … 5 = landing).
    pub fn code(self) -> f64 {
        self as u8 as f64
    }

    /// Whether the robot is walking (state 2b): waist and posture hold their walking references.
    pub fn walking(self) -> bool {
        self != WalkState::DoubleSupport
    }
}

/// A minimum-jerk segment of a point from `from` to `to`, started at `start`.
#[derive(Clone, Copy, Debug)]
struct Segment {
    from: Vector3<f64>,
    to: Vector3<f64>,
    start: f64,
    duration: f64,
}

impl Segment {
    /// At `at`, and already done.
    fn hold(at: Vector3<f64>) -> Segment {
        Segment {
            from: at,
            to: at,
            start: f64::NEG_INFINITY,
            duration: 1.0,
        }
    }

    /// Position and velocity at `t`.
    fn sample(&self, t: f64) -> (Vector3<f64>, Vector3<f64>) {
        let lambda = (t - self.start) / self.duration;
        let mut p = Vector3::zeros();
        let mut v = Vector3::zeros();
        for k in 0..3 {
            let [x, dx, _] = min_jerk_between(self.from[k], self.to[k], lambda, self.duration);
            p[k] = x;
            v[k] = dx;
        }
        (p, v)
    }

    fn done(&self, t: f64) -> bool {
        t >= self.start + self.duration
    }
}

/// What the walk asks of the tasks this tick.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WalkReferences {
    /// The CoM's ground projection and its rate (z unused).
    pub com: Vector3<f64>,
    pub com_velocity: Vector3<f64>,
    /// Each sole's position and linear velocity.
    pub feet: [Vector3<f64>; 2],
    pub feet_velocity: [Vector3<f64>; 2],
    /// Each sole's turn about the vertical since the start (rad) and its rate (rad/s).
    pub feet_yaw: [f64; 2],
    pub feet_yaw_rate: [f64; 2],
    /// The waist's offset from its standing height (m, ≤ 0).
    pub waist_offset: f64,
}

/// Capacity of the queue of steps the operator made and the robot has not.
pub const MAX_PENDING: usize = 32;
/// Steps whose lengths are kept for the metrics (the vector is allocated once).
pub const MAX_RECORDED: usize = 512;

/// The walking state machine.
#[derive(Clone, Debug)]
pub struct TeleopWalk {
    spec: WalkingSpec,
    pub state: WalkState,
    com: Segment,
    feet: [Segment; 2],
    /// The waist offset's segment: from, to, start (over `swing_time`).
    waist: (f64, f64, f64),
    /// Each sole's turn since the start: from, to, start (over twice `swing_time`).
    yaw: [(f64, f64, f64); 2],
    /// The planned horizontal length of the step under way (m).
    planned_length: f64,
    /// The measured soles' yaw at the last update and their turns since the first, summed
    /// update by update (so past ±180°); `measured_turn` is their mean (rad).
    soles_yaw: Option<[f64; 2]>,
    soles_turn: [f64; 2],
    pub measured_turn: f64,
    /// The step under way.
    step: Option<PlannedStep>,
    /// The swing foot's landing point (where it touched down, once it has), and the height
    /// planned for it.
    target: Vector3<f64>,
    planned_z: f64,
    pending: [Option<PlannedStep>; MAX_PENDING],
    head: usize,
    len: usize,
    /// Steps made to the end (the feet swapped roles).
    pub steps_done: usize,
    /// Steps dropped: the queue was full, or the step was not valid.
    pub dropped: usize,
    /// Each step made: the planned horizontal length of the sole's move (Eq 6.6–6.7, or the
    /// scenario's footsteps, a turning step's swing included) and the measured one (the sole
    /// from liftoff to the swap), up to [`MAX_RECORDED`] steps.
    pub lengths: Vec<[f64; 2]>,
    /// The swing sole (measured) when the step began, and whether it has been seen off the
    /// ground (below `f_contact`) since.
    lifted_from: Vector3<f64>,
    unloaded: bool,
    /// The time of the last update.
    last: f64,
}

impl TeleopWalk {
    /// Standing on soles at `feet` (world), the CoM's ground projection at `com`.
    pub fn new(spec: WalkingSpec, feet: [Vector3<f64>; 2], com: Vector3<f64>) -> TeleopWalk {
        TeleopWalk {
            spec,
            state: WalkState::DoubleSupport,
            com: Segment::hold(com),
            feet: feet.map(Segment::hold),
            waist: (0.0, 0.0, 0.0),
            yaw: [(0.0, 0.0, 0.0); 2],
            planned_length: 0.0,
            soles_yaw: None,
            soles_turn: [0.0; 2],
            measured_turn: 0.0,
            step: None,
            target: Vector3::zeros(),
            planned_z: 0.0,
            pending: [None; MAX_PENDING],
            head: 0,
            len: 0,
            steps_done: 0,
            dropped: 0,
            lengths: Vec::with_capacity(MAX_RECORDED),
            lifted_from: Vector3::zeros(),
            unloaded: false,
            last: 0.0,
        }
    }

    /// Its thresholds and timings.
    pub fn spec(&self) -> &WalkingSpec {
        &self.spec
    }

    /// Steps waiting to be made.
    pub fn pending(&self) -> usize {
        self.len
    }

    /// Queues a step (dropped and counted if the queue is full, or if the step names no foot
    /// or is not finite).
    pub fn push(&mut self, step: PlannedStep) {
        let finite = step.travel.iter().all(|x| x.is_finite())
            && step.height.is_finite()
            && step.turn.is_finite();
        if self.len == MAX_PENDING || step.foot > 1 || !finite {
            self.dropped += 1;
            return;
        }
        self.pending[(self.head + self.len) % MAX_PENDING] = Some(step);
        self.len += 1;
    }

    fn pop(&mut self) -> Option<PlannedStep> {
        if self.len == 0 {
            return None;
        }
        let s = self.pending[self.head].take();
        self.head = (self.head + 1) % MAX_PENDING;
        self.len -= 1;
        s
    }

    fn move_com(&mut self, t: f64, to: Vector3<f64>) {
        let (from, _) = self.com.sample(t);
        self.com = Segment {
            from,
            to,
            start: t,
            duration: self.spec.com_time,
        };
    }

    fn move_foot(&mut self, t: f64, k: usize, to: Vector3<f64>) {
        let (from, _) = self.feet[k].sample(t);
        self.feet[k] = Segment {
            from,
            to,
            start: t,
            duration: self.spec.swing_time,
        };
    }

    /// Lowers foot `k`'s reference by `search_speed` over `dt`, down to `search_depth` below
    /// the step's landing point: a sole that has not touched the ground goes looking for it.
    fn lower_foot(&mut self, t: f64, dt: f64, k: usize) {
        let (mut at, _) = self.feet[k].sample(t);
        at.z = (at.z - self.spec.search_speed * dt).max(self.planned_z - self.spec.search_depth);
        self.feet[k] = Segment::hold(at);
        self.target = at;
    }

    /// Stops foot `k` where its reference is at `t`: where it touched the ground, which
    /// becomes the step's landing point.
    fn hold_foot(&mut self, t: f64, k: usize) {
        let (at, _) = self.feet[k].sample(t);
        self.feet[k] = Segment::hold(at);
        self.target = at;
    }

    fn move_waist(&mut self, t: f64, to: f64) {
        self.waist = (self.waist_at(t), to, t);
    }

    /// Turns sole `k` to `to` (rad from its start) over the step's rise and descent.
    fn turn_foot(&mut self, t: f64, k: usize, to: f64) {
        self.yaw[k] = (self.yaw_at(t, k)[0], to, t);
    }

    /// Sole `k`'s turn and its rate at `t`.
    fn yaw_at(&self, t: f64, k: usize) -> [f64; 2] {
        let (from, to, start) = self.yaw[k];
        let duration = 2.0 * self.spec.swing_time;
        let [y, rate, _] = min_jerk_between(from, to, (t - start) / duration, duration);
        [y, rate]
    }

    /// The robot's planned heading: the mean of the soles' planned turns (rad).
    pub fn planned_turn(&self) -> f64 {
        (self.yaw[0].1 + self.yaw[1].1) / 2.0
    }

    fn waist_at(&self, t: f64) -> f64 {
        let (from, to, start) = self.waist;
        min_jerk_between(
            from,
            to,
            (t - start) / self.spec.swing_time,
            self.spec.swing_time,
        )[0]
    }

    /// Advances the machine at `t` from the estimator's CoM and soles and the soles' vertical
    /// forces (left, right), and returns the references of this tick.
    pub fn update(
        &mut self,
        t: f64,
        com: &Vector3<f64>,
        soles: &[Isometry3<f64>; 2],
        forces: [f64; 2],
    ) -> WalkReferences {
        let dt = (t - self.last).max(0.0);
        self.last = t;
        let yaw = soles.map(|s| s.rotation.euler_angles().2);
        let last = *self.soles_yaw.get_or_insert(yaw);
        let wrapped = |a: f64| {
            (a + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU) - std::f64::consts::PI
        };
        for k in 0..2 {
            self.soles_turn[k] += wrapped(yaw[k] - last[k]);
        }
        self.soles_yaw = Some(yaw);
        self.measured_turn = (self.soles_turn[0] + self.soles_turn[1]) / 2.0;
        let e_com = self.spec.e_com;
        let e_foot = self.spec.e_foot;
        // Errors are taken from the feet that stand, measured against planned (the stance
        // sole during a step, else mid-feet): the estimator's world drifts from the plan's.
        let sole = |k: usize| soles[k].translation.vector;
        let offset = match self.step {
            Some(step) => sole(1 - step.foot) - self.feet[1 - step.foot].to,
            None => (sole(0) + sole(1) - self.feet[0].to - self.feet[1].to) / 2.0,
        };
        let com_reached =
            |s: &Segment| s.done(t) && (com.xy() - s.to.xy() - offset.xy()).norm() < e_com;
        let foot_reached =
            |s: &Segment, k: usize| s.done(t) && (sole(k) - s.to - offset).norm() < e_foot;
        // The landing point the step aimed at (the swap's "foot at pose").
        let target = self.target;
        let landed = |k: usize| (sole(k) - target - offset).norm() < e_foot;
        let mid = |feet: &[Segment; 2]| {
            let m = (feet[0].to + feet[1].to) / 2.0;
            Vector3::new(m.x, m.y, 0.0)
        };
        match self.state {
            WalkState::DoubleSupport => {
                if self.len > 0 {
                    self.state = WalkState::WalkingDoubleSupport;
                    let to = mid(&self.feet);
                    self.move_com(t, to);
                }
            }
            WalkState::WalkingDoubleSupport => {
                if com_reached(&self.com) {
                    match self.pop() {
                        Some(step) => {
                            let stance = self.feet[1 - step.foot].to;
                            self.step = Some(step);
                            self.move_com(t, Vector3::new(stance.x, stance.y, 0.0));
                            self.state = WalkState::ShiftToStance;
                        }
                        None => self.state = WalkState::DoubleSupport,
                    }
                }
            }
            WalkState::ShiftToStance => {
                if let Some(step) = self.step {
                    if com_reached(&self.com) {
                        let k = step.foot;
                        let from = self.feet[k].to;
                        // The travel in the robot's heading now; a turning sole first swings
                        // about the stance sole by the heading's change (half its turn: the
                        // heading is the mean of the soles'), which keeps the feet's spacing
                        // and turns it with the heading.
                        let mut travel = turned(self.planned_turn(), step.travel);
                        if step.turn != 0.0 {
                            let r = (from - self.feet[1 - k].to).xy();
                            travel += turned(step.turn / 2.0, r) - Vector3::new(r.x, r.y, 0.0);
                            self.turn_foot(t, k, self.yaw[k].1 + step.turn);
                        }
                        self.target = from + travel;
                        self.planned_length = travel.xy().norm();
                        self.planned_z = self.target.z;
                        self.lifted_from = sole(k);
                        self.unloaded = false;
                        self.move_foot(t, k, from + travel / 2.0 + Vector3::z() * step.height);
                        if self.short() {
                            self.move_waist(t, -self.spec.waist_drop);
                        }
                        self.state = WalkState::Liftoff;
                    }
                }
            }
            WalkState::Liftoff => {
                if let Some(step) = self.step {
                    self.unloaded |= forces[step.foot] < self.spec.f_contact;
                    if self.unloaded && foot_reached(&self.feet[step.foot], step.foot) {
                        self.move_foot(t, step.foot, self.target);
                        self.state = WalkState::Touchdown;
                    }
                }
            }
            WalkState::Touchdown => {
                if let Some(step) = self.step {
                    let k = step.foot;
                    let touched = forces[k] > self.spec.f_contact;
                    if touched {
                        self.hold_foot(t, k);
                    } else if self.feet[k].done(t) {
                        self.lower_foot(t, dt, k);
                    }
                    if touched {
                        let to = mid(&self.feet);
                        self.move_com(t, to);
                        if self.short() {
                            self.move_waist(t, 0.0);
                        }
                        self.state = WalkState::Landing;
                    }
                }
            }
            WalkState::Landing => {
                if let Some(step) = self.step {
                    let k = step.foot;
                    if forces[k] < self.spec.f_contact {
                        self.lower_foot(t, dt, k);
                    }
                    if com_reached(&self.com) && landed(k) && forces[k] > self.spec.f_touchdown {
                        self.steps_done += 1;
                        if self.lengths.len() < MAX_RECORDED {
                            let walked = (sole(k) - self.lifted_from).xy().norm();
                            self.lengths.push([self.planned_length, walked]);
                        }
                        // Both soles loaded: the landed sole's reference goes back to the
                        // height planned for it — from above, where it first touched while
                        // the stance leg bent under the robot's weight, or from below, where
                        // it searched for the ground — so that, the load shared, the model's
                        // soles stay level with the ground's (both feet stay on it).
                        let mut level = self.target;
                        level.z = self.planned_z;
                        self.move_foot(t, k, level);
                        self.step = None;
                        self.state = WalkState::WalkingDoubleSupport;
                    }
                }
            }
        }
        self.references(t)
    }

    /// The references at `t` (no state change).
    pub fn references(&self, t: f64) -> WalkReferences {
        let (c, cv) = self.com.sample(t);
        let (l, lv) = self.feet[0].sample(t);
        let (r, rv) = self.feet[1].sample(t);
        let [ly, lyv] = self.yaw_at(t, 0);
        let [ry, ryv] = self.yaw_at(t, 1);
        WalkReferences {
            com: c,
            com_velocity: cv,
            feet: [l, r],
            feet_velocity: [lv, rv],
            feet_yaw: [ly, ry],
            feet_yaw_rate: [lyv, ryv],
            waist_offset: self.waist_at(t),
        }
    }

    /// A step whose sole moves no more than `short_step` (its travel, and its swing when it
    /// turns).
    fn short(&self) -> bool {
        self.planned_length <= self.spec.short_step
    }
}

/// The horizontal `v` turned by `angle` about the vertical (z = 0).
fn turned(angle: f64, v: Vector2<f64>) -> Vector3<f64> {
    let (s, c) = angle.sin_cos();
    Vector3::new(c * v.x - s * v.y, s * v.x + c * v.y, 0.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spec() -> WalkingSpec {
        WalkingSpec {
            e_com: 0.03,
            e_foot: 0.02,
            f_touchdown: 80.0,
            f_contact: 20.0,
            search_speed: 0.02,
            search_depth: 0.03,
            com_time: 1.0,
            swing_time: 0.5,
            short_step: 0.04,
            waist_drop: 0.01,
        }
    }

    /// A robot that follows its references exactly, its feet loaded when down.
    #[test]
    fn a_step_goes_through_every_state_and_lands_where_planned() {
        let feet = [Vector3::new(0.0, 0.07, 0.0), Vector3::new(0.0, -0.07, 0.0)];
        let mut walk = TeleopWalk::new(spec(), feet, Vector3::zeros());
        walk.push(PlannedStep {
            foot: 0,
            travel: Vector2::new(0.1, 0.0),
            height: 0.025,
            turn: 0.0,
        });
        let mut r = walk.update(
            0.0,
            &Vector3::zeros(),
            &feet.map(|p| Isometry3::translation(p.x, p.y, p.z)),
            [160.0; 2],
        );
        let mut seen = vec![walk.state];
        let dt = 0.01;
        for k in 1..2000 {
            let t = k as f64 * dt;
            let soles = r.feet.map(|p| Isometry3::translation(p.x, p.y, p.z));
            let forces = r.feet.map(|p| if p.z < 1e-4 { 160.0 } else { 0.0 });
            r = walk.update(t, &r.com, &soles, forces);
            if *seen.last().unwrap() != walk.state {
                seen.push(walk.state);
            }
            // A short step is not this one: the waist stays.
            assert_eq!(r.waist_offset, 0.0);
        }
        assert_eq!(
            seen,
            [
                WalkState::WalkingDoubleSupport,
                WalkState::ShiftToStance,
                WalkState::Liftoff,
                WalkState::Touchdown,
                WalkState::Landing,
                WalkState::WalkingDoubleSupport,
                WalkState::DoubleSupport,
            ]
        );
        assert_eq!(walk.steps_done, 1);
        assert_eq!(walk.lengths.len(), 1);
        // The sole stops where it first touches (here 0.1 mm above the ground).
        let [planned, walked] = walk.lengths[0];
        assert!((planned - 0.1).abs() < 1e-12 && (walked - 0.1).abs() < 1e-3);
        assert!((r.feet[0] - Vector3::new(0.1, 0.07, 0.0)).norm() < 1e-3);
        assert!((r.com - Vector3::new(0.05, 0.0, 0.0)).norm() < 1e-3);
    }

    /// Turning in place, 20° a step, four steps: the soles turn 40° each, stay side by side
    /// across the new heading at their distance apart, and the next step's travel goes along
    /// that heading.
    #[test]
    fn turning_steps_keep_the_feet_side_by_side_across_the_heading() {
        let feet = [Vector3::new(0.0, 0.07, 0.0), Vector3::new(0.0, -0.07, 0.0)];
        let mut walk = TeleopWalk::new(spec(), feet, Vector3::zeros());
        let turn = 20f64.to_radians();
        for k in 0..4 {
            walk.push(PlannedStep {
                foot: k % 2,
                travel: Vector2::zeros(),
                height: 0.02,
                turn,
            });
        }
        walk.push(PlannedStep {
            foot: 0,
            travel: Vector2::new(0.1, 0.0),
            height: 0.02,
            turn: 0.0,
        });
        let mut r = walk.references(0.0);
        let dt = 0.01;
        for k in 0..10_000 {
            let t = k as f64 * dt;
            let soles =
                std::array::from_fn(|i| Isometry3::new(r.feet[i], Vector3::z() * r.feet_yaw[i]));
            let forces = r.feet.map(|p| if p.z < 1e-4 { 160.0 } else { 0.0 });
            r = walk.update(t, &r.com, &soles, forces);
            if walk.steps_done == 4 && walk.state == WalkState::WalkingDoubleSupport {
                break;
            }
        }
        assert_eq!(walk.steps_done, 4);
        let heading = 2.0 * turn;
        assert!(
            r.feet_yaw.iter().all(|y| (y - heading).abs() < 1e-9),
            "{:?}",
            r.feet_yaw
        );
        assert!((walk.planned_turn() - heading).abs() < 1e-12);
        assert!(
            (walk.measured_turn - heading).abs() < 1e-6,
            "{}",
            walk.measured_turn
        );
        // Side by side across the heading, 0.14 m apart (within 1 mm: the sole stops where it
        // first touches, 0.1 mm above the ground, and the next steps start from there).
        let across = (r.feet[0] - r.feet[1]).xy();
        let (s, c) = heading.sin_cos();
        let along = c * across.x + s * across.y;
        assert!(
            along.abs() < 1e-3 && (across.norm() - 0.14).abs() < 1e-3,
            "{across:?}"
        );
        let left = r.feet[0];
        for k in 0..5_000 {
            let t = 100.0 + k as f64 * dt;
            let soles =
                std::array::from_fn(|i| Isometry3::new(r.feet[i], Vector3::z() * r.feet_yaw[i]));
            let forces = r.feet.map(|p| if p.z < 1e-4 { 160.0 } else { 0.0 });
            r = walk.update(t, &r.com, &soles, forces);
        }
        assert_eq!(walk.steps_done, 5);
        let moved = (r.feet[0] - left).xy();
        assert!(
            (moved - Vector2::new(c, s) * 0.1).norm() < 1e-3,
            "{moved:?}"
        );
    }

    #[test]
    fn a_sole_that_never_leaves_the_ground_never_ends_its_liftoff() {
        let feet = [Vector3::new(0.0, 0.07, 0.0), Vector3::new(0.0, -0.07, 0.0)];
        let mut walk = TeleopWalk::new(spec(), feet, Vector3::zeros());
        walk.push(PlannedStep {
            foot: 0,
            travel: Vector2::zeros(),
            height: 0.01,
            turn: 0.0,
        });
        let mut r = walk.references(0.0);
        for k in 0..2000 {
            let soles = r.feet.map(|p| Isometry3::translation(p.x, p.y, p.z));
            // The sole rises 1 cm (within e_foot of its apex) but stays loaded: still on the
            // ground as far as its F/T sensor tells.
            r = walk.update(k as f64 * 0.01, &r.com, &soles, [160.0; 2]);
        }
        assert_eq!(walk.state, WalkState::Liftoff);
        assert_eq!(walk.steps_done, 0);
        // A step naming no foot, or not finite, is refused and counted.
        for step in [
            PlannedStep {
                foot: 2,
                travel: Vector2::zeros(),
                height: 0.0,
                turn: 0.0,
            },
            PlannedStep {
                foot: 0,
                travel: Vector2::new(f64::NAN, 0.0),
                height: 0.0,
                turn: 0.0,
            },
        ] {
            walk.push(step);
        }
        assert_eq!((walk.pending(), walk.dropped), (0, 2));
    }

    #[test]
    fn a_sole_that_never_touches_searches_down_and_a_full_queue_counts_its_drops() {
        let feet = [Vector3::new(0.0, 0.07, 0.0), Vector3::new(0.0, -0.07, 0.0)];
        let mut walk = TeleopWalk::new(spec(), feet, Vector3::zeros());
        for _ in 0..MAX_PENDING + 3 {
            walk.push(PlannedStep {
                foot: 1,
                travel: Vector2::zeros(),
                height: 0.05,
                turn: 0.0,
            });
        }
        assert_eq!((walk.pending(), walk.dropped), (MAX_PENDING, 3));
        let mut r = walk.update(
            0.0,
            &Vector3::zeros(),
            &feet.map(|p| Isometry3::translation(p.x, p.y, p.z)),
            [160.0; 2],
        );
        let mut lowest = 0.0f64;
        for k in 1..2000 {
            let t = k as f64 * 0.01;
            let soles = r.feet.map(|p| Isometry3::translation(p.x, p.y, p.z));
            r = walk.update(t, &r.com, &soles, [0.0; 2]);
            lowest = lowest.min(r.waist_offset);
        }
        // The sole never felt the ground: it went looking for it, search_depth below the
        // landing point, and the step does not end.
        assert_eq!(walk.state, WalkState::Touchdown);
        assert!((r.feet[1].z + 0.03).abs() < 1e-12, "{}", r.feet[1].z);
        assert_eq!(walk.steps_done, 0);
        // A step in place is short: the waist went down by waist_drop.
        assert!((lowest + 0.01).abs() < 1e-9, "{lowest}");
    }
}
