//! `[press]`: a tool held in a hand presses on a block under it, and the block may be pulled
//! away (seed 000 §5.4.1, L6411–L6510: a cylinder in TALOS' left hand pushes on a block
//! along z, 10 N then 30 N, the block removed at 32.3 s).
//!
//! The world: the tool is a cylinder hanging straight down from the hand frame's origin at
//! the starting posture (a massless collision shape of the hand's body, with a frame
//! `<hand>_tool_tip` at its lower end, axes world-aligned at the start); the block is a box
//! centred under the tip whose top is at the tip's starting height, so the tool rests on it.
//! The controller holds the tip as a point contact (normal +z), tracks the force schedule
//! with the force task on that contact, and removes both `loss_delay` after the tip has
//! dropped `loss_drop` below where it touched (the thesis's hand-coded emergency action).

use crate::error::{bail, invalid, Result};
use corps_model::spatial::Se3;
use corps_model::{
    forward_kinematics_placements, CollisionGeometry, Data, Frame, FrameKind, Model, Shape,
};
use corps_robot::Robot;
use corps_sim::Surface;
use nalgebra::{DVector, Matrix3, Vector3};
use serde::Deserialize;
use std::sync::Arc;

/// `[press]` of a scenario.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct PressSection {
    /// Label of the hand holding the tool (the robot description's `[[hands]]`).
    pub hand: String,
    #[serde(default)]
    pub tool: ToolSpec,
    #[serde(default)]
    pub block: BlockSpec,
    /// The force reference along +z on the tool (N): `[t, f]` points (s since the handover,
    /// the first after 0), linearly interpolated from the force measured at the handover,
    /// then held after the last (seed 000 L6406–L6408: the references interpolate "between
    /// the actual and desired force").
    pub force: Vec<[f64; 2]>,
    /// How far below its contact point the tip may drop before the contact counts as lost
    /// and the hand's contact and force task are removed (m).
    #[serde(default = "two_centimetres")]
    pub loss_drop: f64,
    /// How long after the loss is seen the contact and the task are removed (s): the
    /// emergency action's reaction time (seed 000 removes the task at 34.4 s, 2.1 s after the
    /// block; default 0, at once).
    #[serde(default)]
    pub loss_delay: f64,
    /// Cutoff of the first-order low-pass through which the force task reads the hand's F/T
    /// sensor (Hz; ours, the thesis gives none). The task's PI+ asks the QP for
    /// `F* + Kp (F* − F)` and the stiff contact delivers the QP's force within a tick, so
    /// unfiltered the loop is `F_{k+1} ≈ (1 + Kp) F* − Kp F_k`, unstable for Kp > 1 (Table
    /// 5.2's Kp is 10); through a filter of gain `a = 1 − exp(−2π f_c dt)` per tick it
    /// settles without overshoot while `(1 + Kp) a < 1` (10 Hz at 1 kHz: 0.67).
    #[serde(default = "ten_hertz")]
    pub force_lowpass_hz: f64,
}

fn ten_hertz() -> f64 {
    10.0
}

/// `[press.tool]`: the cylinder (ours: the thesis gives no size).
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields, default)]
pub struct ToolSpec {
    pub radius: f64,
    pub length: f64,
}

impl Default for ToolSpec {
    fn default() -> Self {
        Self {
            radius: 0.02,
            length: 0.15,
        }
    }
}

/// `[press.block]`: its horizontal size and when it is pulled away.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields, default)]
pub struct BlockSpec {
    /// Side lengths along x and y (m).
    pub size: [f64; 2],
    /// When the block is taken out of the world (s since the handover); absent: never.
    pub removed_at: Option<f64>,
}

impl Default for BlockSpec {
    fn default() -> Self {
        Self {
            size: [0.2, 0.2],
            removed_at: None,
        }
    }
}

fn two_centimetres() -> f64 {
    0.02
}

