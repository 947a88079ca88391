//! Co-navigation with a person (seed 000 §3.17, §4.5; S10): a recorded walk of a person
//! (`shared/data/human-walking`, Maroger et al.) is streamed as a moving point, its rest is
//! predicted with the walking OCP of `corps_ocp::prediction`, and the velocity-driven MPC
//! walk is steered to hold a point relative to the person: `behind` (d behind them),
//! `beside` (d to their right) or `ahead` (d in front), d = 0.3 m by default (the thesis's
//! behind case, L5244).
//!
//! The person's time is the recording's (its time base: `corps_ocp::recorded_walks`) divided
//! by `rate`: 1 streams them at their recorded pace, as the issue asks; the thesis streamed
//! "at an adjustable rate to simulate human speed" (L5120–L5135). The person's walk is laid
//! out in the robot's plan so that it starts with the robot at its point and the person's
//! first heading along the robot's.
//!
//! The command every control period (robot frame, REP-103):
//! `v = r · v̂_person(t + T_look) + K (p*(t) − m_plan)`, `ω = K_ψ wrap(ψ*(t) − ψ_plan)`, where
//! `v̂_person` is the predicted path's velocity in the person's time (predicted every
//! `replan` s from the last `window` observed samples, the walk's end as the goal), `p*` the
//! point to hold, `m_plan` the plan's feet midpoint (free of the CoM's sway) and `ψ_plan` its
//! waist yaw, `ψ*` the person's
//! heading (the direction of their motion). Before the first prediction, after a failed one
//! and after the person's arrival, the velocity observed by then replaces the prediction's.

use crate::error::{invalid, Result};
use crate::targets::FollowTarget;
use crate::velocity_walk::VelocitySource;
use corps_ocp::human_walk::DT as PREDICTION_DT;
use corps_ocp::prediction::predict;
use corps_ocp::recorded_walks::RecordedWalk;
use corps_walk::mpc::VelocityCommand;
use corps_walk::pose::wrap_angle;
use corps_walk::WalkingReference;
use serde::Deserialize;
use std::path::{Path, PathBuf};

/// Where the robot walks relative to the person.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FollowMode {
    #[default]
    Behind,
    Beside,
    Ahead,
}

/// `[human]`: the person the robot walks with.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct HumanSection {
    /// A recorded walk file (the data set's format), relative to the scenario.
    pub file: PathBuf,
    /// The subject's index in the file (0-based).
    pub subject: usize,
    #[serde(default)]
    pub mode: FollowMode,
    /// Distance d (m) between the person and the point the robot holds.
    #[serde(default = "distance")]
    pub distance: f64,
    /// The person's pace over their recorded pace.
    #[serde(default = "one")]
    pub rate: f64,
    /// When the person starts walking (s after the handover): the robot's MPC first shifts
    /// its CoM over a foot for 1.2 s (its walk_mpc `start_double_support`).
    #[serde(default = "start")]
    pub start: f64,
    /// Observed samples the prediction starts from (the prediction test's 50).
    #[serde(default = "window")]
    pub window: usize,
    /// Time between predictions (s).
    #[serde(default = "replan")]
    pub replan: f64,
    /// The person is lost when the robot's CoM is farther than this (m) from its point.
    #[serde(default = "lost")]
    pub lost_beyond: f64,
}

fn distance() -> f64 {
    0.3
}
fn one() -> f64 {
    1.0
}
fn start() -> f64 {
    1.5
}
fn window() -> usize {
    50
}
fn replan() -> f64 {
    0.5
}
fn lost() -> f64 {
    1.0
}

/// Feedback gains of the command: position (1/s) and heading (1/s), and the prediction's
/// look-ahead (s): the MPC answers a velocity within about one step.
const K_POSITION: f64 = 1.0;
const K_HEADING: f64 = 0.5;
const LOOK_AHEAD: f64 = 0.5;
/// The yaw rate's bound (rad/s): the teleoperation's.
const MAX_YAW_RATE: f64 = 0.3;

impl HumanSection {
    /// Checks the values; the error names the key.
    pub fn check(&self) -> Result<(), String> {
        let positive = |name: &str, v: f64| {
            if v > 0.0 && v.is_finite() {
                Ok(())
            } else {
                Err(format!("human.{name} = {v}: must be positive"))
            }
        };
        positive("rate", self.rate)?;
        positive("replan", self.replan)?;
        positive("lost_beyond", self.lost_beyond)?;
        if !(self.distance >= 0.0 && self.distance.is_finite()) {
            return Err(format!("human.distance = {}: must be ≥ 0", self.distance));
        }
        if !(self.start >= 0.0 && self.start.is_finite()) {
            return Err(format!("human.start = {}: must be ≥ 0", self.start));
        }
        if self.window < 2 {
            return Err("human.window: at least 2 samples".into());
        }
        Ok(())
    }

