//! Velocity-driven walking planned as the run goes: the MPC pattern generator of seed 002
//! §4.4 re-plans every control period from the command a [`VelocitySource`] gives at that
//! moment — a scenario's schedule, or a live input such as a keyboard ([`LiveVelocity`]).
//!
//! The controller's contact of a foot about to swing is released `release` s before its
//! lift-off, so the contact flags of the sample in use need the plan `release` s ahead: the MPC
//! runs that many samples ahead of the controller, and a live command reaches the reference
//! `release` s after it is given (0.2 s with seed 002's double support). Driven by a schedule,
//! the samples equal those [`crate::walk::WalkMotion::velocity`] precomputes.

use crate::error::{invalid, Context, Result};
use crate::targets::{FollowTarget, Targets};
use crate::walk::{held_contact, lead_samples, PlanFrame, VelocitySection};
use corps_model::spatial::Se3;
use corps_walk::mpc::{MpcParams, VelocityCommand, WalkingMpc};
use corps_walk::{Lipm, WalkError, WalkingReference};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Arc;

/// Gives the velocity command in force at a plan time (s after the handover), knowing the
/// plan so far (`plan`: its last sample, in the plan's frame).
pub trait VelocitySource: Send {
    fn command(&mut self, t: f64, plan: &WalkingReference) -> VelocityCommand;

    /// Whom the robot follows at `t`, if anyone (co-navigation).
    fn follow(&self, _t: f64) -> Option<FollowTarget> {
        None
    }
}

impl VelocitySource for VelocitySection {
    fn command(&mut self, t: f64, _plan: &WalkingReference) -> VelocityCommand {
        self.at(t)
    }
}

/// A velocity command shared between threads: an input (keyboard, joystick, script) sets it,
/// the walk reads it every control period. Lock-free, never blocks the control tick.
#[derive(Debug, Default)]
pub struct LiveVelocity {
    vx: AtomicU64,
    vy: AtomicU64,
    yaw_rate: AtomicU64,
}

impl LiveVelocity {
    /// A command at rest.
    pub fn new() -> Arc<Self> {
        Arc::new(Self::default())
    }

    /// Replaces the command (each component is read atomically; a reader may see the
    /// components of two consecutive commands for one period).
    pub fn set(&self, c: VelocityCommand) {
        self.vx.store(c.vx.to_bits(), Ordering::Relaxed);
        self.vy.store(c.vy.to_bits(), Ordering::Relaxed);
        self.yaw_rate.store(c.yaw_rate.to_bits(), Ordering::Relaxed);
    }

    /// The command now.
    pub fn get(&self) -> VelocityCommand {
        VelocityCommand::new(
            f64::from_bits(self.vx.load(Ordering::Relaxed)),
            f64::from_bits(self.vy.load(Ordering::Relaxed)),
            f64::from_bits(self.yaw_rate.load(Ordering::Relaxed)),
        )
    }
}

impl VelocitySource for Arc<LiveVelocity> {
    fn command(&mut self, _t: f64, _plan: &WalkingReference) -> VelocityCommand {
        self.get()
    }
}

/// The MPC and its command source, producing one plan sample per control period: sample 0 is
/// the plan at rest, sample k the plan after the tick given the command at `(k − 1) dt`.
pub(crate) struct VelocityGenerator {
    mpc: WalkingMpc,
    source: Box<dyn VelocitySource>,
    produced: usize,
    dt: f64,
    /// The last sample produced.
    last: WalkingReference,
}

impl VelocityGenerator {
    /// The MPC of `robot` (its description's `walk_mpc` settings) for soles `feet0`, the CoM
    /// at `com_height` above them, re-planning every `dt`.
    pub(crate) fn new(
        robot: &corps_robot::Robot,
        source: Box<dyn VelocitySource>,
        feet0: &[Se3; 2],
        com_height: f64,
        dt: f64,
    ) -> Result<Self> {
        let file = robot
            .gains("walk_mpc")
            .map_err(|e| invalid!("motion: {e}"))?;
        let settings: MpcParams = corps_robot::toml_text::parse(&file.text)
            .map_err(|e| invalid!("motion: {}: {e}", file.shown))?;
        let params = MpcParams {
            lipm: Lipm::new(com_height, corps_walk::lipm::GRAVITY).context("motion: LIPM")?,
            control_period: dt,
            feet_distance: (feet0[0].translation - feet0[1].translation).xy().norm(),
            ..settings
        };
        let mpc = WalkingMpc::new(params, 0.0, 0.0, 0.0).context("motion: MPC")?;
        let last = mpc.reference();
        Ok(Self {
            mpc,
            source,
            produced: 0,
            dt,
            last,
        })
    }

