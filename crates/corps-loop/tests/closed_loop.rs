//! The loop's contract on a toy robot, independent of any simulator: a unit mass on a line,
//! sensed by a position encoder, estimated by a copy, driven by a PD controller to a
//! reference. Checks the order of the seams, how a run ends, and that the loop's own
//! machinery allocates nothing per tick.

use corps_estimation::{EstimatedState, EstimationError, Estimator, Readings};
use corps_loop::{
    ClosedLoop, Command, Controller, Feed, Flow, LoopEnd, LoopError, LoopSettings, Observer, Plant,
    PlantError, ReferenceSource, Sensed, Tick, Truth,
};
use corps_testkit::{allocations, CountingAllocator};
use nalgebra::{DVector, Vector3};
use std::sync::atomic::AtomicBool;

#[global_allocator]
static GLOBAL: CountingAllocator = CountingAllocator;

const DT: f64 = 0.01;

/// A unit mass on a line under a force; diverges past `limit`.
struct Mass {
    x: f64,
    v: f64,
    t: f64,
    steps: usize,
    knows_truth: bool,
    /// Gives the true state at `complete` instead of at `sense`.
    late_truth: bool,
    limit: f64,
}

impl Mass {
    fn new() -> Self {
        Self {
            x: 0.0,
            v: 0.0,
            t: 0.0,
            steps: 0,
            knows_truth: true,
            late_truth: false,
            limit: f64::INFINITY,
        }
    }
    fn readings(&self) -> Readings {
        Readings {
            joint_positions: DVector::zeros(1),
            joint_velocities: DVector::zeros(1),
            joint_torques: DVector::zeros(1),
            ..Readings::default()
        }
    }
}

impl Mass {
    fn fill_truth(&self, out: &mut Sensed) {
        if let Some(truth) = &mut out.truth {
            truth.q[0] = self.x;
            truth.readings.joint_positions[0] = self.x;
            truth.readings.joint_velocities[0] = self.v;
        }
    }
}

impl Plant for Mass {
    fn sensed(&self) -> Sensed {
        Sensed {
            time: self.t,
            readings: self.readings(),
            truth: self.knows_truth.then(|| Truth {
                q: DVector::zeros(1),
                v: DVector::zeros(1),
                applied_torques: DVector::zeros(1),
                com: Vector3::zeros(),
                com_velocity: Vector3::zeros(),
                joint_placements: vec![],
                contacts: vec![],
                readings: self.readings(),
            }),
        }
    }
    fn sense(&mut self, out: &mut Sensed) -> Result<(), PlantError> {
        out.time = self.t;
        // The encoder reads 1 mm high; the truth does not.
        out.readings.joint_positions[0] = self.x + 1e-3;
        out.readings.joint_velocities[0] = self.v;
        if !self.late_truth {
            self.fill_truth(out);
        }
        Ok(())
    }
    fn complete(&mut self, out: &mut Sensed) -> Result<(), PlantError> {
        if self.late_truth {
            self.fill_truth(out);
        }
        Ok(())
    }
    fn step(&mut self, command: &Command) -> Result<(), PlantError> {
        let Command::Torque(f) = command else {
            return Err(PlantError::Failed("a force command".into()));
        };
        self.v += f[0] * DT;
        self.x += self.v * DT;
        self.t += DT;
        self.steps += 1;
        if self.x.abs() > self.limit {
            return Err(PlantError::Diverged {
                t: self.t,
                reason: "past the limit".into(),
            });
        }
        Ok(())
    }
}

/// Copies the encoder into the state.
struct Copy {
    state: EstimatedState,
}

impl Copy {
    fn new() -> Self {
        Self {
            state: EstimatedState {
                time: 0.0,
                q: DVector::zeros(1),
                v: DVector::zeros(1),
                com: Vector3::zeros(),
                com_velocity: Vector3::zeros(),
                feet: vec![],
                zmp: None,
                hands: Vec::new(),
            },
        }
    }
}

