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

pub mod controller;
pub mod dynamic_filter;
pub(crate) mod estimation;
pub mod gains;
mod gait;
pub(crate) mod metrics;
pub mod motion;
mod overlap;
mod plot_buffer;
mod plots;
pub mod sensor_profile;
mod stepper;
pub mod targets;
pub mod walk;

pub use controller::{ControllerKind, ControllerSection, WholeBodyController, MAX_SETTLE};
pub use estimation::{EstimatorKind, EstimatorSection};
pub use metrics::{
    Comparison, DynamicFilterMetrics, FootMetrics, Metrics, Stat, ThesisFigures, TickTime,
    TickTimer, WalkMetrics, WalkingErrors,
};
pub use motion::{MotionSection, Side, Targets};
pub use overlap::Overlap;

use crate::output;
use crate::progress::Progress;
use crate::sim_cmd::scenario::Scenario;
use crate::sim_cmd::setup::{self, Setup};
use anyhow::{anyhow, bail, Context, Result};
use clap::Args;
use controller::{behind_stabilizer, IkController, Measured, TsidController, TsidMode};
use corps_control::stabilizer::{StabilizerOutput, Wrench};
use corps_loop::verdict::{TickSample, Verdict, VerdictObserver};
use corps_model::spatial::Se3;
use corps_model::STANDARD_GRAVITY as GRAVITY;
use corps_model::{com_at_placements, frame_placement, Model};
use corps_sim::Simulator;
use motion::MotionPlan;
use nalgebra::Vector3;
use plot_buffer::PlotBuffer;
use sensor_profile::SensorProfile;
use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;
use std::time::Instant;
use stepper::Stepper;

/// Vertical force (N) below which the ZMP is not defined (the robot is in the air).
const ZMP_MIN_FZ: f64 = corps_estimation::ZMP_MIN_FORCE;

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
    estimator: Option<EstimatorKind>,
    /// Sensor noise from this file (`seed` and `[noise.<channel>]` tables, as in a scenario),
    /// replacing the scenario's; see `scenarios/sensors/`.
    #[arg(long, value_name = "FILE")]
    noise: Option<PathBuf>,
    /// The robot, replacing the scenario's: `talos`, `icub`, `simple_humanoid` or a robot
    /// description file (`robots/*/*.toml`).
    #[arg(long, value_name = "ROBOT")]
    robot: Option<String>,
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
            interrupt: Some(&crate::interrupt::FLAG),
        }
    }
}

/// Runs `corps run`.
pub fn run(args: RunArgs) -> Result<()> {
    let mut options = RunOptions::interactive();
    options.max_log_mb = args.max_log_mb;
    options.estimator = args.estimator;
    options.noise = args.noise.as_deref().map(SensorProfile::read).transpose()?;
    options.robot = args.robot;
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
    let mut scenario = Scenario::parse(text).map_err(|e| anyhow!("{shown}: {e}"))?;
    if let Some(d) = duration {
        scenario = scenario
            .with_duration(d)
            .map_err(|e| anyhow!("{shown}: {e}"))?;
    }
    if let Some(mb) = options.max_log_mb {
        scenario = scenario
            .with_max_log_mb(mb)
            .map_err(|e| anyhow!("{shown}: {e}"))?;
    }
    if let Some(robot) = &options.robot {
        scenario.robot = crate::sim_cmd::scenario::RobotSection::from_argument(robot);
    }
    if let Some(kind) = options.estimator {
        scenario.estimator.kind = kind;
    }
    if let Some(profile) = &options.noise {
        scenario.noise = profile.noise.clone();
        scenario.seed = profile.seed.unwrap_or(scenario.seed);
        scenario.force_torque_model = profile
            .force_torque_model
            .unwrap_or(scenario.force_torque_model);
    }
    let name = scenario.run_name(path);
    let base_dir = path.parent().unwrap_or(Path::new("."));
    let dir = output
        .map(Path::to_path_buf)
        .or_else(|| scenario.output.directory.clone())
        .unwrap_or_else(|| PathBuf::from("out").join(&name));
    // A context, not a new message, so that the command still sees an `Interrupted`.
    run_scenario(&scenario, &name, base_dir, &dir, options).with_context(|| shown.to_string())
}