    /// Reads the walk (`file` relative to `base_dir`) and its subject.
    pub fn walk(&self, base_dir: &Path) -> Result<RecordedWalk> {
        let path = base_dir.join(&self.file);
        let walks = corps_ocp::recorded_walks::read_paths(&path)
            .map_err(|e| invalid!("human.file: {e}"))?;
        let n = walks.len();
        walks
            .into_iter()
            .find(|w| w.subject == self.subject)
            .ok_or_else(|| {
                invalid!(
                    "human.subject = {}: {} has subjects 0 to {}",
                    self.subject,
                    path.display(),
                    n.saturating_sub(1)
                )
            })
    }
}

/// The person's walk laid out in the robot's plan, in the run's time.
#[derive(Clone, Debug)]
pub struct Person {
    /// Positions (plan x, y) every `dt` of the run's time from `start`.
    path: Vec<[f64; 2]>,
    /// The direction the person faces at each sample (plan): their motion's over the last
    /// quarter second of recorded walk, kept while they move less than 5 cm in it (slowing
    /// at the end, standing); before they have moved, their first direction.
    headings: Vec<f64>,
    /// The recorded poses (data frame) and their recorded period.
    recorded: RecordedWalk,
    dt: f64,
    start: f64,
    /// Data frame → plan: rotation angle and the translation applied after it.
    angle: f64,
    shift: [f64; 2],
}

impl Person {
    /// The walk of `section`, laid out so that at its start the robot, at the plan point
    /// `robot0` facing +x, is at its point relative to the person.
    pub fn new(section: &HumanSection, walk: RecordedWalk, robot0: [f64; 2]) -> Self {
        let p = &walk.poses;
        // The first direction: over the first `window` samples (as the predictor's).
        let heading0 = match p.len() {
            0 | 1 => 0.0,
            n => {
                let ahead = section.window.clamp(1, n - 1);
                (p[ahead][1] - p[0][1]).atan2(p[ahead][0] - p[0][0])
            }
        };
        let angle = -heading0;
        let offset0 = offset(section.mode, section.distance, 0.0);
        let person0 = [robot0[0] - offset0[0], robot0[1] - offset0[1]];
        let (s, c) = angle.sin_cos();
        let first = p.first().copied().unwrap_or([0.0; 3]);
        let rotated0 = [c * first[0] - s * first[1], s * first[0] + c * first[1]];
        let shift = [person0[0] - rotated0[0], person0[1] - rotated0[1]];
        let mut person = Self {
            path: Vec::new(),
            headings: Vec::new(),
            dt: walk.dt / section.rate,
            recorded: walk,
            start: section.start,
            angle,
            shift,
        };
        person.path = (person.recorded.poses.iter())
            .map(|q| person.to_plan([q[0], q[1]]))
            .collect();
        if person.path.is_empty() {
            person.path.push(robot0);
        }
        let back = ((0.25 / person.recorded.dt).round() as usize).max(1);
        let mut heading = 0.0;
        person.headings = (0..person.path.len())
            .map(|k| {
                let (a, b) = (person.path[k.saturating_sub(back)], person.path[k]);
                if (b[0] - a[0]).hypot(b[1] - a[1]) >= 0.05 {
                    heading = (b[1] - a[1]).atan2(b[0] - a[0]);
                }
                heading
            })
            .collect();
        person
    }

    /// A data-frame point in the plan.
    fn to_plan(&self, q: [f64; 2]) -> [f64; 2] {
        let (s, c) = self.angle.sin_cos();
        [
            c * q[0] - s * q[1] + self.shift[0],
            s * q[0] + c * q[1] + self.shift[1],
        ]
    }

    /// The sample index (fractional) at run time `t`.
    fn index(&self, t: f64) -> f64 {
        ((t - self.start) / self.dt).clamp(0.0, (self.path.len() - 1) as f64)
    }

    /// When the person arrives (run time, s).
    pub fn arrival(&self) -> f64 {
        self.start + (self.path.len() - 1) as f64 * self.dt
    }

    /// Position (plan) at run time `t`, linearly interpolated.
    pub fn position(&self, t: f64) -> [f64; 2] {
        let u = self.index(t);
        let k = (u.floor() as usize).min(self.path.len() - 1);
        let next = (k + 1).min(self.path.len() - 1);
        let f = u - k as f64;
        let (a, b) = (self.path[k], self.path[next]);
        [a[0] + f * (b[0] - a[0]), a[1] + f * (b[1] - a[1])]
    }

