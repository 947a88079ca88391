//! `corps sim SCENARIO.toml`: simulates a scenario (`corps_scenario::simulation`) with a
//! progress bar, writes every signal to `log.csv` and the plots to PNG files in the output
//! directory ([`plots`]), and prints a summary ([`summary`]).

pub(crate) mod plots;
mod summary;

use anyhow::{anyhow, bail, Context, Result};
use clap::Args;
use corps_scenario::overrides::Overrides;
use corps_scenario::scenario::Scenario;
use corps_scenario::simulation::Simulation;
use corps_scenario::ScenarioError;
use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;
use std::time::Instant;
use summary::Summary;

/// Arguments of `corps sim`.
#[derive(Args)]
pub struct SimArgs {
    /// Scenario file (TOML); see `scenarios/` and the README.
    scenario: PathBuf,
    /// Output directory (default: `[output] directory` of the scenario, else `out/<name>`).
    #[arg(short, long)]
    output: Option<PathBuf>,
    /// Simulate this many seconds instead of the scenario's `duration`.
    #[arg(long, value_name = "SECONDS")]
    duration: Option<f64>,
    /// Size cap of the log in MB (replaces `[output] max_log_mb`, default 1024).
    #[arg(long, value_name = "MB")]
    max_log_mb: Option<f64>,
    /// The robot, replacing the scenario's: `talos`, `icub`, `icub_backpacked`, `simple_humanoid` or a robot
    /// description file (`robots/*/*.toml`).
    #[arg(long, value_name = "ROBOT")]
    robot: Option<String>,
}

/// Runs `corps sim`.
pub fn run(args: SimArgs) -> Result<()> {
    let path = &args.scenario;
    let shown = path.display();
    let text = read_scenario(path)?;
    let overrides = Overrides {
        duration: args.duration,
        max_log_mb: args.max_log_mb,
        robot: args.robot.clone(),
        ..Overrides::default()
    };
    let scenario = Scenario::parse_with(&text, path, &overrides).map_err(|e| anyhow!(e))?;
    if scenario.controller.is_some() {
        bail!("{shown}: this scenario has a [controller]: run it with `corps run`");
    }
    let base_dir = path.parent().unwrap_or(Path::new("."));
    let simulation = Simulation::new(&scenario, base_dir).map_err(|e| anyhow!("{shown}: {e:#}"))?;
    let name = scenario.run_name(path);
    let dir = args
        .output
        .or_else(|| scenario.output.directory.clone())
        .unwrap_or_else(|| PathBuf::from("out").join(&name));
    std::fs::create_dir_all(&dir)
        .with_context(|| format!("creating the output directory {}", dir.display()))?;
    let summary = simulate(
        &scenario,
        simulation,
        &dir,
        name,
        Some(&crate::interrupt::FLAG),
    )
    .map_err(|e| anyhow!("{shown}: {e:#}"))?;
    crate::stdout::print(&summary.to_string())?;
    if let Some(t) = summary.interrupted_at {
        return Err(crate::interrupt::Interrupted {
            t,
            dir: dir.display().to_string(),
        }
        .into());
    }
    if summary.verdict.verdict != scenario.expect {
        bail!(
            "{shown}: the run ended {} (the scenario expects {}; outputs in {})",
            summary.verdict,
            scenario.expect,
            dir.display()
        );
    }
    Ok(())
}

/// The text of the scenario file at `path`, or a one-line error naming it.
pub fn read_scenario(path: &Path) -> Result<String> {
    corps_scenario::overrides::read_file(path).map_err(|e| anyhow::anyhow!(e))
}

/// Runs the simulation, logging each tick; writes the log and plots once it finished, or once
/// `interrupt` was raised.
fn simulate(
    scenario: &Scenario,
    simulation: Simulation,
    dir: &Path,
    name: String,
    interrupt: Option<&AtomicBool>,
) -> Result<Summary> {
    let ticks = simulation.ticks();
    let header = simulation.columns().to_vec();
    let cap = scenario.output.max_log_bytes();
    let every = scenario.output.log_every;
    crate::output::check_size(ticks.div_ceil(every), header.len(), cap)?;
    let _lock = crate::output::DirLock::acquire(dir)?;
    let mut csv = crate::output::CsvLog::create(dir, &header, cap)?;
    let mut traces =
        plots::Traces::new(ticks, &simulation.feet_labels(), &simulation.joint_names());
    let mut progress = crate::progress::Progress::new(ticks, scenario.sim.control_dt, true);
    let start = Instant::now();
    let outcome = simulation.run(
        &mut |tick| {
            if tick.index % every == 0 {
                (csv.row(tick.row)).map_err(|e| ScenarioError::Output(format!("{e:#}")))?;
            }
            traces.push(tick.index, &tick.signals);
            progress.tick(tick.index);
            Ok(())
        },
        interrupt,
    )?;
    progress.finish();
    let wall = start.elapsed();
    let (rows, columns) = (csv.rows(), csv.columns());
    let log = csv.finish()?;
    let plots = if scenario.output.plots {
        traces.write_pngs(dir)?
    } else {
        vec![]
    };
    crate::output::remove_stale_plots(dir, &plots)?;
    Ok(Summary {
        name,
        simulated: outcome.simulated,
        ticks: outcome.ticks,
        control_dt: scenario.sim.control_dt,
        wall,
        final_base: outcome.final_base,
        min_base_z: outcome.min_base_z,
        verdict: outcome.verdict,
        interrupted_at: outcome.interrupted_at,
        slip: outcome.slip,
        log,
        rows,
        columns,
        plots,
    })
}
