//! `corps run SCENARIO.toml`: a whole-body controller drives the simulated robot through a
//! reference motion. The robot first settles under the joint PD hold (`[controller] settle`),
//! then the controller takes over; pushes count from the handover. After the run the metrics
//! are printed and written (`metrics.txt`, `metrics.json`) with the log (`log.csv`) and the
//! plots.
//!
//! The scenario file is `corps sim`'s (robot, terrain, initial state, simulator settings,
//! pushes, output) plus `[controller]` and `[motion]`:
//!
//! ```toml
//! duration = 10.0                   # controlled time (s)
//! [controller]
//! kind = "tsid_torque"              # ik_position | tsid_position | tsid_torque
//! gains = "tsid_torque_walk"      # optional: a name of the robot's [gains] or a file;
//!                                 # absent: the robot's gains for the kind
//! [motion]
//! kind = "com_sinusoid"             # stand | com_sinusoid | squat | one_foot
//! amplitude = [0.0, 0.03, 0.0]
//! frequency = 0.5
//! ```

mod plots;
mod top_view;

pub use corps_scenario::controller::{ControllerKind, ControllerSection, MAX_SETTLE};
pub use corps_scenario::estimation::{EstimatorKind, EstimatorSection};
pub use corps_scenario::metrics::{
    Comparison, DynamicFilterMetrics, FootMetrics, Metrics, Stat, ThesisFigures, TickTime,
    TickTimer, WalkMetrics, WalkingErrors,
};
pub use corps_scenario::sensor_profile::SensorProfile;
pub use corps_sim::Overlap;

use crate::output;
use crate::output::recording::{OperatorView, Recording, RecordingScene, RECORDING_NAME};
use crate::progress::Progress;
use anyhow::{anyhow, bail, Context, Result};
use clap::Args;
use corps_loop::verdict::Verdict;
use corps_scenario::overrides::Overrides;
use corps_scenario::run::{RowSink, ScenarioRun};
use corps_scenario::scenario::Scenario;
use corps_scenario::ScenarioError;
use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;

/// Arguments of `corps run`.
#[derive(Args)]
pub struct RunArgs {
    /// Scenario file (TOML) with a [controller] section; see `scenarios/`.
    scenario: PathBuf,
    /// Output directory (default: `[output] directory` of the scenario, else `out/<name>`).
    #[arg(short, long)]
    output: Option<PathBuf>,
    /// Control this many seconds instead of the scenario's `duration`.
    #[arg(long, value_name = "SECONDS")]
    duration: Option<f64>,
    /// Run everything on one thread (the same as `--overlap never`).
    #[arg(long, conflicts_with = "overlap")]
    serial: bool,
    /// Whether the simulator prepares its next step on a second thread while the controller
    /// computes: `adaptive` (the default on two cores or more) overlaps while the run's own
    /// tick times show it gains, `always`, or `never`. The results are bit-identical.
    #[arg(long, value_name = "MODE")]
    overlap: Option<OverlapArg>,
    /// Size cap of the log in MB (replaces `[output] max_log_mb`, default 1024).
    #[arg(long, value_name = "MB")]
    max_log_mb: Option<f64>,
    /// What feeds the controller (replaces `[estimator] kind`): `leg-odometry` (the sensors,
    /// the default) or `ground-truth` (the simulator's exact state, for comparison).
    #[arg(long, value_name = "KIND")]
    estimator: Option<EstimatorArg>,
    /// Sensor noise from this file (`seed` and `[noise.<channel>]` tables, as in a scenario),
    /// replacing the scenario's; see `scenarios/sensors/`.
    #[arg(long, value_name = "FILE")]
    noise: Option<PathBuf>,
    /// The robot, replacing the scenario's: `talos`, `icub`, `icub_backpacked`, `simple_humanoid` or a robot
    /// description file (`robots/*/*.toml`).
    #[arg(long, value_name = "ROBOT")]
    robot: Option<String>,
    /// Also write the run for a 3D viewer: `run.mcap` in the output directory (open it in
    /// Foxglove, desktop or https://app.foxglove.dev).
    #[arg(long)]
    record: bool,
}

