//! The overlap's worker thread and what it shares with the thread that runs the loop.
//!
//! Two kinds of request, each a counter the caller raises and the worker answers in order:
//! - *prepare*: the next step's state-only work ([`Simulator::prepare_step`]);
//! - *step*: the step under the command left in [`Shared::command`]; then the sensors'
//!   readings into [`Shared::readings`] (the caller's estimator waits for them), the true
//!   state into [`Shared::truth`] (only the metrics read it, later in the tick), and the next
//!   step's preparation, which depends on the new state alone.
//!
//! A step done here leaves the simulator's state, its factorization and the contact pass in
//! the worker's cache, where the next preparation and step read them: only the command and
//! the sensed buffers cross between the cores. The caller's thread waits for the worker by
//! spinning for some microseconds and then parking; the worker spins for its next request
//! for a quarter of a millisecond (longer than a tick, so that it keeps its core while
//! overlapping) and then parks, so that a run which stops overlapping leaves the core to
//! the machine's other runs.

use crate::{Sensors, Simulator};
use corps_estimation::Readings;
use corps_loop::{Command, PlantError, Truth};
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::Mutex;
use std::thread::Thread;
use std::time::{Duration, Instant};

/// How long the worker spins for the next request before it parks. The next request comes
/// one controller tick after the last (some 60–100 µs on TALOS); parking between overlapped
/// ticks would add a wake-up, tens of µs on a virtual machine, to every tick. A run that
/// stops overlapping (a serial stretch of [`crate::Overlap::Adaptive`]) lets the worker
/// park after this long.
const WORKER_SPIN: Duration = Duration::from_micros(250);

/// The simulator and the sensors that read it: whoever steps holds them.
pub(super) struct Robot {
    pub sim: Simulator,
    pub sensors: Sensors,
}

/// A step's readings and how it went.
pub(super) struct StepReadings {
    /// Plant time after the step (s).
    pub time: f64,
    pub readings: Readings,
    pub result: Result<(), PlantError>,
}

/// A value alone on its cache lines (two, for the adjacent-line prefetcher): a counter one
/// thread writes while the other spins on its neighbour would otherwise bounce both.
#[repr(align(128))]
pub(super) struct Padded<T>(pub T);

impl<T> std::ops::Deref for Padded<T> {
    type Target = T;
    fn deref(&self) -> &T {
        &self.0
    }
}

/// What the caller's thread and the worker share. The caller writes the requests, the
/// worker the answers, each on its own lines.
pub(super) struct Shared {
    pub robot: Padded<Mutex<Robot>>,
    pub command: Padded<Mutex<Command>>,
    pub readings: Padded<Mutex<StepReadings>>,
    pub truth: Padded<Mutex<Option<Truth>>>,
    pub prepare_requested: Padded<AtomicU64>,
    pub step_requested: Padded<AtomicU64>,
    pub prepared: Padded<AtomicU64>,
    /// Steps whose readings are in [`Shared::readings`].
    pub stepped: Padded<AtomicU64>,
    /// Steps whose true state is in [`Shared::truth`].
    pub truth_ready: Padded<AtomicU64>,
    /// Steps whose following preparation is done as well.
    pub step_prepared: Padded<AtomicU64>,
    pub stop: AtomicBool,
    /// The thread that runs the loop (the worker wakes it), and how many times it changed:
    /// a robot moved to another thread updates it at its next request.
    pub caller: Mutex<Thread>,
    pub caller_changes: AtomicU64,
}

impl Shared {
    /// Whether the worker has answered every request (the robot is the caller's to use).
    pub fn idle(&self, prepares: u64, steps: u64) -> bool {
        self.prepared.load(Ordering::Acquire) == prepares
            && self.step_prepared.load(Ordering::Acquire) == steps
    }
}

/// The worker's copy of the caller's thread handle, refreshed when the caller changes.
struct Caller {
    changes: u64,
    thread: Option<Thread>,
}

impl Caller {
    fn wake(&mut self, shared: &Shared) {
        let changes = shared.caller_changes.load(Ordering::Acquire);
        if self.thread.is_none() || changes != self.changes {
            if let Ok(caller) = shared.caller.lock() {
                self.thread = Some(caller.clone());
                self.changes = changes;
            }
        }
        if let Some(thread) = &self.thread {
            thread.unpark();
        }
    }
}

/// One step of the simulator, its error as the loop reports it.
pub(super) fn step(sim: &mut Simulator, command: &Command) -> Result<(), PlantError> {
    match sim.step(command) {
        Ok(()) => Ok(()),
        Err(crate::SimError::Diverged { t, reason }) => Err(PlantError::Diverged { t, reason }),
        Err(e) => Err(PlantError::Failed(e.to_string())),
    }
}

/// The worker: answers each request in order (a preparation asked before a step is done
/// first), then waits for the next (spinning briefly, then parked) until the robot stops it.
pub(super) fn serve(shared: &Shared) {
    let (mut prepares, mut steps) = (0, 0);
    let mut caller = Caller {
        changes: 0,
        thread: None,
    };
    loop {
        let mut start = Instant::now();
        let mut spins = 0u32;
        loop {
            let prepare = shared.prepare_requested.load(Ordering::Acquire);
            let step = shared.step_requested.load(Ordering::Acquire);
            if prepare != prepares || step != steps {
                break;
            }
            if shared.stop.load(Ordering::Acquire) {
                return;
            }
            spins = spins.wrapping_add(1);
            if !spins.is_multiple_of(64) || start.elapsed() < WORKER_SPIN {
                std::hint::spin_loop();
            } else {
                std::thread::park();
                // Woken ahead of a request (or by one): spin again for it.
                start = Instant::now();
            }
        }
        let Ok(mut robot) = shared.robot.lock() else {
            return;
        };
        let robot = &mut *robot;
        if shared.prepare_requested.load(Ordering::Acquire) != prepares {
            prepares += 1;
            robot.sim.prepare_step();
            shared.prepared.store(prepares, Ordering::Release);
            caller.wake(shared);
        }
        if shared.step_requested.load(Ordering::Acquire) != steps {
            steps += 1;
            let Ok(stepped) = step_and_read(shared, robot) else {
                return;
            };
            shared.stepped.store(steps, Ordering::Release);
            caller.wake(shared);
            if stepped {
                let Ok(mut truth) = shared.truth.lock() else {
                    return;
                };
                if let Some(truth) = &mut *truth {
                    super::read_truth(robot, truth);
                }
            }
            shared.truth_ready.store(steps, Ordering::Release);
            caller.wake(shared);
            if stepped {
                robot.sim.prepare_step();
            }
            shared.step_prepared.store(steps, Ordering::Release);
            caller.wake(shared);
        }
    }
}

/// Steps under the shared command and leaves the readings (or the error) for the caller;
/// returns whether the step went well. Err: a lock was poisoned.
fn step_and_read(shared: &Shared, robot: &mut Robot) -> Result<bool, ()> {
    let result = {
        let command = shared.command.lock().map_err(|_| ())?;
        step(&mut robot.sim, &command)
    };
    let stepped = result.is_ok();
    let mut out = shared.readings.lock().map_err(|_| ())?;
    if stepped {
        out.time = super::read_readings(robot, &mut out.readings);
    }
    out.result = result;
    Ok(stepped)
}
