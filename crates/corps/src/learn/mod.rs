//! `corps learn CAMPAIGN`: learns a controller's task weights (seed 001 ch. 5) with the
//! library's campaign ([`corps_scenario::learning`]): the repeats run in parallel, each
//! evaluation's randomized rollouts too; every evaluation is appended to
//! `DIR/evaluations.csv` as it ends (a rerun with the same directory resumes: recorded
//! evaluations are replayed, not run again), the learned weights go to `DIR/learned.csv` and
//! the best fitness over iterations (mean and spread over the repeats) to `DIR/fitness.png`.

mod csv;
mod plot;

use anyhow::{anyhow, bail, Context, Result};
use clap::Args;
use corps_scenario::learning::campaign::{Campaign, Evaluation};
use corps_scenario::learning::executor::RolloutExecutor;
use corps_scenario::learning::LearnConfig;
use indicatif::{ProgressBar, ProgressStyle};
use rayon::prelude::*;
use std::collections::BTreeMap;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::time::Instant;

#[derive(Args)]
pub struct LearnArgs {
    /// The campaign file (TOML): rollout scenario, weights, fitness, randomization.
    pub campaign: PathBuf,
    /// Iterations of the optimizer per repeat (replaces the campaign's).
    #[arg(long)]
    pub iterations: Option<usize>,
    /// Independent repeats (replaces the campaign's).
    #[arg(long)]
    pub repeats: Option<usize>,
    /// The campaign's seed (replaces the campaign's).
    #[arg(long)]
    pub seed: Option<u64>,
    /// Output directory (default `out/learn/<campaign name>`); an interrupted campaign's
    /// directory resumes it.
    #[arg(short, long)]
    pub output: Option<PathBuf>,
}

pub fn run(args: LearnArgs) -> Result<()> {
    match run_with(args, None) {
        Ok(text) => crate::stdout::print(&text),
        Err(e) => match e.downcast_ref::<CampaignInterrupted>() {
            Some(stop) => {
                eprintln!("corps: {stop}");
                std::process::exit(crate::interrupt::EXIT_STATUS);
            }
            None => Err(e),
        },
    }
}

/// A campaign stopped by Ctrl-C ([`crate::interrupt::FLAG`]) between two evaluations.
#[derive(Debug, thiserror::Error)]
#[error(
    "interrupted; {evaluations} holds every evaluation so far: rerun the same command to resume"
)]
pub struct CampaignInterrupted {
    /// The campaign's `evaluations.csv`.
    pub evaluations: String,
}

