//! A CSV log streamed to disk while the run goes: rows are formatted into a buffer and
//! written in whole rows at least once per simulated second, so memory does not grow with
//! the run's length and a run that is killed leaves every row up to its last flush.
//!
//! The rows go to `log.csv.partial`; only a finished run renames it to `log.csv`, so a run
//! that fails part-way (diverged, disk full, killed) leaves the previous `log.csv` untouched
//! and its own rows, up to the last flush, in `log.csv.partial`. A write error truncates the
//! partial file back to its last whole flush.

use anyhow::{bail, Context, Result};
use std::fs::File;
use std::io::Write;
use std::path::{Path, PathBuf};

/// Name of a finished log in the output directory.
pub const LOG_NAME: &str = "log.csv";
/// Name of the log while the run writes it (and after a run that did not finish).
pub const PARTIAL_LOG_NAME: &str = "log.csv.partial";
/// Simulated time between two flushes at most (s).
const FLUSH_PERIOD: f64 = 1.0;
/// Buffered bytes that force a flush before the period is over.
const FLUSH_BYTES: usize = 4 << 20;

/// A CSV log being streamed to `log.csv.partial`.
pub struct CsvLog {
    file: File,
    partial: PathBuf,
    target: PathBuf,
    buffer: Vec<u8>,
    columns: usize,
    rows: usize,
    /// Bytes on disk after the last successful flush, and the time of its last row.
    flushed_bytes: u64,
    flushed_time: Option<f64>,
    /// Time of the last buffered row.
    last_time: f64,
    next_flush: f64,
    /// The size the log may reach (bytes).
    cap: u64,
    number: ryu::Buffer,
}

impl CsvLog {
    /// Starts `dir/log.csv.partial` with its header; the log may grow to `cap` bytes.
    pub fn create(dir: &Path, header: &[String], cap: u64) -> Result<Self> {
        let partial = dir.join(PARTIAL_LOG_NAME);
        let mut file =
            File::create(&partial).with_context(|| format!("creating {}", partial.display()))?;
        let mut line = header.join(",");
        line.push('\n');
        file.write_all(line.as_bytes())
            .with_context(|| format!("writing {}", partial.display()))?;
        Ok(Self {
            file,
            target: dir.join(LOG_NAME),
            partial,
            buffer: Vec::with_capacity(FLUSH_BYTES + (1 << 16)),
            columns: header.len(),
            rows: 0,
            flushed_bytes: line.len() as u64,
            flushed_time: None,
            last_time: f64::NEG_INFINITY,
            next_flush: f64::NEG_INFINITY,
            cap,
            number: ryu::Buffer::new(),
        })
    }

    /// Buffers one row (as many values as header columns, the time first) and flushes when
    /// a simulated second has passed since the last flush.
    pub fn row(&mut self, values: &[f64]) -> Result<()> {
        if values.len() != self.columns {
            bail!(
                "log row has {} values for {} columns",
                values.len(),
                self.columns
            );
        }
        for (k, x) in values.iter().enumerate() {
            if k > 0 {
                self.buffer.push(b',');
            }
            let text = if x.is_finite() {
                self.number.format_finite(*x)
            } else {
                "nan"
            };
            self.buffer.extend_from_slice(text.as_bytes());
        }
        self.buffer.push(b'\n');
        self.rows += 1;
        let t = values.first().copied().unwrap_or(0.0);
        self.last_time = t;
        if self.next_flush == f64::NEG_INFINITY {
            self.next_flush = t + FLUSH_PERIOD;
        }
        if t >= self.next_flush || self.buffer.len() >= FLUSH_BYTES {
            self.flush()?;
            self.next_flush = t + FLUSH_PERIOD;
        }
        Ok(())
    }

    /// Writes the buffered rows. On failure the file is cut back to its last whole flush and
    /// the error says up to which time the log holds rows.
    pub fn flush(&mut self) -> Result<()> {
        if self.buffer.is_empty() {
            return Ok(());
        }
        let size = self.flushed_bytes + self.buffer.len() as u64;
        if size > self.cap {
            bail!(
                "{}: the log reached its size cap of {} (raise it with [output] max_log_mb or --max-log-mb); {}",
                self.partial.display(),
                megabytes(self.cap),
                self.holds()
            );
        }
        if let Err(e) = self.file.write_all(&self.buffer) {
            let _ = self.file.set_len(self.flushed_bytes);
            bail!("writing {}: {e}; {}", self.partial.display(), self.holds());
        }
        self.buffer.clear();
        self.flushed_bytes = size;
        self.flushed_time = Some(self.last_time);
        Ok(())
    }