/// `--estimator` values.
#[derive(Clone, Copy, Debug, clap::ValueEnum)]
enum EstimatorArg {
    LegOdometry,
    GroundTruth,
}

impl From<EstimatorArg> for EstimatorKind {
    fn from(a: EstimatorArg) -> Self {
        match a {
            EstimatorArg::LegOdometry => EstimatorKind::LegOdometry,
            EstimatorArg::GroundTruth => EstimatorKind::GroundTruth,
        }
    }
}

/// `--overlap` values.
#[derive(Clone, Copy, Debug, clap::ValueEnum)]
enum OverlapArg {
    Adaptive,
    Always,
    Never,
}

/// How a run executes, and what replaces the scenario's estimator or sensor noise.
#[derive(Clone, Debug)]
pub struct RunOptions {
    /// Progress on stderr: a bar on a terminal, a line every few seconds otherwise.
    pub progress: bool,
    /// Whether the simulator prepares its next step on a second thread while the controller
    /// computes (bit-identical to the serial run).
    pub overlap: Overlap,
    /// Size cap of the log in MB, replacing the scenario's `[output] max_log_mb`.
    pub max_log_mb: Option<f64>,
    /// Replaces the scenario's `[estimator] kind`.
    pub estimator: Option<EstimatorKind>,
    /// Replaces the scenario's `[noise]` (and its `seed` when the profile gives one).
    pub noise: Option<SensorProfile>,
    /// Replaces the scenario's robot (`--robot`).
    pub robot: Option<String>,
    /// Writes `run.mcap` for a 3D viewer (`--record`).
    pub record: bool,
    /// Raised to stop the run at the next tick: it then writes what it has, marked
    /// interrupted (the command's Ctrl-C, [`crate::interrupt`]).
    pub interrupt: Option<&'static AtomicBool>,
}

impl RunOptions {
    /// No progress, one thread: for tests and tools that run several scenarios at once.
    pub fn quiet() -> Self {
        Self {
            progress: false,
            overlap: Overlap::Never,
            max_log_mb: None,
            estimator: None,
            noise: None,
            robot: None,
            record: false,
            interrupt: None,
        }
    }

    /// What `corps run` does: progress, the adaptive overlap when the machine has two cores
    /// or more, and a clean stop on Ctrl-C.
    pub fn interactive() -> Self {
        let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
        Self {
            progress: true,
            overlap: if cores >= 2 {
                Overlap::Adaptive
            } else {
                Overlap::Never
            },
            max_log_mb: None,
            estimator: None,
            noise: None,
            robot: None,
            record: false,
            interrupt: Some(&crate::interrupt::FLAG),
        }
    }
}

/// Runs `corps run`.
pub fn run(args: RunArgs) -> Result<()> {
    let mut options = RunOptions::interactive();
    options.max_log_mb = args.max_log_mb;
    options.estimator = args.estimator.map(EstimatorKind::from);
    options.noise = args.noise.as_deref().map(SensorProfile::read).transpose()?;
    options.robot = args.robot;
    options.record = args.record;
    match (args.serial, args.overlap) {
        (true, _) | (_, Some(OverlapArg::Never)) => options.overlap = Overlap::Never,
        (_, Some(OverlapArg::Always)) => options.overlap = Overlap::Always,
        (_, Some(OverlapArg::Adaptive)) => options.overlap = Overlap::Adaptive,
        (false, None) => {}
    }
    let report = run_file(
        &args.scenario,
        args.output.as_deref(),
        args.duration,
        options,
    )?;
    print_report(&report)?;
    report.check_interrupted()?;
    report.check_expected()
}

fn print_report(report: &RunReport) -> Result<()> {
    let mut text = format!("{}  wrote {}\n", report.metrics, report.dir.display());
    for p in &report.files {
        text.push_str(&format!("    {}\n", p.display()));
    }
    crate::stdout::print(&text)
}

/// What a run produced.
pub struct RunReport {
    pub metrics: Metrics,
    /// The verdict the scenario expects.
    pub expected: Verdict,
    pub dir: PathBuf,
    pub files: Vec<PathBuf>,
}

