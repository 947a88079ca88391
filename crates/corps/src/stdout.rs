//! Printing a command's results on standard output, where a closed pipe (`corps … | head`)
//! is the reader's choice and not an error: the command stops printing and exits 0.

use anyhow::{Context, Result};
use std::io::Write;

/// Writes `text` to standard output; a closed pipe is not an error.
pub fn print(text: &str) -> Result<()> {
    let mut out = std::io::stdout().lock();
    match out.write_all(text.as_bytes()).and_then(|_| out.flush()) {
        Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => Err(e).context("printing"),
        _ => Ok(()),
    }
}
