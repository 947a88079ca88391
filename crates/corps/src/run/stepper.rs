//! The simulator of a run, stepped either on the run's thread alone or with its next step's
//! state-only work ([`Simulator::prepare_step`]: h(q, v), the contact pass, the factorization)
//! done on a second thread while the controller computes the command. Both give bit-identical
//! steps, so a run may switch between them at any tick.
//!
//! The hand-over is two counters. Each side waits for the other by spinning for a few
//! microseconds and then parking (the other side unparks it), so a waiting thread never holds
//! a core that the other runs of the machine need. Whether a tick overlaps is decided by an
//! [`OverlapSchedule`]: with [`Overlap::Adaptive`] the run times its own ticks both ways and
//! keeps the faster, so the overlap is used only while it gains.

use super::overlap::{Overlap, OverlapSchedule};
use anyhow::{anyhow, bail, Result};
use corps_sim::{Command, SimError, Simulator};
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Mutex, MutexGuard};
use std::thread::{Scope, ScopedJoinHandle, Thread};
use std::time::{Duration, Instant};

/// How long the run's thread spins for a preparation before it parks (a preparation takes
/// tens of microseconds and usually ends while the controller computes).
const RUN_SPIN: Duration = Duration::from_micros(20);
/// How long the worker spins for the next request before it parks. The next request comes
/// one controller tick after the last (some 60–100 µs on TALOS, the preparation itself
/// 25–35 µs of it); parking between overlapped ticks would add a wake-up, tens of µs on a
/// virtual machine, to every preparation. A run that stops overlapping (a serial stretch of
/// [`Overlap::Adaptive`]) lets the worker park after this long.
const WORKER_SPIN: Duration = Duration::from_micros(250);
/// Longest single park of the run's thread before it checks the worker is alive.
const PARK_CHECK: Duration = Duration::from_millis(5);

/// What the run's thread and the worker share.
pub(crate) struct Shared {
    sim: Mutex<Simulator>,
    requested: AtomicU64,
    done: AtomicU64,
    stop: AtomicBool,
}

impl Shared {
    pub(crate) fn new(sim: Simulator) -> Self {
        Self {
            sim: Mutex::new(sim),
            requested: AtomicU64::new(0),
            done: AtomicU64::new(0),
            stop: AtomicBool::new(false),
        }
    }

    /// The simulator back, once the stepper is gone.
    pub(crate) fn into_inner(self) -> Result<Simulator> {
        self.sim
            .into_inner()
            .map_err(|_| anyhow!("the simulator's preparing thread failed"))
    }

    fn lock(&self) -> Result<MutexGuard<'_, Simulator>> {
        self.sim
            .lock()
            .map_err(|_| anyhow!("the simulator's preparing thread failed"))
    }
}

/// Steps the shared simulator, with or without the preparing worker.
pub(crate) struct Stepper<'scope> {
    shared: &'scope Shared,
    worker: Option<ScopedJoinHandle<'scope, ()>>,
    requested: u64,
    /// A preparation was asked for this tick.
    pending: bool,
    schedule: OverlapSchedule,
    last_step: Option<Instant>,
}

impl<'scope> Stepper<'scope> {
    /// Starts the worker in `scope` unless `overlap` is [`Overlap::Never`].
    pub(crate) fn new<'env>(
        scope: &'scope Scope<'scope, 'env>,
        shared: &'scope Shared,
        overlap: Overlap,
    ) -> Self {
        let run_thread = std::thread::current();
        let worker = (overlap != Overlap::Never)
            .then(|| scope.spawn(move || prepare_on_request(shared, run_thread)));
        Self {
            shared,
            worker,
            requested: 0,
            pending: false,
            schedule: OverlapSchedule::new(overlap),
            last_step: None,
        }
    }

    /// The simulator, for reading the state and sensors. Held across neither
    /// [`Stepper::prepare`] nor [`Stepper::step`] (they take `&mut self`).
    pub(crate) fn sim(&self) -> Result<MutexGuard<'_, Simulator>> {
        self.shared.lock()
    }

    /// Starts the next step's state-only work on the worker when this tick overlaps.
    pub(crate) fn prepare(&mut self) {
        let Some(worker) = &self.worker else { return };
        if !self.schedule.overlap_this_tick() {
            return;
        }
        self.requested += 1;
        self.shared
            .requested
            .store(self.requested, Ordering::Release);
        worker.thread().unpark();
        self.pending = true;
    }

    /// Steps under `cmd`, once the preparation asked for is done. A diverged simulation is
    /// no error here but the run's end: its time and reason.
    pub(crate) fn step(&mut self, cmd: &Command) -> Result<Option<(f64, String)>> {
        let parked = std::mem::take(&mut self.pending) && self.wait_for_preparation()?;
        match self.shared.lock()?.step(cmd) {
            Err(SimError::Diverged { t, reason }) => return Ok(Some((t, reason))),
            other => other?,
        }
        let now = Instant::now();
        if let Some(last) = self.last_step.replace(now) {
            self.schedule.record_tick(now - last, parked);
        }
        Ok(None)
    }

    /// Spins briefly, then parks until the worker says the preparation is done; returns
    /// whether it had to park (the worker was late: no free core, or a slow preparation).
    fn wait_for_preparation(&self) -> Result<bool> {
        let Some(worker) = &self.worker else {
            return Ok(false);
        };
        let done = || self.shared.done.load(Ordering::Acquire) == self.requested;
        let start = Instant::now();
        let mut spins = 0u32;
        let mut parked = false;
        while !done() {
            spins = spins.wrapping_add(1);
            if !spins.is_multiple_of(64) || start.elapsed() < RUN_SPIN {
                std::hint::spin_loop();
                continue;
            }
            if worker.is_finished() {
                bail!("the simulator's preparing thread stopped");
            }
            parked = true;
            std::thread::park_timeout(PARK_CHECK);
        }
        Ok(parked)
    }

    /// How many ticks overlapped and how many ran serially, for the run's report.
    pub(crate) fn overlap_counts(&self) -> (u64, u64) {
        self.schedule.counts()
    }
}

impl Drop for Stepper<'_> {
    /// Stops the worker (the scope joins it).
    fn drop(&mut self) {
        if let Some(worker) = &self.worker {
            self.shared.stop.store(true, Ordering::Release);
            worker.thread().unpark();
        }
    }
}

/// The worker: prepares each requested step, tells the run's thread, then waits for the next
/// request (spinning briefly, then parked) until the run stops.
fn prepare_on_request(shared: &Shared, run_thread: Thread) {
    let mut seen = 0;
    loop {
        let start = Instant::now();
        let mut spins = 0u32;
        let requested = loop {
            let requested = shared.requested.load(Ordering::Acquire);
            if requested != seen {
                break requested;
            }
            if shared.stop.load(Ordering::Acquire) {
                return;
            }
            spins = spins.wrapping_add(1);
            if !spins.is_multiple_of(64) || start.elapsed() < WORKER_SPIN {
                std::hint::spin_loop();
            } else {
                std::thread::park();
            }
        };
        seen = requested;
        match shared.sim.lock() {
            Ok(mut sim) => sim.prepare_step(),
            Err(_) => return,
        }
        shared.done.store(seen, Ordering::Release);
        run_thread.unpark();
    }
}
