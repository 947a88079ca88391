//! When a run overlaps the simulator's next-step preparation with the controller.
//!
//! The overlap gains only while a second core is free: alone on a 2-core machine it makes a
//! torque walk about a fifth faster; beside other runs it only adds hand-overs. A run cannot
//! see the machine's load, but it can see its own speed: [`Overlap::Adaptive`] times its
//! ticks in short alternating windows of each mode (a probe, serial first; an overlapped
//! window is cut short as soon as it is a quarter slower than the serial window before it),
//! keeps the mode of the fastest window for a while, and probes again, less often while the
//! same mode keeps winning. An overlapped
//! stretch ends early when the run's thread keeps having to park for the worker's answer (the
//! worker lost its core to another process). Both modes step the simulator bit-identically,
//! so the schedule changes the run's speed, never its result.

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

/// Indices of the modes' windows.
const OVERLAPPED: usize = 0;
const SERIAL: usize = 1;
/// Ticks in one probe window (some 10 ms on TALOS: short, so that a probe costs a lone run
/// little, and three of each mode, so that one preempted window does not decide).
const WINDOW: u32 = 100;
/// Windows of each mode in one probe (alternating).
const WINDOWS_PER_MODE: usize = 3;
/// Ticks the winner runs after a probe, doubled while the same mode wins, up to the maximum
/// (short at first: a probe misled by a noisy moment costs at most this stretch).
const FIRST_STRETCH: u32 = 3_000;
const MAX_STRETCH: u32 = 48_000;
/// An overlapped stretch ends when more than this many ticks of one window had to wait
/// parked for the worker.
const LATE_PER_WINDOW: u32 = WINDOW / 10;

