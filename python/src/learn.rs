//! `_corps.learn` and `_corps.learning_rollout`: a learning campaign (seed 001 ch. 5) run
//! from Python with the files `corps learn` writes, its rollouts on this machine's threads or
//! handed in batches to a Python callable (a cluster's map, `corps.learn.RayMap`); and the one
//! rollout such a callable's workers run, the same as this machine would run it.

use crate::errors::scenario_error;
use corps_scenario::learning::campaign::Campaign;
use corps_scenario::learning::executor::{RolloutExecutor, RolloutJob, RolloutResult};
use corps_scenario::learning::LearnConfig;
use pyo3::prelude::*;
use std::collections::HashMap;
use std::path::PathBuf;
use std::sync::atomic::Ordering;
use std::sync::{Arc, Mutex};

/// A job as Python sees it: (test run or None, weights, seed).
type JobTuple = (Option<usize>, Vec<f64>, u64);
/// A result as Python sees it: (fitness, joint-limit constraint, torque constraint, failed,
/// error or None, steps, verdict).
type ResultTuple = (f64, f64, f64, bool, Option<String>, usize, String);

fn job_tuple(j: &RolloutJob) -> JobTuple {
    (j.test_run, j.weights.clone(), j.seed)
}

fn result_tuple(r: RolloutResult) -> ResultTuple {
    let [g0, g1] = r.constraints;
    (r.fitness, g0, g1, r.failed, r.error, r.steps, r.verdict)
}

/// Rollouts handed to a Python callable: `map(jobs) -> results`, one result per job, in order.
struct PythonMap {
    map: Py<PyAny>,
    description: String,
}

impl RolloutExecutor for PythonMap {
    fn run(&self, _: &Campaign, jobs: &[RolloutJob]) -> Result<Vec<RolloutResult>, String> {
        Python::attach(|py| {
            let jobs: Vec<JobTuple> = jobs.iter().map(job_tuple).collect();
            let out = self.map.call1(py, (jobs,)).map_err(|e| e.to_string())?;
            let results: Vec<ResultTuple> = out
                .extract(py)
                .map_err(|e| format!("the map returned something else than results: {e}"))?;
            Ok(results
                .into_iter()
                .map(
                    |(fitness, g0, g1, failed, error, steps, verdict)| RolloutResult {
                        fitness,
                        constraints: [g0, g1],
                        failed,
                        error,
                        steps,
                        verdict,
                    },
                )
                .collect())
        })
    }
    fn describe(&self) -> String {
        self.description.clone()
    }
}

/// Runs the campaign file `campaign` as `corps learn` does (same files in `output`, same
/// resume, same summary, returned); `map`, if given, runs every batch of rollouts.
#[pyfunction]
#[pyo3(signature = (campaign, iterations=None, repeats=None, seed=None, output=None, map=None, description=None))]
#[allow(clippy::too_many_arguments)]
pub fn learn(
    py: Python<'_>,
    campaign: PathBuf,
    iterations: Option<usize>,
    repeats: Option<usize>,
    seed: Option<u64>,
    output: Option<PathBuf>,
    map: Option<Py<PyAny>>,
    description: Option<String>,
) -> PyResult<String> {
    let args = corps::learn::LearnArgs {
        campaign,
        iterations,
        repeats,
        seed,
        output,
    };
    let executor = map.map(|map| {
        Box::new(PythonMap {
            map,
            description: description.unwrap_or_else(|| "a Python map".into()),
        }) as Box<dyn RolloutExecutor>
    });
    // The campaign runs on its own thread; this one polls Python's signal handlers (the main
    // thread is the only one that runs them) and turns Ctrl-C into the campaign's stop flag.
    let flag = &corps::interrupt::FLAG;
    flag.store(false, Ordering::SeqCst);
    let mut interrupt = None;
    let result = std::thread::scope(|scope| {
        let campaign = scope.spawn(move || corps::learn::run_with(args, executor));
        while !campaign.is_finished() {
            py.detach(|| std::thread::sleep(SIGNAL_POLL));
            if interrupt.is_none() {
                if let Err(e) = py.check_signals() {
                    interrupt = Some(e);
                    flag.store(true, Ordering::SeqCst);
                }
            }
        }
        campaign.join()
    });
    flag.store(false, Ordering::SeqCst);
    let result = result.map_err(|_| scenario_error("the campaign's thread panicked"))?;
    match (result, interrupt) {
        (Ok(text), None) => Ok(text),
        (Err(e), Some(signal)) if e.is::<corps::learn::CampaignInterrupted>() => Err(signal),
        (Err(e), _) => Err(scenario_error(format!("{e:#}"))),
        (Ok(_), Some(signal)) => Err(signal),
    }
}

/// How often a campaign run from Python checks for Ctrl-C.
const SIGNAL_POLL: std::time::Duration = std::time::Duration::from_millis(50);

/// Campaigns a worker has built, by the file's path and the driver's text of it.
type Campaigns = Mutex<HashMap<(PathBuf, String), Arc<Campaign>>>;
static CAMPAIGNS: std::sync::OnceLock<Campaigns> = std::sync::OnceLock::new();

/// One rollout of the campaign file `campaign` whose text is `text` (the driver's copy: a
/// worker reads the campaign from it, not from its own file, and the scenarios and robots
/// relative to `campaign`'s directory), `job` = (test run or None, weights, seed), run here:
/// what a cluster's worker calls. Returns (fitness, joint-limit constraint, torque
/// constraint, failed, error, steps, verdict).
#[pyfunction]
pub fn learning_rollout(
    py: Python<'_>,
    campaign: PathBuf,
    text: String,
    job: JobTuple,
) -> PyResult<ResultTuple> {
    let key = (campaign.clone(), text);
    let cache = CAMPAIGNS.get_or_init(Default::default);
    let cached = cache
        .lock()
        .unwrap_or_else(|p| p.into_inner())
        .get(&key)
        .cloned();
    let c = match cached {
        Some(c) => c,
        None => {
            let (config, dir) = LearnConfig::parse(&key.1, &campaign).map_err(scenario_error)?;
            let c = py
                .detach(|| Campaign::new(config, &dir))
                .map_err(|e| scenario_error(format!("{}: {e}", campaign.display())))?;
            let c = Arc::new(c);
            cache
                .lock()
                .unwrap_or_else(|p| p.into_inner())
                .insert(key, c.clone());
            c
        }
    };
    let (test_run, weights, seed) = job;
    let job = RolloutJob {
        test_run,
        weights,
        seed,
    };
    Ok(result_tuple(py.detach(|| c.run_job(&job))))
}