impl Estimator for Copy {
    fn reset(&mut self, q: &[f64], v: &[f64]) -> Result<(), EstimationError> {
        self.state.q[0] = q[0];
        self.state.v[0] = v[0];
        Ok(())
    }
    fn update(&mut self, r: &Readings) -> Result<(), EstimationError> {
        self.state.q[0] = r.joint_positions[0];
        self.state.v[0] = r.joint_velocities[0];
        Ok(())
    }
    fn state(&self) -> &EstimatedState {
        &self.state
    }
}

/// f = kp (x_ref − x) − kd v; falls back to zero force when the reference is not finite.
struct Pd {
    command: Command,
}

impl Controller for Pd {
    type References = f64;
    type Fallback = &'static str;
    fn tick(&mut self, _t: f64, s: &EstimatedState, x_ref: &f64) -> Option<&'static str> {
        let Command::Torque(f) = &mut self.command else {
            unreachable!()
        };
        if !x_ref.is_finite() {
            f[0] = 0.0;
            return Some("reference not finite");
        }
        f[0] = 100.0 * (x_ref - s.q[0]) - 20.0 * s.v[0];
        None
    }
    fn command(&self) -> &Command {
        &self.command
    }
}

/// A step to 0.5 at t = 0.1 s, NaN from t = `bad_from`.
struct Step {
    bad_from: f64,
}

impl ReferenceSource<f64> for Step {
    fn sample(&mut self, t: f64, out: &mut f64) {
        *out = if t >= self.bad_from {
            f64::NAN
        } else if t >= 0.1 {
            0.5
        } else {
            0.0
        };
    }
}

/// Records what it saw, without allocating; stops at tick `stop_at`.
struct Watch {
    seen: usize,
    last_t: f64,
    fallbacks: usize,
    stop_at: usize,
    error_sum: f64,
}

impl Watch {
    fn new(stop_at: usize) -> Self {
        Self {
            seen: 0,
            last_t: -1.0,
            fallbacks: 0,
            stop_at,
            error_sum: 0.0,
        }
    }
}

impl Observer<Pd> for Watch {
    fn observe(&mut self, tick: &Tick<'_, Pd>) -> Flow {
        assert_eq!(tick.index, self.seen, "ticks in order, none skipped");
        assert!((tick.t - tick.index as f64 * DT).abs() < 1e-12);
        assert!(tick.t > self.last_t);
        let truth = tick
            .sensed
            .truth
            .as_ref()
            .expect("the toy plant knows its truth");
        // The estimate is what the sensors said, 1 mm above the truth.
        self.error_sum += tick.estimate.q[0] - truth.q[0];
        self.fallbacks += usize::from(tick.fallback.is_some());
        self.last_t = tick.t;
        self.seen += 1;
        if self.seen == self.stop_at {
            Flow::Stop
        } else {
            Flow::Continue
        }
    }
}

fn closed_loop(plant: Mass, bad_from: f64) -> ClosedLoop<Mass, Copy, Pd, Step> {
    ClosedLoop {
        plant,
        estimator: Copy::new(),
        controller: Pd {
            command: Command::Torque(DVector::zeros(1)),
        },
        references: Step { bad_from },
        current: 0.0,
    }
}

fn settings(ticks: usize, feed: Feed) -> LoopSettings {
    LoopSettings {
        dt: DT,
        ticks,
        feed,
    }
}

#[test]
fn the_loop_tracks_the_reference_through_the_sensors_and_steps_once_per_tick() {
    let mut run = closed_loop(Mass::new(), f64::INFINITY);
    let mut watch = Watch::new(usize::MAX);
    let out = run
        .run(&settings(300, Feed::Measured), &mut [&mut watch], None)
        .unwrap();
    assert_eq!(out.ticks_run, 300);
    assert_eq!(out.end, LoopEnd::Completed);
    assert_eq!(run.plant.steps, 300);
    assert_eq!(watch.seen, 300);
    // The controller sees the biased encoder: it settles 1 mm below the reference.
    assert!((run.plant.x - 0.499).abs() < 1e-4, "x = {}", run.plant.x);
    assert!((watch.error_sum / 300.0 - 1e-3).abs() < 1e-12);
}