    /// Velocity (plan, m/s of run time) over the last quarter second of recorded walk
    /// before `t`: what has been seen by then, the gait's sway averaged out. Zero before the
    /// start and after the arrival.
    pub fn observed_velocity(&self, t: f64) -> [f64; 2] {
        if t < self.start || t >= self.arrival() {
            return [0.0; 2];
        }
        let span = 0.25 / self.recorded.dt * self.dt;
        let (a, b) = (self.position(t - span), self.position(t));
        let seen = (self.index(t) - self.index(t - span)) * self.dt;
        if seen <= 0.0 {
            return [0.0; 2];
        }
        [(b[0] - a[0]) / seen, (b[1] - a[1]) / seen]
    }

    /// The direction the person faces at `t` (plan; see `headings`).
    pub fn heading(&self, t: f64) -> f64 {
        let k = (self.index(t).floor() as usize).min(self.headings.len() - 1);
        self.headings[k]
    }
}

/// The robot's point relative to the person facing `heading`: behind, to their right, ahead.
fn offset(mode: FollowMode, d: f64, heading: f64) -> [f64; 2] {
    let (s, c) = heading.sin_cos();
    match mode {
        FollowMode::Behind => [-d * c, -d * s],
        FollowMode::Ahead => [d * c, d * s],
        // To the right: −d along the left normal (−sin, cos).
        FollowMode::Beside => [d * s, -d * c],
    }
}

/// The velocity source of a robot walking with a person.
pub struct CoNavigation {
    section: HumanSection,
    /// Set at the first command, from the plan's CoM at the start.
    person: Option<Person>,
    walk: Option<RecordedWalk>,
    /// The last prediction: its run time and its poses (plan frame, every PREDICTION_DT of
    /// recorded time).
    predicted_at: f64,
    prediction: Vec<[f64; 2]>,
    /// When the last prediction was attempted (run time).
    last_attempt: f64,
    /// The plan-to-world offset (the plan's origin in the world, x and y).
    origin: [f64; 2],
}

impl CoNavigation {
    /// The source for `section`, its walk read (and checked) from `base_dir`; the plan's
    /// origin is set by [`CoNavigation::placed_at`] once the robot stands.
    pub fn new(section: &HumanSection, base_dir: &Path) -> Result<Self> {
        section.check().map_err(|e| invalid!("{e}"))?;
        let walk = section.walk(base_dir)?;
        if section.window >= walk.poses.len() {
            return Err(invalid!(
                "human.window = {}: the walk has {} samples",
                section.window,
                walk.poses.len()
            ));
        }
        Ok(Self {
            section: section.clone(),
            person: None,
            walk: Some(walk),
            predicted_at: f64::NEG_INFINITY,
            prediction: Vec::new(),
            last_attempt: f64::NEG_INFINITY,
            origin: [0.0; 2],
        })
    }

    /// The source for a plan whose origin is at `origin` in the world (x, y).
    pub fn placed_at(self, origin: [f64; 2]) -> Self {
        Self { origin, ..self }
    }

    fn person(&mut self, plan: &WalkingReference) -> Option<&Person> {
        if self.person.is_none() {
            let walk = self.walk.take()?;
            self.person = Some(Person::new(&self.section, walk, [plan.com.x, plan.com.y]));
        }
        self.person.as_ref()
    }

    /// Predicts the rest of the walk from the samples observed by `t`.
    fn repredict(&mut self, t: f64) {
        let Some(person) = &self.person else { return };
        let observed = person.index(t).floor() as usize + 1;
        let w = self.section.window;
        if t < person.start || observed < w || t >= person.arrival() {
            self.prediction.clear();
            return;
        }
        let poses = &person.recorded.poses;
        let window = &poses[observed - w..observed];
        let end = poses[poses.len() - 1];
        let tail = &poses[poses.len().saturating_sub(w)..];
        let goal_heading = (end[1] - tail[0][1]).atan2(end[0] - tail[0][0]);
        match predict(window, person.recorded.dt, [end[0], end[1], goal_heading]) {
            Ok(p) => {
                self.prediction = p
                    .poses
                    .iter()
                    .map(|q| person.to_plan([q[0], q[1]]))
                    .collect();
            }
            Err(_) => self.prediction.clear(),
        }
        // The prediction's first node is the last observed sample.
        self.predicted_at = person.start + (observed - 1) as f64 * person.dt;
    }

    /// The person's velocity (plan, run time) expected `LOOK_AHEAD` after `now`: the
    /// prediction's, else the one observed by `now`.
    fn expected_velocity(&self, now: f64) -> [f64; 2] {
        let Some(person) = &self.person else {
            return [0.0; 2];
        };
        let p = &self.prediction;
        let t = now + LOOK_AHEAD;
        if p.len() >= 2 && t < person.arrival() {
            // Prediction nodes are PREDICTION_DT of recorded time apart: `rate` times as long
            // in the run's time.
            let node_dt = PREDICTION_DT / self.section.rate;
            let k = (((t - self.predicted_at) / node_dt) as usize).min(p.len() - 2);
            return [
                (p[k + 1][0] - p[k][0]) / node_dt,
                (p[k + 1][1] - p[k][1]) / node_dt,
            ];
        }
        person.observed_velocity(now)
    }