/// The log's columns, in row order: the tracked signals, then with a stabilizer each foot's
/// ankle admittance (roll, pitch) offset and rate, measured and desired CoP in the sole frame,
/// and the DCM controller's desired ZMP (world x, y).
fn log_columns(stabilized: bool) -> Vec<String> {
    let mut header: Vec<String> = [
        "t",
        "com_x",
        "com_y",
        "com_z",
        "com_ref_x",
        "com_ref_y",
        "com_ref_z",
        "zmp_x",
        "zmp_y",
        "zmp_ref_x",
        "zmp_ref_y",
        "left_foot_z",
        "left_foot_z_ref",
        "right_foot_z",
        "right_foot_z_ref",
        "left_foot_fz",
        "right_foot_fz",
        "base_x",
        "base_y",
        "base_z",
        "com_est_x",
        "com_est_y",
        "com_est_z",
        "base_est_x",
        "base_est_y",
        "base_est_z",
        "tick_us",
    ]
    .map(String::from)
    .to_vec();
    if stabilized {
        for foot in ["left", "right"] {
            for (signal, axes) in [
                ("ankle", ["roll", "pitch"]),
                ("ankle_rate", ["roll", "pitch"]),
                ("cop", ["x", "y"]),
                ("cop_des", ["x", "y"]),
            ] {
                header.extend(axes.map(|a| format!("{foot}_{signal}_{a}")));
            }
        }
        header.extend(["zmp_des_x", "zmp_des_y"].map(String::from));
    }
    header
}

/// Appends the stabilizer's signals of one tick to `row` (NaN where it failed or a foot is
/// unloaded), in [`log_columns`]' order.
fn push_stabilizer(row: &mut Vec<f64>, out: Option<&StabilizerOutput>, contact: &ContactSample) {
    let nan2 = nalgebra::Vector2::repeat(f64::NAN);
    for f in 0..2 {
        let a = out.map(|o| o.ankle[f]);
        let cop = if contact.foot_fz[f] >= ZMP_MIN_FZ {
            contact.foot_wrenches[f].cop()
        } else {
            nan2
        };
        let cop_des = out.map_or(nan2, |o| o.foot_cops[f]);
        row.extend((0..2).map(|k| a.map_or(f64::NAN, |a| a.offset[k])));
        row.extend((0..2).map(|k| a.map_or(f64::NAN, |a| a.velocity[k])));
        row.extend((0..2).map(|k| cop[k]));
        row.extend((0..2).map(|k| cop_des[k]));
    }
    row.extend((0..2).map(|k| out.map_or(f64::NAN, |o| o.zmp_des[k])));
}

