//! `corps teleop [SCENARIO]`: keyboard teleoperation of a walking robot (seed 002 §4.14). The
//! scenario's velocity walk (`[motion] kind = "velocity"`, no `commands`) takes its command
//! from the keys as the run goes: the MPC pattern generator places the footsteps, the
//! scenario's controller tracks them on the simulated robot, in real time, while a terminal
//! display shows the commanded and achieved velocities, the steps and the controller's time.
//! With `--keys FILE` a key script replaces the keyboard: the run is headless, as fast as the
//! machine goes, and prints the final pose. The run writes its log, metrics and plots as
//! `corps run` does (and `run.mcap` for the 3D viewer with `--record`). A fall ends it with
//! the verdict; `q`, Esc or Ctrl-C end it and restore the terminal.

mod keys;
mod screen;
mod status;

pub use keys::{parse_script, KeyAction, TimedKey};
pub use status::{Status, TeleopSink};

use crate::output::recording::{LiveStream, Recording, RecordingScene};
use crate::run::{library_options, parse_run, run_built, ParsedRun, RunOptions, RunReport};
use anyhow::{anyhow, bail, Context, Result};
use clap::Args;
use corps_loop::verdict::Verdict;
use corps_scenario::overrides::Overrides;
use corps_scenario::run::{RowSink, ScenarioRun};
use corps_scenario::teleop::{PadSettings, VelocityPad};
use corps_scenario::velocity_walk::LiveVelocity;
use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};

/// The scenario `corps teleop` runs without one: TALOS under the TSID torque controller
/// (`scenarios/teleop/talos_keyboard.toml`, built in).
pub const DEFAULT_SCENARIO: &str = include_str!("../../../../scenarios/teleop/talos_keyboard.toml");

/// How long (s) a session goes on after a fall before it ends.
const FALL_GRACE: f64 = 0.5;

/// Arguments of `corps teleop`.
#[derive(Args)]
pub struct TeleopArgs {
    /// Scenario file (TOML) with `[motion] kind = "velocity"` and no commands (default: TALOS
    /// under the TSID torque controller, `scenarios/teleop/talos_keyboard.toml`).
    scenario: Option<PathBuf>,
    /// Keys from a script instead of the keyboard: one `time key` per line (seconds after the
    /// controller takes over; `space` for the space bar). Runs headless, faster than real
    /// time, and prints the final pose.
    #[arg(long, value_name = "FILE")]
    keys: Option<PathBuf>,
    /// Output directory (default: `[output] directory` of the scenario, else `out/<name>`).
    #[arg(short, long)]
    output: Option<PathBuf>,
    /// The longest session (s), replacing the scenario's `duration`.
    #[arg(long, value_name = "SECONDS")]
    duration: Option<f64>,
    /// The robot, replacing the scenario's (a name or a robot description file).
    #[arg(long, value_name = "ROBOT")]
    robot: Option<String>,
    /// Also write `run.mcap` for the 3D viewer (Foxglove).
    #[arg(long)]
    record: bool,
    /// Stream the session live to Foxglove: `--stream` on 127.0.0.1:8765, `--stream=HOST:PORT`
    /// elsewhere (open a "Foxglove WebSocket" connection to ws://HOST:PORT). A key script
    /// then plays in real time.
    #[arg(
        long,
        value_name = "HOST:PORT",
        num_args = 0..=1,
        require_equals = true,
        default_missing_value = "127.0.0.1:8765"
    )]
    stream: Option<String>,
}

/// What a teleoperated run produced.
pub struct TeleopReport {
    pub run: RunReport,
    pub status: Status,
}

/// Runs `corps teleop`.
pub fn run(args: TeleopArgs) -> Result<()> {
    let (text, path) = match &args.scenario {
        Some(p) => (crate::sim_cmd::read_scenario(p)?, p.clone()),
        None => (
            DEFAULT_SCENARIO.to_string(),
            PathBuf::from("talos_keyboard.toml"),
        ),
    };
    let script = args.keys.as_deref().map(keys::read_script).transpose()?;
    if script.is_none() && !(std::io::stdin().is_terminal() && std::io::stdout().is_terminal()) {
        bail!(
            "teleoperation needs a terminal for the keyboard; give --keys FILE to run a key script"
        );
    }
    // Listening first: a taken or malformed address fails before the robot moves.
    let stream = args.stream.as_deref().map(LiveStream::bind).transpose()?;
    if let Some(s) = &stream {
        eprintln!(
            "streaming on ws://{} (Foxglove: open connection, Foxglove WebSocket)",
            s.address()
        );
    }
    let mut options = RunOptions::interactive();
    options.robot = args.robot.clone();
    options.record = args.record;
    // The display replaces the progress bar; a script run shows the bar.
    options.progress = script.is_some();
    let session = Session {
        output: args.output.as_deref(),
        duration: args.duration,
        script,
        stream,
    };
    let report = teleoperate(&text, &path, options, session)?;
    print_report(&report)?;
    // Quitting is how a session ends: not an error. A fall is, quit or not.
    let m = &report.run.metrics;
    if m.interrupted_at.is_none() || m.verdict.verdict != Verdict::Completed {
        report.run.check_expected()?;
    }
    Ok(())
}

