//! The operator's steps (seed 001 §6.1.1): a foot lifted more than `lift` above the ground
//! and moved more than `travel` from where it stood is stepping; back within `land` of the
//! ground, the step ends and is counted (the robot makes as many). Its length (the
//! foot's horizontal travel) and height (its highest point above rest) are normalised from the
//! operator's range into the robot's, Eq 6.6–6.7 — `o = (x_H − x_min,H)/(x_max,H − x_min,H)`,
//! `x_R = o (x_max,R − x_min,R) + x_min,R` — clipped to the robot's range (each clipping
//! counted); the step's direction is kept.

use crate::retarget::StepsSpec;
use nalgebra::Vector3;

/// A finished step of one foot, in the operator's body coordinates at rest.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Step {
    /// 0 left, 1 right.
    pub foot: usize,
    /// When it lifted and landed (s).
    pub start: f64,
    pub end: f64,
    /// The operator's horizontal travel (m) and highest point above rest (m).
    pub human_travel: Vector3<f64>,
    pub human_height: f64,
    /// The robot's step: Eq 6.6–6.7 along the operator's direction.
    pub robot_travel: Vector3<f64>,
    pub robot_height: f64,
    /// Whether length or height went past the robot's range and was clipped to it.
    pub clipped: bool,
}

#[derive(Clone, Copy, Debug)]
enum FootState {
    Standing {
        at: Vector3<f64>,
    },
    Stepping {
        from: Vector3<f64>,
        start: f64,
        top: f64,
    },
}

/// Detects and counts both feet's steps.
#[derive(Clone, Debug)]
pub struct StepDetector {
    spec: StepsSpec,
    /// The feet's height standing (their joint's, not the sole's): the lower foot's at rest,
    /// then the lowest either has been (an operator at rest may have a foot in the air).
    ground: f64,
    state: [FootState; 2],
    /// Each foot's highest point since it last touched the ground (a foot may rise before
    /// it travels far enough to be stepping).
    peak: [f64; 2],
    /// Steps counted so far.
    pub count: usize,
    /// Steps whose length or height was clipped.
    pub clipped: usize,
}

impl StepDetector {
    /// The feet at `feet` (body coordinates, z above the floor) at rest.
    pub fn new(spec: &StepsSpec, feet: [Vector3<f64>; 2]) -> StepDetector {
        StepDetector {
            spec: spec.clone(),
            ground: feet[0].z.min(feet[1].z),
            state: feet.map(|at| FootState::Standing { at }),
            peak: [0.0; 2],
            count: 0,
            clipped: 0,
        }
    }

    /// Whether foot `k` is stepping.
    pub fn stepping(&self, k: usize) -> bool {
        matches!(self.state[k], FootState::Stepping { .. })
    }

    /// Feeds the feet's positions at `t`; the steps that end here are returned, left foot's
    /// then right foot's.
    pub fn update(&mut self, t: f64, feet: [Vector3<f64>; 2]) -> [Option<Step>; 2] {
        let s = &self.spec;
        let mut ended = [None; 2];
        if feet[0].z.is_finite() && feet[1].z.is_finite() {
            self.ground = self.ground.min(feet[0].z).min(feet[1].z);
        }
        for (k, &p) in feet.iter().enumerate() {
            let height = p.z - self.ground;
            match self.state[k] {
                FootState::Standing { at } => {
                    let travel = (p - at).xy().norm();
                    self.peak[k] = if height > s.land {
                        self.peak[k].max(height)
                    } else {
                        0.0
                    };
                    if height > s.lift && travel > s.travel {
                        self.state[k] = FootState::Stepping {
                            from: at,
                            start: t,
                            top: self.peak[k].max(height),
                        };
                    } else if height <= s.land {
                        // Still on the ground: where it stands follows it (a shuffle).
                        self.state[k] = FootState::Standing { at: p };
                    }
                }
                FootState::Stepping { from, start, top } => {
                    let top = top.max(height);
                    if height <= s.land {
                        self.state[k] = FootState::Standing { at: p };
                        self.count += 1;
                        let step = self.normalise(k, start, t, p - from, top);
                        if step.clipped {
                            self.clipped += 1;
                        }
                        ended[k] = Some(step);
                    } else {
                        self.state[k] = FootState::Stepping { from, start, top };
                    }
                }
            }
        }
        ended
    }

    fn normalise(&self, foot: usize, start: f64, end: f64, d: Vector3<f64>, top: f64) -> Step {
        let s = &self.spec;
        let horizontal = Vector3::new(d.x, d.y, 0.0);
        let length = horizontal.norm();
        let (robot_length, c1) = map_range(length, s.human_length, s.robot_length);
        let (robot_height, c2) = map_range(top, s.human_height, s.robot_height);
        let direction = horizontal.try_normalize(1e-9).unwrap_or_else(Vector3::x);
        Step {
            foot,
            start,
            end,
            human_travel: horizontal,
            human_height: top,
            robot_travel: direction * robot_length,
            robot_height,
            clipped: c1 || c2,
        }
    }
}

/// Eq 6.6–6.7 with the result clipped to the robot's range: (value, clipped).
pub fn map_range(x: f64, human: [f64; 2], robot: [f64; 2]) -> (f64, bool) {
    let o = (x - human[0]) / (human[1] - human[0]);
    let r = o * (robot[1] - robot[0]) + robot[0];
    let c = r.clamp(robot[0], robot[1]);
    (c, c != r)
}