/// Runs a parsed scenario; relative paths resolve from `base_dir`; writes into `dir`.
pub fn run_scenario(
    scenario: &Scenario,
    name: &str,
    base_dir: &Path,
    dir: &Path,
    options: RunOptions,
) -> Result<RunReport> {
    let Some(section) = &scenario.controller else {
        bail!("no [controller] section: this is a `corps sim` scenario");
    };
    let Setup {
        robot,
        criteria,
        model,
        mut sim,
        mut sensors,
        command: hold,
        q0,
        feet: foot_sensors,
        imu_frame,
        ..
    } = setup::build(scenario, base_dir)?;
    let Some(robot) = robot else {
        bail!("robot: corps run needs a robot description (robot.description), not a bare URDF");
    };
    let source = gains::GainsSource::resolve(
        section.gains.as_deref(),
        section.kind.name(),
        &robot,
        base_dir,
    )
    .context("controller.gains")?;
    let soles = controller::two_feet(&robot)?;
    let dt = scenario.sim.control_dt;
    let settle_ticks = (section.settle / dt).round() as usize;
    for _ in 0..settle_ticks {
        if crate::interrupt::raised(options.interrupt) {
            return Err(crate::interrupt::Interrupted {
                t: 0.0,
                dir: dir.display().to_string(),
            }
            .into());
        }
        sim.step(&hold)?;
    }
    let handover = sim.time();
    // Pushes count from the handover (the setup added none).
    let pushes = crate::sim_cmd::pushes::schedule(
        &scenario.pushes,
        sim.time(),
        scenario.duration,
        Some(model.total_mass()),
    )
    .map_err(|e| anyhow!("{e}"))?;
    for push in pushes {
        sim.add_push(push)?;
    }
    let (q, v) = (sim.q().clone_owned(), sim.v().clone_owned());
    let mass = model.total_mass();
    // The controller, and whether a stabilizer runs (its signals go to the log).
    let (mut ctrl, stabilized) = match section.kind {
        ControllerKind::TsidTorque | ControllerKind::TsidPosition => {
            let mode = if section.kind == ControllerKind::TsidTorque {
                TsidMode::Torque
            } else {
                TsidMode::Position
            };
            let g: gains::TsidGains =
                gains::load(&source, &section.set).context("controller.gains")?;
            let stabilizer = g.stabilizer.clone();
            let inner =
                TsidController::new(&robot, mode, g, dt, &q, &v, &q0).context("controller")?;
            if mode == TsidMode::Torque && stabilizer.is_some() {
                bail!("controller.gains: [stabilizer] is for the position-mode controllers")
            }
            let ctrl = behind_stabilizer(inner, stabilizer.as_ref(), soles[0], mass, dt)
                .context("controller.gains.stabilizer")?;
            (ctrl, stabilizer.is_some())
        }
        ControllerKind::IkPosition => {
            let g: gains::IkGainsFile =
                gains::load(&source, &section.set).context("controller.gains")?;
            let stabilizer = g.stabilizer.clone();
            let inner = IkController::new(&robot, g, dt, &q, &q0).context("controller")?;
            let ctrl = behind_stabilizer(inner, stabilizer.as_ref(), soles[0], mass, dt)
                .context("controller.gains.stabilizer")?;
            (ctrl, stabilizer.is_some())
        }
    };

    let ankles = soles.map(|f| {
        f.ankle
            .map(|j| model.joints[j].idx_v - model.first_actuated())
    });
    let soles = soles.map(|f| f.frame);
    let foot_joints = soles.map(|f| model.frames[f].parent_joint.unwrap_or(usize::MAX));
    let mut estimator = estimation::RunEstimator::new(
        &scenario.estimator,
        &model,
        &foot_sensors,
        soles,
        imu_frame,
        scenario.sim.gravity,
        scenario.force_torque_model == corps_sim::ForceTorqueModel::Transmitted,
    )?;
    estimator.reset(q.as_slice(), v.as_slice())?;
    let (com0, _, feet0) = com_and_soles(&sim, &soles)?;
    let ticks = (scenario.duration / dt).round() as usize;
    let mut plan = MotionPlan::new(
        &robot,
        scenario.motion.clone(),
        motion::Handover {
            com: com0,
            feet: feet0,
        },
        dt,
        scenario.duration,
        base_dir,
        sim.terrain(),
    )?;
    let dynamic_filter = match &scenario.motion {
        MotionSection::Walk(w) if w.dynamic_filter => Some(
            dynamic_filter::filter_walk(&robot, &q, &q0, &mut plan, ticks)
                .context("motion.dynamic_filter")?,
        ),
        _ => None,
    };
    let mut targets = plan.initial_targets();
    let mut m = Metrics {
        scenario: name.to_string(),
        controller: section.kind.label().to_string(),
        duration: ticks as f64 * dt,
        feet: ["left", "right"]
            .map(|label| FootMetrics {
                label: label.into(),
                ..Default::default()
            })
            .to_vec(),
        min_base_height: f64::INFINITY,
        ..Default::default()
    };
    let base0 = Vector3::new(q[0], q[1], q[2]);
    let mut contact_start: [Option<Vector3<f64>>; 2] = [None, None];
    let mut pgm = gait::PassivityGaitMeasure::default();
    // The walk proper: its errors beside the whole run's, and the gait measure over it only.
    let walking_window = plan.walk().and_then(|w| w.walking_window());
    m.while_walking = walking_window.map(|(start, end)| WalkingErrors {
        start,
        end,
        ..Default::default()
    });
    let walking = |t: f64| walking_window.is_some_and(|(a, b)| t >= a && t < b);
    // The log streams to disk as the run goes; the plots keep a bounded decimated copy.
    let header = log_columns(stabilized);
    let log_every = scenario.output.log_every;
    let cap = scenario.output.max_log_bytes();
    output::check_size(ticks.div_ceil(log_every), header.len(), cap)?;
    let _lock = output::DirLock::acquire(dir)?;
    let mut log = output::CsvLog::create(dir, &header, cap)?;
    let mut row = Vec::with_capacity(header.len());
    let mut plot_buffer = PlotBuffer::new(header.len());
    let mut tick_time = TickTimer::default();
    let support = |feet: &[Se3; 2]| feet[0].translation.z.min(feet[1].translation.z);
    let mut verdict = VerdictObserver::new(criteria, mass * GRAVITY, com0.z - support(&feet0))
        .context("verdict")?;
    let mut force_sum = [0.0; 2];
    let mut progress = Progress::new(ticks, dt, options.progress);
    // The controller reads the state from these copies while the simulator prepares its
    // next step.
    let (mut q, mut v) = (q, v);
    let shared = stepper::Shared::new(sim);
    let mut ticks_run = 0;
    let (mut state_finite, mut base_speed, mut true_base) = (true, 0.0, base0);
    let overlap_counts = std::thread::scope(|scope| -> Result<(u64, u64)> {
        let mut stepper = Stepper::new(scope, &shared, options.overlap);
        for tick in 0..ticks {
            let t = tick as f64 * dt;
            if crate::interrupt::raised(options.interrupt) {
                m.interrupted_at = Some(ticks_run as f64 * dt);
                break;
            }
            plan.sample(t, &mut targets);
            // What the robot does (the metrics' ground truth) and what its sensors tell the
            // controller (through the estimator).
            let (com, placements, mut contact) = {
                let sim = stepper.sim()?;
                let (com, _, placements) = com_and_soles(&sim, &soles)?;
                let contact = measure_contacts(&sim, &foot_joints, &placements);
                let (w, w_pos) = work(&sim, &model, dt);
                m.work += w;
                m.positive_work += w_pos;
                if walking(t) {
                    pgm.push(
                        sim.applied_torques().as_slice(),
                        &ankles,
                        [targets.feet[0].supporting, targets.feet[1].supporting],
                    );
                }
                sensors.update(&sim);
                state_finite = sim.q().iter().chain(sim.v().iter()).all(|x| x.is_finite());
                base_speed = Vector3::new(sim.v()[0], sim.v()[1], sim.v()[2]).norm();
                true_base = Vector3::new(sim.q()[0], sim.q()[1], sim.q()[2]);
                (com, placements, contact)
            };
            stepper.prepare();
            estimator.update(&sensors, t);
            let est = estimator.state();
            q.copy_from(&est.q);
            v.copy_from(&est.v);
            m.estimate_error.push(
                (est.com - com).norm(),
                (Vector3::new(q[0], q[1], q[2]) - true_base).norm(),
            );
            // The ZMP as the thesis measured it, from the ankle F/T sensors' wrenches, placed
            // at the soles' true placements so that it compares with the world's reference
            // (the estimator's own ZMP is in its estimated world, for the controller).
            let sensed = [0, 1].map(|k| corps_estimation::FootEstimate {
                placement: placements[k],
                ..est.feet[k]
            });
            contact.zmp = corps_estimation::zmp_of_feet(&sensed).map(|p| [p.x, p.y]);
            let measured = Measured {
                com: est.com,
                com_velocity: est.com_velocity,
                zmp: est.zmp,
                feet: [0, 1].map(|k| isometry(&est.feet[k].placement)),
                foot_wrenches: [0, 1].map(|k| {
                    let w = &est.feet[k].wrench;
                    Wrench::new(
                        Vector3::new(w[0], w[1], w[2]),
                        Vector3::new(w[3], w[4], w[5]),
                    )
                }),
            };
            let start = Instant::now();
            let reason = ctrl.tick(t, q.as_slice(), v.as_slice(), &targets, &measured);
            let us = start.elapsed().as_secs_f64() * 1e6;
            tick_time.push(us);
            let safe_command = reason.is_some();
            if let Some(r) = reason {
                m.fallbacks += 1;
                m.first_fallback
                    .get_or_insert_with(|| format!("t = {t:.3} s: {r}"));
            }
            for (sum, fz) in force_sum.iter_mut().zip(contact.foot_fz) {
                *sum += fz;
            }
            let feet = placements.map(|p| p.translation);
            record(
                &mut m,
                &mut row,
                Sample {
                    t,
                    base: true_base,
                    base0,
                    com,
                    feet,
                    targets: &targets,
                    contact: &contact,
                    tick_us: us,
                    walking: walking(t),
                    com_estimate: est.com,
                    base_estimate: Vector3::new(q[0], q[1], q[2]),
                },
                &mut contact_start,
            );
            if stabilized {
                push_stabilizer(&mut row, ctrl.stabilizer_output(), &contact);
            }
            if tick % log_every == 0 {
                log.row(&row)?;
            }
            plot_buffer.push(&row);
            ticks_run = tick + 1;
            let sample = TickSample {
                t,
                com_height: com.z - support(&placements),
                base_speed,
                total_contact_force: contact.total,
                other_contact_force: contact.other,
                state_finite,
                safe_command,
            };
            if verdict.observe(&sample).is_some() {
                break;
            }
            if let Some((t, why)) = stepper.step(ctrl.command())? {
                verdict.diverged(t - handover, format!("the simulation: {why}"));
                break;
            }
            progress.tick(tick);
        }
        Ok(stepper.overlap_counts())
    })?;
    let sim = shared.into_inner()?;
    progress.finish();
    m.tick_time = tick_time.summary();
    m.duration = ticks_run as f64 * dt;
    m.verdict = verdict.finish(m.duration);
    m.overlapped_ticks = overlap_counts.0;
    m.estimator = scenario.estimator.kind;
    m.sensor_noise = match &options.noise {
        Some(profile) => format!("noise of {}", profile.name),
        None if scenario.noise == corps_sim::SensorNoise::default() => "noiseless".into(),
        None => "the scenario's [noise]".into(),
    };
    m.estimator_errors = estimator.errors;
    m.first_estimator_error = estimator.first_error.clone();
    m.thesis = scenario.thesis.clone();
    if let Some(walk) = plan.walk() {
        // Where the plan puts the base: its final feet midpoint plus the base's starting
        // offset from the feet midpoint.
        let r = walk.final_reference();
        let mid = walk.world(Vector3::new(
            (r.left_foot.x + r.right_foot.x) / 2.0,
            (r.left_foot.y + r.right_foot.y) / 2.0,
            0.0,
        ));
        let mid0 = (feet0[0].translation + feet0[1].translation) / 2.0;
        let planned = mid + (base0 - mid0);
        let q = sim.q();
        let base = Vector3::new(q[0], q[1], q[2]);
        let distance = (base - base0).xy().norm();
        let weight = model.total_mass() * GRAVITY * distance.max(1e-9);
        m.walk = Some(WalkMetrics {
            distance,
            final_base_error: (base - planned).xy().norm(),
            cost_of_transport: m.work / weight,
            mechanical_cost_of_transport: m.positive_work / weight,
            passivity_gait_measure: pgm.values(),
            dynamic_filter,
        });
    }
    for (foot, sum) in m.feet.iter_mut().zip(force_sum) {
        foot.force_mean = sum / ticks_run.max(1) as f64;
    }
    m.against_thesis = m.thesis_comparison();
    let mut files = vec![
        log.finish()?,
        output::write_atomic(dir, "metrics.txt", m.to_string().as_bytes())?,
        output::write_atomic(
            dir,
            "metrics.json",
            serde_json::to_string_pretty(&m)?.as_bytes(),
        )?,
    ];
    if scenario.output.plots {
        files.extend(plots::write(dir, &plot_buffer, &header, &m.scenario)?);
    }
    output::remove_stale_plots(dir, &files)?;
    Ok(RunReport {
        metrics: m,
        expected: scenario.expect,
        dir: dir.to_path_buf(),
        files,
    })
}

