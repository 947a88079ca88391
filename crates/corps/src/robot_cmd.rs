//! `corps robot init URDF [SRDF]`: writes a starting robot description for a new robot, with
//! the feet guessed from the lowest collision bodies and every guess marked `# CHECK`.

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
}

pub fn run(cmd: RobotCommand) -> Result<()> {
    let RobotCommand::Init { urdf, srdf, output } = cmd;
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
