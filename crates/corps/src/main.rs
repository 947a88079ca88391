//! `corps`: the command-line entry point. Library errors become one clear line on stderr and a
//! non-zero exit status.

mod model_cmd;

use corps::{run, sim_cmd};

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
    /// Run a whole-body controller on the simulated robot (TOML scenario): print the metrics,
    /// write the log, metrics and plots.
    Run(run::RunArgs),
}

fn main() {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Model(cmd) => model_cmd::run(cmd),
        Command::Sim(args) => sim_cmd::run(args),
        Command::Run(args) => run::run(args),
    };
    if let Err(e) = result {
        eprintln!("corps: error: {e:#}");
        std::process::exit(1);
    }
}