/// The CoM, its velocity and the sole placements of the simulated robot, from the
/// kinematics the simulator keeps for its current state (no second kinematic pass).
fn com_and_soles(
    sim: &Simulator,
    soles: &[usize; 2],
) -> Result<(Vector3<f64>, Vector3<f64>, [Se3; 2])> {
    let (model, data) = (sim.model(), sim.data());
    let (com, com_velocity) = com_at_placements(model, data);
    let soles = [
        frame_placement(model, data, soles[0])?,
        frame_placement(model, data, soles[1])?,
    ];
    Ok((com, com_velocity, soles))
}

/// Contact forces of one tick.
struct ContactSample {
    /// ZMP (world x, y) from the ankle F/T wrenches, None when the robot is in the air
    /// (filled by the run once the estimator has read the sensors).
    zmp: Option<[f64; 2]>,
    /// Height of the contact plane (force-weighted mean height of the loaded points).
    plane_z: f64,
    /// Vertical force on each foot (N).
    foot_fz: [f64; 2],
    /// Each foot's wrench in its sole frame, about the sole origin.
    foot_wrenches: [Wrench; 2],
    /// Total force on other bodies (N).
    other: f64,
    /// Norm of the total contact force (N).
    total: f64,
}

/// Forces from the simulator's contact points (world frame): the contact plane's height, each
/// foot's vertical force and wrench in its sole frame `soles[k]` about the sole origin, the
/// force on other bodies and the total.
fn measure_contacts(sim: &Simulator, foot_joints: &[usize; 2], soles: &[Se3; 2]) -> ContactSample {
    let c = sim.contact();
    let points = sim.contact_points();
    let (mut fz, mut zf) = (0.0, 0.0);
    let mut foot_fz = [0.0; 2];
    let mut world = [(Vector3::zeros(), Vector3::zeros()); 2];
    let mut other = 0.0;
    let mut total = Vector3::zeros();
    for ((f, p), cp) in c.point_forces.iter().zip(&c.point_positions).zip(points) {
        // Most sampled points are clear of the ground: they add nothing to any sum.
        if *f == Vector3::zeros() {
            continue;
        }
        total += f;
        fz += f.z;
        zf += p.z * f.z;
        match foot_joints.iter().position(|j| *j == cp.joint) {
            Some(k) => {
                foot_fz[k] += f.z;
                world[k].0 += f;
                world[k].1 += (p - soles[k].translation).cross(f);
            }
            None => other += f.norm(),
        }
    }
    let foot_wrenches = [0, 1].map(|k| {
        let rt = soles[k].rotation.transpose();
        Wrench::new(rt * world[k].0, rt * world[k].1)
    });
    ContactSample {
        zmp: None,
        plane_z: if fz < ZMP_MIN_FZ { 0.0 } else { zf / fz },
        foot_fz,
        foot_wrenches,
        other,
        total: total.norm(),
    }
}

