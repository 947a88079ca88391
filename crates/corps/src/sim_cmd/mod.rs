//! `corps sim SCENARIO.toml`: runs a scenario in the simulator with a progress bar, writes
//! every signal to `log.csv` and the plots to PNG files in the output directory, and prints a
//! summary.
//!
//! - [`scenario`]: the TOML schema and the checks that need no model;
//! - [`setup`]: builds robot, terrain, simulator, sensors and command, checking the rest;
//! - [`log`]: the CSV log; [`plots`]: the PNG plots; [`summary`]: the printed summary.

pub(crate) mod log;
pub(crate) mod plots;
pub(crate) mod pushes;
pub(crate) mod scenario;
pub(crate) mod setup;
mod summary;

use anyhow::{anyhow, bail, Context, Result};
use clap::Args;
use corps_model::{center_of_mass, forward_kinematics_placements, frame_placement, Data};
use nalgebra::Vector3;
use scenario::Scenario;
use setup::Setup;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::time::Instant;
use summary::{Summary, Tracker};

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
}

/// Runs `corps sim`.
pub fn run(args: SimArgs) -> Result<()> {
    let path = &args.scenario;
    let shown = path.display();
    let text = read_scenario(path)?;
    let mut scenario = Scenario::parse(&text).map_err(|e| anyhow!("{shown}: {e}"))?;
    if scenario.controller.is_some() {
        bail!("{shown}: this scenario has a [controller]: run it with `corps run`");
    }
    if let Some(d) = args.duration {
        scenario = scenario
            .with_duration(d)
            .map_err(|e| anyhow!("{shown}: {e}"))?;
    }
    if let Some(mb) = args.max_log_mb {
        scenario = scenario
            .with_max_log_mb(mb)
            .map_err(|e| anyhow!("{shown}: {e}"))?;
    }
    let base_dir = path.parent().unwrap_or(Path::new("."));
    let setup = setup::build(&scenario, base_dir).map_err(|e| anyhow!("{shown}: {e:#}"))?;
    let name = scenario.run_name(path);
    let dir = args
        .output
        .or_else(|| scenario.output.directory.clone())
        .unwrap_or_else(|| PathBuf::from("out").join(&name));
    std::fs::create_dir_all(&dir)
        .with_context(|| format!("creating the output directory {}", dir.display()))?;
    let summary = simulate(&scenario, setup, &dir, name).map_err(|e| anyhow!("{shown}: {e:#}"))?;
    // A closed pipe (`corps sim ... | head`) is not an error of the run.
    match write!(std::io::stdout().lock(), "{summary}") {
        Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => {
            Err(e).context("printing the summary")
        }
        _ => Ok(()),
    }
}

/// The text of the scenario file at `path`, or a one-line error naming it.
pub fn read_scenario(path: &Path) -> Result<String> {
    let shown = path.display();
    match std::fs::read_to_string(path) {
        Ok(t) => Ok(t),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
            bail!("{shown}: no such scenario file")
        }
        Err(e) => bail!("{shown}: cannot read the scenario file: {e}"),
    }
}

/// Runs the simulation loop, logging each tick; writes the log and plots once it finished.
fn simulate(scenario: &Scenario, setup: Setup, dir: &Path, name: String) -> Result<Summary> {
    let Setup {
        model,
        mut sim,
        mut sensors,
        command,
        feet,
        ticks,
        q0,
    } = setup;
    let ft_names: Vec<String> = sensors.force_torque_names().map(String::from).collect();
    let header = log::columns(&model, &ft_names, &feet);
    let cap = scenario.output.max_log_bytes();
    crate::output::check_size(ticks.div_ceil(scenario.output.log_every), header.len(), cap)?;
    let _lock = crate::output::DirLock::acquire(dir)?;
    let mut csv = crate::output::CsvLog::create(dir, &header, cap)?;
    let joints: Vec<String> = log::actuated_joints(&model)
        .into_iter()
        .map(|(n, _)| n)
        .collect();
    let labels: Vec<String> = feet.iter().map(|f| f.label.clone()).collect();
    let mut traces = plots::Traces::new(ticks, &labels, &joints);

    let mut data = Data::new(&model);
    forward_kinematics_placements(&model, &mut data, q0.as_slice())?;
    let feet_start = feet
        .iter()
        .map(|f| Ok(frame_placement(&model, &data, f.frame)?.translation))
        .collect::<Result<Vec<_>>>()?;
    let mut tracker = Tracker::new(feet_start);

    let zeros = vec![0.0; model.nv];
    let mut row = Vec::with_capacity(header.len());
    let mut feet_fz = vec![0.0; feet.len()];
    let mut feet_ft = vec![[0.0; 6]; feet.len()];
    let mut feet_pos = vec![Vector3::zeros(); feet.len()];
    let mut progress = crate::progress::Progress::new(ticks, scenario.sim.control_dt, true);
    let start = Instant::now();
    for tick in 0..ticks {
        sim.step(&command)?;
        sensors.update(&sim);
        let (truth, measured) = (sensors.truth(), sensors.measured());
        let (q, v) = (sim.q().as_slice(), sim.v().as_slice());
        let com = center_of_mass(&model, &mut data, q, v, &zeros)?;
        let com_velocity = data.vcom;
        for (k, f) in feet.iter().enumerate() {
            feet_fz[k] = truth.contact_wrenches[f.joint][2];
            feet_ft[k] = measured.force_torque[f.sensor];
            feet_pos[k] = frame_placement(&model, sim.data(), f.frame)?.translation;
        }
        let total_fz = truth.contact_wrenches.iter().map(|w| w[2]).sum();
        log::fill_row(
            &mut row,
            truth,
            measured,
            &log::Extra {
                com: &com,
                com_velocity: &com_velocity,
                feet_fz: &feet_fz,
                total_fz,
            },
        );
        if tick % scenario.output.log_every == 0 {
            csv.row(&row)?;
        }
        traces.push(
            tick,
            &plots::Sample {
                t: truth.time,
                base_z: q[2],
                com: com.into(),
                feet_fz: &feet_fz,
                feet_ft: &feet_ft,
                total_fz,
                tau: truth.joint_torques.as_slice(),
            },
        );
        tracker.update(truth.time, q[2], &feet_pos);
        progress.tick(tick);
    }
    progress.finish();
    let wall = start.elapsed();
    let (rows, columns) = (csv.rows(), csv.columns());
    let log = csv.finish()?;
    let plots = if scenario.output.plots {
        traces.write_pngs(dir)?
    } else {
        vec![]
    };
    let q = sim.q();
    Ok(Summary {
        name,
        simulated: sim.time(),
        ticks,
        control_dt: scenario.sim.control_dt,
        wall,
        final_base: [q[0], q[1], q[2]],
        min_base_z: tracker.min_base_z,
        fell_at: tracker.fell_at,
        slip: labels.into_iter().zip(tracker.max_slip).collect(),
        log,
        rows,
        columns,
        plots,
    })
}