impl RunReport {
    /// [`Interrupted`](crate::interrupt::Interrupted) when Ctrl-C stopped the run.
    pub fn check_interrupted(&self) -> Result<()> {
        match self.metrics.interrupted_at {
            Some(t) => Err(crate::interrupt::Interrupted {
                t,
                dir: self.dir.display().to_string(),
            }
            .into()),
            None => Ok(()),
        }
    }

    /// An error when the run ended otherwise than its scenario expects.
    pub fn check_expected(&self) -> Result<()> {
        let v = &self.metrics.verdict;
        if v.verdict != self.expected {
            bail!(
                "the run ended {v} (the scenario expects {}; outputs in {})",
                self.expected,
                self.dir.display()
            );
        }
        Ok(())
    }
}

/// Reads, runs and records the scenario at `path`. `output` replaces the output directory,
/// `duration` the controlled time.
pub fn run_file(
    path: &Path,
    output: Option<&Path>,
    duration: Option<f64>,
    options: RunOptions,
) -> Result<RunReport> {
    let text = crate::sim_cmd::read_scenario(path)?;
    run_text(&text, path, output, duration, options)
}

/// The main job (`corps` without arguments): TALOS walks 6 × 20 cm plus a closing step
/// under the TSID torque controller (`scenarios/walk/tsid_torque_20cm.toml`, built in).
pub const MAIN_JOB: &str = include_str!("../../../../scenarios/walk/tsid_torque_20cm.toml");

/// Runs the main job into `out/tsid_torque_20cm`, with a progress bar.
pub fn run_main_job() -> Result<()> {
    let report = run_text(
        MAIN_JOB,
        Path::new("tsid_torque_20cm.toml"),
        None,
        None,
        RunOptions::interactive(),
    )?;
    print_report(&report)?;
    report.check_interrupted()?;
    report.check_expected()
}

/// Runs scenario `text`, read from `path` (which names the run and anchors relative paths).
pub fn run_text(
    text: &str,
    path: &Path,
    output: Option<&Path>,
    duration: Option<f64>,
    options: RunOptions,
) -> Result<RunReport> {
    let shown = path.display();
    let overrides = Overrides {
        duration,
        max_log_mb: options.max_log_mb,
        robot: options.robot.clone(),
        estimator: options.estimator,
        noise: options.noise.clone(),
    };
    let ParsedRun {
        scenario,
        name,
        base_dir,
        dir,
    } = parse_run(text, path, output, &overrides)?;
    // A context, not a new message, so that the command still sees an `Interrupted`.
    run_scenario(&scenario, &name, base_dir, &dir, options).with_context(|| shown.to_string())
}

/// A scenario read for a run.
pub struct ParsedRun<'a> {
    pub scenario: Scenario,
    /// The run's name (the file's, unless the scenario gives one).
    pub name: String,
    /// Where the scenario's relative paths resolve from.
    pub base_dir: &'a Path,
    /// The output directory: `output`, else `[output] directory`, else `out/<name>`.
    pub dir: PathBuf,
}

/// Parses scenario `text`, read from `path`, with `overrides`; `output` replaces its output
/// directory.
pub fn parse_run<'a>(
    text: &str,
    path: &'a Path,
    output: Option<&Path>,
    overrides: &Overrides,
) -> Result<ParsedRun<'a>> {
    let scenario = Scenario::parse_with(text, path, overrides).map_err(|e| anyhow!(e))?;
    let name = scenario.run_name(path);
    let dir = output
        .map(Path::to_path_buf)
        .or_else(|| scenario.output.directory.clone())
        .unwrap_or_else(|| PathBuf::from("out").join(&name));
    Ok(ParsedRun {
        scenario,
        name,
        base_dir: path.parent().unwrap_or(Path::new(".")),
        dir,
    })
}

/// Streams the rows to the CSV log (every `every`-th) and moves the progress bar.
struct LogSink {
    log: output::CsvLog,
    every: usize,
    progress: Progress,
}

