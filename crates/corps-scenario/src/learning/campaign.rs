//! A learning campaign's runs: each repeat is one constrained (1+1)-CMA-ES (`corps_learn`)
//! on the log10 of the free weights, from the start weights on the first of up to
//! [`START_DRAWS`] draws of the conditions they pass (the search needs a feasible start); an evaluation first checks the weights' bounds, then
//! runs K rollouts through the campaign's executor ([`super::executor`]: this machine's
//! threads by default) (the bound and the rollouts' joint-limit and torque
//! constraints before any fitness is taken: an infeasible candidate's fitness is never
//! computed) and averages their fitness. Every random draw comes from the campaign's seed, the
//! repeat, the iteration and the condition, so results are the same on any number of threads,
//! and a repeat interrupted part-way replays from its recorded evaluations.

use super::executor::{Local, RolloutExecutor, RolloutJob, RolloutResult};
use super::fitness::{fitness, rollout_constraints};
use super::rollout::{rollout_scenario, rollout_seed, run_rollout};
use super::LearnConfig;
use crate::error::{bail, invalid, Result};
use crate::scenario::Scenario;
use crate::ScenarioError;
use corps_learn::{OnePlusOne, Settings, StepOutcome};
use std::cell::RefCell;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// Draws of the randomized conditions the start weights get to find one they pass.
pub const START_DRAWS: usize = 20;

/// One evaluation, as `evaluations.csv` keeps it.
#[derive(Clone, Debug, PartialEq)]
pub struct Evaluation {
    pub repeat: usize,
    /// 0 is the start point, then the optimizer's iterations from 1.
    pub iteration: usize,
    /// Mean ϕ over the conditions (None: infeasible, never computed).
    pub fitness: Option<f64>,
    pub feasible: bool,
    /// Every weight of the campaign (the fixed ones too), in its order.
    pub weights: Vec<f64>,
    /// The largest joint-limit excursion (rad, ≤ 0: none) and |τ| − limit (N·m) over the
    /// rollouts (None: the bounds rejected the weights before any rollout).
    pub constraints: Option<[f64; 2]>,
    /// Rollouts that fell, failed their QP or could not run.
    pub failed_rollouts: usize,
    /// The best fitness of the repeat after this evaluation.
    pub best_fitness: f64,
    /// The first rollout error, with its seed.
    pub error: Option<String>,
}

/// A repeat's outcome.
#[derive(Clone, Debug, PartialEq)]
pub struct RepeatResult {
    pub repeat: usize,
    pub best_weights: Vec<f64>,
    pub best_fitness: f64,
}

/// The campaign's rollout scenario and settings, ready to run repeats.
pub struct Campaign {
    pub config: LearnConfig,
    scenario: Scenario,
    base_dir: PathBuf,
    /// The campaign file's directory (test runs' robot files are relative to it).
    dir: PathBuf,
    /// Where the rollouts run.
    executor: Box<dyn RolloutExecutor>,
    /// The test rollout and its directory, if the campaign tests.
    test: Option<(Scenario, PathBuf)>,
    /// Training rollouts run so far (replayed ones not counted).
    rollouts: std::sync::atomic::AtomicUsize,
}

/// One test of one weight vector.
#[derive(Clone, Debug, PartialEq)]
pub struct TestOutcome {
    pub run: String,
    pub success: bool,
    /// Touchdowns of both feet before the run ended.
    pub steps: usize,
    pub verdict: String,
}