    /// The point to hold at `t` (plan).
    fn point(person: &Person, section: &HumanSection, t: f64) -> [f64; 2] {
        let p = person.position(t);
        let o = offset(section.mode, section.distance, person.heading(t));
        [p[0] + o[0], p[1] + o[1]]
    }
}

impl VelocitySource for CoNavigation {
    fn command(&mut self, t: f64, plan: &WalkingReference) -> VelocityCommand {
        if self.person(plan).is_none() {
            return VelocityCommand::default();
        }
        if t - self.last_attempt >= self.section.replan {
            self.last_attempt = t;
            self.repredict(t);
        }
        let Some(person) = &self.person else {
            return VelocityCommand::default();
        };
        let target = Self::point(person, &self.section, t);
        let feedforward = self.expected_velocity(t);
        // The robot's place: the plan's feet midpoint, which has none of the CoM's sway from
        // foot to foot (fed back, the sway became sideways steps).
        let here = [
            (plan.left_foot.x + plan.right_foot.x) / 2.0,
            (plan.left_foot.y + plan.right_foot.y) / 2.0,
        ];
        let error = [target[0] - here[0], target[1] - here[1]];
        let arrived = t >= person.arrival();
        if arrived && error[0].hypot(error[1]) < 0.05 {
            return VelocityCommand::default();
        }
        let v = [
            feedforward[0] + K_POSITION * error[0],
            feedforward[1] + K_POSITION * error[1],
        ];
        let yaw = plan.waist_yaw;
        let (s, c) = yaw.sin_cos();
        let omega =
            (K_HEADING * wrap_angle(person.heading(t) - yaw)).clamp(-MAX_YAW_RATE, MAX_YAW_RATE);
        VelocityCommand::new(c * v[0] + s * v[1], -s * v[0] + c * v[1], omega)
    }

    fn follow(&self, t: f64) -> Option<FollowTarget> {
        let person = self.person.as_ref()?;
        let p = person.position(t);
        let q = Self::point(person, &self.section, t);
        let o = self.origin;
        Some(FollowTarget {
            person: [p[0] + o[0], p[1] + o[1]],
            point: [q[0] + o[0], q[1] + o[1]],
            lost_beyond: self.section.lost_beyond,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    fn section(mode: FollowMode) -> HumanSection {
        HumanSection {
            file: PathBuf::new(),
            subject: 0,
            mode,
            distance: 0.3,
            rate: 0.5,
            start: 1.0,
            window: 5,
            replan: 0.5,
            lost_beyond: 1.0,
        }
    }

    /// A person walking 2 m along the data frame's y axis in 20 samples of 0.1 s.
    fn walk() -> RecordedWalk {
        RecordedWalk {
            subject: 0,
            poses: (0..21)
                .map(|k| [3.0, -2.0 + 0.1 * k as f64, PI / 2.0])
                .collect(),
            dt: 0.1,
        }
    }

    #[test]
    fn the_person_is_laid_out_ahead_of_the_robot_and_slowed_by_the_rate() {
        let person = Person::new(&section(FollowMode::Behind), walk(), [0.1, 0.0]);
        // The robot 0.3 m behind: the person starts 0.3 m ahead of it, walking along +x.
        let p0 = person.position(0.0);
        assert!((p0[0] - 0.4).abs() < 1e-12 && p0[1].abs() < 1e-12, "{p0:?}");
        // Half the recorded pace: 1 m/s becomes 0.5 m/s, the 2 s walk 4 s from t = 1 s.
        assert!((person.arrival() - 5.0).abs() < 1e-12);
        let v = person.observed_velocity(3.0);
        assert!((v[0] - 0.5).abs() < 1e-9 && v[1].abs() < 1e-9, "{v:?}");
        assert!(person.heading(3.0).abs() < 1e-9);
        let end = person.position(9.0);
        assert!((end[0] - 2.4).abs() < 1e-9, "{end:?}");
    }

    #[test]
    fn each_mode_holds_its_point() {
        for (mode, expected) in [
            (FollowMode::Behind, [-0.3, 0.0]),
            (FollowMode::Ahead, [0.3, 0.0]),
            (FollowMode::Beside, [0.0, -0.3]),
        ] {
            let o = offset(mode, 0.3, 0.0);
            assert!((o[0] - expected[0]).abs() < 1e-12 && (o[1] - expected[1]).abs() < 1e-12);
        }
        // Facing +y, "beside" (to the right) is +x.
        let o = offset(FollowMode::Beside, 0.3, PI / 2.0);
        assert!((o[0] - 0.3).abs() < 1e-12 && o[1].abs() < 1e-12, "{o:?}");
    }
}
