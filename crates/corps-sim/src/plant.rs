//! The simulator as the loop's [`Plant`]: the simulator and its sensors, stepped either on the
//! caller's thread alone or with each next step's state-only work
//! ([`Simulator::prepare_step`]: h(q, v), the contact pass, the factorization) done on a
//! worker thread while the controller computes. Both give bit-identical steps, so a run may
//! switch between them at any tick.
//!
//! The hand-over is two counters. Each side waits for the other by spinning for a few
//! microseconds and then parking (the other side unparks it), so a waiting thread never holds
//! a core that the other runs of the machine need. Whether a tick overlaps is decided by an
//! [`OverlapSchedule`]: with [`Overlap::Adaptive`] the run times its own ticks both ways and
//! keeps the faster, so the overlap is used only while it gains.

use crate::overlap::{Overlap, OverlapSchedule};
use crate::{Sensors, SimError, Simulator};
use corps_loop::{Command, ContactForce, Plant, PlantError, Sensed, Truth};
use corps_model::com_at_placements;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, Mutex};
use std::thread::{JoinHandle, Thread};
use std::time::{Duration, Instant};

/// How long the caller's thread spins for a preparation before it parks (a preparation takes
/// tens of microseconds and usually ends while the controller computes).
const RUN_SPIN: Duration = Duration::from_micros(20);
/// How long the worker spins for the next request before it parks. The next request comes
/// one controller tick after the last (some 60–100 µs on TALOS, the preparation itself
/// 25–35 µs of it); parking between overlapped ticks would add a wake-up, tens of µs on a
/// virtual machine, to every preparation. A run that stops overlapping (a serial stretch of
/// [`Overlap::Adaptive`]) lets the worker park after this long.
const WORKER_SPIN: Duration = Duration::from_micros(250);
/// Longest single park of the caller's thread before it checks the worker is alive.
const PARK_CHECK: Duration = Duration::from_millis(5);

/// What the caller's thread and the worker share.
struct Shared {
    sim: Mutex<Simulator>,
    requested: AtomicU64,
    done: AtomicU64,
    stop: AtomicBool,
    /// The thread that steps the robot (the worker wakes it); a robot moved to another
    /// thread updates it at its next preparation.
    stepper: Mutex<Thread>,
}

fn worker_failed() -> PlantError {
    PlantError::Failed("the simulator's preparing thread failed".into())
}

/// A simulated robot: the simulator, its sensors and, when overlapping, the preparing worker.
pub struct SimulatedRobot {
    shared: Arc<Shared>,
    sensors: Sensors,
    worker: Option<JoinHandle<()>>,
    requested: u64,
    /// A preparation was asked for this tick.
    pending: bool,
    schedule: OverlapSchedule,
    last_step: Option<Instant>,
    /// Contact points of the simulator (the capacity of [`Truth::contacts`]).
    points: usize,
}

impl SimulatedRobot {
    /// `sim` read through `sensors`; a worker thread starts unless `overlap` is
    /// [`Overlap::Never`]. The robot may be moved to another thread between ticks.
    pub fn new(sim: Simulator, sensors: Sensors, overlap: Overlap) -> Self {
        let points = sim.contact_points().len();
        let shared = Arc::new(Shared {
            sim: Mutex::new(sim),
            requested: AtomicU64::new(0),
            done: AtomicU64::new(0),
            stop: AtomicBool::new(false),
            stepper: Mutex::new(std::thread::current()),
        });
        let worker = (overlap != Overlap::Never).then(|| {
            let shared = shared.clone();
            std::thread::spawn(move || prepare_on_request(&shared))
        });
        Self {
            shared,
            sensors,
            worker,
            requested: 0,
            pending: false,
            schedule: OverlapSchedule::new(overlap),
            last_step: None,
            points,
        }
    }

    /// How many ticks overlapped and how many ran serially.
    pub fn overlap_counts(&self) -> (u64, u64) {
        self.schedule.counts()
    }

    /// The simulator back (the worker stops).
    pub fn into_simulator(self) -> Result<Simulator, PlantError> {
        self.into_parts().map(|(sim, _)| sim)
    }

    /// The simulator and its sensors back (the worker stops).
    pub fn into_parts(mut self) -> Result<(Simulator, Sensors), PlantError> {
        self.stop_worker();
        let shared = self.shared.clone();
        let sensors = self.sensors.clone();
        drop(self);
        let sim = Arc::try_unwrap(shared)
            .map_err(|_| worker_failed())?
            .sim
            .into_inner()
            .map_err(|_| worker_failed())?;
        Ok((sim, sensors))
    }