impl Campaign {
    /// Reads the rollout scenario (relative to `dir`, the campaign file's directory) and
    /// checks that the weights' keys reach the controller's gains by building one rollout.
    pub fn new(config: LearnConfig, dir: &Path) -> Result<Campaign> {
        let path = dir.join(&config.scenario);
        let text = crate::overrides::read_file(&path).map_err(|e| invalid!("scenario: {e}"))?;
        let scenario = Scenario::parse(&text).map_err(|e| invalid!("{}: {e}", path.display()))?;
        if scenario.controller.is_none() {
            bail!(
                "scenario: {} has no [controller] to learn the weights of",
                path.display()
            );
        }
        let base_dir = path.parent().unwrap_or(Path::new("")).to_path_buf();
        let test = match &config.test {
            Some(t) => {
                let path = dir.join(&t.scenario);
                let text = crate::overrides::read_file(&path)
                    .map_err(|e| invalid!("test.scenario: {e}"))?;
                let s = Scenario::parse(&text).map_err(|e| invalid!("{}: {e}", path.display()))?;
                Some((s, path.parent().unwrap_or(Path::new("")).to_path_buf()))
            }
            None => None,
        };
        let campaign = Campaign {
            config,
            scenario,
            base_dir,
            dir: dir.to_path_buf(),
            executor: Box::new(Local),
            test,
            rollouts: Default::default(),
        };
        let start: Vec<f64> = campaign.config.weights.iter().map(|w| w.start).collect();
        let probe = rollout_scenario(&campaign.scenario, &campaign.config, &start, false, 0);
        crate::run::ScenarioRun::new(
            &probe,
            "probe",
            &campaign.base_dir,
            crate::run::RunOptions::default(),
        )
        .map_err(|e| invalid!("the start weights in {}: {e}", path.display()))?;
        // Each test run builds too (its robot, its conditions), before any training.
        if let (Some(spec), Some((scenario, base_dir))) = (&campaign.config.test, &campaign.test) {
            for (k, run) in spec.runs.iter().enumerate() {
                let mut s = rollout_scenario(scenario, &campaign.config, &start, false, 0);
                s.robot = crate::scenario::RobotSection::from_argument(&test_robot(run, dir));
                crate::run::ScenarioRun::new(
                    &s,
                    "probe",
                    base_dir,
                    crate::run::RunOptions::default(),
                )
                .map_err(|e| invalid!("test.runs[{k}] ('{}'): {e}", run.name))?;
            }
        }
        Ok(campaign)
    }

    /// Training rollouts run so far by this campaign (not the replayed ones).
    pub fn rollouts(&self) -> usize {
        self.rollouts.load(std::sync::atomic::Ordering::Relaxed)
    }

    /// Runs the rollouts through `executor` instead of this machine's threads.
    pub fn with_executor(mut self, executor: Box<dyn RolloutExecutor>) -> Campaign {
        self.executor = executor;
        self
    }

    /// Where the rollouts run ("2 threads", …).
    pub fn executor(&self) -> String {
        self.executor.describe()
    }

    /// Runs one rollout here, as every executor must: the training scenario or a test run,
    /// with the job's weights and seed. Never fails: a rollout that cannot run, panics or
    /// falls is a failed result with its reason.
    pub fn run_job(&self, job: &RolloutJob) -> RolloutResult {
        let c = &self.config;
        let outcome = match job.test_run {
            None => {
                let s = rollout_scenario(&self.scenario, c, &job.weights, c.randomize, job.seed);
                run_rollout(&s, &self.base_dir)
            }
            Some(k) => match (&c.test, &self.test) {
                (Some(spec), Some((scenario, base_dir))) if k < spec.runs.len() => {
                    let run = &spec.runs[k];
                    let mut config = c.clone();
                    config.randomization = run.randomization.clone();
                    let mut s =
                        rollout_scenario(scenario, &config, &job.weights, run.randomize, job.seed);
                    s.robot =
                        crate::scenario::RobotSection::from_argument(&test_robot(run, &self.dir));
                    run_rollout(&s, base_dir)
                }
                _ => super::rollout::RolloutOutcome {
                    metrics: Default::default(),
                    failed: true,
                    error: Some(format!("the campaign has no test run {k}")),
                },
            },
        };
        RolloutResult {
            fitness: fitness(c.fitness, &outcome, c.penalty),
            constraints: rollout_constraints(c, &outcome),
            failed: outcome.failed,
            steps: outcome.metrics.feet.iter().map(|f| f.landings).sum(),
            verdict: outcome.metrics.verdict.to_string(),
            error: outcome.error,
        }
    }

    /// Runs every test of the campaign on each candidate's weights, all through the
    /// executor in one batch; candidate k's run j is seeded from the campaign's seed, k and j.
    pub fn test(&self, candidates: &[Vec<f64>]) -> Result<Vec<Vec<TestOutcome>>> {
        let Some(spec) = &self.config.test else {
            return Ok(vec![Vec::new(); candidates.len()]);
        };
        let runs = spec.runs.len();
        let jobs: Vec<RolloutJob> = (candidates.iter().enumerate())
            .flat_map(|(k, weights)| {
                let seed = rollout_seed(self.config.seed, k, usize::MAX - 2, 0);
                (0..runs).map(move |j| RolloutJob {
                    test_run: Some(j),
                    weights: weights.clone(),
                    seed: rollout_seed(seed, j, usize::MAX - 1, 0),
                })
            })
            .collect();
        let results = self.execute(&jobs)?;
        Ok(results
            .chunks(runs.max(1))
            .map(|chunk| {
                (chunk.iter().zip(&spec.runs))
                    .map(|(r, run)| TestOutcome {
                        run: run.name.clone(),
                        success: !r.failed && r.steps >= spec.steps,
                        steps: r.steps,
                        verdict: r.error.clone().unwrap_or_else(|| r.verdict.clone()),
                    })
                    .collect()
            })
            .collect())
    }

