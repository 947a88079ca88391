//! When a run overlaps the simulator's next-step preparation with the controller.
//!
//! The overlap gains only while a second core is free: alone on a 2-core machine it makes a
//! torque walk about a fifth faster; beside other runs it only adds hand-overs. A run cannot
//! see the machine's load, but it can see its own speed: [`Overlap::Adaptive`] times its
//! ticks in short alternating windows of each mode (a probe), keeps the faster mode for a
//! while, and probes again, less often while the same mode keeps winning. Both modes step
//! the simulator bit-identically, so the schedule changes the run's speed, never its result.

use std::time::Duration;

/// How a run uses the second thread.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Overlap {
    /// One thread.
    Never,
    /// Every tick overlaps.
    Always,
    /// Each tick takes the mode that the run's own timings show to be faster.
    Adaptive,
}

/// Ticks in one probe window.
const WINDOW: u32 = 200;
/// Windows of each mode in one probe (alternating).
const WINDOWS_PER_MODE: usize = 3;
/// Ticks the winner runs after a probe, doubled while the same mode wins, up to the maximum.
const FIRST_STRETCH: u32 = 6_000;
const MAX_STRETCH: u32 = 48_000;

/// The adaptive schedule's state.
#[derive(Clone, Copy, Debug)]
enum Phase {
    /// Window `window` of a probe (even: overlapped, odd: serial).
    Probe { window: usize, ticks: u32 },
    /// The probe's winner for `left` more ticks.
    Stretch { overlap: bool, left: u32 },
}

/// Decides tick by tick whether to overlap, and learns from the tick times.
pub(crate) struct OverlapSchedule {
    mode: Overlap,
    phase: Phase,
    /// Mode of the tick being run.
    current: bool,
    /// Time of the current window so far, and the finished windows' times per mode.
    window_time: Duration,
    windows: [[Duration; WINDOWS_PER_MODE]; 2],
    stretch: u32,
    last_winner: Option<bool>,
    /// Ticks run overlapped and serially.
    counts: (u64, u64),
}

impl OverlapSchedule {
    pub(crate) fn new(mode: Overlap) -> Self {
        Self {
            mode,
            phase: Phase::Probe {
                window: 0,
                ticks: 0,
            },
            current: mode != Overlap::Never,
            window_time: Duration::ZERO,
            windows: [[Duration::ZERO; WINDOWS_PER_MODE]; 2],
            stretch: FIRST_STRETCH,
            last_winner: None,
            counts: (0, 0),
        }
    }

    /// Whether the tick about to run overlaps.
    pub(crate) fn overlap_this_tick(&mut self) -> bool {
        self.current = match (self.mode, self.phase) {
            (Overlap::Never, _) => false,
            (Overlap::Always, _) => true,
            (Overlap::Adaptive, Phase::Probe { window, .. }) => window % 2 == 0,
            (Overlap::Adaptive, Phase::Stretch { overlap, .. }) => overlap,
        };
        if self.current {
            self.counts.0 += 1;
        } else {
            self.counts.1 += 1;
        }
        self.current
    }

    /// Records the wall time of the tick just run (step to step).
    pub(crate) fn record_tick(&mut self, elapsed: Duration) {
        if self.mode != Overlap::Adaptive {
            return;
        }
        self.phase = match self.phase {
            Phase::Probe { window, ticks } => {
                self.window_time += elapsed;
                if ticks + 1 < WINDOW {
                    Phase::Probe {
                        window,
                        ticks: ticks + 1,
                    }
                } else {
                    self.windows[window % 2][window / 2] = std::mem::take(&mut self.window_time);
                    if window + 1 < 2 * WINDOWS_PER_MODE {
                        Phase::Probe {
                            window: window + 1,
                            ticks: 0,
                        }
                    } else {
                        self.decide()
                    }
                }
            }
            Phase::Stretch { overlap, left } if left > 1 => Phase::Stretch {
                overlap,
                left: left - 1,
            },
            Phase::Stretch { .. } => Phase::Probe {
                window: 0,
                ticks: 0,
            },
        };
    }

    /// The probe's winner: the mode with the shorter median window.
    fn decide(&mut self) -> Phase {
        let median = |w: &[Duration; WINDOWS_PER_MODE]| {
            let mut w = *w;
            w.sort();
            w[WINDOWS_PER_MODE / 2]
        };
        let overlap = median(&self.windows[0]) < median(&self.windows[1]);
        self.stretch = if self.last_winner == Some(overlap) {
            (self.stretch * 2).min(MAX_STRETCH)
        } else {
            FIRST_STRETCH
        };
        self.last_winner = Some(overlap);
        Phase::Stretch {
            overlap,
            left: self.stretch,
        }
    }

    /// Ticks run overlapped and serially so far (of those asked about).
    pub(crate) fn counts(&self) -> (u64, u64) {
        self.counts
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Runs `ticks` ticks whose time is `overlapped` or `serial` µs by mode; returns the
    /// overlapped share.
    fn share(overlapped: u64, serial: u64, ticks: usize) -> f64 {
        let mut s = OverlapSchedule::new(Overlap::Adaptive);
        for _ in 0..ticks {
            let o = s.overlap_this_tick();
            s.record_tick(Duration::from_micros(if o { overlapped } else { serial }));
        }
        let (o, n) = s.counts();
        o as f64 / (o + n) as f64
    }

    #[test]
    fn the_faster_mode_takes_most_ticks_and_the_loser_is_probed_less_and_less() {
        assert!(share(80, 100, 100_000) > 0.96);
        assert!(share(120, 100, 100_000) < 0.04);
        // A short run still spends most of its time in the faster mode.
        assert!(share(80, 100, 11_000) > 0.85);
    }

    #[test]
    fn fixed_modes_never_switch() {
        for (mode, expected) in [(Overlap::Never, false), (Overlap::Always, true)] {
            let mut s = OverlapSchedule::new(mode);
            for _ in 0..5_000 {
                assert_eq!(s.overlap_this_tick(), expected);
                s.record_tick(Duration::from_micros(if expected { 500 } else { 1 }));
            }
        }
    }
}
