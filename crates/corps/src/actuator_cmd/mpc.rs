//! `corps actuator mpc`.

use super::ActuatorArg;
use crate::sim_cmd::plots::{draw_figure, Panel};
use anyhow::Result;
use clap::Args;
use corps_actuator::mpc::{MpcPlant, MpcScenario, MpcSeries};
use serde_json::json;
use std::path::PathBuf;

#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
enum PlantArg {
    Sim,
    Model,
}

#[derive(Args)]
pub struct MpcArgs {
    /// Payload on the link, kg (seed 000 §4.1: raised to 30 kg).
    #[arg(long, default_value_t = 30.0)]
    payload_kg: f64,
    /// Its distance from the joint, m.
    #[arg(long, default_value_t = 0.05)]
    distance_m: f64,
    /// Drop the exponential barriers (the comparison of Fig 3.10).
    #[arg(long)]
    no_barrier: bool,
    /// The plant: the joint in corps-sim behind its drive (current loop, one period of
    /// delay), or the MPC's own model.
    #[arg(long, value_enum, default_value_t = PlantArg::Sim)]
    plant: PlantArg,
    /// Period of the reference swing, s.
    #[arg(long, default_value_t = MpcScenario::default().period_s)]
    period_s: f64,
    /// Simulated time, s.
    #[arg(long, default_value_t = MpcScenario::default().duration_s)]
    duration_s: f64,
    /// Print the closed-loop series as JSON: {"t", "q_rad", "q_ref_rad", "current_A", …}.
    #[arg(long)]
    json: bool,
    /// Write mpc.csv and mpc.png to this directory.
    #[arg(short, long, value_name = "DIR")]
    output: Option<PathBuf>,
    #[command(flatten)]
    actuator: ActuatorArg,
}

pub fn run(args: MpcArgs) -> Result<()> {
    let d = args.actuator.load()?;
    let scenario = MpcScenario {
        payload_kg: args.payload_kg,
        distance_m: args.distance_m,
        period_s: args.period_s,
        duration_s: args.duration_s,
        barrier: !args.no_barrier,
        plant: match args.plant {
            PlantArg::Sim => MpcPlant::Simulator,
            PlantArg::Model => MpcPlant::Model,
        },
        ..MpcScenario::default()
    };
    let mut solve_us = Vec::new();
    let series = scenario.run_timed(&d, |elapsed| solve_us.push(elapsed.as_secs_f64() * 1e6))?;
    let ticks = series.t.len();
    solve_us.sort_by(f64::total_cmp);
    let pct = |p: f64| solve_us[((solve_us.len() - 1) as f64 * p) as usize];
    let min_i = series.current.iter().copied().fold(f64::INFINITY, f64::min);
    let max_i = series
        .current
        .iter()
        .copied()
        .fold(f64::NEG_INFINITY, f64::max);
    let min_q = series.q.iter().copied().fold(f64::INFINITY, f64::min);
    if let Some(dir) = &args.output {
        write_outputs(dir, &series, &d.limits)?;
    }
    if args.json {
        let out = json!({
            "t": series.t,
            "q_rad": series.q,
            "q_ref_rad": series.q_ref,
            "current_A": series.current,
            "iterations": series.iterations,
            "min_current_A": min_i,
            "max_current_A": max_i,
            "min_q_rad": min_q,
            "current_limit_A": d.limits.current,
            "position_limit_rad": d.limits.position,
        });
        return crate::stdout::print(&format!("{}\n", serde_json::to_string(&out)?));
    }
    let iterations = series.iterations.iter().sum::<usize>() as f64 / ticks.max(1) as f64;
    crate::stdout::print(&format!(
        "{} with {} kg at {} m, {} barriers, swing {:.2} → {:.2} rad every {} s, {} ticks at 1 kHz \
         on the {}\n\
         command {min_i:.2} … {max_i:.2} A (limit {:?}); lowest q {min_q:.3} rad (limit {:?})\n\
         solve (100 nodes, ≤ {} iterations, {iterations:.2} on average): median {:.0} µs, \
         95 % {:.0} µs, max {:.0} µs\n",
        d.joint,
        scenario.payload_kg,
        scenario.distance_m,
        if scenario.barrier { "with" } else { "without" },
        scenario.q_start,
        scenario.q_target,
        scenario.period_s,
        ticks,
        match scenario.plant {
            MpcPlant::Simulator => "simulated joint and drive",
            MpcPlant::Model => "MPC's own model",
        },
        d.limits.current,
        d.limits.position,
        scenario.iterations_per_tick,
        pct(0.5),
        pct(0.95),
        pct(1.0),
    ))
}

fn write_outputs(
    dir: &PathBuf,
    s: &MpcSeries,
    limits: &corps_actuator::elbow::Limits,
) -> Result<()> {
    std::fs::create_dir_all(dir)?;
    let mut csv = String::from("t_s,q_rad,q_ref_rad,current_A,iterations\n");
    for k in 0..s.t.len() {
        csv.push_str(&format!(
            "{},{},{},{},{}\n",
            s.t[k], s.q[k], s.q_ref[k], s.current[k], s.iterations[k]
        ));
    }
    crate::output::write_atomic(dir, "mpc.csv", csv.as_bytes())?;
    let n = s.t.len();
    let q_limit = vec![limits.position[0]; n];
    let i_limit = vec![limits.current[0]; n];
    let panels = [
        Panel::new(
            "joint position",
            "rad",
            vec![
                ("q".into(), &s.q),
                ("q reference".into(), &s.q_ref),
                ("limit".into(), &q_limit),
            ],
        ),
        Panel::new(
            "motor current command",
            "A",
            vec![("current".into(), &s.current), ("limit".into(), &i_limit)],
        ),
    ];
    draw_figure(
        &dir.join("mpc.png"),
        "Current-limiting iLQR in closed loop (seed 000 §3.13)",
        &s.t,
        &panels,
        1,
    )
}