    /// `jobs` through the executor, checked to come back one result each.
    fn execute(&self, jobs: &[RolloutJob]) -> Result<Vec<RolloutResult>> {
        let results = self
            .executor
            .run(self, jobs)
            .map_err(ScenarioError::Rollouts)?;
        if results.len() != jobs.len() {
            return Err(ScenarioError::Rollouts(format!(
                "{} results for {} rollouts",
                results.len(),
                jobs.len()
            )));
        }
        Ok(results)
    }

    /// Every weight from the free ones' log10 values `theta`.
    fn weights(&self, theta: &[f64]) -> Vec<f64> {
        let mut free = theta.iter();
        (self.config.weights.iter())
            .map(|w| {
                if w.fixed() {
                    w.start
                } else {
                    free.next().map_or(w.start, |t| 10f64.powf(*t))
                }
            })
            .collect()
    }

    /// The K rollouts of one evaluation, through the executor: mean ϕ, the constraints'
    /// worst values, failed rollouts and the first error.
    fn evaluate(
        &self,
        weights: &[f64],
        seed: u64,
        repeat: usize,
        iteration: usize,
        attempt: usize,
    ) -> Result<(f64, [f64; 2], usize, Option<String>)> {
        let c = &self.config;
        let jobs: Vec<RolloutJob> = (0..c.conditions)
            .map(|k| RolloutJob {
                test_run: None,
                weights: weights.to_vec(),
                seed: rollout_seed(seed, repeat, iteration, k + attempt * c.conditions),
            })
            .collect();
        let results = self.execute(&jobs)?;
        self.rollouts
            .fetch_add(jobs.len(), std::sync::atomic::Ordering::Relaxed);
        let mut phi = 0.0;
        let mut g = [f64::NEG_INFINITY; 2];
        let mut failed = 0;
        let mut error = None;
        for (job, r) in jobs.iter().zip(&results) {
            phi += r.fitness;
            for (gi, v) in g.iter_mut().zip(r.constraints) {
                *gi = gi.max(v);
            }
            if r.failed {
                failed += 1;
                if error.is_none() {
                    error = Some(format!(
                        "seed {}: {}",
                        job.seed,
                        r.error.clone().unwrap_or_else(|| r.verdict.clone())
                    ));
                }
            }
        }
        Ok((phi / results.len() as f64, g, failed, error))
    }

