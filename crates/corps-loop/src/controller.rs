//! The controller side of the loop, and where its references come from.

use crate::command::Command;
use corps_estimation::EstimatedState;
use std::fmt::Display;

/// Estimated state + references → command, once per control period, for any robot.
pub trait Controller: Send {
    /// What the controller tracks (a motion's targets, a set of task references, ...).
    type References;
    /// Why a tick fell back to the safe command.
    type Fallback: Display;
    /// Computes the command at `t` (s since the loop started). Returns why the safe command
    /// was used instead, if it was; [`Controller::command`] is defined either way.
    fn tick(
        &mut self,
        t: f64,
        state: &EstimatedState,
        references: &Self::References,
    ) -> Option<Self::Fallback>;
    /// The command of the last tick.
    fn command(&self) -> &Command;
}

/// Gives the references of each tick (a motion plan, a teleoperation stream, ...).
pub trait ReferenceSource<R>: Send {
    /// Writes the references at `t` (s since the loop started) into `out`.
    fn sample(&mut self, t: f64, out: &mut R);
}