/// The adaptive schedule's state.
#[derive(Clone, Copy, Debug)]
enum Phase {
    /// Window `window` of a probe (even: serial, odd: overlapped).
    Probe { window: usize, ticks: u32 },
    /// The probe's winner for `left` more ticks; `late` ticks of the current window
    /// (`tick` ticks in) waited parked for the worker.
    Stretch {
        overlap: bool,
        left: u32,
        tick: u32,
        late: u32,
    },
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
            (Overlap::Adaptive, Phase::Probe { window, .. }) => window % 2 == 1,
            (Overlap::Adaptive, Phase::Stretch { overlap, .. }) => overlap,
        };
        if self.current {
            self.counts.0 += 1;
        } else {
            self.counts.1 += 1;
        }
        self.current
    }

    /// Records the wall time of the tick just run (step to step) and whether it waited
    /// parked for the worker.
    pub(crate) fn record_tick(&mut self, elapsed: Duration, parked: bool) {
        if self.mode != Overlap::Adaptive {
            return;
        }
        self.phase = match self.phase {
            Phase::Probe { window, ticks } => {
                // A window's first tick pays for the switch (the worker, parked through a
                // serial window, wakes up); both modes' windows count their other ticks.
                if ticks > 0 {
                    self.window_time += elapsed;
                }
                // An overlapped window already a quarter slower than the serial window before
                // it has lost: stop paying for it (on a loaded machine its ticks are slow).
                let serial_window = self.windows[SERIAL][window / 2];
                if window % 2 == 1 && self.window_time > serial_window * 5 / 4 {
                    self.window_time = Duration::ZERO;
                    self.settle(false)
                } else if ticks + 1 < WINDOW {
                    Phase::Probe {
                        window,
                        ticks: ticks + 1,
                    }
                } else {
                    let mode = if window % 2 == 1 { OVERLAPPED } else { SERIAL };
                    self.windows[mode][window / 2] = std::mem::take(&mut self.window_time);
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
            Phase::Stretch {
                overlap,
                left,
                tick,
                late,
            } => {
                let late = late + u32::from(parked);
                if left <= 1 || late > LATE_PER_WINDOW {
                    if left > 1 {
                        // The machine changed under the stretch: start over.
                        self.last_winner = None;
                    }
                    Phase::Probe {
                        window: 0,
                        ticks: 0,
                    }
                } else {
                    let (tick, late) = if tick + 1 == WINDOW {
                        (0, 0)
                    } else {
                        (tick + 1, late)
                    };
                    Phase::Stretch {
                        overlap,
                        left: left - 1,
                        tick,
                        late,
                    }
                }
            }
        };
    }

    /// The probe's winner: the mode with the shorter fastest window. Noise on a shared or
    /// virtual machine only adds time, so each mode's fastest window is its best estimate;
    /// a machine whose other core is busy slows every overlapped window, the fastest too.
    fn decide(&mut self) -> Phase {
        let fastest = |w: &[Duration; WINDOWS_PER_MODE]| w.iter().copied().min();
        let overlap = fastest(&self.windows[OVERLAPPED]) < fastest(&self.windows[SERIAL]);
        self.settle(overlap)
    }

    /// A stretch of the winner, longer while the same mode keeps winning.
    fn settle(&mut self, overlap: bool) -> Phase {
        self.stretch = if self.last_winner == Some(overlap) {
            (self.stretch * 2).min(MAX_STRETCH)
        } else {
            FIRST_STRETCH
        };
        self.last_winner = Some(overlap);
        Phase::Stretch {
            overlap,
            left: self.stretch,
            tick: 0,
            late: 0,
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
            s.record_tick(
                Duration::from_micros(if o { overlapped } else { serial }),
                false,
            );
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
    fn an_overlap_that_is_much_slower_costs_little_to_find_out() {
        // Overlapped ticks 10x slower (a machine with no free core): each probe pays the
        // time of 1.25 serial windows for an eighth of an overlapped window; three probes in
        // 20,000 ticks cost about 3.4%.
        let mut s = OverlapSchedule::new(Overlap::Adaptive);
        let mut total = Duration::ZERO;
        for _ in 0..20_000 {
            let o = s.overlap_this_tick();
            let d = Duration::from_micros(if o { 1000 } else { 100 });
            total += d;
            s.record_tick(d, o);
        }
        let serial_only = Duration::from_micros(100) * 20_000;
        assert!(
            total.as_secs_f64() < 1.05 * serial_only.as_secs_f64(),
            "{total:?}"
        );
    }

    #[test]
    fn an_overlapped_stretch_whose_preparations_come_late_is_probed_again_at_once() {
        let mut s = OverlapSchedule::new(Overlap::Adaptive);
        // The probe finds the overlap faster; then its preparations start coming late.
        for _ in 0..2 * WINDOWS_PER_MODE as u32 * WINDOW {
            let o = s.overlap_this_tick();
            s.record_tick(Duration::from_micros(if o { 80 } else { 100 }), false);
        }
        assert!(matches!(s.phase, Phase::Stretch { overlap: true, .. }));
        for _ in 0..=LATE_PER_WINDOW {
            assert!(s.overlap_this_tick());
            s.record_tick(Duration::from_micros(80), true);
        }
        assert!(matches!(s.phase, Phase::Probe { window: 0, .. }));
    }

    #[test]
    fn the_wake_up_after_a_serial_window_does_not_decide_the_probe() {
        // The first overlapped tick after a serial one waits for the worker to wake (on a
        // virtual machine, up to milliseconds); the overlap still wins the ticks after it.
        let mut s = OverlapSchedule::new(Overlap::Adaptive);
        let mut previous = false;
        for _ in 0..20_000 {
            let o = s.overlap_this_tick();
            let micros = match (o, previous) {
                (true, false) => 5_000,
                (true, true) => 80,
                (false, _) => 100,
            };
            s.record_tick(Duration::from_micros(micros), false);
            previous = o;
        }
        let (o, n) = s.counts();
        assert!(
            o as f64 / (o + n) as f64 > 0.9,
            "{o} overlapped, {n} serial"
        );
    }

    #[test]
    fn fixed_modes_never_switch() {
        for (mode, expected) in [(Overlap::Never, false), (Overlap::Always, true)] {
            let mut s = OverlapSchedule::new(mode);
            for _ in 0..5_000 {
                assert_eq!(s.overlap_this_tick(), expected);
                s.record_tick(Duration::from_micros(if expected { 500 } else { 1 }), true);
            }
        }
    }
}