impl PressSection {
    /// Checks the values; errors name the key.
    pub fn check(&self) -> Result<(), String> {
        let positive = |name: &str, x: f64| {
            if x > 0.0 && x.is_finite() {
                Ok(())
            } else {
                Err(format!(
                    "press.{name}: must be positive and finite, got {x}"
                ))
            }
        };
        positive("tool.radius", self.tool.radius)?;
        positive("tool.length", self.tool.length)?;
        positive("block.size[0]", self.block.size[0])?;
        positive("block.size[1]", self.block.size[1])?;
        positive("loss_drop", self.loss_drop)?;
        positive("force_lowpass_hz", self.force_lowpass_hz)?;
        if !(self.loss_delay >= 0.0 && self.loss_delay.is_finite()) {
            return Err(format!(
                "press.loss_delay: must be a time ≥ 0 s, got {}",
                self.loss_delay
            ));
        }
        if let Some(t) = self.block.removed_at {
            if !(t >= 0.0 && t.is_finite()) {
                return Err(format!(
                    "press.block.removed_at: must be a time ≥ 0 s, got {t}"
                ));
            }
        }
        if self.force.is_empty() {
            return Err("press.force: give at least one [t, f] point".into());
        }
        for (k, [t, f]) in self.force.iter().enumerate() {
            if !(t.is_finite() && f.is_finite()) {
                return Err(format!("press.force[{k}]: must be finite, got [{t}, {f}]"));
            }
            if k == 0 && *t <= 0.0 {
                return Err(format!(
                    "press.force[0]: the first point's time must be after the handover (0 s), got {t}"
                ));
            }
            if k > 0 && *t <= self.force[k - 1][0] {
                return Err(format!(
                    "press.force[{k}]: times must increase, {t} s follows {} s",
                    self.force[k - 1][0]
                ));
            }
        }
        Ok(())
    }

    /// The force reference at `t` (s since the handover) and its rate (N, N/s), starting
    /// from `f0` (N) at the handover.
    pub fn force_at(&self, t: f64, f0: f64) -> (f64, f64) {
        if let Some(&[t1, f1]) = self.force.first() {
            if t < t1 {
                return force_at(&[[0.0, f0], [t1, f1]], t);
            }
        }
        force_at(&self.force, t)
    }
}

/// Piecewise-linear `points` at `t`, held at both ends: value and slope.
pub fn force_at(points: &[[f64; 2]], t: f64) -> (f64, f64) {
    let Some(first) = points.first() else {
        return (0.0, 0.0);
    };
    if t <= first[0] {
        return (first[1], 0.0);
    }
    for w in points.windows(2) {
        let ([t0, f0], [t1, f1]) = (w[0], w[1]);
        if t <= t1 {
            let slope = (f1 - f0) / (t1 - t0);
            return (f0 + slope * (t - t0), slope);
        }
    }
    (points[points.len() - 1][1], 0.0)
}

/// What `[press]` added to the world.
#[derive(Clone, Debug)]
pub struct PressWorld {
    /// Frame at the tool's tip (world-aligned at the start).
    pub tip_frame: usize,
    /// Index of the F/T sensor above the hand among the run's sensors, and its frame.
    pub hand_sensor: usize,
    pub sensor_frame: usize,
    /// The block's index in the terrain.
    pub block_surface: usize,
    pub section: PressSection,
}

