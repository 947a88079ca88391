//! `corps sim SCENARIO.toml`: runs a scenario in the simulator with a progress bar, writes
//! every signal to `log.csv` and the plots to PNG files in the output directory, and prints a
//! summary.
//!
//! - [`scenario`]: the TOML schema and the checks that need no model;
//! - [`setup`]: builds robot, terrain, simulator, sensors and command, checking the rest;
//! - [`log`]: the CSV log; [`plots`]: the PNG plots; [`summary`]: the printed summary.

pub(crate) mod log;
pub(crate) mod plots;
mod summary;

use anyhow::{anyhow, bail, Context, Result};
use clap::Args;
use corps_loop::verdict::{TickSample, VerdictObserver};
use corps_model::{center_of_mass, forward_kinematics_placements, frame_placement, Data};
use corps_scenario::scenario::{self, Scenario};
use corps_scenario::setup::{self, Setup};
use nalgebra::Vector3;
use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;
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
    /// The robot, replacing the scenario's: `talos`, `icub`, `simple_humanoid` or a robot
    /// description file (`robots/*/*.toml`).
    #[arg(long, value_name = "ROBOT")]
    robot: Option<String>,
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
    if let Some(robot) = &args.robot {
        scenario.robot = scenario::RobotSection::from_argument(robot);
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
    let summary = simulate(&scenario, setup, &dir, name, Some(&crate::interrupt::FLAG))
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
    let shown = path.display();
    match std::fs::read_to_string(path) {
        Ok(t) => Ok(t),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
            bail!("{shown}: no such scenario file")
        }
        Err(e) => bail!("{shown}: cannot read the scenario file: {e}"),
    }
}

/// Runs the simulation loop, logging each tick; writes the log and plots once it finished,
/// or once `interrupt` was raised.
fn simulate(
    scenario: &Scenario,
    setup: Setup,
    dir: &Path,
    name: String,
    interrupt: Option<&AtomicBool>,
) -> Result<Summary> {
    let Setup {
        model,
        mut sim,
        mut sensors,
        command,
        feet,
        ticks,
        q0,
        criteria,
        ..
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
    // The verdict: the CoM height above the lowest sole (the ground when no foot is named),
    // the contact on bodies other than the feet (not judged when no foot is named).
    // Forces are judged in body weights; without gravity, in weights under standard gravity.
    let g = Vector3::from(scenario.sim.gravity).norm();
    let weight = model.total_mass()
        * if g > 0.0 {
            g
        } else {
            corps_model::STANDARD_GRAVITY
        };
    let support = |feet: &[Vector3<f64>]| feet.iter().map(|p| p.z).fold(f64::INFINITY, f64::min);
    let ground = if feet.is_empty() {
        0.0
    } else {
        support(&feet_start)
    };
    let zeros_v = vec![0.0; model.nv];
    let com0 = center_of_mass(&model, &mut data, q0.as_slice(), &zeros_v, &zeros_v)?;
    let mut verdict = VerdictObserver::new(criteria, weight, com0.z - ground).context("verdict")?;
    let foot_joints: Vec<usize> = feet.iter().map(|f| f.joint).collect();
    let mut tracker = Tracker::new(feet_start);

    let zeros = vec![0.0; model.nv];
    let mut row = Vec::with_capacity(header.len());
    let mut feet_fz = vec![0.0; feet.len()];
    let mut feet_ft = vec![[0.0; 6]; feet.len()];
    let mut feet_pos = vec![Vector3::zeros(); feet.len()];
    let mut progress = crate::progress::Progress::new(ticks, scenario.sim.control_dt, true);
    let start = Instant::now();
    let mut ticks_run = 0;
    let mut interrupted_at = None;
    for tick in 0..ticks {
        if crate::interrupt::raised(interrupt) {
            interrupted_at = Some(sim.time());
            break;
        }
        if let Err(e) = sim.step(&command) {
            match e {
                corps_sim::SimError::Diverged { t, reason } => {
                    verdict.diverged(t, format!("the simulation: {reason}"));
                    break;
                }
                other => return Err(other.into()),
            }
        }
        ticks_run = tick + 1;
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
        tracker.update(q[2], &feet_pos);
        let total = truth
            .contact_wrenches
            .iter()
            .fold(Vector3::zeros(), |s, w| s + Vector3::new(w[0], w[1], w[2]));
        let other = if feet.is_empty() {
            0.0
        } else {
            truth
                .contact_wrenches
                .iter()
                .enumerate()
                .filter(|(j, _)| !foot_joints.contains(j))
                .fold(Vector3::zeros(), |s, (_, w)| {
                    s + Vector3::new(w[0], w[1], w[2])
                })
                .norm()
        };
        let stop = verdict.observe(&TickSample {
            t: truth.time,
            com_height: com.z
                - if feet.is_empty() {
                    ground
                } else {
                    support(&feet_pos)
                },
            base_speed: Vector3::new(v[0], v[1], v[2]).norm(),
            total_contact_force: total.norm(),
            other_contact_force: other,
            state_finite: q.iter().chain(v).all(|x| x.is_finite()),
            safe_command: false,
        });
        if stop.is_some() {
            break;
        }
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
    crate::output::remove_stale_plots(dir, &plots)?;
    let q = sim.q();
    Ok(Summary {
        name,
        simulated: sim.time(),
        ticks: ticks_run,
        control_dt: scenario.sim.control_dt,
        wall,
        final_base: [q[0], q[1], q[2]],
        min_base_z: tracker.min_base_z,
        verdict: verdict.finish(sim.time()),
        interrupted_at,
        slip: labels.into_iter().zip(tracker.max_slip).collect(),
        log,
        rows,
        columns,
        plots,
    })
}