impl RowSink for LogSink {
    fn row(&mut self, index: usize, row: &[f64]) -> Result<(), ScenarioError> {
        if index.is_multiple_of(self.every) {
            self.log
                .row(row)
                .map_err(|e| ScenarioError::Output(format!("{e:#}")))?;
        }
        self.progress.tick(index);
        Ok(())
    }
}

/// A scenario error as the command reports it: an interruption keeps its type, so that the
/// command says where the outputs are.
pub(crate) fn command_error(e: ScenarioError, dir: &Path) -> anyhow::Error {
    match e.interrupted_at() {
        Some(t) => crate::interrupt::Interrupted {
            t,
            dir: dir.display().to_string(),
        }
        .into(),
        None => e.into(),
    }
}

/// Runs a parsed scenario; relative paths resolve from `base_dir`; writes into `dir`.
pub fn run_scenario(
    scenario: &Scenario,
    name: &str,
    base_dir: &Path,
    dir: &Path,
    options: RunOptions,
) -> Result<RunReport> {
    let run = ScenarioRun::new(scenario, name, base_dir, library_options(&options))
        .map_err(|e| command_error(e, dir))?;
    run_built(run, scenario, dir, options, &mut [])
}

/// The library's options of a run executed with `options`.
pub fn library_options(options: &RunOptions) -> corps_scenario::run::RunOptions {
    corps_scenario::run::RunOptions {
        overlap: options.overlap,
        interrupt: options.interrupt,
        stop_after_failure: None,
    }
}

/// Runs a built scenario, writing its log, metrics, plots (and recording) into `dir`; every
/// row also goes to `extra` (a live display, for instance).
pub fn run_built(
    run: ScenarioRun,
    scenario: &Scenario,
    dir: &Path,
    options: RunOptions,
    extra: &mut [&mut dyn RowSink],
) -> Result<RunReport> {
    let header = run.columns().to_vec();
    let log_every = scenario.output.log_every;
    let cap = scenario.output.max_log_bytes();
    output::check_size(run.ticks().div_ceil(log_every), header.len(), cap)?;
    let _lock = output::DirLock::acquire(dir)?;
    let mut sink = LogSink {
        log: output::CsvLog::create(dir, &header, cap)?,
        every: log_every,
        progress: Progress::new(run.ticks(), run.dt(), options.progress),
    };
    let mut recording = if options.record {
        Some(Recording::create(
            dir,
            RecordingScene {
                model: run.model().clone(),
                feet: run.soles().to_vec(),
                operator: run
                    .operator_clip()
                    .map(|(clip, units)| OperatorView::new(clip.clone(), *units)),
            },
            &header,
            run.dt(),
            log_every,
        )?)
    } else {
        None
    };
    let mut sinks: Vec<&mut dyn RowSink> = vec![&mut sink];
    if let Some(rec) = &mut recording {
        sinks.push(rec);
    }
    sinks.extend(extra.iter_mut().map(|s| &mut **s as &mut dyn RowSink));
    let result = run.run(&mut sinks).map_err(|e| command_error(e, dir))?;
    sink.progress.finish();
    let mut m = result.metrics;
    if let Some(profile) = &options.noise {
        m.sensor_noise = format!("noise of {}", profile.name);
    }
    let mut files = vec![
        sink.log.finish()?,
        output::write_atomic(dir, "metrics.txt", m.to_string().as_bytes())?,
        output::write_atomic(
            dir,
            "metrics.json",
            serde_json::to_string_pretty(&m)?.as_bytes(),
        )?,
    ];
    match recording {
        Some(rec) => files.extend(rec.finish()?),
        // No recording of an earlier run stays beside this run's log.
        None => match std::fs::remove_file(dir.join(RECORDING_NAME)) {
            Err(e) if e.kind() != std::io::ErrorKind::NotFound => {
                return Err(e).context("removing the stale recording")
            }
            _ => {}
        },
    }
    if scenario.output.plots {
        files.extend(plots::write(dir, &result.series, &header, &m.scenario)?);
    }
    output::remove_stale_plots(dir, &files)?;
    Ok(RunReport {
        metrics: m,
        expected: scenario.expect,
        dir: dir.to_path_buf(),
        files,
    })
}
