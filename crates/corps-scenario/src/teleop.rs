//! Velocity teleoperation: an operator's discrete actions (key presses, joystick buttons)
//! turned into the velocity command of a steered walk ([`crate::velocity_walk`]). Detecting
//! the keys is the caller's; this is the update logic alone, so that a joystick can replace
//! the keyboard (seed 002 §4.14).
//!
//! The update follows the author's keyboard script of seed 002 §4.14 (sot-talos-balance,
//! `keyboard_teleop.py`): each move adds one increment to its component, "faster"/"slower"
//! move every non-zero component one increment away from/towards zero, "stop" zeroes all;
//! with REP-103 signs (+y left, +yaw counter-clockwise), which that script inverts. The
//! script leaves saturation to the pattern generator (0.3 m/s on the speed, seed 002 S5);
//! here each component is also clamped to [`PadSettings`]' limits.

use corps_walk::mpc::VelocityCommand;

/// An operator's action.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PadAction {
    Forward,
    Backward,
    /// Sideways to the robot's left (+y).
    Left,
    /// Sideways to the robot's right (−y).
    Right,
    /// Turn counter-clockwise (+yaw).
    TurnLeft,
    /// Turn clockwise (−yaw).
    TurnRight,
    /// Every non-zero component one increment further from zero.
    Faster,
    /// Every non-zero component one increment closer to zero.
    Slower,
    /// All components to zero: the walk closes with a last step and stands.
    Stop,
}

/// Increments and limits of the velocity command.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PadSettings {
    /// Linear increment (m/s); seed 002 §4.14: 0.1.
    pub linear_step: f64,
    /// Yaw-rate increment (rad/s); seed 002 §4.14: 0.1.
    pub yaw_step: f64,
    /// Bound on |v_x| and |v_y| (m/s): the pattern generator's speed saturation, 0.3 (seed 002
    /// S5), which it also applies to the norm.
    pub max_linear: f64,
    /// Bound on |ω| (rad/s): 0.3, our choice (the documents give none; seed 002 §4.13 walked
    /// stably at 0.01 rad/s only).
    pub max_yaw: f64,
}

impl Default for PadSettings {
    fn default() -> Self {
        Self {
            linear_step: 0.1,
            yaw_step: 0.1,
            max_linear: 0.3,
            max_yaw: 0.3,
        }
    }
}

/// The velocity command an operator builds up action by action.
#[derive(Clone, Debug, Default)]
pub struct VelocityPad {
    settings: PadSettings,
    command: VelocityCommand,
}

impl VelocityPad {
    /// A pad at rest.
    pub fn new(settings: PadSettings) -> Self {
        Self {
            settings,
            command: VelocityCommand::default(),
        }
    }

    /// The command now.
    pub fn command(&self) -> VelocityCommand {
        self.command
    }

    /// Applies `action` and returns the new command.
    pub fn apply(&mut self, action: PadAction) -> VelocityCommand {
        let PadSettings {
            linear_step: l,
            yaw_step: w,
            ..
        } = self.settings;
        let c = &mut self.command;
        match action {
            PadAction::Forward => c.vx += l,
            PadAction::Backward => c.vx -= l,
            PadAction::Left => c.vy += l,
            PadAction::Right => c.vy -= l,
            PadAction::TurnLeft => c.yaw_rate += w,
            PadAction::TurnRight => c.yaw_rate -= w,
            PadAction::Faster | PadAction::Slower => {
                let k = if action == PadAction::Faster {
                    1.0
                } else {
                    -1.0
                };
                for (x, step) in [(&mut c.vx, l), (&mut c.vy, l), (&mut c.yaw_rate, w)] {
                    if *x != 0.0 {
                        *x += k * step * x.signum();
                    }
                }
            }
            PadAction::Stop => *c = VelocityCommand::default(),
        }
        // On the increments' grid (no drift from repeated additions), then within the limits.
        let s = self.settings;
        let snap = |x: f64, step: f64, max: f64| ((x / step).round() * step).clamp(-max, max);
        c.vx = snap(c.vx, l, s.max_linear);
        c.vy = snap(c.vy, l, s.max_linear);
        c.yaw_rate = snap(c.yaw_rate, w, s.max_yaw);
        *c
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn increments_add_up_and_saturate_at_the_limits() {
        let mut pad = VelocityPad::new(PadSettings::default());
        for _ in 0..2 {
            pad.apply(PadAction::Forward);
        }
        pad.apply(PadAction::Left);
        let c = pad.apply(PadAction::TurnRight);
        assert_eq!((c.vx, c.vy, c.yaw_rate), (0.2, 0.1, -0.1));
        // Faster moves every non-zero component away from zero; the linear ones stop at 0.3.
        for _ in 0..3 {
            pad.apply(PadAction::Faster);
        }
        let c = pad.command();
        assert_eq!((c.vx, c.vy, c.yaw_rate), (0.3, 0.3, -0.3));
        let c = pad.apply(PadAction::Slower);
        assert_eq!((c.vx, c.vy, c.yaw_rate), (0.2, 0.2, -0.2));
        // Ten steps back and forth leave no rounding residue.
        for _ in 0..10 {
            pad.apply(PadAction::Backward);
            pad.apply(PadAction::Forward);
        }
        assert_eq!(pad.command().vx, 0.2);
        let c = pad.apply(PadAction::Stop);
        assert_eq!(c, VelocityCommand::default());
        // Slower on a zero command stays zero (no sign to follow).
        assert_eq!(pad.apply(PadAction::Slower), VelocityCommand::default());
    }
}