    fn stop_worker(&mut self) {
        if let Some(worker) = self.worker.take() {
            self.shared.stop.store(true, Ordering::Release);
            worker.thread().unpark();
            let _ = worker.join();
        }
    }

    /// Spins briefly, then parks until the worker says the preparation is done; returns
    /// whether it had to park (the worker was late: no free core, or a slow preparation).
    fn wait_for_preparation(&self) -> Result<bool, PlantError> {
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
                return Err(PlantError::Failed(
                    "the simulator's preparing thread stopped".into(),
                ));
            }
            parked = true;
            std::thread::park_timeout(PARK_CHECK);
        }
        Ok(parked)
    }
}

/// The simulator's contact points that carry a force, into `out` (cleared first): the truth's
/// contact list. Allocation-free within `out`'s capacity.
pub fn touching_points(sim: &Simulator, out: &mut Vec<ContactForce>) {
    out.clear();
    let c = sim.contact();
    let points = c.point_forces.iter().zip(&c.point_positions);
    for ((force, position), point) in points.zip(sim.contact_points()) {
        // Most sampled points are clear of the ground.
        if *force != nalgebra::Vector3::zeros() {
            out.push(ContactForce {
                joint: point.joint,
                position: *position,
                force: *force,
            });
        }
    }
}

impl Drop for SimulatedRobot {
    fn drop(&mut self) {
        self.stop_worker();
    }
}

impl Plant for SimulatedRobot {
    fn sensed(&self) -> Sensed {
        let sim = self.shared.sim.lock().unwrap_or_else(|p| p.into_inner());
        let readings = self.sensors.measured().clone();
        Sensed {
            time: sim.time(),
            truth: Some(Truth {
                q: sim.q().clone_owned(),
                v: sim.v().clone_owned(),
                applied_torques: sim.applied_torques().clone_owned(),
                com: Default::default(),
                com_velocity: Default::default(),
                joint_placements: sim.data().o_m_i.clone(),
                contacts: Vec::with_capacity(self.points),
                readings: readings.clone(),
            }),
            readings,
        }
    }

    fn sense(&mut self, out: &mut Sensed) -> Result<(), PlantError> {
        let sim = self.shared.sim.lock().map_err(|_| worker_failed())?;
        self.sensors.update(&sim);
        out.time = sim.time();
        out.readings.copy_from(self.sensors.measured());
        if let Some(truth) = &mut out.truth {
            let (model, data) = (sim.model(), sim.data());
            truth.readings.copy_from(self.sensors.truth());
            truth.q.copy_from(sim.q());
            truth.v.copy_from(sim.v());
            truth.applied_torques.copy_from(sim.applied_torques());
            (truth.com, truth.com_velocity) = com_at_placements(model, data);
            truth.joint_placements.copy_from_slice(&data.o_m_i);
            touching_points(&sim, &mut truth.contacts);
        }
        Ok(())
    }

    fn prepare(&mut self) {
        let Some(worker) = &self.worker else { return };
        if !self.schedule.overlap_this_tick() {
            return;
        }
        let here = std::thread::current();
        if let Ok(mut stepper) = self.shared.stepper.lock() {
            if stepper.id() != here.id() {
                *stepper = here;
            }
        }
        self.requested += 1;
        self.shared
            .requested
            .store(self.requested, Ordering::Release);
        worker.thread().unpark();
        self.pending = true;
    }

    fn step(&mut self, command: &Command) -> Result<(), PlantError> {
        let parked = std::mem::take(&mut self.pending) && self.wait_for_preparation()?;
        let mut sim = self.shared.sim.lock().map_err(|_| worker_failed())?;
        match sim.step(command) {
            Ok(()) => {}
            Err(SimError::Diverged { t, reason }) => {
                return Err(PlantError::Diverged { t, reason });
            }
            Err(e) => return Err(PlantError::Failed(e.to_string())),
        }
        drop(sim);
        let now = Instant::now();
        if let Some(last) = self.last_step.replace(now) {
            self.schedule.record_tick(now - last, parked);
        }
        Ok(())
    }
}

/// The worker: prepares each requested step, tells the caller's thread, then waits for the
/// next request (spinning briefly, then parked) until the robot stops it.
fn prepare_on_request(shared: &Shared) {
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
        if let Ok(stepper) = shared.stepper.lock() {
            stepper.unpark();
        }
    }
}
