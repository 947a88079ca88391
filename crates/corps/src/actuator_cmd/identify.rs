//! `corps actuator identify`.

use super::ActuatorArg;
use anyhow::{bail, Context, Result};
use clap::Args;
use corps_actuator::identification::{identify, IdentificationSettings, PARAMETER_NAMES};
use corps_actuator::records::{read_csv, truth, write_csv, RecordSimulation};
use serde_json::{json, Map, Value};
use std::path::PathBuf;

#[derive(Args)]
pub struct IdentifyArgs {
    /// Recorded data: CSV with columns t_s, q_rad, current_A, torque_sensor_Nm, payload
    /// (0/1; the runs with and without the known payload).
    data: Option<PathBuf>,
    /// Simulate the two experiments (exciting S-curves, 2 kHz, 19-bit encoder, current and
    /// torque-sensor noise) on the description's model instead of reading data.
    #[arg(long, conflicts_with = "data")]
    simulate: bool,
    /// The known payload's first moment L_Y (kg·m) in the recorded data.
    #[arg(long, value_name = "KGM")]
    payload_moment: Option<f64>,
    /// Seed of the simulated noise.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Write the simulated record to this CSV file (the format `identify DATA.csv` reads).
    #[arg(long, value_name = "FILE", requires = "simulate")]
    write_data: Option<PathBuf>,
    /// Print JSON: {"parameters": {"M_X": {"value", "sigma_percent", "truth"}, …},
    /// "rmsd_Nm", "cond"} ("truth" only when simulated).
    #[arg(long)]
    json: bool,
    #[command(flatten)]
    actuator: ActuatorArg,
}

pub fn run(args: IdentifyArgs) -> Result<()> {
    let description = args.actuator.load()?;
    let (data, truth) = if args.simulate {
        let sim = RecordSimulation {
            seed: args.seed,
            ..RecordSimulation::default()
        };
        let data = sim.run(&description);
        if let Some(path) = &args.write_data {
            super::write_file(path, write_csv(&data).as_bytes())?;
        }
        (data, Some(truth(&description, &sim.payload())))
    } else {
        let Some(path) = &args.data else {
            bail!("give a CSV file of recorded data, or --simulate");
        };
        let Some(moment) = args.payload_moment else {
            bail!("--payload-moment (the known payload's L_Y, kg·m) is needed with recorded data");
        };
        let text =
            std::fs::read_to_string(path).with_context(|| format!("reading {}", path.display()))?;
        let data = read_csv(&text, moment).with_context(|| path.display().to_string())?;
        (data, None)
    };
    let r = identify(&data, &IdentificationSettings::default())?;
    if args.json {
        let mut params = Map::new();
        for (i, name) in PARAMETER_NAMES.iter().enumerate() {
            let mut p = Map::new();
            p.insert("value".into(), json!(r.values[i]));
            p.insert("sigma_percent".into(), json!(r.sigma_percent[i]));
            if let Some(t) = &truth {
                p.insert("truth".into(), json!(t[i]));
            }
            params.insert((*name).into(), Value::Object(p));
        }
        let out = json!({
            "parameters": params,
            "rmsd_Nm": r.rmsd_nm,
            "cond": r.cond,
            "samples": r.samples,
        });
        return crate::stdout::print(&format!("{}\n", serde_json::to_string_pretty(&out)?));
    }
    let mut text = format!(
        "Identification of {} (seed 000 §6; Table 3.1 names; L_Y is the known payload moment)\n",
        description.joint
    );
    text.push_str(if truth.is_some() {
        "parameter    value     σ%      truth   |error|/σ\n"
    } else {
        "parameter    value     σ%\n"
    });
    for (i, name) in PARAMETER_NAMES.iter().enumerate() {
        text.push_str(&format!(
            "{name:8} {:10.4} {:7.2}",
            r.values[i], r.sigma_percent[i]
        ));
        if let Some(t) = &truth {
            let sigma = r.sigma_percent[i] / 100.0 * r.values[i].abs();
            let z = if sigma > 0.0 {
                format!("{:8.2}", (r.values[i] - t[i]).abs() / sigma)
            } else {
                "   known".into()
            };
            text.push_str(&format!(" {:10.4} {z}", t[i]));
        }
        text.push('\n');
    }
    text.push_str(&format!(
        "torque RMSD {:.3} N·m (thesis 0.6), cond(W_b) {:.1} (thesis 36; columns normalised), \
         {} decimated samples\n",
        r.rmsd_nm, r.cond, r.samples
    ));
    crate::stdout::print(&text)
}