/// An `Se3` as a nalgebra isometry.
fn isometry(m: &Se3) -> nalgebra::Isometry3<f64> {
    let r = nalgebra::Rotation3::from_matrix_unchecked(m.rotation);
    nalgebra::Isometry3::from_parts(
        nalgebra::Translation3::from(m.translation),
        nalgebra::UnitQuaternion::from_rotation_matrix(&r),
    )
}

/// Mechanical work of the joints over one step: (Σ|τ q̇| dt, Σ max(τ q̇, 0) dt).
fn work(sim: &Simulator, model: &Model, dt: f64) -> (f64, f64) {
    let tau = sim.applied_torques();
    let v = sim.v();
    let first = model.nv - tau.len();
    (0..tau.len()).fold((0.0, 0.0), |(a, p), k| {
        let power = tau[k] * v[first + k];
        (a + power.abs() * dt, p + power.max(0.0) * dt)
    })
}

struct Sample<'a> {
    t: f64,
    base: Vector3<f64>,
    base0: Vector3<f64>,
    com: Vector3<f64>,
    feet: [Vector3<f64>; 2],
    targets: &'a Targets,
    contact: &'a ContactSample,
    tick_us: f64,
    /// Within the walk proper (the walking statistics count this tick).
    walking: bool,
    /// The controller's estimate of the CoM and base position.
    com_estimate: Vector3<f64>,
    base_estimate: Vector3<f64>,
}

