//! `corps robot init URDF [SRDF]`: writes a starting robot description for a new robot, with
//! the feet guessed from the lowest collision bodies and every guess marked `# CHECK`.
//! `corps robot stiffness SCENARIO --joints A,B`: identifies the stiffness of passive joints
//! from a one-leg stance ([`corps_scenario::identify`], seed 000 App. 4).

use anyhow::{bail, Context, Result};
use clap::Subcommand;
use std::path::{Path, PathBuf};

#[derive(Subcommand)]
pub enum RobotCommand {
    /// Write a starting description (TOML) for the robot of URDF, to check and complete.
    Init {
        /// The robot's URDF.
        urdf: PathBuf,
        /// Its SRDF with a reference posture (group_state).
        srdf: Option<PathBuf>,
        /// Where to write the description, a `.toml` file (default: `<urdf stem>.toml` in the
        /// current directory). An existing file is never replaced.
        #[arg(short, long)]
        output: Option<PathBuf>,
    },
    /// Identify one stiffness for passive joints of the robot (a side of a flexible hip) from
    /// a one-leg stance scenario under `[controller.flexibility] compensation = "model"`:
    /// the stiffness at which the F/T sensors' CoP meets the controller's CoM.
    Stiffness {
        /// The one-foot scenario (TOML).
        scenario: PathBuf,
        /// The passive joints (names of the description's `[[passive_joints]]`), comma-separated.
        #[arg(long, value_delimiter = ',', required = true)]
        joints: Vec<String>,
        /// The second run's stiffness (the first has no compensation), N·m/rad.
        #[arg(long, default_value_t = 1000.0)]
        first_guess: f64,
        /// Runs at most.
        #[arg(long, default_value_t = 8)]
        max_runs: usize,
    },
}

pub fn run(cmd: RobotCommand) -> Result<()> {
    let (urdf, srdf, output) = match cmd {
        RobotCommand::Init { urdf, srdf, output } => (urdf, srdf, output),
        RobotCommand::Stiffness {
            scenario,
            joints,
            first_guess,
            max_runs,
        } => return stiffness(&scenario, &joints, first_guess, max_runs),
    };
    let model = corps_scenario::default_robot::load_model(Some(&urdf), srdf.as_deref(), false)?;
    let output = output.unwrap_or_else(|| {
        let stem = urdf
            .file_stem()
            .map_or("robot".into(), |s| s.to_string_lossy().into_owned());
        PathBuf::from(format!("{stem}.toml"))
    });
    if output.extension().is_none_or(|e| e != "toml") {
        bail!("{}: a robot description is a .toml file", output.display());
    }
    if output.exists() {
        bail!(
            "{}: already exists; corps robot init does not replace a file",
            output.display()
        );
    }
    let dir = output
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let relative = |p: &Path| relative_path(p, dir);
    let text = corps_robot::init::draft(
        &model,
        &relative(&urdf),
        srdf.as_deref().map(relative).as_deref(),
    );
    std::fs::write(&output, text).with_context(|| format!("writing {}", output.display()))?;
    corps::stdout::print(&format!(
        "wrote {}: check every line marked CHECK, then run it with --robot {}\n",
        output.display(),
        output.display()
    ))
}

/// `path` as seen from `dir` (both made absolute), with `/` separators.
fn relative_path(path: &Path, dir: &Path) -> String {
    let abs = |p: &Path| {
        std::fs::canonicalize(p)
            .unwrap_or_else(|_| std::env::current_dir().unwrap_or_default().join(p))
    };
    let (path, dir) = (abs(path), abs(dir));
    let common = path
        .components()
        .zip(dir.components())
        .take_while(|(a, b)| a == b)
        .count();
    let mut out = PathBuf::new();
    for _ in dir.components().skip(common) {
        out.push("..");
    }
    for c in path.components().skip(common) {
        out.push(c);
    }
    out.to_string_lossy().replace('\\', "/")
}

/// `corps robot stiffness`: the search, one line per run, then the estimate.
fn stiffness(path: &Path, joints: &[String], first_guess: f64, max_runs: usize) -> Result<()> {
    let text =
        std::fs::read_to_string(path).with_context(|| format!("reading {}", path.display()))?;
    let scenario = corps_scenario::scenario::Scenario::parse(&text)
        .map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))?;
    let base = path.parent().unwrap_or(Path::new("."));
    let search = corps_scenario::identify::StiffnessSearch {
        first_guess,
        max_runs,
        ..Default::default()
    };
    let estimate = corps_scenario::identify::identify_stiffness(&scenario, base, joints, &search)
        .map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))?;
    let mut out = String::new();
    for (k, p) in estimate.probes.iter().enumerate() {
        let assumed = p
            .stiffness
            .map_or("none (no compensation)".to_string(), |s| {
                format!("{s:.1} N·m/rad")
            });
        out += &format!(
            "run {}: stiffness {assumed}: CoP − controller CoM {:+.3} mm sideways, sole moment x {:+.2} N·m\n",
            k + 1,
            p.cop_offset * 1e3,
            p.moment
        );
    }
    out += &format!(
        "stiffness of {}: {:.0} N·m/rad ({})\n",
        joints.join(", "),
        estimate.stiffness,
        if estimate.converged {
            "converged"
        } else {
            "not converged within the runs"
        }
    );
    corps::stdout::print(&out)
}
