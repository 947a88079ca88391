//! One rollout of a learning campaign: the scenario with the candidate weights set in its
//! controller's gains and, when randomized, one draw of seed 001 Table 5.1's conditions
//! (seeded: the same seed gives the same rollout on any thread).

use super::{LearnConfig, Randomization};
use crate::pushes::PushSpec;
use crate::run::{RunOptions, ScenarioRun};
use crate::scenario::Scenario;
use corps_loop::verdict::Verdict;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::path::Path;

/// What a rollout returns to the campaign.
#[derive(Clone, Debug)]
pub struct RolloutOutcome {
    pub metrics: crate::metrics::Metrics,
    /// It ended otherwise than completed (a fall, a failed QP, a divergence), or could not run.
    pub failed: bool,
    /// Why, if it could not run at all (an error building or running it).
    pub error: Option<String>,
}

/// A seed for rollout `condition` of `iteration` of `repeat` (SplitMix64 of the four).
pub fn rollout_seed(seed: u64, repeat: usize, iteration: usize, condition: usize) -> u64 {
    let mut x = seed;
    for v in [repeat as u64, iteration as u64, condition as u64] {
        x = splitmix(x ^ v.wrapping_mul(0x9E37_79B9_7F4A_7C15));
    }
    x
}

fn splitmix(mut z: u64) -> u64 {
    z = z.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// Sets the dotted `key` of `table` to `value`, making the tables on the way.
pub fn set_path(table: &mut toml::Table, key: &str, value: toml::Value) {
    let mut parts = key.split('.').peekable();
    let mut t = table;
    while let Some(part) = parts.next() {
        if parts.peek().is_none() {
            t.insert(part.to_string(), value);
            return;
        }
        let entry = t
            .entry(part.to_string())
            .or_insert_with(|| toml::Value::Table(toml::Table::new()));
        if !entry.is_table() {
            *entry = toml::Value::Table(toml::Table::new());
        }
        let toml::Value::Table(next) = entry else {
            return;
        };
        t = next;
    }
}

/// The scenario of one rollout: `weights` (one per [`LearnConfig::weights`]) in its
/// controller's gains, and when `randomize`, the conditions drawn from `seed`.
pub fn rollout_scenario(
    base: &Scenario,
    config: &LearnConfig,
    weights: &[f64],
    randomize: bool,
    seed: u64,
) -> Scenario {
    let mut s = base.clone();
    s.seed = seed;
    let Some(controller) = s.controller.as_mut() else {
        return s;
    };
    for (spec, w) in config.weights.iter().zip(weights) {
        set_path(&mut controller.set, &spec.key, toml::Value::Float(*w));
    }
    if randomize {
        draw_conditions(&config.randomization, &mut s, seed);
    }
    s
}

/// Table 5.1: sensor noise, swing foot and direction, CoM offset, chest wrenches.
fn draw_conditions(r: &Randomization, s: &mut Scenario, seed: u64) {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    s.noise.force.std = r.force_noise;
    s.noise.torque.std = r.torque_noise;
    s.noise.joint_velocities.std = r.joint_velocity_noise;
    let Some(controller) = s.controller.as_mut() else {
        return;
    };
    let set = &mut controller.set;
    if r.swing_foot {
        let first = if rng.gen_bool(0.5) { "left" } else { "right" };
        set_path(set, "fsm.first_stance", toml::Value::String(first.into()));
    }
    if r.swing_direction {
        let x = if rng.gen_bool(0.5) { 0.025 } else { -0.025 };
        let offset = [x, 0.0, 0.025].map(toml::Value::Float).to_vec();
        set_path(set, "fsm.swing_offset", toml::Value::Array(offset));
    }
    let delta = rng.gen::<f64>() * r.com_offset;
    let com = [delta, 0.0, 0.0].map(toml::Value::Float).to_vec();
    set_path(set, "fsm.com_offset", toml::Value::Array(com));
    let n = rng.gen_range(0..=r.pushes);
    for _ in 0..n {
        let start = (rng.gen::<f64>() * r.push_before * 100.0).floor() / 100.0;
        let duration = ((1.0 - rng.gen::<f64>()) * r.push_duration * 100.0).ceil() / 100.0;
        let force = direction(&mut rng) * (rng.gen::<f64>() * r.push_force);
        let torque = direction(&mut rng) * (rng.gen::<f64>() * r.push_torque);
        s.pushes.push(PushSpec {
            frame: r.push_frame.clone(),
            start,
            duration,
            force: force.into(),
            torque: torque.into(),
            every: None,
            alternate: false,
            for_mass: None,
        });
    }
}

/// A unit vector drawn uniformly on the sphere.
fn direction(rng: &mut ChaCha8Rng) -> nalgebra::Vector3<f64> {
    let z: f64 = rng.gen_range(-1.0..=1.0);
    let phi = rng.gen::<f64>() * std::f64::consts::TAU;
    let r = (1.0 - z * z).max(0.0).sqrt();
    nalgebra::Vector3::new(r * phi.cos(), r * phi.sin(), z)
}

/// Runs `scenario` in memory (relative paths from `base_dir`) until its end or its first
/// failure (seed 001's early termination); a build or run error is a failed rollout with its
/// message, not a lost campaign.
pub fn run_rollout(scenario: &Scenario, base_dir: &Path) -> RolloutOutcome {
    let options = RunOptions {
        stop_after_failure: Some(0.0),
        ..RunOptions::default()
    };
    let result = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        ScenarioRun::new(scenario, "rollout", base_dir, options)?.run(&mut [])
    }));
    match result {
        Ok(Ok(r)) => RolloutOutcome {
            failed: r.metrics.verdict.verdict != Verdict::Completed || r.metrics.fallbacks > 0,
            metrics: r.metrics,
            error: None,
        },
        Ok(Err(e)) => RolloutOutcome {
            metrics: Default::default(),
            failed: true,
            error: Some(e.to_string()),
        },
        Err(_) => RolloutOutcome {
            metrics: Default::default(),
            failed: true,
            error: Some("the rollout panicked".into()),
        },
    }
}