/// Adds the tool (collision cylinder and tip frame) of `section` to the robot's model at the
/// starting configuration `q0`, and returns the block (friction coefficient `mu`) to add to
/// the terrain, the tip frame and the hand's sensor. The robot's model is replaced by the
/// equipped one.
pub fn equip(
    robot: &mut Robot,
    section: &PressSection,
    q0: &DVector<f64>,
    mu: f64,
) -> Result<(Surface, usize, usize)> {
    section.check().map_err(|e| invalid!("{e}"))?;
    let Some(hand) = robot.hands.iter().find(|h| h.label == section.hand) else {
        let labels: Vec<&str> = robot.hands.iter().map(|h| h.label.as_str()).collect();
        bail!(
            "press.hand: robot '{}' has no hand '{}' (hands: {})",
            robot.name,
            section.hand,
            if labels.is_empty() {
                "none".into()
            } else {
                labels.join(", ")
            }
        );
    };
    let Some(hand_sensor) = hand.force_torque else {
        bail!(
            "press.hand: hand '{}' has no force/torque sensor in the robot description",
            hand.label
        );
    };
    let model = &robot.model;
    let hand_frame = &model.frames[hand.frame];
    let Some(joint) = hand_frame.parent_joint else {
        bail!(
            "press.hand: the frame of hand '{}' is fixed to the world",
            hand.label
        );
    };
    let mut data = Data::new(model);
    forward_kinematics_placements(model, &mut data, q0.as_slice())?;
    let o_m_joint = data.o_m_i[joint];
    let origin = (o_m_joint * hand_frame.placement).translation;
    let length = section.tool.length;
    let down = Vector3::new(0.0, 0.0, -1.0);
    // In the joint frame: world-aligned axes, the cylinder's centre and its tip.
    let aligned = o_m_joint.rotation.transpose();
    let in_joint = |world: Vector3<f64>| o_m_joint.act_inv_point(&world);
    let tip_world = origin + down * length;
    let mut equipped: Model = (**model).clone();
    equipped.collisions.push(CollisionGeometry {
        link: format!("{}_tool", hand.label),
        parent_joint: Some(joint),
        placement: Se3::new(aligned, in_joint(origin + down * (length / 2.0))),
        shape: Shape::Cylinder {
            radius: section.tool.radius,
            length,
        },
    });
    let tip_name = format!("{}_tool_tip", hand.label);
    if model.frame_id(&tip_name).is_ok() {
        bail!("press: the model already has a frame '{tip_name}'");
    }
    equipped.frames.push(Frame {
        name: tip_name,
        kind: FrameKind::FixedJoint,
        parent_joint: Some(joint),
        placement: Se3::new(aligned, in_joint(tip_world)),
    });
    let tip_frame = equipped.frames.len() - 1;
    robot.model = Arc::new(equipped);
    // The block: from 5 cm below the ground up to the tip.
    let [sx, sy] = section.block.size;
    let bottom = -0.05;
    let half_height = (tip_world.z - bottom) / 2.0;
    if half_height <= 0.05 {
        bail!(
            "press: the tool's tip starts {:.3} m above the ground: no room for a block",
            tip_world.z
        );
    }
    let block = Surface::Box {
        pose: Se3::new(
            Matrix3::identity(),
            Vector3::new(tip_world.x, tip_world.y, bottom + half_height),
        ),
        half_extents: Vector3::new(sx / 2.0, sy / 2.0, half_height),
        mu,
    };
    Ok((block, tip_frame, hand_sensor))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_force_schedule_interpolates_and_holds() {
        let pts = [[1.0, 0.0], [6.0, 10.0], [15.0, 10.0], [20.0, 30.0]];
        assert_eq!(force_at(&pts, 0.0), (0.0, 0.0));
        assert_eq!(force_at(&pts, 3.5), (5.0, 2.0));
        assert_eq!(force_at(&pts, 10.0), (10.0, 0.0));
        assert_eq!(force_at(&pts, 17.5), (20.0, 4.0));
        assert_eq!(force_at(&pts, 40.0), (30.0, 0.0));
        let s = PressSection {
            hand: "left".into(),
            tool: ToolSpec::default(),
            block: BlockSpec::default(),
            force: vec![[4.0, 10.0], [8.0, 30.0]],
            loss_drop: 0.02,
            loss_delay: 0.0,
            force_lowpass_hz: 10.0,
        };
        // From the measured 42 N at the handover down to 10 N at 4 s.
        assert_eq!(s.force_at(0.0, 42.0).0, 42.0);
        assert_eq!(s.force_at(2.0, 42.0), (26.0, -8.0));
        assert_eq!(s.force_at(6.0, 42.0), (20.0, 5.0));
    }

    #[test]
    fn bad_schedules_are_refused_with_the_key() {
        let mut s = PressSection {
            hand: "left".into(),
            tool: ToolSpec::default(),
            block: BlockSpec::default(),
            force: vec![[1.0, 0.0], [1.0, 10.0]],
            loss_drop: 0.02,
            loss_delay: 0.0,
            force_lowpass_hz: 10.0,
        };
        assert!(s.check().unwrap_err().contains("press.force[1]"));
        s.force = vec![];
        assert!(s.check().unwrap_err().contains("press.force"));
        s.force = vec![[0.0, 1.0]];
        assert!(s.check().unwrap_err().contains("after the handover"));
        s.force = vec![[1.0, 1.0]];
        s.tool.radius = -1.0;
        assert!(s.check().unwrap_err().contains("press.tool.radius"));
        s.tool.radius = 0.02;
        s.block.removed_at = Some(f64::NAN);
        assert!(s.check().unwrap_err().contains("removed_at"));
    }
}
