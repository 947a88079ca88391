//! `corps actuator thermal identify` and `corps actuator thermal predict`.

use super::ActuatorArg;
use anyhow::{bail, Context, Result};
use clap::{Args, Subcommand};
use corps_actuator::thermal::{identify_thermal, HeatingRecord, HeatingSimulation};
use serde_json::json;
use std::path::PathBuf;

#[derive(Subcommand)]
pub enum ThermalCommand {
    /// Fit C_th, R_th and the drives' heat P_0 to a heating record (CSV with columns t_s,
    /// current_A, temperature_C), or to a simulated one.
    Identify(IdentifyArgs),
    /// Predict the motor temperature while the joint holds a load still.
    Predict(PredictArgs),
}

#[derive(Args)]
pub struct IdentifyArgs {
    /// Heating record: CSV with columns t_s, current_A (RMS over the interval ending at the
    /// sample), temperature_C.
    data: Option<PathBuf>,
    /// Simulate a record (30 min of sinusoidal motion under load, 30 min of cooling, a
    /// 0.1 °C sensor) on the description's thermal model.
    #[arg(long, conflicts_with = "data")]
    simulate: bool,
    #[arg(long, default_value_t = 1)]
    seed: u64,
    #[arg(long)]
    json: bool,
    #[command(flatten)]
    actuator: ActuatorArg,
}

#[derive(Args)]
pub struct PredictArgs {
    /// Load held, kg.
    #[arg(long, default_value_t = 20.0)]
    hold_kg: f64,
    /// Its distance from the joint along the link, m.
    #[arg(long, default_value_t = 0.05)]
    distance_m: f64,
    /// Joint angle, rad (default: the forearm horizontal, the largest gravity torque).
    #[arg(long, default_value_t = -std::f64::consts::FRAC_PI_2, allow_hyphen_values = true)]
    angle_rad: f64,
    /// How long it is held, s.
    #[arg(long, default_value_t = 3600.0)]
    duration_s: f64,
    #[arg(long)]
    json: bool,
    #[command(flatten)]
    actuator: ActuatorArg,
}

pub fn run(cmd: ThermalCommand) -> Result<()> {
    match cmd {
        ThermalCommand::Identify(args) => identify(args),
        ThermalCommand::Predict(args) => predict(args),
    }
}

fn read_record(path: &PathBuf) -> Result<HeatingRecord> {
    let text =
        std::fs::read_to_string(path).with_context(|| format!("reading {}", path.display()))?;
    HeatingRecord::read_csv(&text).with_context(|| path.display().to_string())
}

fn identify(args: IdentifyArgs) -> Result<()> {
    let d = args.actuator.load()?;
    let record = if args.simulate {
        HeatingSimulation {
            seed: args.seed,
            ..HeatingSimulation::default()
        }
        .run(&d.thermal)
    } else {
        let Some(path) = &args.data else {
            bail!("give a heating record (CSV), or --simulate");
        };
        read_record(path)?
    };
    let fit = identify_thermal(&record, &d.thermal)?;
    let truth = args.simulate.then_some(d.thermal);
    if args.json {
        let mut out = json!({
            "C_th_J_per_K": {"value": fit.heat_capacity_j_per_k, "sigma_percent": fit.sigma_percent[0]},
            "R_th_K_per_W": {"value": fit.thermal_resistance_k_per_w, "sigma_percent": fit.sigma_percent[1]},
            "P_0_W": {"value": fit.idle_power_w, "sigma_percent": fit.sigma_percent[2]},
            "rmsd_K": fit.rmsd_k,
        });
        if let Some(t) = truth {
            out["C_th_J_per_K"]["truth"] = json!(t.heat_capacity_j_per_k);
            out["R_th_K_per_W"]["truth"] = json!(t.thermal_resistance_k_per_w);
            out["P_0_W"]["truth"] = json!(t.idle_power());
        }
        return crate::stdout::print(&format!("{}\n", serde_json::to_string_pretty(&out)?));
    }
    let row = |name: &str, v: f64, s: f64, t: Option<f64>| {
        let t = t.map(|t| format!("  (truth {t:.4})")).unwrap_or_default();
        format!("{name:6} {v:10.4}  σ {s:.3} %{t}\n")
    };
    let mut text = format!("Thermal model of {} (seed 000 Eq 3.6–3.8)\n", d.joint);
    text += &row(
        "C_th",
        fit.heat_capacity_j_per_k,
        fit.sigma_percent[0],
        truth.map(|t| t.heat_capacity_j_per_k),
    );
    text += &row(
        "R_th",
        fit.thermal_resistance_k_per_w,
        fit.sigma_percent[1],
        truth.map(|t| t.thermal_resistance_k_per_w),
    );
    text += &row(
        "P_0",
        fit.idle_power_w,
        fit.sigma_percent[2],
        truth.map(|t| t.idle_power()),
    );
    text += &format!(
        "temperature RMSD {:.3} K over {} samples\n",
        fit.rmsd_k,
        record.t.len()
    );
    crate::stdout::print(&text)
}

fn predict(args: PredictArgs) -> Result<()> {
    let d = args.actuator.load()?;
    let finite = [
        args.hold_kg,
        args.distance_m,
        args.duration_s,
        args.angle_rad,
    ]
    .iter()
    .all(|x| x.is_finite());
    if !(finite && args.hold_kg >= 0.0 && args.distance_m >= 0.0 && args.duration_s >= 0.0) {
        bail!(
            "--hold-kg, --distance-m and --duration-s must be finite and ≥ 0, --angle-rad finite"
        );
    }
    if args.duration_s > 1e7 {
        bail!(
            "--duration-s {} is beyond 10⁷ s: the equilibrium temperature is the answer",
            args.duration_s
        );
    }
    let payload = corps_actuator::elbow::Payload::point_mass(args.hold_kg, args.distance_m);
    let m = &d.model;
    // Holding still: gravity and the offset, friction taken as neither helping nor hindering.
    let (_, _, off) = m.friction();
    let torque = m.gravity(args.angle_rad, &payload) + off;
    let current = torque / m.drive_gain;
    let th = &d.thermal;
    let after = th.predict(th.idle_c, current, args.duration_s);
    let steady = th.steady_state(current);
    let safe = steady.is_some_and(|t| t < th.max_temperature_c);
    if args.json {
        let out = json!({
            "current_A": current,
            "torque_Nm": torque,
            "temperature_after_C": after,
            "steady_state_C": steady,
            "max_temperature_C": th.max_temperature_c,
            "safe": safe,
        });
        return crate::stdout::print(&format!("{}\n", serde_json::to_string_pretty(&out)?));
    }
    let steady_text = steady
        .map(|t| format!("{t:.1} °C"))
        .unwrap_or_else(|| "none (thermal runaway)".into());
    crate::stdout::print(&format!(
        "{} holding {} kg at {} m, angle {:.3} rad: {torque:.2} N·m, {current:.2} A\n\
         temperature after {} s: {after:.1} °C; equilibrium {steady_text}; limit {} °C: {}\n",
        d.joint,
        args.hold_kg,
        args.distance_m,
        args.angle_rad,
        args.duration_s,
        th.max_temperature_c,
        if safe { "safe" } else { "NOT safe" },
    ))
}
