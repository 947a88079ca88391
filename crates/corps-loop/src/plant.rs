//! The robot side of the loop: a simulator, another physics engine or a real robot. A plant
//! takes one command per control period and gives the sensor readings of its state; a
//! simulated plant also gives the true state, which only the metrics read.

use crate::command::Command;
use corps_estimation::Readings;
use corps_model::spatial::Se3;
use corps_model::Model;
use nalgebra::{DVector, Vector3};
use thiserror::Error;

/// Why a plant could not step or read its sensors.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum PlantError {
    /// The plant's state blew up at plant time `t` (s): the run ends, diverged.
    #[error("diverged at t = {t:.4} s ({reason})")]
    Diverged { t: f64, reason: String },
    /// The plant refused the command or failed otherwise.
    #[error("{0}")]
    Failed(String),
}

/// A ground force at one contact point, world frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactForce {
    /// Joint whose body the point belongs to.
    pub joint: usize,
    pub position: Vector3<f64>,
    pub force: Vector3<f64>,
}

/// The true state of a simulated plant: what the metrics compare the estimate and the
/// references with. A real robot has none.
#[derive(Clone, Debug, PartialEq)]
pub struct Truth {
    pub q: DVector<f64>,
    pub v: DVector<f64>,
    /// Joint torques applied over the last period (as the plant reports them).
    pub applied_torques: DVector<f64>,
    pub com: Vector3<f64>,
    pub com_velocity: Vector3<f64>,
    /// World placement of every joint (Pinocchio's `oMi`).
    pub joint_placements: Vec<Se3>,
    /// The contact points that carry a force (capacity reserved by the plant).
    pub contacts: Vec<ContactForce>,
    /// The noiseless sensor readings.
    pub readings: Readings,
}

impl Truth {
    /// World placement of frame `frame` of `model`: oMf = oMi · iMf.
    pub fn frame_placement(&self, model: &Model, frame: usize) -> Se3 {
        let f = &model.frames[frame];
        match f.parent_joint {
            Some(j) => self.joint_placements[j] * f.placement,
            None => f.placement,
        }
    }
}

/// What a plant gives each tick.
#[derive(Clone, Debug, PartialEq)]
pub struct Sensed {
    /// Plant time (s).
    pub time: f64,
    /// The readings as the robot's sensors give them (noise, bias).
    pub readings: Readings,
    /// The true state, where the plant knows it.
    pub truth: Option<Truth>,
}

/// The robot in the loop. Implementations size [`Sensed`] once ([`Plant::sensed`]) and then
/// fill it each tick without allocating.
pub trait Plant: Send {
    /// A buffer of the right sizes for [`Plant::sense`].
    fn sensed(&self) -> Sensed;
    /// Reads the sensors (and the true state, if known) of the current state into `out`. A
    /// plant may leave the true state to [`Plant::complete`]: a caller that reads
    /// [`Sensed::truth`] calls it first.
    fn sense(&mut self, out: &mut Sensed) -> Result<(), PlantError>;
    /// Fills in what [`Plant::sense`] left for later (the true state, which only the metrics
    /// read, while the readings went ahead to the estimator). Nothing by default.
    fn complete(&mut self, _out: &mut Sensed) -> Result<(), PlantError> {
        Ok(())
    }
    /// Called between [`Plant::sense`] and [`Plant::step`], while the controller computes: a
    /// plant may start its next step's state-only work here (the simulator also decides here
    /// whether the tick's step runs on its second thread; without this call it steps on the
    /// caller's).
    fn prepare(&mut self) {}
    /// Applies `command` for one control period.
    fn step(&mut self, command: &Command) -> Result<(), PlantError>;
}

impl<P: Plant + ?Sized> Plant for Box<P> {
    fn sensed(&self) -> Sensed {
        (**self).sensed()
    }
    fn sense(&mut self, out: &mut Sensed) -> Result<(), PlantError> {
        (**self).sense(out)
    }
    fn complete(&mut self, out: &mut Sensed) -> Result<(), PlantError> {
        (**self).complete(out)
    }
    fn prepare(&mut self) {
        (**self).prepare()
    }
    fn step(&mut self, command: &Command) -> Result<(), PlantError> {
        (**self).step(command)
    }
}