fn print_report(report: &TeleopReport) -> Result<()> {
    let s = &report.status;
    let m = &report.run.metrics;
    let (distance, heading) = s.travelled();
    let ended = match m.interrupted_at {
        Some(t) => format!(
            "stopped by the operator at t = {t:.2} s; verdict {}",
            m.verdict
        ),
        None => format!("{}", m.verdict),
    };
    let mut text = format!(
        "teleop: {ended}\n\
         final pose: x = {:.3} m, y = {:.3} m, yaw = {:.1}° (world; from x = {:.3}, y = {:.3}, \
         yaw = {:.1}°)\n\
         travelled {distance:.3} m, turned {:.1}°, {} steps; last command \
         (v_x, v_y, ω) = ({:.2}, {:.2}, {:.2})\n",
        s.pose.x,
        s.pose.y,
        s.pose.yaw.to_degrees(),
        s.start.x,
        s.start.y,
        s.start.yaw.to_degrees(),
        heading.to_degrees(),
        s.steps,
        s.commanded.vx,
        s.commanded.vy,
        s.commanded.yaw_rate,
    );
    text.push_str(&format!("wrote {}\n", report.run.dir.display()));
    for p in &report.run.files {
        text.push_str(&format!("    {}\n", p.display()));
    }
    crate::stdout::print(&text)
}

/// What a session takes besides its scenario.
pub struct Session<'a> {
    /// Replaces the output directory.
    pub output: Option<&'a Path>,
    /// Replaces the scenario's duration (s).
    pub duration: Option<f64>,
    /// Keys from a script (headless, unpaced unless streamed) instead of the keyboard.
    pub script: Option<Vec<TimedKey>>,
    /// Streams the session live to viewers.
    pub stream: Option<LiveStream>,
}

/// Runs the teleoperation of scenario `text` (read from `path`): keys from the session's
/// script, else from the keyboard with the display (real time).
pub fn teleoperate(
    text: &str,
    path: &Path,
    options: RunOptions,
    session: Session<'_>,
) -> Result<TeleopReport> {
    let Session {
        output,
        duration,
        script,
        stream,
    } = session;
    let overrides = Overrides {
        duration,
        robot: options.robot.clone(),
        ..Default::default()
    };
    let ParsedRun {
        scenario,
        name,
        base_dir,
        dir,
    } = parse_run(text, path, output, &overrides)?;
    let input = LiveVelocity::new();
    // The keys' quit stops the run: the run watches the flag they raise.
    let quit = options.interrupt.unwrap_or(&crate::interrupt::FLAG);
    let run_options = corps_scenario::run::RunOptions {
        // A fall ends the session (half a second later, for the log to show it).
        stop_after_failure: Some(FALL_GRACE),
        interrupt: Some(quit),
        ..library_options(&options)
    };
    let steering = Box::new(input.clone());
    let run = ScenarioRun::steered(&scenario, &name, base_dir, run_options, steering)
        .map_err(|e| anyhow!(e))
        .with_context(|| path.display().to_string())?;
    let headless = script.is_some();
    // A streamed script plays in real time, for the viewer to show it as it happens.
    let realtime = !headless || stream.is_some();
    let pad = VelocityPad::new(PadSettings::default());
    let mut sink = TeleopSink::new(
        run.columns(),
        run.dt(),
        input.clone(),
        realtime,
        script.unwrap_or_default(),
        pad.clone(),
        quit,
    )?;
    let shared = sink.shared();
    let mut live = match stream {
        Some(stream) => {
            let scene = RecordingScene {
                model: run.model().clone(),
                feet: run.soles().to_vec(),
                operator: None,
            };
            let every = scenario.output.log_every;
            Some(Recording::stream(
                stream,
                scene,
                run.columns(),
                run.dt(),
                every,
            )?)
        }
        None => None,
    };
    let mut extra: Vec<&mut dyn RowSink> = vec![&mut sink];
    if let Some(live) = &mut live {
        extra.push(live);
    }
    let report = if headless {
        run_built(run, &scenario, &dir, options, &mut extra)
    } else {
        let finished = AtomicBool::new(false);
        std::thread::scope(|scope| {
            let worker = scope.spawn(|| {
                // Raised however the run ends, a panic included, so the display never waits
                // for a run that is gone.
                let _done = RaiseOnDrop(&finished);
                run_built(run, &scenario, &dir, options, &mut extra)
            });
            let shown = screen::show(&name, &shared, &input, pad, quit, &finished);
            if shown.is_err() {
                quit.store(true, Ordering::SeqCst);
            }
            let report = worker
                .join()
                .map_err(|_| anyhow!("the run's thread panicked"))?;
            shown.context("the terminal display")?;
            report
        })
    }
    .with_context(|| path.display().to_string())?;
    if let Some(live) = live {
        live.finish()?;
    }
    Ok(TeleopReport {
        run: report,
        status: sink.finish(),
    })
}

/// Raises its flag when dropped.
struct RaiseOnDrop<'a>(&'a AtomicBool);

impl Drop for RaiseOnDrop<'_> {
    fn drop(&mut self) {
        self.0.store(true, Ordering::SeqCst);
    }
}
