//! What a run writes into its output directory: the streamed CSV log, files replaced whole
//! (metrics), and the lock that keeps two runs out of one directory.

mod csv_log;
mod dir_lock;
pub mod recording;

pub use csv_log::{check_size, estimated_size, megabytes, CsvLog, LOG_NAME, PARTIAL_LOG_NAME};
pub use dir_lock::DirLock;

use anyhow::{Context, Result};
use std::io::Write;
use std::path::{Path, PathBuf};

/// Every figure `corps run` and `corps sim` may write; a run removes those it did not write
/// this time, so no plot of an earlier run stays beside this run's log.
pub const PLOT_FILES: &[&str] = &[
    "com.png",
    "zmp.png",
    "feet.png",
    "tick_time.png",
    "ankle.png",
    "base_height.png",
    "cop.png",
    "contact_forces.png",
    "joint_torques.png",
    "following.png",
    "paths.png",
];

/// The index of column `name` in a run's log `columns`.
pub fn column(columns: &[String], name: &str) -> Result<usize> {
    columns
        .iter()
        .position(|c| c == name)
        .ok_or_else(|| anyhow::anyhow!("the log has no column '{name}'"))
}

/// Removes from `dir` the figures of [`PLOT_FILES`] that are not among `written`.
pub fn remove_stale_plots(dir: &Path, written: &[PathBuf]) -> Result<()> {
    for name in PLOT_FILES {
        let path = dir.join(name);
        if written.contains(&path) {
            continue;
        }
        match std::fs::remove_file(&path) {
            Err(e) if e.kind() != std::io::ErrorKind::NotFound => {
                return Err(e)
                    .with_context(|| format!("removing the stale plot {}", path.display()))
            }
            _ => {}
        }
    }
    Ok(())
}

pub use corps_scenario::scenario::DEFAULT_MAX_LOG_MB;

/// Writes `bytes` to `dir/name` through a temporary file, so a failed run never leaves half a
/// file over a previous one. The file is an ordinary one (0o666 less the umask).
pub fn write_atomic(dir: &Path, name: &str, bytes: &[u8]) -> Result<PathBuf> {
    let target = dir.join(name);
    let prefix = format!(".{name}.");
    let mut builder = tempfile::Builder::new();
    builder.prefix(&prefix).suffix(".partial");
    #[cfg(unix)]
    builder.permissions(std::os::unix::fs::PermissionsExt::from_mode(0o666));
    let mut tmp = builder
        .tempfile_in(dir)
        .with_context(|| format!("writing {}", target.display()))?;
    tmp.write_all(bytes)?;
    tmp.as_file().sync_all()?;
    tmp.persist(&target)
        .with_context(|| format!("writing {}", target.display()))?;
    Ok(target)
}