/// Runs the campaign `args` name, its rollouts on `executor` (None: this machine's threads),
/// and returns the summary `corps learn` prints.
pub fn run_with(args: LearnArgs, executor: Option<Box<dyn RolloutExecutor>>) -> Result<String> {
    let text = corps_scenario::overrides::read_file(&args.campaign).map_err(|e| anyhow!("{e}"))?;
    let (mut config, dir) =
        LearnConfig::parse(&text, &args.campaign).map_err(|e| anyhow!("{e}"))?;
    if let Some(n) = args.iterations {
        config.iterations = n;
    }
    if let Some(n) = args.repeats {
        config.repeats = n;
    }
    if let Some(s) = args.seed {
        config.seed = s;
    }
    config
        .check()
        .map_err(|e| anyhow!("{}: {e}", args.campaign.display()))?;
    let name = args
        .campaign
        .file_stem()
        .map_or("campaign".into(), |s| s.to_string_lossy().into_owned());
    let out = args
        .output
        .unwrap_or_else(|| Path::new("out/learn").join(&name));
    let mut campaign =
        Campaign::new(config, &dir).map_err(|e| anyhow!("{}: {e}", args.campaign.display()))?;
    if let Some(executor) = executor {
        campaign = campaign.with_executor(executor);
    }
    let c = &campaign.config;
    let names: Vec<String> = c.weights.iter().map(|w| w.name.clone()).collect();
    std::fs::create_dir_all(&out).with_context(|| format!("creating {}", out.display()))?;
    let evaluations = out.join("evaluations.csv");
    // The campaign a directory holds: its file's text and seed; a rerun resumes only the same
    // campaign (more iterations or repeats may be asked).
    let fingerprint = format!("seed = {}\n{text}", c.seed);
    let stamp = out.join("campaign.toml");
    match std::fs::read_to_string(&stamp) {
        Ok(old) if old != fingerprint => bail!(
            "{}: holds another campaign (or this one with another seed): choose another -o",
            out.display()
        ),
        Ok(_) => {}
        Err(_) if evaluations.exists() => bail!(
            "{}: has evaluations but no campaign.toml to tell which campaign they are: choose another -o",
            out.display()
        ),
        Err(_) => {}
    }
    let known = csv::read(&evaluations, &names)?;
    let resumed: usize = known.values().map(BTreeMap::len).sum();
    std::fs::write(&stamp, &fingerprint).with_context(|| format!("writing {}", stamp.display()))?;
    let file = csv::open_for_append(&evaluations, &names)?;
    let file = Mutex::new(file);

    let total = (c.repeats * (c.iterations + 1)) as u64;
    let bar = ProgressBar::new(total);
    if let Ok(style) = ProgressStyle::with_template(
        "learning [{bar:40}] {pos}/{len} evaluations  {msg}  eta {eta}",
    ) {
        bar.set_style(style.progress_chars("=> "));
    }
    if !std::io::IsTerminal::is_terminal(&std::io::stderr()) {
        bar.set_draw_target(indicatif::ProgressDrawTarget::hidden());
    }
    let start = Instant::now();
    let best = Mutex::new(f64::NEG_INFINITY);
    let write_error: Mutex<Option<std::io::Error>> = Mutex::new(None);
    let record = |e: &Evaluation| {
        let replayed = known
            .get(&e.repeat)
            .is_some_and(|m| m.contains_key(&e.iteration));
        if !replayed {
            if let Ok(mut f) = file.lock() {
                let line = format!("{}\n", csv::row(e));
                if let Err(err) = f.write_all(line.as_bytes()).and_then(|_| f.flush()) {
                    write_error.lock().map(|mut w| *w = Some(err)).ok();
                }
            }
        }
        let b = {
            let mut b = best.lock().unwrap_or_else(|p| p.into_inner());
            *b = b.max(e.best_fitness);
            *b
        };
        let done = campaign.rollouts();
        bar.set_message(format!(
            "best fitness {b:.4}, {:.1} rollouts/s",
            done as f64 / start.elapsed().as_secs_f64().max(1e-9)
        ));
        bar.inc(1);
    };
    let empty = BTreeMap::new();
    // A repeat that fails stops the others at their next evaluation.
    let abort = std::sync::atomic::AtomicBool::new(false);
    let stop = || {
        crate::interrupt::FLAG.load(std::sync::atomic::Ordering::Relaxed)
            || abort.load(std::sync::atomic::Ordering::Relaxed)
    };
    let results: Vec<_> = (0..c.repeats)
        .into_par_iter()
        .map(|r| {
            let result =
                campaign.run_repeat(r, c.iterations, known.get(&r).unwrap_or(&empty), &record, &stop);
            if matches!(&result, Err(e) if !matches!(e, corps_scenario::ScenarioError::Interrupted { .. })) {
                abort.store(true, std::sync::atomic::Ordering::Relaxed);
            }
            result
        })
        .collect();
    bar.finish_and_clear();
    let training = start.elapsed().as_secs_f64();
    let rollouts_run = campaign.rollouts();
    if let Some(err) = write_error.into_inner().unwrap_or(None) {
        bail!("writing {}: {err}", evaluations.display());
    }
    // A failed repeat's error first (the others stopped because of it).
    if let Some(Err(e)) = results.iter().find(
        |r| matches!(r, Err(e) if !matches!(e, corps_scenario::ScenarioError::Interrupted { .. })),
    ) {
        bail!("{}: {e}", args.campaign.display());
    }
    let mut learned = Vec::with_capacity(results.len());
    for r in results {
        match r {
            Ok(r) => learned.push(r),
            Err(corps_scenario::ScenarioError::Interrupted { .. }) => {
                return Err(CampaignInterrupted {
                    evaluations: evaluations.display().to_string(),
                }
                .into())
            }
            Err(e) => bail!("{}: {e}", args.campaign.display()),
        }
    }
    let rows = csv::read(&evaluations, &names)?;
    csv::write_learned(&out.join("learned.csv"), &names, &learned)?;
    plot::fitness(&out.join("fitness.png"), &name, c.iterations, &rows)?;
    let mut text = format!(
        "{name}: {} repeats × {} iterations, fitness {}, {} conditions per evaluation{}; {} evaluations replayed from an earlier run\n  training: {rollouts_run} rollouts in {training:.1} s ({:.1} rollouts/s on {})\n",
        c.repeats,
        c.iterations,
        c.fitness.name(),
        c.conditions,
        if c.randomize { ", randomized" } else { "" },
        resumed,
        rollouts_run as f64 / training.max(1e-9),
        campaign.executor()
    );
    for (k, w) in names.iter().enumerate() {
        let v: Vec<f64> = learned.iter().map(|r| r.best_weights[k]).collect();
        let mean = v.iter().sum::<f64>() / v.len() as f64;
        let std = (v.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / v.len() as f64).sqrt();
        text += &format!("  {w}: {mean:.4e} ± {std:.2e}\n");
    }
    if c.test.is_some() {
        // The start weights and each repeat's best, on every test run, in parallel.
        let start: Vec<f64> = c.weights.iter().map(|w| w.start).collect();
        let mut candidates: Vec<(String, Vec<f64>)> = vec![("start".into(), start)];
        let mut sorted: Vec<_> = learned.iter().collect();
        sorted.sort_by_key(|r| r.repeat);
        candidates.extend(
            sorted
                .iter()
                .map(|r| (r.repeat.to_string(), r.best_weights.clone())),
        );
        let weights: Vec<Vec<f64>> = candidates.iter().map(|(_, w)| w.clone()).collect();
        let tested = campaign
            .test(&weights)
            .map_err(|e| anyhow!("{}: testing: {e}", args.campaign.display()))?;
        let outcomes: Vec<_> = candidates
            .iter()
            .map(|(who, _)| who.clone())
            .zip(tested)
            .collect();
        let mut csv_text = String::from("weights,run,success,steps,verdict\n");
        let mut counts: BTreeMap<String, (usize, usize)> = BTreeMap::new();
        let mut start_line = Vec::new();
        for (who, tests) in &outcomes {
            for t in tests {
                csv_text += &format!(
                    "{who},{},{},{},{}\n",
                    t.run,
                    t.success,
                    t.steps,
                    t.verdict.replace([',', '\n'], ";")
                );
                if who == "start" {
                    start_line.push(format!(
                        "{} {}",
                        t.run,
                        if t.success { "1/1" } else { "0/1" }
                    ));
                } else {
                    let e = counts.entry(t.run.clone()).or_default();
                    e.0 += usize::from(t.success);
                    e.1 += 1;
                }
            }
        }
        let tests_path = out.join("tests.csv");
        std::fs::write(&tests_path, csv_text)
            .with_context(|| format!("writing {}", tests_path.display()))?;
        let learned_line: Vec<String> = counts
            .iter()
            .map(|(run, (ok, n))| format!("{run} {ok}/{n}"))
            .collect();
        text += &format!(
            "  tests ({} steps): learned weights {}; start weights {} ({})\n",
            c.test.as_ref().map_or(0, |t| t.steps),
            learned_line.join(", "),
            start_line.join(", "),
            tests_path.display()
        );
    }
    let fits: Vec<f64> = learned.iter().map(|r| r.best_fitness).collect();
    let mean = fits.iter().sum::<f64>() / fits.len() as f64;
    text += &format!(
        "  best fitness: mean {mean:.4}, from {:.4} to {:.4}\nwrote {}, {}, {}\n",
        fits.iter().copied().fold(f64::INFINITY, f64::min),
        fits.iter().copied().fold(f64::NEG_INFINITY, f64::max),
        evaluations.display(),
        out.join("learned.csv").display(),
        out.join("fitness.png").display()
    );
    Ok(text)
}