    /// The MPC's double-support duration (s).
    pub(crate) fn double_support(&self) -> f64 {
        self.mpc.params().double_support
    }

    /// The time (s) of the command the next sample takes.
    pub(crate) fn next_time(&self) -> f64 {
        self.produced.saturating_sub(1) as f64 * self.dt
    }

    /// The next sample. On an MPC failure no sample is produced (the MPC keeps its last
    /// plan, though its command and gait bookkeeping are updated) and the next call retries.
    pub(crate) fn next(&mut self) -> Result<WalkingReference, WalkError> {
        let r = if self.produced == 0 {
            self.mpc.reference()
        } else {
            let command = self.source.command(self.next_time(), &self.last);
            self.mpc.tick(command)?
        };
        self.produced += 1;
        self.last = r;
        Ok(r)
    }
}

/// A velocity walk planned as the run samples it: the generator runs the release time ahead
/// of the sample in use, its samples kept in a ring allocated once.
pub struct LiveWalk {
    generator: VelocityGenerator,
    frame: PlanFrame,
    /// Samples `first … first + ring.len() − 1` (index `k` at `k % ring.len()`).
    ring: Vec<WalkingReference>,
    /// Samples produced so far.
    count: usize,
    lead: usize,
    /// Ticks where the MPC failed and the previous sample was repeated.
    failures: usize,
    first_failure: Option<String>,
}

impl LiveWalk {
    /// The walk of `robot` from soles `feet0` (CoM `com_height` above them) steered by
    /// `source`, with the contact released `release` s before lift-off (default: the MPC's
    /// double support).
    pub fn new(
        robot: &corps_robot::Robot,
        source: Box<dyn VelocitySource>,
        release: Option<f64>,
        feet0: &[Se3; 2],
        com_height: f64,
        dt: f64,
    ) -> Result<Self> {
        let generator = VelocityGenerator::new(robot, source, feet0, com_height, dt)?;
        let lead = lead_samples(release.unwrap_or(generator.double_support()), dt);
        Ok(Self {
            generator,
            frame: PlanFrame::new(feet0, dt),
            // The sample in use, the one before it (accelerations) and `lead` ahead.
            ring: vec![WalkingReference::default(); lead + 2],
            count: 0,
            lead,
            failures: 0,
            first_failure: None,
        })
    }

    /// Control periods where the MPC failed (the reference held its previous sample), and
    /// the first failure.
    pub fn failures(&self) -> (usize, Option<&str>) {
        (self.failures, self.first_failure.as_deref())
    }

    /// Produces samples up to index `last`.
    fn produce_to(&mut self, last: usize) {
        let n = self.ring.len();
        while self.count <= last {
            let t = self.generator.next_time();
            let r = match self.generator.next() {
                Ok(r) => r,
                Err(e) => {
                    self.failures += 1;
                    if self.first_failure.is_none() {
                        self.first_failure = Some(format!("MPC at t = {t:.3} s: {e}"));
                    }
                    if self.count == 0 {
                        WalkingReference::default()
                    } else {
                        self.ring[(self.count - 1) % n]
                    }
                }
            };
            self.ring[self.count % n] = r;
            self.count += 1;
        }
    }

    /// Writes the targets at `t` (s after the handover) into `out`. Times go forward: a time
    /// earlier than the ring holds gets the earliest sample whose look-ahead is produced.
    pub fn sample(&mut self, t: f64, out: &mut Targets) {
        let n = self.ring.len();
        let wanted = (t.max(0.0) / self.frame.dt).round() as usize;
        self.produce_to(wanted + self.lead);
        let i = wanted.max(self.count + 1 - n);
        let now = &self.ring[i % n];
        let prev = &self.ring[i.saturating_sub(1) % n];
        let contact = held_contact(now, &self.ring[(i + self.lead) % n]);
        self.frame.write(now, prev, contact, [[0.0; 2]; 2], out);
        out.follow = self.generator.source.follow(t);
    }
}
