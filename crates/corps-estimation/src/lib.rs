//! State estimation: what a controller knows of the robot comes from its sensors, through an
//! [`Estimator`].
//!
//! - [`Readings`]: one instant of encoders, joint velocities, F/T sensors, IMU (and, where a
//!   motion-capture system or a simulator gives them, the base pose and twist);
//! - [`KinematicEstimator`]: the floating base from leg odometry fused with the IMU
//!   ([`BaseSource::LegOdometry`], seed 000 §3.16: feet in contact weighted by their normal
//!   force, orientation and rate from the IMU) or read from the base channels
//!   ([`BaseSource::Direct`]: ground truth when fed the simulator's exact readings); the
//!   contact wrench of each foot in its sole frame from the F/T sensor above it, contact
//!   detection with hysteresis on the normal force, and the ZMP from those wrenches, as the
//!   thesis measured it (seed 002 §4.12, `SimpleZmpEstimator`);
//! - [`EstimatedState`]: the estimate a controller reads (q, v, CoM, feet, ZMP).
//!
//! ```
//! use corps_estimation::{BaseSource, Estimator, EstimatorSettings, FootSensor, KinematicEstimator};
//! # fn demo(model: std::sync::Arc<corps_model::Model>, feet: Vec<FootSensor>, imu: usize,
//! #         q0: &[f64], readings: &corps_estimation::Readings) -> Result<(), Box<dyn std::error::Error>> {
//! let settings = EstimatorSettings { base: BaseSource::LegOdometry, ..Default::default() };
//! let mut estimator = KinematicEstimator::new(model, feet, imu, settings)?;
//! estimator.reset(q0, &vec![0.0; q0.len() - 1])?;   // a known start, as a robot is powered on
//! estimator.update(readings)?;                      // every control tick
//! let com = estimator.state().com;
//! # Ok(()) }
//! ```

mod kinematic;
pub mod lowpass;
mod readings;
mod soles;

pub use kinematic::{BaseSource, EstimatorSettings, FootSensor, KinematicEstimator};
pub use readings::{ImuReading, Readings};
pub use soles::{zmp_of_feet, ZMP_MIN_FORCE};

use corps_model::spatial::Se3;
use nalgebra::{DVector, Vector2, Vector3, Vector6};

/// What went wrong in an estimator.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum EstimationError {
    /// The estimator cannot be built for this robot (a frame, joint or sensor that is not
    /// there, a robot without a floating base).
    #[error("estimator: {0}")]
    Setup(String),
    /// A reading of the wrong size.
    #[error("estimator: {channel} has {got} values, the robot {expected}")]
    Dimension {
        channel: &'static str,
        got: usize,
        expected: usize,
    },
    /// A reading that is NaN or infinite: the estimate is held at its last value.
    #[error("estimator: {channel} reads a non-finite value; the estimate is held")]
    NonFinite { channel: &'static str },
}

/// The estimate of one foot.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FootEstimate {
    /// Sole placement in the world.
    pub placement: Se3,
    /// Contact wrench on the foot in its sole frame, moment about the sole origin
    /// `[fx, fy, fz, τx, τy, τz]`.
    pub wrench: Vector6<f64>,
    /// Whether the foot is in contact (hysteresis on the normal force).
    pub in_contact: bool,
}

/// The state a controller reads.
#[derive(Clone, Debug, PartialEq)]
pub struct EstimatedState {
    /// Time of the readings (s).
    pub time: f64,
    /// Configuration (free-flyer first, as the model's q).
    pub q: DVector<f64>,
    /// Velocity (base twist in the base frame first, as the model's v).
    pub v: DVector<f64>,
    pub com: Vector3<f64>,
    pub com_velocity: Vector3<f64>,
    /// One per [`FootSensor`], in their order.
    pub feet: Vec<FootEstimate>,
    /// ZMP (world x, y) on the plane of the loaded soles; `None` when no foot is loaded.
    pub zmp: Option<Vector2<f64>>,
    /// One per hand sensor ([`KinematicEstimator::with_hands`]), in their order: the wrench
    /// the environment puts on the hand (or its tool) in the given frame, read as the feet's;
    /// hands take no part in the odometry or the ZMP.
    pub hands: Vec<FootEstimate>,
}

/// Sensor readings → estimated state, once per control tick, without allocating.
pub trait Estimator: Send {
    /// Starts from a known state (q, v), as a robot's estimator starts from its pose at
    /// power-on; forgets the feet's anchors.
    fn reset(&mut self, q: &[f64], v: &[f64]) -> Result<(), EstimationError>;
    /// Folds in one tick's readings. On an error the previous estimate is kept.
    fn update(&mut self, readings: &Readings) -> Result<(), EstimationError>;
    /// The current estimate.
    fn state(&self) -> &EstimatedState;
}
