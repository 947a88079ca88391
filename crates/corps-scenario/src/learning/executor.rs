//! Where a campaign's rollouts run. An executor gets a batch of [`RolloutJob`]s and returns,
//! in the same order, what [`Campaign::run_job`] returns for each: [`Local`] runs them on
//! this machine's threads (rayon); another executor (a cluster's tasks, each calling
//! `run_job` in its own process) must do the same, so a campaign ends identically wherever
//! its rollouts run.

use super::campaign::Campaign;
use rayon::prelude::*;

/// One rollout: the training scenario (`test_run` None) or test run `test_run` of the
/// campaign, the candidate's weights (every weight, the fixed ones too) and its seed.
#[derive(Clone, Debug, PartialEq)]
pub struct RolloutJob {
    pub test_run: Option<usize>,
    pub weights: Vec<f64>,
    pub seed: u64,
}

/// What a campaign keeps of one rollout.
#[derive(Clone, Debug, PartialEq)]
pub struct RolloutResult {
    /// ϕ of the rollout (seed 001 Eq 5.17–5.18, the penalty included).
    pub fitness: f64,
    /// The joint-limit and torque constraints, feasible where ≤ 0.
    pub constraints: [f64; 2],
    /// It fell, failed its QP, diverged or could not run.
    pub failed: bool,
    /// Why it could not run, if it could not.
    pub error: Option<String>,
    /// Touchdowns of both feet before it ended.
    pub steps: usize,
    /// The run's verdict (`completed`, `fell`, …).
    pub verdict: String,
}

/// Runs batches of rollouts.
pub trait RolloutExecutor: Send + Sync {
    /// The results of `jobs`, in their order; an error (the executor itself failed, not a
    /// rollout: those are failed results) stops the campaign, which resumes from its file.
    fn run(&self, campaign: &Campaign, jobs: &[RolloutJob]) -> Result<Vec<RolloutResult>, String>;
    /// Where the rollouts run, for the summary ("2 threads", "a Ray cluster").
    fn describe(&self) -> String;
}

/// This machine's threads (rayon's pool).
#[derive(Clone, Copy, Debug, Default)]
pub struct Local;

impl RolloutExecutor for Local {
    fn run(&self, campaign: &Campaign, jobs: &[RolloutJob]) -> Result<Vec<RolloutResult>, String> {
        Ok(jobs.par_iter().map(|j| campaign.run_job(j)).collect())
    }
    fn describe(&self) -> String {
        format!("{} threads", rayon::current_num_threads())
    }
}
