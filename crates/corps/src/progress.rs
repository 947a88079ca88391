//! Progress of a run on stderr: a bar on a terminal; off a terminal (a log file, CI, a pipe)
//! a line every few seconds with the percentage done and the real-time factor, so a long run
//! never looks hung.

use indicatif::{ProgressBar, ProgressStyle};
use std::io::{IsTerminal, Write};
use std::time::{Duration, Instant};

/// Wall time between two progress lines off a terminal.
const LINE_PERIOD: Duration = Duration::from_secs(5);

/// Reports a run of `ticks` control ticks of `dt` seconds.
pub struct Progress {
    bar: Option<ProgressBar>,
    lines: bool,
    ticks: usize,
    dt: f64,
    start: Instant,
    next_line: Instant,
}

impl Progress {
    /// Shows nothing unless `enabled`.
    pub fn new(ticks: usize, dt: f64, enabled: bool) -> Self {
        let terminal = std::io::stderr().is_terminal();
        let bar = (enabled && terminal).then(|| {
            let bar = ProgressBar::new(ticks as u64);
            if let Ok(style) = ProgressStyle::with_template(
                "simulating [{bar:40}] {percent:>3}%  {msg}  eta {eta}",
            ) {
                bar.set_style(style.progress_chars("=> "));
            }
            bar
        });
        let start = Instant::now();
        Self {
            bar,
            lines: enabled && !terminal,
            ticks,
            dt,
            start,
            next_line: start + LINE_PERIOD,
        }
    }

    /// After tick `tick` (counted from 0).
    pub fn tick(&mut self, tick: usize) {
        if !tick.is_multiple_of(50) {
            return;
        }
        let t = tick as f64 * self.dt;
        if let Some(bar) = &self.bar {
            bar.set_position(tick as u64);
            bar.set_message(format!("t = {t:.2} s"));
        } else if self.lines {
            let now = Instant::now();
            if now >= self.next_line {
                self.next_line = now + LINE_PERIOD;
                let wall = (now - self.start).as_secs_f64();
                let _ = writeln!(
                    std::io::stderr(),
                    "corps: {:3.0}% (t = {t:.1} of {:.1} s), {:.1}x real time",
                    100.0 * tick as f64 / self.ticks.max(1) as f64,
                    self.ticks as f64 * self.dt,
                    t / wall.max(1e-9)
                );
            }
        }
    }

    /// Clears the bar.
    pub fn finish(&self) {
        if let Some(bar) = &self.bar {
            bar.finish_and_clear();
        }
    }
}