#[test]
fn a_true_state_given_late_reaches_the_observers_and_the_exact_feed() {
    let mut mass = Mass::new();
    mass.late_truth = true;
    let mut run = closed_loop(mass, f64::INFINITY);
    let mut watch = Watch::new(usize::MAX);
    run.run(&settings(300, Feed::Measured), &mut [&mut watch], None)
        .unwrap();
    assert!((watch.error_sum / 300.0 - 1e-3).abs() < 1e-12);
    let mut mass = Mass::new();
    mass.late_truth = true;
    let mut run = closed_loop(mass, f64::INFINITY);
    run.run(&settings(300, Feed::Exact), &mut [], None).unwrap();
    assert!((run.plant.x - 0.5).abs() < 1e-4, "x = {}", run.plant.x);
}

#[test]
fn the_exact_feed_reads_the_truth_and_needs_a_plant_that_knows_it() {
    let mut run = closed_loop(Mass::new(), f64::INFINITY);
    run.run(&settings(300, Feed::Exact), &mut [], None).unwrap();
    assert!((run.plant.x - 0.5).abs() < 1e-4, "x = {}", run.plant.x);
    let mut blind = Mass::new();
    blind.knows_truth = false;
    let mut run = closed_loop(blind, f64::INFINITY);
    let e = run
        .run(&settings(10, Feed::Exact), &mut [], None)
        .unwrap_err();
    assert_eq!(e, LoopError::NoTruth);
    assert_eq!(run.plant.steps, 0);
}

#[test]
fn an_observer_stops_the_run_before_the_plant_steps_again() {
    let mut run = closed_loop(Mass::new(), f64::INFINITY);
    let (mut a, mut b) = (Watch::new(7), Watch::new(usize::MAX));
    let out = run
        .run(&settings(100, Feed::Measured), &mut [&mut a, &mut b], None)
        .unwrap();
    assert_eq!(
        out,
        corps_loop::LoopOutcome {
            ticks_run: 7,
            end: LoopEnd::Stopped
        }
    );
    // Every observer saw the last tick; the plant did not step after it.
    assert_eq!((a.seen, b.seen, run.plant.steps), (7, 7, 6));
}

#[test]
fn a_diverging_plant_ends_the_run_with_its_time_and_reason() {
    let mut mass = Mass::new();
    mass.limit = 0.2;
    let mut run = closed_loop(mass, f64::INFINITY);
    let out = run
        .run(&settings(300, Feed::Measured), &mut [], None)
        .unwrap();
    let LoopEnd::Diverged { t, reason } = out.end else {
        panic!("{out:?}")
    };
    assert_eq!(reason, "past the limit");
    assert!((t - out.ticks_run as f64 * DT).abs() < 1e-9);
}

#[test]
fn the_fallback_reaches_the_observers_and_the_safe_command_the_plant() {
    let mut run = closed_loop(Mass::new(), 1.0);
    let mut watch = Watch::new(usize::MAX);
    run.run(&settings(150, Feed::Measured), &mut [&mut watch], None)
        .unwrap();
    assert_eq!(watch.fallbacks, 50);
    assert_eq!(
        run.controller.command(),
        &Command::Torque(DVector::zeros(1))
    );
}

#[test]
fn a_raised_interrupt_stops_before_the_next_tick() {
    static STOP: AtomicBool = AtomicBool::new(true);
    let mut run = closed_loop(Mass::new(), f64::INFINITY);
    let out = run
        .run(&settings(100, Feed::Measured), &mut [], Some(&STOP))
        .unwrap();
    assert_eq!(out.end, LoopEnd::Interrupted);
    assert_eq!((out.ticks_run, run.plant.steps), (0, 0));
}

#[test]
fn the_loop_allocates_nothing_per_tick() {
    let count = |ticks| {
        let mut run = closed_loop(Mass::new(), f64::INFINITY);
        let mut watch = Watch::new(usize::MAX);
        let before = allocations();
        run.run(&settings(ticks, Feed::Measured), &mut [&mut watch], None)
            .unwrap();
        allocations() - before
    };
    let (short, long) = (count(10), count(1000));
    // The sensed buffer is sized once per run; the ticks add nothing.
    assert_eq!(
        short, long,
        "10 ticks: {short} allocations, 1000 ticks: {long}"
    );
}

#[test]
fn a_closed_loop_of_send_parts_is_send() {
    fn send<T: Send>(_: &T) {}
    send(&closed_loop(Mass::new(), f64::INFINITY));
}
