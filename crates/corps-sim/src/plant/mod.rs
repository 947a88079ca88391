//! The simulator as the loop's [`Plant`]: the simulator and its sensors, stepped either on the
//! caller's thread alone or on a worker thread that also prepares each next step
//! ([`Simulator::prepare_step`]: h(q, v), the contact pass, the factorization) while the
//! controller computes. Both give bit-identical steps, readings and true states, so a run may
//! switch between them at any tick. (The sensors draw their noise when the worker steps
//! rather than at [`Plant::sense`]: the same draws, in the same order, one per step.)
//!
//! An overlapped tick: the worker steps under the command and reads the sensors; the caller's
//! thread takes the readings (a swap of buffers) and estimates and controls while the worker
//! writes the true state and prepares the next step; the true state reaches the caller at
//! [`Plant::complete`], before the metrics read it. Whether a tick overlaps is decided by an
//! [`OverlapSchedule`]: with [`Overlap::Adaptive`] the run times its own ticks both ways and
//! keeps the faster, so the overlap is used only while it gains.

mod worker;

use crate::overlap::{Overlap, OverlapSchedule};
use crate::{Sensors, Simulator};
use corps_estimation::Readings;
use corps_loop::{Command, ContactForce, Plant, PlantError, Sensed, Truth};
use corps_model::com_at_placements;
use nalgebra::DVector;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, Mutex};
use std::thread::{JoinHandle, ThreadId};
use std::time::{Duration, Instant};
use worker::{Padded, Robot, Shared, StepReadings};

/// How long the caller's thread spins for the worker before it parks (a step takes a few
/// microseconds, a preparation tens, and the preparation usually ends while the controller
/// computes).
const RUN_SPIN: Duration = Duration::from_micros(20);
/// Longest single park of the caller's thread before it checks the worker is alive.
const PARK_CHECK: Duration = Duration::from_millis(5);

fn worker_failed() -> PlantError {
    PlantError::Failed("the simulator's worker thread failed".into())
}

/// A simulated robot: the simulator, its sensors and, when overlapping, the worker thread.
pub struct SimulatedRobot {
    shared: Arc<Shared>,
    worker: Option<JoinHandle<()>>,
    /// Requests raised so far: preparations alone, and steps.
    prepares: u64,
    steps: u64,
    /// The current tick steps on the worker (decided by [`Plant::prepare`]).
    overlapped: bool,
    /// The last step ran on the worker, which went on to prepare the next step there.
    stepped_on_worker: bool,
    /// The last step's readings, and its true state, wait on the worker's side.
    readings_pending: bool,
    truth_pending: bool,
    schedule: OverlapSchedule,
    last_step: Option<Instant>,
    /// Contact points of the simulator (the capacity of [`Truth::contacts`]).
    points: usize,
    /// The thread the worker wakes.
    caller: ThreadId,
}

