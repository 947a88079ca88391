//! What watches the loop: metrics, logs, verdicts. Each observer sees every tick after the
//! controller has computed, and may end the run.

use crate::controller::Controller;
use crate::plant::Sensed;
use corps_estimation::{EstimatedState, EstimationError};

/// One tick as the observers see it.
pub struct Tick<'a, C: Controller + ?Sized> {
    /// Tick index, from 0.
    pub index: usize,
    /// Time since the loop started (s).
    pub t: f64,
    pub sensed: &'a Sensed,
    pub estimate: &'a EstimatedState,
    /// Why the estimator could not use this tick's readings (it held its estimate).
    pub estimator_error: Option<&'a EstimationError>,
    pub references: &'a C::References,
    pub controller: &'a C,
    pub fallback: Option<&'a C::Fallback>,
    /// Wall time of the controller's tick (µs).
    pub tick_us: f64,
}

/// Whether the run goes on after an observer has seen a tick.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Flow {
    Continue,
    Stop,
}

/// Fed each tick.
pub trait Observer<C: Controller + ?Sized>: Send {
    fn observe(&mut self, tick: &Tick<'_, C>) -> Flow;
}
