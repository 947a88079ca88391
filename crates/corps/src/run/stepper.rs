//! The simulator of a run, stepped either on the run's thread alone or with its next step's
//! state-only work ([`Simulator::prepare_step`]: h(q, v), the contact pass, the factorization)
//! done on a second thread while the controller computes the command. Both give bit-identical
//! runs; the second overlaps about a fifth of a torque walk's work with the controller.
//!
//! The hand-over is two counters: the run asks for a preparation, then, before the step, waits
//! for it to be done (the controller takes longer than the preparation, so it usually is).
//! The worker spins between requests: woken from sleep each tick instead, it made the 20 cm
//! walk slower than the serial run (the run's thread waited 0.3–2.7 s in all for it on this
//! project's 2-core VM). It keeps a core busy, so the overlap is for a run that has the machine
//! ([`super::RunOptions::interactive`]), not for test suites that run several scenarios at once.

use anyhow::{anyhow, bail, Result};
use corps_sim::{Command, Simulator};
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Mutex, MutexGuard};
use std::thread::{Scope, ScopedJoinHandle};

/// Waits that spin before yielding the core (a preparation takes tens of microseconds).
const SPINS_BEFORE_YIELD: u32 = 2_000;
/// How long the worker spins without a request before it sleeps.
const IDLE_BEFORE_SLEEP: std::time::Duration = std::time::Duration::from_millis(1);

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
}

impl<'scope> Stepper<'scope> {
    /// With `overlap`, starts the worker in `scope`.
    pub(crate) fn new<'env>(
        scope: &'scope Scope<'scope, 'env>,
        shared: &'scope Shared,
        overlap: bool,
    ) -> Self {
        let worker = overlap.then(|| scope.spawn(move || prepare_on_request(shared)));
        Self {
            shared,
            worker,
            requested: 0,
        }
    }

    /// The simulator, for reading the state and sensors. Held across neither
    /// [`Stepper::prepare`] nor [`Stepper::step`] (they take `&mut self`).
    pub(crate) fn sim(&self) -> Result<MutexGuard<'_, Simulator>> {
        self.shared.lock()
    }

    /// Starts the next step's state-only work on the worker (nothing without one).
    pub(crate) fn prepare(&mut self) {
        if let Some(worker) = &self.worker {
            self.requested += 1;
            self.shared
                .requested
                .store(self.requested, Ordering::Release);
            worker.thread().unpark();
        }
    }

    /// Steps under `cmd`, once the preparation asked for is done.
    pub(crate) fn step(&mut self, cmd: &Command) -> Result<()> {
        if let Some(worker) = &self.worker {
            let mut spins = 0u32;
            while self.shared.done.load(Ordering::Acquire) != self.requested {
                if spins < SPINS_BEFORE_YIELD {
                    std::hint::spin_loop();
                    spins += 1;
                } else if worker.is_finished() {
                    bail!("the simulator's preparing thread stopped");
                } else {
                    std::thread::yield_now();
                }
            }
        }
        self.shared.lock()?.step(cmd)?;
        Ok(())
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

/// The worker: spins while requests come (one per control tick), sleeps after a quiet
/// millisecond, until the run stops.
fn prepare_on_request(shared: &Shared) {
    let mut seen = 0;
    let mut idle_since = std::time::Instant::now();
    let mut spins = 0u32;
    loop {
        let requested = shared.requested.load(Ordering::Acquire);
        if requested == seen {
            if shared.stop.load(Ordering::Acquire) {
                return;
            }
            spins += 1;
            if spins.is_multiple_of(256) && idle_since.elapsed() > IDLE_BEFORE_SLEEP {
                std::thread::park();
            } else {
                std::hint::spin_loop();
            }
            continue;
        }
        seen = requested;
        match shared.sim.lock() {
            Ok(mut sim) => sim.prepare_step(),
            Err(_) => return,
        }
        shared.done.store(seen, Ordering::Release);
        idle_since = std::time::Instant::now();
        spins = 0;
    }
}