impl SimulatedRobot {
    /// `sim` read through `sensors`; a worker thread starts unless `overlap` is
    /// [`Overlap::Never`]. The robot may be moved to another thread between ticks.
    pub fn new(sim: Simulator, sensors: Sensors, overlap: Overlap) -> Self {
        let points = sim.contact_points().len();
        let robot = Robot { sim, sensors };
        let buffer = sensed_buffer(&robot, points);
        let shared = Arc::new(Shared {
            command: Padded(Mutex::new(Command::Torque(DVector::zeros(
                robot.sim.applied_torques().len(),
            )))),
            readings: Padded(Mutex::new(StepReadings {
                time: buffer.time,
                readings: buffer.readings,
                result: Ok(()),
            })),
            truth: Padded(Mutex::new(buffer.truth)),
            robot: Padded(Mutex::new(robot)),
            prepare_requested: Padded(AtomicU64::new(0)),
            step_requested: Padded(AtomicU64::new(0)),
            prepared: Padded(AtomicU64::new(0)),
            stepped: Padded(AtomicU64::new(0)),
            truth_ready: Padded(AtomicU64::new(0)),
            step_prepared: Padded(AtomicU64::new(0)),
            stop: AtomicBool::new(false),
            caller: Mutex::new(std::thread::current()),
            caller_changes: AtomicU64::new(0),
        });
        let worker = (overlap != Overlap::Never).then(|| {
            let shared = shared.clone();
            std::thread::spawn(move || worker::serve(&shared))
        });
        Self {
            shared,
            worker,
            prepares: 0,
            steps: 0,
            overlapped: false,
            stepped_on_worker: false,
            readings_pending: false,
            truth_pending: false,
            schedule: OverlapSchedule::new(overlap),
            last_step: None,
            points,
            caller: std::thread::current().id(),
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
        drop(self);
        let robot = Arc::try_unwrap(shared)
            .map_err(|_| worker_failed())?
            .robot
            .0
            .into_inner()
            .map_err(|_| worker_failed())?;
        Ok((robot.sim, robot.sensors))
    }

    fn stop_worker(&mut self) {
        if let Some(worker) = self.worker.take() {
            self.shared.stop.store(true, Ordering::Release);
            worker.thread().unpark();
            let _ = worker.join();
        }
    }

    /// Makes this thread the one the worker wakes (a robot moved to another thread).
    fn register_caller(&mut self) {
        let here = std::thread::current().id();
        if self.caller != here {
            if let Ok(mut caller) = self.shared.caller.lock() {
                *caller = std::thread::current();
                self.caller = here;
                self.shared.caller_changes.fetch_add(1, Ordering::Release);
            }
        }
    }

    /// Raises a request (`counter` to `value`) from this thread, the one the worker wakes.
    fn request(&mut self, counter: impl Fn(&Shared) -> &AtomicU64, value: u64) {
        self.register_caller();
        counter(&self.shared).store(value, Ordering::Release);
        if let Some(worker) = &self.worker {
            worker.thread().unpark();
        }
    }

    /// Spins briefly, then parks until `ready`; returns whether it had to park (the worker
    /// was late: no free core, or a slow preparation).
    fn wait_for(&mut self, ready: impl Fn(&Shared) -> bool) -> Result<bool, PlantError> {
        if self.worker.is_none() {
            return Ok(false);
        }
        self.register_caller();
        let Some(worker) = &self.worker else {
            return Ok(false);
        };
        let start = Instant::now();
        let mut spins = 0u32;
        let mut parked = false;
        while !ready(&self.shared) {
            spins = spins.wrapping_add(1);
            if !spins.is_multiple_of(64) || start.elapsed() < RUN_SPIN {
                std::hint::spin_loop();
                continue;
            }
            if worker.is_finished() {
                return Err(PlantError::Failed(
                    "the simulator's worker thread stopped".into(),
                ));
            }
            parked = true;
            std::thread::park_timeout(PARK_CHECK);
        }
        Ok(parked)
    }

    /// The step on the worker: the command across, then wait for the readings.
    fn step_on_worker(&mut self, command: &Command) -> Result<bool, PlantError> {
        if self.worker.is_none() {
            return Err(worker_failed());
        }
        (self.shared.command.lock().map_err(|_| worker_failed())?).copy_from(command);
        self.steps += 1;
        self.request(|s| &s.step_requested, self.steps);
        let steps = self.steps;
        let parked = self.wait_for(|s| s.stepped.load(Ordering::Acquire) == steps)?;
        let mut out = self.shared.readings.lock().map_err(|_| worker_failed())?;
        std::mem::replace(&mut out.result, Ok(()))?;
        self.readings_pending = true;
        self.truth_pending = true;
        Ok(parked)
    }

    /// The step on the caller's thread, once the worker has answered every request.
    fn step_here(&mut self, command: &Command) -> Result<bool, PlantError> {
        let (prepares, steps) = (self.prepares, self.steps);
        let parked = self.wait_for(|s| s.idle(prepares, steps))?;
        let mut robot = self.shared.robot.lock().map_err(|_| worker_failed())?;
        worker::step(&mut robot.sim, command)?;
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

/// A [`Sensed`] buffer of `robot`'s sizes, filled with its current readings and state.
fn sensed_buffer(robot: &Robot, points: usize) -> Sensed {
    let sim = &robot.sim;
    let readings = robot.sensors.measured().clone();
    Sensed {
        time: sim.time(),
        truth: Some(Truth {
            q: sim.q().clone_owned(),
            v: sim.v().clone_owned(),
            applied_torques: sim.applied_torques().clone_owned(),
            com: Default::default(),
            com_velocity: Default::default(),
            joint_placements: sim.data().o_m_i.clone(),
            contacts: Vec::with_capacity(points),
            readings: readings.clone(),
        }),
        readings,
    }
}

/// Reads the sensors of the current state (drawing their noise) into `out`; returns the
/// plant time.
fn read_readings(robot: &mut Robot, out: &mut Readings) -> f64 {
    robot.sensors.update(&robot.sim);
    out.copy_from(robot.sensors.measured());
    robot.sim.time()
}

/// The true state of the current state (after [`read_readings`]) into `truth`.
fn read_truth(robot: &Robot, truth: &mut Truth) {
    let Robot { sim, sensors } = robot;
    let (model, data) = (sim.model(), sim.data());
    truth.readings.copy_from(sensors.truth());
    truth.q.copy_from(sim.q());
    truth.v.copy_from(sim.v());
    truth.applied_torques.copy_from(sim.applied_torques());
    (truth.com, truth.com_velocity) = com_at_placements(model, data);
    truth.joint_placements.copy_from_slice(&data.o_m_i);
    touching_points(sim, &mut truth.contacts);
}

/// Whether two readings have the same sizes, so that swapping them hands each side a buffer
/// it can fill (else they are copied, which, as the serial read, requires the same sizes).
fn same_readings_shape(x: &Readings, y: &Readings) -> bool {
    x.joint_positions.len() == y.joint_positions.len()
        && x.joint_velocities.len() == y.joint_velocities.len()
        && x.joint_torques.len() == y.joint_torques.len()
        && x.force_torque.len() == y.force_torque.len()
        && x.contact_wrenches.len() == y.contact_wrenches.len()
}

/// As [`same_readings_shape`], for true states.
fn same_truth_shape(x: &Truth, y: &Truth) -> bool {
    x.q.len() == y.q.len()
        && x.v.len() == y.v.len()
        && x.applied_torques.len() == y.applied_torques.len()
        && x.joint_placements.len() == y.joint_placements.len()
        && x.contacts.capacity() == y.contacts.capacity()
        && same_readings_shape(&x.readings, &y.readings)
}

/// `src` into `dst` (allocation-free but for a contact list longer than `dst`'s capacity).
fn copy_truth(dst: &mut Truth, src: &Truth) {
    dst.q.copy_from(&src.q);
    dst.v.copy_from(&src.v);
    dst.applied_torques.copy_from(&src.applied_torques);
    dst.com = src.com;
    dst.com_velocity = src.com_velocity;
    dst.joint_placements.copy_from_slice(&src.joint_placements);
    dst.contacts.clear();
    dst.contacts.extend_from_slice(&src.contacts);
    dst.readings.copy_from(&src.readings);
}

impl Drop for SimulatedRobot {
    fn drop(&mut self) {
        self.stop_worker();
    }
}

impl Plant for SimulatedRobot {
    fn sensed(&self) -> Sensed {
        let robot = self.shared.robot.lock().unwrap_or_else(|p| p.into_inner());
        sensed_buffer(&robot, self.points)
    }

    fn sense(&mut self, out: &mut Sensed) -> Result<(), PlantError> {
        if std::mem::take(&mut self.readings_pending) {
            let mut from = self.shared.readings.lock().map_err(|_| worker_failed())?;
            out.time = from.time;
            if same_readings_shape(&out.readings, &from.readings) {
                std::mem::swap(&mut out.readings, &mut from.readings);
            } else {
                out.readings.copy_from(&from.readings);
            }
            return Ok(());
        }
        let mut robot = self.shared.robot.lock().map_err(|_| worker_failed())?;
        out.time = read_readings(&mut robot, &mut out.readings);
        if let Some(truth) = &mut out.truth {
            read_truth(&robot, truth);
        }
        Ok(())
    }

    fn complete(&mut self, out: &mut Sensed) -> Result<(), PlantError> {
        if !std::mem::take(&mut self.truth_pending) {
            return Ok(());
        }
        let steps = self.steps;
        self.wait_for(|s| s.truth_ready.load(Ordering::Acquire) == steps)?;
        let mut from = self.shared.truth.lock().map_err(|_| worker_failed())?;
        if let (Some(to), Some(from)) = (&mut out.truth, &mut *from) {
            if same_truth_shape(to, from) {
                std::mem::swap(to, from);
            } else {
                copy_truth(to, from);
            }
        }
        Ok(())
    }

    fn prepare(&mut self) {
        if self.worker.is_none() {
            return;
        }
        self.overlapped = self.schedule.overlap_this_tick();
        if !self.overlapped {
            return;
        }
        if self.stepped_on_worker {
            // The preparation is already under way on the worker; if the worker has parked
            // since (a slow tick), wake it now rather than when the step is asked for.
            if let Some(worker) = &self.worker {
                worker.thread().unpark();
            }
        } else {
            self.prepares += 1;
            self.request(|s| &s.prepare_requested, self.prepares);
        }
    }

    fn step(&mut self, command: &Command) -> Result<(), PlantError> {
        let on_worker = std::mem::take(&mut self.overlapped);
        self.readings_pending = false;
        self.truth_pending = false;
        self.stepped_on_worker = false;
        let parked = if on_worker {
            self.step_on_worker(command)?
        } else {
            self.step_here(command)?
        };
        self.stepped_on_worker = on_worker;
        let now = Instant::now();
        if let Some(last) = self.last_step.replace(now) {
            self.schedule.record_tick(now - last, parked);
        }
        Ok(())
    }
}
