//! The closed loop: each control period the references are sampled, the plant's sensors read,
//! the state estimated, the command computed, the observers fed and the plant stepped. The
//! plant's true state, which the observers read (and the estimator, fed the exact readings),
//! may arrive after the readings ([`Plant::complete`]), while the estimator and the
//! controller run.
//!
//! ```text
//! references(t) ─┐
//! plant ── sensed ──> estimator ── state ──> controller ── command ──> plant.step
//!    └──────────────────────────── observers (metrics, log, verdict) ─┘
//! ```

use crate::controller::{Controller, ReferenceSource};
use crate::observer::{Flow, Observer, Tick};
use crate::plant::{Plant, PlantError};
use corps_estimation::Estimator;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;
use thiserror::Error;

/// What the estimator reads.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Feed {
    /// The sensors as the robot has them (noise, bias).
    #[default]
    Measured,
    /// The plant's noiseless readings: for comparison only; the plant must know its truth.
    Exact,
}

/// How long and how fast the loop runs.
#[derive(Clone, Copy, Debug)]
pub struct LoopSettings {
    /// Control period (s).
    pub dt: f64,
    /// Control periods to run.
    pub ticks: usize,
    pub feed: Feed,
}

/// Why the loop ended.
#[derive(Clone, Debug, PartialEq)]
pub enum LoopEnd {
    /// Every tick ran.
    Completed,
    /// An observer stopped it (a fall, for instance).
    Stopped,
    /// The interrupt flag was raised.
    Interrupted,
    /// The plant diverged at plant time `t`.
    Diverged { t: f64, reason: String },
}

/// How a loop ended and how many ticks ran.
#[derive(Clone, Debug, PartialEq)]
pub struct LoopOutcome {
    pub ticks_run: usize,
    pub end: LoopEnd,
}

/// A loop that could not go on.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum LoopError {
    #[error("the plant: {0}")]
    Plant(PlantError),
    #[error("the estimator is fed the exact readings, but the plant does not know its true state")]
    NoTruth,
    #[error("the control period must be positive and finite, got {0} s")]
    Period(f64),
}

/// The parts of one closed-loop run. It is `Send` when its parts are, so that independent
/// rollouts run on threads.
pub struct ClosedLoop<P, E, C: Controller, R> {
    pub plant: P,
    pub estimator: E,
    pub controller: C,
    pub references: R,
    /// The references of the current tick.
    pub current: C::References,
}

impl<P, E, C, R> ClosedLoop<P, E, C, R>
where
    P: Plant,
    E: Estimator,
    C: Controller,
    R: ReferenceSource<C::References>,
{
    /// Runs `settings.ticks` control periods from t = 0 (the references' time), or until an
    /// observer stops it, the plant diverges or `interrupt` is raised. A loop runs once: a
    /// second call would sample the references from 0 again while the plant goes on. The tick
    /// allocates nothing beyond what the parts do.
    pub fn run(
        &mut self,
        settings: &LoopSettings,
        observers: &mut [&mut dyn Observer<C>],
        interrupt: Option<&AtomicBool>,
    ) -> Result<LoopOutcome, LoopError> {
        if !(settings.dt > 0.0 && settings.dt.is_finite()) {
            return Err(LoopError::Period(settings.dt));
        }
        let mut sensed = self.plant.sensed();
        if settings.feed == Feed::Exact && sensed.truth.is_none() {
            return Err(LoopError::NoTruth);
        }
        for index in 0..settings.ticks {
            let done = |end| LoopOutcome {
                ticks_run: index,
                end,
            };
            if interrupt.is_some_and(|f| f.load(Ordering::Relaxed)) {
                return Ok(done(LoopEnd::Interrupted));
            }
            let t = index as f64 * settings.dt;
            self.references.sample(t, &mut self.current);
            let sensed_now = match self.plant.sense(&mut sensed) {
                // The estimator fed the exact readings needs the true state at once.
                Ok(()) if settings.feed == Feed::Exact => self.plant.complete(&mut sensed),
                other => other,
            };
            match sensed_now {
                Ok(()) => {}
                Err(PlantError::Diverged { t, reason }) => {
                    return Ok(done(LoopEnd::Diverged { t, reason }))
                }
                Err(e) => return Err(LoopError::Plant(e)),
            }
            self.plant.prepare();
            let readings = match (&settings.feed, &sensed.truth) {
                (Feed::Exact, Some(truth)) => &truth.readings,
                _ => &sensed.readings,
            };
            let estimator_error = self.estimator.update(readings).err();
            let start = Instant::now();
            let fallback = self
                .controller
                .tick(t, self.estimator.state(), &self.current);
            let tick_us = start.elapsed().as_secs_f64() * 1e6;
            if settings.feed == Feed::Measured {
                match self.plant.complete(&mut sensed) {
                    Ok(()) => {}
                    Err(PlantError::Diverged { t, reason }) => {
                        return Ok(done(LoopEnd::Diverged { t, reason }))
                    }
                    Err(e) => return Err(LoopError::Plant(e)),
                }
            }
            let tick = Tick {
                index,
                t,
                sensed: &sensed,
                estimate: self.estimator.state(),
                estimator_error: estimator_error.as_ref(),
                references: &self.current,
                controller: &self.controller,
                fallback: fallback.as_ref(),
                tick_us,
            };
            let mut flow = Flow::Continue;
            for o in observers.iter_mut() {
                if o.observe(&tick) == Flow::Stop {
                    flow = Flow::Stop;
                }
            }
            if flow == Flow::Stop {
                return Ok(LoopOutcome {
                    ticks_run: index + 1,
                    end: LoopEnd::Stopped,
                });
            }
            match self.plant.step(self.controller.command()) {
                Ok(()) => {}
                Err(PlantError::Diverged { t, reason }) => {
                    return Ok(LoopOutcome {
                        ticks_run: index + 1,
                        end: LoopEnd::Diverged { t, reason },
                    })
                }
                Err(e) => return Err(LoopError::Plant(e)),
            }
        }
        Ok(LoopOutcome {
            ticks_run: settings.ticks,
            end: LoopEnd::Completed,
        })
    }
}
