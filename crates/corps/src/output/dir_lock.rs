//! An exclusive lock on an output directory for the length of a run, so two runs never write
//! into one directory at once: the second is refused with one line. The lock is the
//! directory's own advisory lock (flock on Unix), released when the run ends or dies; it
//! leaves no file behind.

use anyhow::{bail, Context, Result};
use std::fs::File;
use std::path::Path;

/// Holds the lock while alive.
pub struct DirLock {
    _dir: File,
}

impl DirLock {
    /// Creates `dir` if needed and locks it, or says that another run holds it.
    pub fn acquire(dir: &Path) -> Result<Self> {
        std::fs::create_dir_all(dir)
            .with_context(|| format!("creating the output directory {}", dir.display()))?;
        let handle = File::open(dir)
            .with_context(|| format!("opening the output directory {}", dir.display()))?;
        match handle.try_lock() {
            Ok(()) => Ok(Self { _dir: handle }),
            Err(std::fs::TryLockError::WouldBlock) => bail!(
                "{}: another corps run is writing into this directory (choose another with -o)",
                dir.display()
            ),
            // A file system without locks: run unlocked rather than not at all.
            Err(std::fs::TryLockError::Error(_)) => Ok(Self { _dir: handle }),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_second_run_into_a_locked_directory_is_refused_until_the_first_ends() {
        let tmp = tempfile::tempdir().unwrap();
        let dir = tmp.path().join("out");
        let first = DirLock::acquire(&dir).unwrap();
        let e = DirLock::acquire(&dir).err().expect("refused").to_string();
        assert!(e.contains("another corps run"), "{e}");
        drop(first);
        assert!(DirLock::acquire(&dir).is_ok());
        assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 0, "no lock file");
    }
}
