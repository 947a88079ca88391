//! `[estimator]` of a `corps run` scenario: what the controller knows of the robot. By default
//! it sees the sensors (encoders, joint velocities, IMU, ankle F/T, with the scenario's
//! `[noise]`) through leg odometry; `kind = "ground_truth"` gives it the simulator's exact
//! state, for comparison only.
//!
//! ```toml
//! [estimator]
//! kind = "leg_odometry"      # or "ground_truth"
//! contact_on = 30.0          # N: a foot enters contact above this normal force
//! contact_off = 15.0         # N: and leaves it below this one
//! velocity_fusion_time = 0.02 # s: base velocity from the IMU below 1/T, from the legs above
//! settle_share = 0.25        # a landing foot anchors the odometry once it carries this share
//! ```

use crate::error::{bail, Result};
use crate::foot::Foot;
use corps_estimation::{BaseSource, EstimatorSettings, FootSensor, KinematicEstimator};
use corps_loop::Feed;
use corps_model::Model;
use serde::{Deserialize, Serialize};
use std::sync::Arc;

/// What feeds the controller.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum EstimatorKind {
    /// Leg odometry and the IMU on the measured (noisy) readings.
    #[default]
    LegOdometry,
    /// The simulator's exact state and contact wrenches.
    GroundTruth,
}

/// `[estimator]`.
#[derive(Clone, Copy, Debug, PartialEq, Deserialize, Serialize)]
#[serde(default, deny_unknown_fields)]
pub struct EstimatorSection {
    pub kind: EstimatorKind,
    pub contact_on: f64,
    pub contact_off: f64,
    pub velocity_fusion_time: f64,
    pub settle_share: f64,
    pub ft_lowpass: f64,
}

impl Default for EstimatorSection {
    fn default() -> Self {
        let d = EstimatorSettings::default();
        Self {
            kind: EstimatorKind::default(),
            contact_on: d.contact_on,
            contact_off: d.contact_off,
            velocity_fusion_time: d.velocity_fusion_time,
            settle_share: d.settle_share,
            ft_lowpass: d.ft_lowpass,
        }
    }
}

/// What the estimator of `kind` reads.
pub fn feed(kind: EstimatorKind) -> Feed {
    match kind {
        EstimatorKind::LegOdometry => Feed::Measured,
        EstimatorKind::GroundTruth => Feed::Exact,
    }
}

/// The estimator of `section` for the feet `feet` (left, right) standing on the soles
/// `soles`, with the IMU at `imu_frame` (None: the root body); `foot_weight`: the F/T
/// sensors carry the feet's weight, which the estimator removes.
pub fn build(
    section: &EstimatorSection,
    model: &Arc<Model>,
    feet: &[Foot],
    soles: [usize; 2],
    imu_frame: Option<usize>,
    gravity: [f64; 3],
    foot_weight: bool,
) -> Result<KinematicEstimator> {
    if feet.len() != 2 {
        bail!(
            "estimator: corps run needs two feet with F/T sensors in [sensors] feet, found {}",
            feet.len()
        );
    }
    let feet = feet
        .iter()
        .zip(soles)
        .map(|(f, sole)| FootSensor {
            sensor: f.sensor,
            sensor_frame: f.frame,
            sole_frame: sole,
        })
        .collect();
    let imu = match imu_frame {
        Some(f) => f,
        // The root body, as the simulator places an unnamed IMU: the root joint's frame.
        None => model
            .frames
            .iter()
            .position(|f| f.parent_joint == Some(0) && f.kind == corps_model::FrameKind::Joint)
            .unwrap_or(0),
    };
    let settings = EstimatorSettings {
        base: match section.kind {
            EstimatorKind::LegOdometry => BaseSource::LegOdometry,
            EstimatorKind::GroundTruth => BaseSource::Direct,
        },
        contact_on: section.contact_on,
        contact_off: section.contact_off,
        gravity,
        velocity_fusion_time: section.velocity_fusion_time,
        settle_share: section.settle_share,
        calibrate_foot_weight: foot_weight,
        // Ground truth is exact: no filter's lag on its wrenches.
        ft_lowpass: match section.kind {
            EstimatorKind::LegOdometry => section.ft_lowpass,
            EstimatorKind::GroundTruth => 0.0,
        },
    };
    Ok(KinematicEstimator::new(model.clone(), feet, imu, settings)?)
}