    /// Where the rows written so far are, for an error message.
    fn holds(&self) -> String {
        match self.flushed_time {
            Some(t) => format!("it holds the rows up to t = {t:.3} s"),
            None => "it holds the header only".into(),
        }
    }

    /// Rows written so far.
    pub fn rows(&self) -> usize {
        self.rows
    }

    /// Number of columns.
    pub fn columns(&self) -> usize {
        self.columns
    }

    /// Flushes, syncs and renames the log to `log.csv`, replacing the previous one.
    pub fn finish(mut self) -> Result<PathBuf> {
        self.flush()?;
        self.file
            .sync_all()
            .with_context(|| format!("writing {}", self.partial.display()))?;
        std::fs::rename(&self.partial, &self.target)
            .with_context(|| format!("writing {}", self.target.display()))?;
        Ok(self.target)
    }
}

/// Estimated size (bytes) of a log of `rows` rows of `columns` numbers: 20 bytes a number,
/// the length of a typical shortest round-trip double with its separator.
pub fn estimated_size(rows: usize, columns: usize) -> u64 {
    (rows as u64).saturating_mul(columns as u64 * 20)
}

/// `bytes` in MB, for messages.
pub fn megabytes(bytes: u64) -> String {
    format!("{:.0} MB", bytes as f64 / 1e6)
}

/// Refuses a log estimated larger than `cap` bytes before the run starts.
pub fn check_size(rows: usize, columns: usize, cap: u64) -> Result<()> {
    let estimate = estimated_size(rows, columns);
    if estimate > cap {
        bail!(
            "the log would take about {} ({rows} rows of {columns} columns), over its cap of {}: raise [output] max_log_mb or --max-log-mb, or log fewer rows ([output] log_every)",
            megabytes(estimate),
            megabytes(cap)
        );
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn header(n: usize) -> Vec<String> {
        (0..n).map(|k| format!("c{k}")).collect()
    }

    #[test]
    fn rows_reach_the_disk_every_simulated_second_and_the_log_is_renamed_at_the_end() {
        let dir = tempfile::tempdir().unwrap();
        let mut log = CsvLog::create(dir.path(), &header(2), u64::MAX).unwrap();
        let partial = dir.path().join(PARTIAL_LOG_NAME);
        for k in 0..2500 {
            log.row(&[k as f64 * 1e-3, 1.0]).unwrap();
        }
        // Flushed at t = 1 and t = 2 s: 2001 rows on disk, the rest buffered.
        let text = std::fs::read_to_string(&partial).unwrap();
        assert_eq!(text.lines().count(), 1 + 2001);
        assert!(text.ends_with("2.0,1.0\n"), "whole rows only");
        let path = log.finish().unwrap();
        assert!(!partial.exists());
        assert_eq!(std::fs::read_to_string(path).unwrap().lines().count(), 2501);
    }

    #[test]
    fn a_full_disk_leaves_whole_rows_and_says_up_to_when() {
        let dir = tempfile::tempdir().unwrap();
        let mut log = CsvLog::create(dir.path(), &header(1), u64::MAX).unwrap();
        for k in 0..1500 {
            log.row(&[k as f64 * 1e-3]).unwrap();
        }
        // Another file behind the same name: a file on a full device.
        log.file = File::options().write(true).open("/dev/full").unwrap();
        let mut failed = None;
        for k in 1500..3000 {
            if let Err(e) = log.row(&[k as f64 * 1e-3]) {
                failed = Some(e.to_string());
                break;
            }
        }
        let e = failed.expect("the write fails");
        assert!(e.contains("No space left on device"), "{e}");
        assert!(e.contains("up to t = 1.000 s"), "{e}");
    }

    #[test]
    fn a_log_over_its_cap_stops_with_a_clear_line() {
        let dir = tempfile::tempdir().unwrap();
        let mut log = CsvLog::create(dir.path(), &header(1), 100).unwrap();
        let e = (0..2000)
            .find_map(|k| log.row(&[k as f64 * 1e-3]).err())
            .expect("the cap stops the log");
        assert!(e.to_string().contains("size cap"), "{e}");
        assert!(check_size(1000, 10, 1_000_000).is_ok());
        let e = check_size(1_000_000, 100, 1_000_000)
            .unwrap_err()
            .to_string();
        assert!(e.contains("about 2000 MB"), "{e}");
    }
}
