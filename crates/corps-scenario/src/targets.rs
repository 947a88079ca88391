//! What the controller is asked at one tick: a CoM reference and one target per foot
//! ([`Targets`]), which every reference motion (`motion`, `walk`) produces.

use corps_control::tasks::{Reference, Se3Reference};
use corps_model::spatial::{Motion, Se3};
use nalgebra::{DVector, Vector3};
use serde::Deserialize;

/// Which foot.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Side {
    Left,
    Right,
}

impl Side {
    /// Index in [`Targets::feet`] (left 0, right 1).
    pub fn index(self) -> usize {
        match self {
            Side::Left => 0,
            Side::Right => 1,
        }
    }

    /// The other foot.
    pub fn other(self) -> Side {
        match self {
            Side::Left => Side::Right,
            Side::Right => Side::Left,
        }
    }
}

/// `Ok` when `x` is positive and finite, else an error naming `motion.<name>`.
pub(crate) fn positive(name: &str, x: f64) -> Result<(), String> {
    if x > 0.0 && x.is_finite() {
        Ok(())
    } else {
        Err(format!("motion.{name} = {x}: must be positive and finite"))
    }
}

/// One foot's target: where it should be, whether the controller should hold it as a contact,
/// and whether the plan has it on the ground.
#[derive(Clone, Debug, PartialEq)]
pub struct FootTarget {
    pub reference: Se3Reference,
    /// The controller's contact: a walk releases it ahead of lift-off so that its force has
    /// ramped to zero by then (`[motion] release`).
    pub in_contact: bool,
    /// The plan's support phase: the foot is planned on the ground (no early release). The
    /// stabilizer's support polygon and wrench distribution, the gait phases of the metrics
    /// and the slip measure follow this, since the foot carries weight until it lifts.
    pub supporting: bool,
}

/// What the controller is asked at one tick.
#[derive(Clone, Debug, PartialEq)]
pub struct Targets {
    /// CoM position, velocity and acceleration (world, 3 each).
    pub com: Reference,
    /// Left and right soles.
    pub feet: [FootTarget; 2],
    /// Waist (base) yaw about the world z axis, relative to its start (walks: the mean of
    /// the feet yaws, seed 002 §4.13).
    pub waist_yaw: f64,
    /// The dynamic filter's CoM correction included in `com` (x, y): position and
    /// acceleration; zero without the filter.
    pub com_correction: [[f64; 2]; 2],
    /// A joint motion added to the posture reference (None: hold the starting posture).
    pub posture: Option<PostureWave>,
    /// A person the robot follows, and where it should be relative to them (co-navigation).
    pub follow: Option<FollowTarget>,
}

/// Where a following robot should be: the person's position and the point the robot's CoM
/// should hold relative to them (world x, y), and the distance from that point beyond which
/// the person is lost.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FollowTarget {
    pub person: [f64; 2],
    pub point: [f64; 2],
    pub lost_beyond: f64,
}

/// A posture reference `q* = q₀ + a s(t)`: per-actuated-joint amplitudes `a` (rad, zero for
/// joints that stay) times one scalar wave `s` with its two derivatives.
#[derive(Clone, Debug, PartialEq)]
pub struct PostureWave {
    pub amplitude: std::sync::Arc<DVector<f64>>,
    /// `[s, ṡ, s̈]`.
    pub wave: [f64; 3],
}

impl Targets {
    /// Standing still: the CoM at `com`, both feet held in contact at `feet` (left, right).
    pub fn at_rest(com: &Vector3<f64>, feet: &[Se3; 2]) -> Targets {
        let foot = |m: Se3| FootTarget {
            reference: Se3Reference {
                placement: m,
                velocity: Motion::zero(),
                acceleration: Motion::zero(),
            },
            in_contact: true,
            supporting: true,
        };
        Targets {
            com: Reference::constant(DVector::from_column_slice(com.as_slice())),
            feet: [foot(feet[0]), foot(feet[1])],
            waist_yaw: 0.0,
            com_correction: [[0.0; 2]; 2],
            posture: None,
            follow: None,
        }
    }

    /// The ZMP of the planned CoM on the ground at height `ground` (LIPM, seed 000 Eq 2.22):
    /// `p = c − (c_z − z_ground)/g · c̈`, world x and y, with `c` the CoM reference before
    /// the dynamic filter's correction: the filter moves the CoM so that the whole body's ZMP
    /// lands on this one (seed 002 §4.5).
    pub fn reference_zmp(&self, ground: f64, gravity: f64) -> [f64; 2] {
        let c = &self.com;
        let h = c.pos[2] - ground;
        let [dc, ddc] = self.com_correction;
        [0, 1].map(|k| (c.pos[k] - dc[k]) - h / gravity * (c.acc[k] - ddc[k]))
    }

    /// Mean height of the supporting feet targets (0 when none is).
    pub fn contact_ground(&self) -> f64 {
        let supporting = self.feet.iter().filter(|f| f.supporting);
        let (z, n) = supporting.fold((0.0, 0.0), |(z, n), f| {
            (z + f.reference.placement.translation.z, n + 1.0)
        });
        if n > 0.0 {
            z / n
        } else {
            0.0
        }
    }
}