/// Updates the metrics with one tick and fills `row` with its tracked signals, in
/// [`log_columns`]' order (without the stabilizer's).
fn record(
    m: &mut Metrics,
    row: &mut Vec<f64>,
    s: Sample,
    contact_start: &mut [Option<Vector3<f64>>; 2],
) {
    let c_ref = &s.targets.com;
    // Reference ZMP of the CoM reference on the measured contact plane.
    let zmp_ref = s.targets.reference_zmp(s.contact.plane_z, GRAVITY);
    let mut walking = m.while_walking.as_mut().filter(|_| s.walking);
    for k in 0..3 {
        let e = s.com[k] - c_ref.pos[k];
        m.com_error[k].push(e);
        if let Some(w) = walking.as_deref_mut() {
            w.com_error[k].push(e);
        }
    }
    if let Some(p) = s.contact.zmp {
        for k in 0..2 {
            let e = p[k] - zmp_ref[k];
            m.zmp_error[k].push(e);
            if let Some(w) = walking.as_deref_mut() {
                w.zmp_error[k].push(e);
            }
        }
    }
    row.clear();
    row.push(s.t);
    row.extend(s.com.iter());
    row.extend(c_ref.pos.iter());
    let zmp = s.contact.zmp.unwrap_or([f64::NAN; 2]);
    row.extend(zmp);
    row.extend([zmp_ref[0], zmp_ref[1]]);
    for (k, foot) in m.feet.iter_mut().enumerate() {
        let target = &s.targets.feet[k];
        let r = target.reference.placement.translation;
        for (a, stat) in foot.error.iter_mut().enumerate() {
            let e = s.feet[k][a] - r[a];
            stat.push(e);
            if let Some(w) = walking.as_deref_mut() {
                w.feet_error[k][a].push(e);
            }
        }
        foot.force_peak = foot.force_peak.max(s.contact.foot_fz[k]);
        // Slip: horizontal motion while the plan has the foot on the ground and it is loaded.
        if target.supporting && s.contact.foot_fz[k] > ZMP_MIN_FZ {
            let start = *contact_start[k].get_or_insert(s.feet[k]);
            foot.slip = foot.slip.max((s.feet[k] - start).xy().norm());
        } else {
            contact_start[k] = None;
        }
        row.extend([s.feet[k].z, r.z]);
    }
    row.extend(s.contact.foot_fz);
    row.extend(s.base.iter());
    row.extend(s.com_estimate.iter());
    row.extend(s.base_estimate.iter());
    row.push(s.tick_us);
    let drift = (s.base - s.base0).norm();
    m.base_drift = drift;
    m.base_drift_peak = m.base_drift_peak.max(drift);
    m.min_base_height = m.min_base_height.min(s.base.z);
    m.other_contact_peak = m.other_contact_peak.max(s.contact.other);
}
