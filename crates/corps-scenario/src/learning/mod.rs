//! Learning the soft-task weights of a whole-body controller (seed 001 ch. 5): a campaign
//! file names the rollout scenario, the weights (each a key of the controller's gains, its
//! bounds and start), the fitness, the randomized conditions and the optimizer's settings;
//! [`campaign`] runs the constrained (1+1)-CMA-ES of `corps_learn` on it, each evaluation the
//! mean fitness of K randomized rollouts run in parallel ([`rollout`], [`fitness`]).
//!
//! ```toml
//! scenario = "../scenarios/icub/fsm2_one_step.toml"
//! fitness = "performance_robustness"   # performance | robustness | performance_robustness
//! iterations = 200
//! repeats = 10
//! sigma0 = 0.1
//! [[weights]]
//! name = "w_stance"
//! key = "weights.stance"               # a key of the controller's gains ([controller.set])
//! lower = 1e-4
//! upper = 10.0
//! start = 1.0
//! ```

pub mod campaign;
pub mod executor;
pub mod fitness;
pub mod rollout;

use crate::error::{bail, Result};
use serde::Deserialize;
use std::path::{Path, PathBuf};

/// Seed 001 Eq 5.17–5.18.
#[derive(Clone, Copy, Debug, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum FitnessKind {
    /// ϕp: task errors and effort.
    Performance,
    /// ϕr: the ZMP's excursion from the support polygon's centre.
    Robustness,
    /// ϕpr = (ϕp + ϕr) / 2.
    PerformanceRobustness,
}

impl FitnessKind {
    pub fn name(self) -> &'static str {
        match self {
            FitnessKind::Performance => "performance",
            FitnessKind::Robustness => "robustness",
            FitnessKind::PerformanceRobustness => "performance_robustness",
        }
    }
}

/// One weight: a key of the controller's gains, its bounds and start (the search runs on
/// log10 of the weight, seed 001 L6891–L6897; lower = upper holds it fixed).
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct WeightSpec {
    pub name: String,
    /// Dotted path in the gains file, e.g. `weights.stance` or `posture.weight`.
    pub key: String,
    pub lower: f64,
    pub upper: f64,
    pub start: f64,
}

impl WeightSpec {
    pub fn fixed(&self) -> bool {
        self.lower == self.upper
    }
}

/// Seed 001 Table 5.1's randomized conditions (the noise levels are ours: the thesis gives
/// none).
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields, default)]
pub struct Randomization {
    /// σ of the F/T sensors' force (N) and torque (N·m) noise, and of the joint velocities
    /// (rad/s).
    pub force_noise: f64,
    pub torque_noise: f64,
    pub joint_velocity_noise: f64,
    /// The swing foot drawn left or right, its motion front or back.
    pub swing_foot: bool,
    pub swing_direction: bool,
    /// The CoM reference moved forward by δ ∈ [0, com_offset] (m).
    pub com_offset: f64,
    /// Up to `pushes` wrenches on `push_frame`: each starts before `push_before` s (1e-2 s
    /// precision), lasts at most `push_duration` s, its force at most `push_force` N and its
    /// torque at most `push_torque` N·m in uniformly drawn directions.
    pub pushes: usize,
    pub push_frame: String,
    pub push_force: f64,
    pub push_torque: f64,
    pub push_duration: f64,
    pub push_before: f64,
}

impl Default for Randomization {
    /// Table 5.1: swing foot and direction drawn, δ ≤ 0.02 m, up to 7 chest wrenches of
    /// ≤ 10 N / 10 N·m for ≤ 1 s before 10 s; F/T noise 1 N / 0.05 N·m and joint-velocity
    /// noise 0.01 rad/s (our choice).
    fn default() -> Self {
        Self {
            force_noise: 1.0,
            torque_noise: 0.05,
            joint_velocity_noise: 0.01,
            swing_foot: true,
            swing_direction: true,
            com_offset: 0.02,
            pushes: 7,
            push_frame: "chest".into(),
            push_force: 10.0,
            push_torque: 10.0,
            push_duration: 1.0,
            push_before: 10.0,
        }
    }
}

/// A learning campaign (a `.toml` file).
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct LearnConfig {
    /// The training rollout, relative to the campaign file.
    pub scenario: PathBuf,
    pub fitness: FitnessKind,
    #[serde(default = "two_hundred")]
    pub iterations: usize,
    /// Independent runs of the optimizer (seed 001: 10 per fitness).
    #[serde(default = "ten")]
    pub repeats: usize,
    /// σ0 on the log10 weights (seed 001 Eq 5.3: 0.1).
    #[serde(default = "tenth")]
    pub sigma0: f64,
    #[serde(default)]
    pub seed: u64,
    /// Randomized rollouts averaged per evaluation (K).
    #[serde(default = "one")]
    pub conditions: usize,
    /// Draw Table 5.1's conditions (false: every rollout the scenario as it is).
    #[serde(default = "yes")]
    pub randomize: bool,
    #[serde(default)]
    pub randomization: Randomization,
    /// |τ| bound of every joint, a constraint (seed 001 §5.3.2: 60 N·m).
    #[serde(default = "sixty")]
    pub torque_limit: f64,
    /// How far past its URDF limit a joint may go before the rollout violates the joint-limit
    /// constraint (rad): with `[sim] joint_stops`, the stops' give (default 0.01 rad, 100 N·m
    /// into a 1e4 N·m/rad stop).
    #[serde(default = "hundredth")]
    pub joint_limit_tolerance: f64,
    /// Added to the fitness of a rollout that falls or whose QP fails (seed 001: −1.5).
    #[serde(default = "penalty")]
    pub penalty: f64,
    pub weights: Vec<WeightSpec>,
    /// How the learned weights are tested (seed 001 L6684–L6741), if they are.
    pub test: Option<TestSpec>,
}

