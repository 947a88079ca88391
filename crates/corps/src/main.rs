//! `corps`: the command-line entry point. Library errors become one clear line on stderr and a
//! non-zero exit status.

mod model_cmd;
mod robot_cmd;

use corps::{actuator_cmd, drill_cmd, learn, mocap_cmd, run, sim_cmd, teleop};

use clap::{Parser, Subcommand};

#[derive(Parser)]
#[command(
    name = "corps",
    version,
    about = "Whole-body control of humanoid robots"
)]
struct Cli {
    /// Without a command: the main job, TALOS walking 1.2 m under the TSID torque controller
    /// (`corps run scenarios/walk/tsid_torque_20cm.toml`).
    #[command(subcommand)]
    command: Option<Command>,
}

#[derive(Subcommand)]
enum Command {
    /// Robot models: inspect a URDF, evaluate dynamics at given states.
    #[command(subcommand)]
    Model(model_cmd::ModelCommand),
    /// Robot descriptions: draft one for a new robot from its URDF.
    #[command(subcommand)]
    Robot(robot_cmd::RobotCommand),
    /// Run a simulation scenario (TOML): log every signal to CSV, plot, summarize.
    Sim(sim_cmd::SimArgs),
    /// Run a whole-body controller on the simulated robot (TOML scenario): print the metrics,
    /// write the log, metrics and plots.
    Run(run::RunArgs),
    /// Walk the robot from the keyboard (velocity commands to the walking MPC, seed 002
    /// §4.14) in real time with a terminal display, or from a key script (`--keys`).
    Teleop(teleop::TeleopArgs),
    /// Joint actuators (seed 000 ch. 3): identification, thermal model, current-limiting MPC.
    #[command(subcommand)]
    Actuator(actuator_cmd::ActuatorCommand),
    /// Learn a controller's task weights (seed 001 ch. 5) with the constrained (1+1)-CMA-ES
    /// over randomized rollouts (a campaign file, TOML).
    Learn(learn::LearnArgs),
    /// Motion capture of an operator (seed 001 ch. 6): retarget a clip onto a robot, or play
    /// one on the live stream.
    #[command(subcommand)]
    Mocap(mocap_cmd::MocapCommand),
    /// A fixed-base arm drills a plate under the passive QP (seed 000 §3.19, Table 6.2): the
    /// clamping force against its bounds, the energy tank, the two loops.
    Drill(drill_cmd::DrillArgs),
}

fn main() {
    let cli = Cli::parse();
    corps::interrupt::install();
    let result = match cli.command {
        None => run::run_main_job(),
        Some(Command::Model(cmd)) => model_cmd::run(cmd),
        Some(Command::Robot(cmd)) => robot_cmd::run(cmd),
        Some(Command::Sim(args)) => sim_cmd::run(args),
        Some(Command::Run(args)) => run::run(args),
        Some(Command::Teleop(args)) => teleop::run(args),
        Some(Command::Actuator(cmd)) => actuator_cmd::run(cmd),
        Some(Command::Learn(args)) => learn::run(args),
        Some(Command::Mocap(cmd)) => mocap_cmd::run(cmd),
        Some(Command::Drill(args)) => drill_cmd::run(args),
    };
    if let Err(e) = result {
        if let Some(stop) = e.downcast_ref::<corps::interrupt::Interrupted>() {
            eprintln!("corps: {stop}");
            std::process::exit(corps::interrupt::EXIT_STATUS);
        }
        eprintln!("corps: error: {e:#}");
        std::process::exit(1);
    }
}