    /// Runs repeat `repeat` for `iterations`, calling `record` after each evaluation.
    /// `known` holds evaluations already made (an interrupted run's file): those are replayed,
    /// not run again; their weights must be the ones the replay draws. `stop` returning true
    /// ends the repeat between two evaluations (`ScenarioError::Interrupted`).
    pub fn run_repeat(
        &self,
        repeat: usize,
        iterations: usize,
        known: &BTreeMap<usize, Evaluation>,
        record: &(dyn Fn(&Evaluation) + Sync),
        stop: &(dyn Fn() -> bool + Sync),
    ) -> Result<RepeatResult> {
        let c = &self.config;
        let free: Vec<_> = c.free().collect();
        let lower: Vec<f64> = free.iter().map(|w| w.lower.log10()).collect();
        let upper: Vec<f64> = free.iter().map(|w| w.upper.log10()).collect();
        let theta0: Vec<f64> = free.iter().map(|w| w.start.log10()).collect();
        let n = free.len();
        let seed = c.seed;
        // The evaluation of the candidate in hand, shared by the constraint and fitness calls.
        let current: RefCell<Option<Evaluation>> = RefCell::new(None);
        let iteration = std::cell::Cell::new(0usize);
        let failure: RefCell<Option<crate::ScenarioError>> = RefCell::new(None);
        let g = |theta: &[f64], out: &mut [f64]| {
            let it = iteration.get();
            let weights = self.weights(theta);
            for k in 0..n {
                out[2 * k] = theta[k] - upper[k];
                out[2 * k + 1] = lower[k] - theta[k];
            }
            let in_bounds = out[..2 * n].iter().all(|v| *v <= 0.0);
            let mut e = Evaluation {
                repeat,
                iteration: it,
                fitness: None,
                feasible: false,
                weights: weights.clone(),
                constraints: None,
                failed_rollouts: 0,
                best_fitness: f64::NAN,
                error: None,
            };
            let rollout = if let Some(k) = known.get(&it) {
                if !same_weights(&k.weights, &weights) {
                    failure.borrow_mut().get_or_insert_with(|| {
                        invalid!(
                            "evaluations.csv: repeat {repeat}, iteration {it} has other weights than this campaign draws (another campaign's file?)"
                        )
                    });
                }
                e.fitness = k.fitness;
                e.failed_rollouts = k.failed_rollouts;
                e.error = k.error.clone();
                k.constraints
            } else if in_bounds {
                // The start needs to be feasible: it takes the first of its draws of the
                // conditions it passes (a fair parent for the candidates, which get one draw).
                let attempts = if it == 0 && c.randomize {
                    START_DRAWS
                } else {
                    1
                };
                let mut result = self.evaluate(&weights, seed, repeat, it, 0);
                for attempt in 1..attempts {
                    if !matches!(&result, Ok(r) if r.1.iter().any(|g| *g > 0.0)) {
                        break;
                    }
                    result = self.evaluate(&weights, seed, repeat, it, attempt);
                }
                match result {
                    Ok((phi, gc, failed, error)) => {
                        e.fitness = Some(phi);
                        e.failed_rollouts = failed;
                        e.error = error;
                        Some(gc)
                    }
                    Err(err) => {
                        failure.borrow_mut().get_or_insert(err);
                        None
                    }
                }
            } else {
                None
            };
            e.constraints = rollout;
            let gc = rollout.unwrap_or([-1.0, -1.0]);
            out[2 * n] = gc[0];
            out[2 * n + 1] = gc[1];
            e.feasible = out.iter().all(|v| *v <= 0.0);
            if !e.feasible {
                e.fitness = None;
            }
            *current.borrow_mut() = Some(e);
        };
        let f = |_: &[f64]| {
            let phi = current.borrow().as_ref().and_then(|e| e.fitness);
            phi.map_or(f64::INFINITY, |p| -p)
        };
        let constraints = 2 * n + 2;
        let mut es = OnePlusOne::new(&theta0, constraints, Settings {
            sigma0: c.sigma0,
            seed: rollout_seed(seed, repeat, usize::MAX, 0),
        }, g, f)
        .map_err(|e| match (failure.borrow_mut().take(), current.borrow().as_ref()) {
            (Some(err), _) => err,
            (None, Some(ev)) if !ev.feasible => invalid!(
                "repeat {repeat}: the start weights are infeasible in every one of their first rollouts (the last: {}): {e}",
                match ev.constraints {
                    Some([joints, torque]) => format!(
                        "a joint {joints:+.3} rad past its limit's tolerance, |τ| {torque:+.1} N·m past {} N·m{}",
                        c.torque_limit,
                        ev.error.as_ref().map_or(String::new(), |e| format!("; {e}"))
                    ),
                    None => "outside the weights' bounds".into(),
                }
            ),
            (None, _) => invalid!("{e}"),
        })?;
        if let Some(err) = failure.borrow_mut().take() {
            return Err(err);
        }
        let emit = |es: &OnePlusOne| {
            if let Some(mut e) = current.borrow_mut().take() {
                e.best_fitness = -es.best_fitness();
                record(&e);
            }
        };
        emit(&es);
        for it in 1..=iterations {
            if stop() {
                return Err(crate::ScenarioError::Interrupted { t: 0.0 });
            }
            iteration.set(it);
            let outcome = es.step(g, f);
            if let Some(err) = failure.borrow_mut().take() {
                return Err(err);
            }
            debug_assert!(
                !matches!(outcome, StepOutcome::Infeasible { .. })
                    || current.borrow().as_ref().is_some_and(|e| !e.feasible)
            );
            emit(&es);
        }
        Ok(RepeatResult {
            repeat,
            best_weights: self.weights(es.best()),
            best_fitness: -es.best_fitness(),
        })
    }
}

/// A test run's robot: a built-in name, or a description file relative to the campaign.
fn test_robot(run: &super::TestRun, dir: &Path) -> String {
    if run.robot.ends_with(".toml") {
        dir.join(&run.robot).display().to_string()
    } else {
        run.robot.clone()
    }
}

/// The weights a replay draws against those recorded (written with 17 significant digits).
fn same_weights(a: &[f64], b: &[f64]) -> bool {
    a.len() == b.len()
        && a.iter()
            .zip(b)
            .all(|(x, y)| (x - y).abs() <= 1e-12 * x.abs().max(y.abs()).max(1e-300))
}