/// The tests of the learned weights: a longer rollout, run on each robot of `runs`.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct TestSpec {
    /// The test rollout, relative to the campaign file.
    pub scenario: PathBuf,
    /// Steps (touchdowns) that make a success, the run completed.
    pub steps: usize,
    pub runs: Vec<TestRun>,
}

/// One test: a robot, with or without randomized conditions.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct TestRun {
    pub name: String,
    /// A built-in robot or a description file (relative to the campaign file).
    pub robot: String,
    #[serde(default)]
    pub randomize: bool,
    #[serde(default)]
    pub randomization: Randomization,
}

fn two_hundred() -> usize {
    200
}
fn ten() -> usize {
    10
}
fn one() -> usize {
    1
}
fn tenth() -> f64 {
    0.1
}
fn yes() -> bool {
    true
}
fn sixty() -> f64 {
    60.0
}
fn hundredth() -> f64 {
    0.01
}
fn penalty() -> f64 {
    -1.5
}

impl LearnConfig {
    /// Reads and checks the campaign file at `path`.
    pub fn read(path: &Path) -> Result<(LearnConfig, PathBuf)> {
        let text = crate::overrides::read_file(path).map_err(|e| crate::error::invalid!("{e}"))?;
        Self::parse(&text, path)
    }

    /// Parses and checks campaign `text` read from `path` (relative paths from its directory).
    pub fn parse(text: &str, path: &Path) -> Result<(LearnConfig, PathBuf)> {
        let config: LearnConfig = corps_robot::toml_text::parse(text)
            .map_err(|e| crate::error::invalid!("{}: {e}", path.display()))?;
        config
            .check()
            .map_err(|e| crate::error::invalid!("{}: {e}", path.display()))?;
        let dir = path.parent().unwrap_or(Path::new("")).to_path_buf();
        Ok((config, dir))
    }

    /// Bounds ordered, starts inside them, σ0 > 0, ranges not empty, counts ≥ 1.
    pub fn check(&self) -> Result<()> {
        if self.weights.is_empty() {
            bail!("weights: name at least one");
        }
        for (k, w) in self.weights.iter().enumerate() {
            let key = format!("weights[{k}] ('{}')", w.name);
            for (what, v) in [("lower", w.lower), ("upper", w.upper), ("start", w.start)] {
                if !(v.is_finite() && v > 0.0) {
                    bail!("{key}.{what}: must be a finite number > 0 (weights are searched in log scale), got {v}");
                }
            }
            if w.lower > w.upper {
                bail!("{key}: lower {} > upper {}", w.lower, w.upper);
            }
            if w.start < w.lower || w.start > w.upper {
                bail!(
                    "{key}.start: {} is outside [{}, {}]",
                    w.start,
                    w.lower,
                    w.upper
                );
            }
            if w.key.split('.').any(str::is_empty) {
                bail!("{key}.key: '{}' is not a dotted path", w.key);
            }
        }
        if self.weights.iter().all(WeightSpec::fixed) {
            bail!("weights: every weight is fixed (lower = upper): nothing to learn");
        }
        if !(self.sigma0.is_finite() && self.sigma0 > 0.0) {
            bail!("sigma0: must be > 0, got {}", self.sigma0);
        }
        for (what, n) in [
            ("iterations", self.iterations),
            ("repeats", self.repeats),
            ("conditions", self.conditions),
        ] {
            if n == 0 {
                bail!("{what}: must be at least 1");
            }
        }
        if !(self.torque_limit.is_finite() && self.torque_limit > 0.0) {
            bail!("torque_limit: must be > 0, got {}", self.torque_limit);
        }
        if !(self.joint_limit_tolerance.is_finite() && self.joint_limit_tolerance >= 0.0) {
            bail!(
                "joint_limit_tolerance: must be ≥ 0, got {}",
                self.joint_limit_tolerance
            );
        }
        if !self.penalty.is_finite() {
            bail!("penalty: must be finite");
        }
        check_randomization(&self.randomization, "randomization")?;
        if let Some(t) = &self.test {
            if t.runs.is_empty() || t.steps == 0 {
                bail!("test: needs at least one run and steps ≥ 1");
            }
            for (k, run) in t.runs.iter().enumerate() {
                check_randomization(&run.randomization, &format!("test.runs[{k}].randomization"))?;
            }
        }
        Ok(())
    }

    /// The weights searched (lower < upper), in order.
    pub fn free(&self) -> impl Iterator<Item = &WeightSpec> {
        self.weights.iter().filter(|w| !w.fixed())
    }
}

/// Noise levels and ranges finite and not negative; ranges not empty.
fn check_randomization(r: &Randomization, key: &str) -> Result<()> {
    {
        for (what, v) in [
            ("force_noise", r.force_noise),
            ("torque_noise", r.torque_noise),
            ("joint_velocity_noise", r.joint_velocity_noise),
            ("com_offset", r.com_offset),
            ("push_force", r.push_force),
            ("push_torque", r.push_torque),
        ] {
            if !(v.is_finite() && v >= 0.0) {
                bail!("{key}.{what}: must be a finite number ≥ 0, got {v}");
            }
        }
        for (what, v) in [
            ("push_duration", r.push_duration),
            ("push_before", r.push_before),
        ] {
            if r.pushes > 0 && !(v.is_finite() && v > 0.0) {
                bail!("{key}.{what}: the range (0, {v}] is empty");
            }
        }
    }
    Ok(())
}
