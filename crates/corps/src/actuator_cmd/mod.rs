//! `corps actuator`: the single-joint drive of seed 000 ch. 3 — identification of its
//! parameters, its thermal model, and the current-limiting iLQR in closed loop.

mod identify;
mod mpc;
mod thermal;

use anyhow::{Context, Result};
use clap::{Args, Subcommand};
use corps_actuator::ActuatorDescription;
use corps_robot::files::FileSource;
use std::path::{Path, PathBuf};

/// The description used when none is given: the TALOS elbow, built in.
const DEFAULT_ACTUATOR: &str = "config/talos/actuators/elbow.toml";

#[derive(Subcommand)]
pub enum ActuatorCommand {
    /// Identify the drive's parameters (seed 000 §6: total least squares with the gains
    /// inside, σ% per parameter) from a recorded CSV file, or from simulated experiments.
    Identify(identify::IdentifyArgs),
    /// The motor's thermal model (Eq 3.6–3.8): identify it from a heating record, or predict
    /// the temperature of holding a load.
    #[command(subcommand)]
    Thermal(thermal::ThermalCommand),
    /// The current-limiting iLQR (§3.13) in closed loop at 1 kHz on the joint with a payload.
    Mpc(mpc::MpcArgs),
}

/// The actuator description option shared by the subcommands.
#[derive(Args, Clone)]
pub struct ActuatorArg {
    /// Actuator description (TOML: joint, [model], [limits], [thermal]); default: the
    /// built-in TALOS elbow (config/talos/actuators/elbow.toml).
    #[arg(long, value_name = "FILE")]
    actuator: Option<PathBuf>,
}

impl ActuatorArg {
    fn load(&self) -> Result<ActuatorDescription> {
        let (source, path) = match &self.actuator {
            Some(p) => (FileSource::Disk, p.as_path()),
            None => (FileSource::BuiltIn, Path::new(DEFAULT_ACTUATOR)),
        };
        let text = source.read(path).map_err(anyhow::Error::msg)?;
        ActuatorDescription::from_toml(&text).with_context(|| source.show(path))
    }
}

pub fn run(cmd: ActuatorCommand) -> Result<()> {
    match cmd {
        ActuatorCommand::Identify(args) => identify::run(args),
        ActuatorCommand::Thermal(cmd) => thermal::run(cmd),
        ActuatorCommand::Mpc(args) => mpc::run(args),
    }
}

/// Writes `bytes` to `path` through a temporary file in its directory.
fn write_file(path: &Path, bytes: &[u8]) -> Result<PathBuf> {
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    let name = path
        .file_name()
        .with_context(|| format!("{} names no file", path.display()))?
        .to_string_lossy()
        .into_owned();
    crate::output::write_atomic(dir, &name, bytes)
}
