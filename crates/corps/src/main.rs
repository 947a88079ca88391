//! `corps`: the command-line entry point. Library errors become one clear line on stderr and a
//! non-zero exit status.

mod default_robot;
mod model_cmd;
mod sim_cmd;

use clap::{Parser, Subcommand};

#[derive(Parser)]
#[command(
    name = "corps",
    version,
    about = "Whole-body control of humanoid robots"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Robot models: inspect a URDF, evaluate dynamics at given states.
    #[command(subcommand)]
    Model(model_cmd::ModelCommand),
    /// Run a simulation scenario (TOML): log every signal to CSV, plot, summarize.
    Sim(sim_cmd::SimArgs),
}

fn main() {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Model(cmd) => model_cmd::run(cmd),
        Command::Sim(args) => sim_cmd::run(args),
    };
    if let Err(e) = result {
        eprintln!("corps: error: {e:#}");
        std::process::exit(1);
    }
}
