//! `[footsteps]`: steps a teleoperation scenario's robot walks on its own, its upper body held
//! (seed 001 §6.1.2, Fig 6.6's autonomous walking; the walking experiments of S11): a pattern
//! repeated `count` times, each step in the robot's own directions when it begins (x forward,
//! y left), its sole raised `height` at mid-step and turned `turn` degrees about the vertical
//! (counter-clockwise; the robot's heading is the mean of the soles' turns and the sole swings
//! about the stance sole by the heading's change, so that a pattern of turning steps with no
//! travel turns the robot in place, the feet side by side).
//!
//! ```toml
//! [footsteps]
//! count = 10
//! pattern = [
//!     { foot = "left", height = 0.05 },
//!     { foot = "right", height = 0.05 },
//! ]
//! ```

use crate::controller::teleop_walk::{PlannedStep, MAX_PENDING};
use crate::error::{invalid, Result};
use nalgebra::Vector2;
use serde::Deserialize;

/// `[footsteps]`.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct FootstepsSection {
    /// How many steps: the pattern repeated (and cut) to this many.
    pub count: usize,
    pub pattern: Vec<Footstep>,
}

/// Which foot steps.
#[derive(Clone, Copy, Debug, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum StepFoot {
    Left,
    Right,
}

/// One step of the pattern.
#[derive(Clone, Copy, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Footstep {
    pub foot: StepFoot,
    /// The sole's travel (m), in the robot's directions when the step begins.
    #[serde(default)]
    pub forward: f64,
    #[serde(default)]
    pub left: f64,
    /// How high the sole rises (m).
    pub height: f64,
    /// How much the sole turns (degrees, counter-clockwise).
    #[serde(default)]
    pub turn: f64,
}

/// No step of a scenario travels or rises further than this (m).
const MAX_STEP: f64 = 1.0;
/// No step turns its sole more than this (degrees).
const MAX_TURN: f64 = 45.0;

impl FootstepsSection {
    /// The steps to walk, checked.
    pub fn steps(&self) -> Result<Vec<PlannedStep>> {
        if self.pattern.is_empty() {
            return Err(invalid!("footsteps.pattern: needs at least one step"));
        }
        if !(1..=MAX_PENDING).contains(&self.count) {
            return Err(invalid!(
                "footsteps.count: {} steps, must be 1 to {MAX_PENDING}",
                self.count
            ));
        }
        for (k, s) in self.pattern.iter().enumerate() {
            let within = |x: f64| x.is_finite() && x.abs() <= MAX_STEP;
            if !(within(s.forward) && within(s.left) && within(s.height) && s.height >= 0.0) {
                return Err(invalid!(
                    "footsteps.pattern[{k}]: forward, left and height must be finite, at most {MAX_STEP} m, the height ≥ 0"
                ));
            }
            if !(s.turn.is_finite() && s.turn.abs() <= MAX_TURN) {
                return Err(invalid!(
                    "footsteps.pattern[{k}]: turn must be finite, at most {MAX_TURN}° either way"
                ));
            }
        }
        Ok((self.pattern.iter().cycle().take(self.count))
            .map(|s| PlannedStep {
                foot: match s.foot {
                    StepFoot::Left => 0,
                    StepFoot::Right => 1,
                },
                travel: Vector2::new(s.forward, s.left),
                height: s.height,
                turn: s.turn.to_radians(),
            })
            .collect())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_pattern_repeats_to_the_count_and_bad_steps_are_refused() {
        let f: FootstepsSection = toml::from_str(
            "count = 3\npattern = [{ foot = \"left\", forward = 0.1, height = 0.02 }, { foot = \"right\", left = -0.05, height = 0.03 }]",
        )
        .unwrap();
        let s = f.steps().unwrap();
        assert_eq!(s.len(), 3);
        assert_eq!((s[0].foot, s[1].foot, s[2].foot), (0, 1, 0));
        assert_eq!(s[1].travel, Vector2::new(0.0, -0.05));
        for (text, fault) in [
            (
                "count = 0\npattern = [{ foot = \"left\", height = 0.0 }]",
                "footsteps.count",
            ),
            (
                "count = 99\npattern = [{ foot = \"left\", height = 0.0 }]",
                "footsteps.count",
            ),
            ("count = 1\npattern = []", "footsteps.pattern"),
            (
                "count = 1\npattern = [{ foot = \"left\", height = -0.1 }]",
                "pattern[0]",
            ),
            (
                "count = 1\npattern = [{ foot = \"left\", forward = 5.0, height = 0.0 }]",
                "pattern[0]",
            ),
            (
                "count = 1\npattern = [{ foot = \"left\", turn = 90.0, height = 0.0 }]",
                "turn",
            ),
        ] {
            let f: FootstepsSection = toml::from_str(text).unwrap();
            let e = f.steps().unwrap_err().to_string();
            assert!(e.contains(fault), "{text}: {e}");
        }
        assert!(toml::from_str::<FootstepsSection>(
            "count = 1\npattern = [{ foot = \"middle\", height = 0.0 }]"
        )
        .is_err());
    }
}
