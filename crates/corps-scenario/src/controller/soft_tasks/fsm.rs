//! A stepping state machine read from data (seed 001 §2.7): each state names its CoM and
//! swing-foot set-points, whether the swing foot is a contact, when it may leave (all its
//! conditions hold after `min_time`, or `max_time` has passed) and the state that follows.
//! FSM #2 (App. B.1, Table B.2) is five such states, `config/icub/soft_tasks.toml`:
//!
//! | state | CoM | swing foot | swing contact | leaves when |
//! |---|---|---|---|---|
//! | two-feet balancing | initial | initial | kept | after t_min |
//! | CoM over the stance foot | over stance + δ_CoM | initial | kept | CoM error < e_CoM after t_min, or t_max |
//! | stance-foot balancing | over stance | initial + δ_swing | released | feet error < e_feet, or t_max |
//! | prepare touch-down | over stance | initial | released | feet error < e_feet after t_min, or t_max |
//! | two-feet balancing, swap | initial | initial | on touch (F_z > F_zmin) | CoM error < e_CoM after t_min, or t_max |
//!
//! FSM #1 (App. A.1, Tables A.3–A.7, `config/icub/soft_tasks_fsm1.toml`) is eleven such
//! states whose entries also give their own gains ([`StateGains`]), CoM and swing offsets and
//! postural set-point, and leave on the swing foot's unloading (f_liftoff) and on the legs'
//! joint errors (e_leg) besides the CoM and feet errors.
//!
//! Errors are distances to the state's set-points (not to the smoothed references), the
//! feet error the larger of the two feet's. Set-points are taken, when a state is entered,
//! relative to where the stance foot is then (the handover's offsets from it), so that an
//! estimate that drifts between steps moves them with the feet.

use crate::error::{bail, Result};
use crate::targets::Side;
use nalgebra::Vector3;
use serde::Deserialize;
use std::collections::{BTreeSet, HashMap};

/// Where a state puts the CoM.
#[derive(Clone, Copy, Debug, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum ComSetpoint {
    /// Where it was at the handover.
    Initial,
    /// Its lateral position on the stance foot's, x and height kept, plus `com_offset`.
    OverStance,
    /// The stance sole's x and y, the initial height, plus the offset (FSM #1: "CoM xy =
    /// left-foot origin + δ_CoM", seed 001 App. A.1).
    OnStance,
}

/// Where a state puts the swing foot.
#[derive(Clone, Copy, Debug, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum SwingSetpoint {
    /// Its placement at the handover.
    Initial,
    /// Its placement at the handover moved by `swing_offset`.
    Raised,
}

/// Whether the swing foot is a contact in a state.
#[derive(Clone, Copy, Debug, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum SwingContact {
    Kept,
    Released,
    /// Becomes a contact once its measured normal force exceeds `touchdown_force`; the state
    /// is not left before, whatever its conditions and `max_time`.
    OnTouch,
}

/// Conditions to leave a state; all given ones must hold (none: only `min_time`).
#[derive(Clone, Copy, Debug, Default, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Conditions {
    /// CoM distance to its set-point below this (m).
    pub com_error_below: Option<f64>,
    /// Both feet's distances to their set-points below this (m).
    pub feet_error_below: Option<f64>,
    /// The swing foot's measured normal force below this (N; FSM #1's f_liftoff).
    pub swing_force_below: Option<f64>,
    /// Every joint of both legs within this of the state's postural set-point (degrees;
    /// FSM #1's e_leg and e_legc).
    pub legs_error_below_deg: Option<f64>,
}

/// A state's own proportional gains (seed 001 Tables A.4–A.5; D = 2√P); what a state does
/// not give is the file's.
#[derive(Clone, Debug, Default, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct StateGains {
    /// CoM P per axis.
    pub com: Option<[f64; 3]>,
    /// The stance foot's P, [linear, angular].
    pub stance: Option<[f64; 2]>,
    /// The swing foot's P, [linear, angular], in contact or not.
    pub swing: Option<[f64; 2]>,
    /// The orientation task's P (K0).
    pub orientation: Option<f64>,
    /// Posture P per joint group (joint-name prefix → one P per joint, as `posture.groups`).
    #[serde(default)]
    pub posture: std::collections::BTreeMap<String, Vec<f64>>,
}

/// One state.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct StateConfig {
    pub name: String,
    pub com: ComSetpoint,
    pub swing: SwingSetpoint,
    pub swing_contact: SwingContact,
    /// The next state.
    pub next: String,
    /// Conditions count only after this time in the state (s).
    #[serde(default)]
    pub min_time: f64,
    /// Leave after this time in the state whatever the conditions (s).
    pub max_time: Option<f64>,
    #[serde(default)]
    pub when: Conditions,
    /// Stance and swing feet exchange roles when the state is left.
    #[serde(default)]
    pub swap_feet_on_exit: bool,
    /// δ_CoM of this state, replacing the machine's `com_offset`.
    pub com_offset: Option<[f64; 3]>,
    /// δ_swingfoot of this state, replacing the machine's `swing_offset`.
    pub swing_offset: Option<[f64; 3]>,
    /// The postural set-point of this state: joint → degrees; the other joints keep the
    /// initial posture.
    #[serde(default)]
    pub posture_deg: std::collections::BTreeMap<String, f64>,
    #[serde(default)]
    pub gains: StateGains,
}

/// The machine (`[fsm]`).
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct FsmConfig {
    /// The foot that stands first.
    pub first_stance: Side,
    /// Duration of the minimum-jerk move towards each new set-point (s).
    pub t_smooth: f64,
    /// δ_CoM: added to the CoM set-point over the stance foot (m, world).
    pub com_offset: [f64; 3],
    /// δ_swingfoot: the raised swing foot's offset from its initial position (m, world).
    pub swing_offset: [f64; 3],
    /// F_zmin: the normal force at which a landing swing foot becomes a contact (N).
    pub touchdown_force: f64,
    /// Each state's leg joints take, as postural set-point, the inverse kinematics of its CoM,
    /// feet and orientation set-points ([`super::stance_ik`]) instead of `posture_deg`.
    #[serde(default)]
    pub legs_from_kinematics: bool,
    /// The states; the first is the initial one.
    pub states: Vec<StateConfig>,
}

fn positive_or_zero(what: &str, x: f64) -> Result<()> {
    if !(x >= 0.0 && x.is_finite()) {
        bail!("{what} = {x}: must be finite and not negative");
    }
    Ok(())
}

impl FsmConfig {
    /// Checks the machine: unique names, known `next` states, every state reachable from the
    /// first, thresholds positive, times not negative, `max_time ≥ min_time`.
    pub fn check(&self) -> Result<()> {
        if self.states.is_empty() {
            bail!("fsm.states: the state machine has no state");
        }
        positive_or_zero("fsm.t_smooth", self.t_smooth)?;
        positive_or_zero("fsm.touchdown_force", self.touchdown_force)?;
        for (k, x) in self.com_offset.iter().chain(&self.swing_offset).enumerate() {
            if !x.is_finite() {
                bail!("fsm offsets: entry {k} is {x}");
            }
        }
        for s in &self.states {
            let offsets = s.com_offset.iter().chain(&s.swing_offset).flatten();
            let degrees = s.posture_deg.values();
            if let Some(x) = offsets.chain(degrees).find(|x| !x.is_finite()) {
                bail!("fsm state '{}': an offset or posture angle is {x}", s.name);
            }
            let g = &s.gains;
            let gains = (g.com.iter().flatten())
                .chain(g.stance.iter().flatten())
                .chain(g.swing.iter().flatten())
                .chain(&g.orientation)
                .chain(g.posture.values().flatten());
            if let Some(x) = gains.into_iter().find(|x| !(**x >= 0.0 && x.is_finite())) {
                bail!(
                    "fsm state '{}': gain {x} must be finite and not negative",
                    s.name
                );
            }
        }
        let mut index = HashMap::new();
        for (k, s) in self.states.iter().enumerate() {
            if index.insert(s.name.as_str(), k).is_some() {
                bail!("fsm.states: two states are named '{}'", s.name);
            }
        }
        for s in &self.states {
            let at = format!("fsm state '{}'", s.name);
            if !index.contains_key(s.next.as_str()) {
                bail!("{at}: next state '{}' is not defined", s.next);
            }
            positive_or_zero(&format!("{at}: min_time"), s.min_time)?;
            if let Some(max) = s.max_time {
                if !(max.is_finite() && max >= s.min_time) {
                    bail!(
                        "{at}: max_time = {max} must be finite and at least min_time = {}",
                        s.min_time
                    );
                }
            }
            for (name, x) in [
                ("com_error_below", s.when.com_error_below),
                ("feet_error_below", s.when.feet_error_below),
                ("swing_force_below", s.when.swing_force_below),
                ("legs_error_below_deg", s.when.legs_error_below_deg),
            ] {
                if let Some(x) = x {
                    if !(x > 0.0 && x.is_finite()) {
                        bail!("{at}: when.{name} = {x}: a threshold must be positive");
                    }
                }
            }
        }
        let mut seen = BTreeSet::new();
        let mut k = 0;
        while seen.insert(k) {
            k = index[self.states[k].next.as_str()];
        }
        if let Some(s) = (0..self.states.len()).find(|k| !seen.contains(k)) {
            bail!(
                "fsm state '{}' is never reached from the first state '{}'",
                self.states[s].name,
                self.states[0].name
            );
        }
        Ok(())
    }
}

/// What the machine reads each tick (world, the estimator's).
pub struct FsmInput {
    pub t: f64,
    pub com: Vector3<f64>,
    /// Sole positions, left then right.
    pub feet: [Vector3<f64>; 2],
    /// Measured normal forces on the soles, left then right (N).
    pub normal_forces: [f64; 2],
    /// The largest distance of a leg joint to the current state's postural set-point (rad),
    /// left leg then right.
    pub leg_errors: [f64; 2],
}

/// The running machine.
pub struct StateMachine {
    config: FsmConfig,
    next: Vec<usize>,
    current: usize,
    entered_at: f64,
    stance: Side,
    swing_in_contact: bool,
    com0: Vector3<f64>,
    feet0: [Vector3<f64>; 2],
    com_setpoint: Vector3<f64>,
    swing_setpoint: Vector3<f64>,
    /// The feet where the last input put them.
    feet: [Vector3<f64>; 2],
    /// The stance foot's position when the state was entered.
    stance_at_entry: Vector3<f64>,
    /// Completed steps (feet swaps).
    pub steps: usize,
}

impl StateMachine {
    /// Starts in the first state at `t`, from the handover's CoM and soles.
    pub fn new(config: FsmConfig, t: f64, com0: Vector3<f64>, feet0: [Vector3<f64>; 2]) -> Self {
        let next = (config.states.iter())
            .map(|s| {
                (config.states.iter())
                    .position(|o| o.name == s.next)
                    .unwrap_or(0)
            })
            .collect();
        let stance = config.first_stance;
        let mut m = Self {
            config,
            next,
            current: 0,
            entered_at: t,
            stance,
            swing_in_contact: true,
            com0,
            feet0,
            com_setpoint: com0,
            swing_setpoint: Vector3::zeros(),
            feet: feet0,
            stance_at_entry: feet0[stance.index()],
            steps: 0,
        };
        m.enter(0, t);
        m
    }

    fn state(&self) -> &StateConfig {
        &self.config.states[self.current]
    }

    /// The stance foot.
    pub fn stance(&self) -> Side {
        self.stance
    }

    /// The swing foot.
    pub fn swing(&self) -> Side {
        self.stance.other()
    }

    /// Whether the swing foot is a contact now.
    pub fn swing_in_contact(&self) -> bool {
        self.swing_in_contact
    }

    /// Index of the current state in the file's order.
    pub fn current(&self) -> usize {
        self.current
    }

    pub fn current_name(&self) -> &str {
        &self.state().name
    }

    /// The CoM set-point of the current state.
    pub fn com_setpoint(&self) -> Vector3<f64> {
        self.com_setpoint
    }

    /// The set-point of foot `side` (the stance foot's is where it stood when the state was
    /// entered).
    pub fn foot_setpoint(&self, side: Side) -> Vector3<f64> {
        if side == self.swing() {
            self.swing_setpoint
        } else {
            self.stance_at_entry
        }
    }

    /// The smoothing time of set-point changes.
    pub fn t_smooth(&self) -> f64 {
        self.config.t_smooth
    }

    /// The CoM and swing-foot set-points of state `k` with `stance` standing at `stance_at`,
    /// the feet having moved by `moved` since the handover.
    fn set_points(
        &self,
        k: usize,
        stance: Side,
        stance_at: Vector3<f64>,
        moved: Vector3<f64>,
    ) -> (Vector3<f64>, Vector3<f64>) {
        let s = &self.config.states[k];
        let swing = stance.other();
        let com0 = self.com0 + moved;
        let com_offset = Vector3::from(s.com_offset.unwrap_or(self.config.com_offset));
        let swing_offset = Vector3::from(s.swing_offset.unwrap_or(self.config.swing_offset));
        let com = match s.com {
            ComSetpoint::Initial => com0,
            ComSetpoint::OverStance => Vector3::new(com0.x, stance_at.y, com0.z) + com_offset,
            ComSetpoint::OnStance => Vector3::new(stance_at.x, stance_at.y, com0.z) + com_offset,
        };
        let foot = match s.swing {
            SwingSetpoint::Initial => self.feet0[swing.index()] + moved,
            SwingSetpoint::Raised => self.feet0[swing.index()] + moved + swing_offset,
        };
        (com, foot)
    }

    /// The CoM and swing-foot set-points state `k` would take with `stance` standing, the
    /// feet where they were at the handover.
    pub fn planned(&self, k: usize, stance: Side) -> (Vector3<f64>, Vector3<f64>) {
        let at = self.feet0[stance.index()];
        self.set_points(k, stance, at, Vector3::zeros())
    }

    /// The feet's placements at the handover, left then right.
    pub fn initial_feet(&self) -> [Vector3<f64>; 2] {
        self.feet0
    }

    fn enter(&mut self, k: usize, t: f64) {
        self.current = k;
        self.entered_at = t;
        let s = &self.config.states[k];
        let stance = self.feet[self.stance.index()];
        // How far the stance foot is from where it was at the handover.
        let moved = stance - self.feet0[self.stance.index()];
        self.stance_at_entry = stance;
        (self.com_setpoint, self.swing_setpoint) = self.set_points(k, self.stance, stance, moved);
        self.swing_in_contact = match s.swing_contact {
            SwingContact::Kept => true,
            SwingContact::Released => false,
            // Stays as it was until the foot touches.
            SwingContact::OnTouch => self.swing_in_contact,
        };
    }

    /// Advances the machine one tick; returns whether the state or the contacts changed.
    pub fn update(&mut self, input: &FsmInput) -> bool {
        let mut changed = false;
        self.feet = input.feet;
        let s = &self.config.states[self.current];
        let (min_time, max_time, when, swap) =
            (s.min_time, s.max_time, s.when, s.swap_feet_on_exit);
        let on_touch = s.swing_contact == SwingContact::OnTouch;
        if on_touch
            && !self.swing_in_contact
            && input.normal_forces[self.swing().index()] > self.config.touchdown_force
        {
            self.swing_in_contact = true;
            changed = true;
        }
        let elapsed = input.t - self.entered_at;
        let com_ok =
            (when.com_error_below).is_none_or(|e| (input.com - self.com_setpoint).norm() < e);
        let feet_error = [Side::Left, Side::Right]
            .map(|side| (input.feet[side.index()] - self.foot_setpoint(side)).norm());
        let feet_ok = (when.feet_error_below).is_none_or(|e| feet_error.iter().all(|f| *f < e));
        let swing_force = input.normal_forces[self.swing().index()];
        let unloaded = (when.swing_force_below).is_none_or(|f| swing_force < f);
        let legs_ok = (when.legs_error_below_deg)
            .is_none_or(|e| input.leg_errors.iter().all(|x| x.to_degrees() < e));
        let timed_out = max_time.is_some_and(|m| elapsed >= m);
        // An on-touch state waits for the touch, whatever its conditions and times: leaving
        // it (and swapping the feet) with the swing foot in the air would stand on it.
        let touched = !on_touch || self.swing_in_contact;
        let conditions = com_ok && feet_ok && unloaded && legs_ok;
        if touched && ((elapsed >= min_time && conditions) || timed_out) {
            if swap {
                self.stance = self.swing();
                self.steps += 1;
            }
            let next = self.next[self.current];
            self.enter(next, input.t);
            changed = true;
        }
        changed
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const FSM2: &str = r#"
first_stance = "left"
t_smooth = 2.0
com_offset = [0.0, 0.0, 0.0]
swing_offset = [-0.025, 0.0, 0.025]
touchdown_force = 0.1

[[states]]
name = "balancing"
com = "initial"
swing = "initial"
swing_contact = "kept"
next = "com_to_stance"
min_time = 2.0

[[states]]
name = "com_to_stance"
com = "over_stance"
swing = "initial"
swing_contact = "kept"
next = "stance_balancing"
min_time = 2.0
max_time = 6.0
when = { com_error_below = 0.025 }

[[states]]
name = "stance_balancing"
com = "over_stance"
swing = "raised"
swing_contact = "released"
next = "prepare_touchdown"
max_time = 6.0
when = { feet_error_below = 0.025 }

[[states]]
name = "prepare_touchdown"
com = "over_stance"
swing = "initial"
swing_contact = "released"
next = "two_feet"
min_time = 2.0
max_time = 6.0
when = { feet_error_below = 0.025 }

[[states]]
name = "two_feet"
com = "initial"
swing = "initial"
swing_contact = "on_touch"
next = "com_to_stance"
min_time = 2.0
max_time = 6.0
when = { com_error_below = 0.025 }
swap_feet_on_exit = true
"#;

    fn fsm2() -> FsmConfig {
        toml::from_str(FSM2).unwrap()
    }

    fn input(t: f64, m: &StateMachine, fz: [f64; 2]) -> FsmInput {
        // A robot that follows its set-points exactly.
        FsmInput {
            t,
            com: m.com_setpoint(),
            feet: [Side::Left, Side::Right].map(|s| m.foot_setpoint(s)),
            normal_forces: fz,
            leg_errors: [0.0; 2],
        }
    }

    #[test]
    fn fsm2_steps_through_its_states_and_swaps_the_feet() {
        let c = fsm2();
        c.check().unwrap();
        let feet0 = [Vector3::new(0.0, 0.07, 0.0), Vector3::new(0.0, -0.07, 0.0)];
        let mut m = StateMachine::new(c, 0.0, Vector3::new(0.01, 0.0, 0.5), feet0);
        let mut visited = vec![m.current_name().to_string()];
        let (mut t, dt) = (0.0, 0.01);
        let mut saw_released = false;
        while t < 40.0 {
            t += dt;
            // The landing foot touches 0.5 s into the last state.
            let fz = if m.current_name() == "two_feet" {
                [5.0, 5.0]
            } else {
                [0.0, 0.0]
            };
            let i = input(t, &m, fz);
            if m.update(&i) && visited.last().map(String::as_str) != Some(m.current_name()) {
                visited.push(m.current_name().to_string());
            }
            saw_released |= !m.swing_in_contact();
            if m.current_name() == "com_to_stance" {
                let y_stance = feet0[m.stance().index()].y;
                assert_eq!(m.com_setpoint().y, y_stance);
            }
        }
        assert!(saw_released);
        assert_eq!(
            &visited[..6],
            [
                "balancing",
                "com_to_stance",
                "stance_balancing",
                "prepare_touchdown",
                "two_feet",
                "com_to_stance"
            ]
        );
        assert!(m.steps >= 2, "steps {}", m.steps);
    }

    #[test]
    fn a_machine_that_cannot_leave_times_out() {
        let mut c = fsm2();
        c.states[1].when.com_error_below = Some(1e-9);
        let mut m = StateMachine::new(c, 0.0, Vector3::zeros(), [Vector3::y(), -Vector3::y()]);
        let far = |t| FsmInput {
            t,
            com: Vector3::new(1.0, 1.0, 1.0),
            feet: [Vector3::y(), -Vector3::y()],
            normal_forces: [0.0; 2],
            leg_errors: [0.0; 2],
        };
        m.update(&far(2.0));
        assert_eq!(m.current_name(), "com_to_stance");
        m.update(&far(7.9));
        assert_eq!(m.current_name(), "com_to_stance");
        m.update(&far(8.0));
        assert_eq!(m.current_name(), "stance_balancing");
    }

    #[test]
    fn an_on_touch_state_waits_for_the_touch_past_its_maximum_time() {
        let feet0 = [Vector3::new(0.0, 0.07, 0.0), Vector3::new(0.0, -0.07, 0.0)];
        let mut m = StateMachine::new(fsm2(), 0.0, Vector3::zeros(), feet0);
        let (mut t, dt) = (0.0, 0.01);
        // Follow the set-points exactly, never touching, up to the last state.
        while m.current_name() != "two_feet" {
            t += dt;
            m.update(&input(t, &m, [0.0, 0.0]));
            assert!(t < 30.0);
        }
        let entered = t;
        let swing = m.swing();
        while t < entered + 10.0 {
            t += dt;
            m.update(&input(t, &m, [0.0, 0.0]));
        }
        assert_eq!(m.current_name(), "two_feet", "left without a touch");
        assert_eq!(m.steps, 0);
        let mut fz = [0.0, 0.0];
        fz[swing.index()] = 1.0;
        t += dt;
        m.update(&input(t, &m, fz));
        t += dt;
        m.update(&input(t, &m, fz));
        assert_eq!(m.current_name(), "com_to_stance");
        assert_eq!(m.steps, 1);
    }

    /// FSM #1's conditions: the swing foot unloaded below f_liftoff and the legs within e_leg
    /// of the state's set-point; a state's own δ_CoM on the stance sole.
    #[test]
    fn fsm1_conditions_hold_a_state_until_the_foot_unloads_and_the_legs_settle() {
        let mut c = fsm2();
        c.states[1].com = ComSetpoint::OnStance;
        c.states[1].com_offset = Some([0.01, 0.01, 0.0]);
        c.states[1].min_time = 0.0;
        c.states[1].when = Conditions {
            com_error_below: Some(0.01),
            swing_force_below: Some(60.0),
            legs_error_below_deg: Some(5.0),
            ..Default::default()
        };
        c.check().unwrap();
        let feet0 = [Vector3::new(0.02, 0.07, 0.0), Vector3::new(0.0, -0.07, 0.0)];
        let mut m = StateMachine::new(c, 0.0, Vector3::new(0.0, 0.0, 0.5), feet0);
        m.update(&input(2.0, &m, [140.0, 140.0]));
        assert_eq!(m.current_name(), "com_to_stance");
        assert_eq!(m.com_setpoint(), Vector3::new(0.03, 0.08, 0.5));
        // CoM on its set-point, but the right foot still carries 100 N.
        m.update(&input(2.1, &m, [180.0, 100.0]));
        assert_eq!(m.current_name(), "com_to_stance");
        // Unloaded, but a leg joint 6° off.
        let mut i = input(2.2, &m, [250.0, 30.0]);
        i.leg_errors = [0.0, 6f64.to_radians()];
        m.update(&i);
        assert_eq!(m.current_name(), "com_to_stance");
        i.leg_errors = [0.0, 4f64.to_radians()];
        i.t = 2.3;
        m.update(&i);
        assert_eq!(m.current_name(), "stance_balancing");
    }

    #[test]
    fn bad_machines_are_refused_with_the_state_named() {
        let mut c = fsm2();
        c.states[4].next = "nowhere".into();
        assert!(c
            .check()
            .unwrap_err()
            .to_string()
            .contains("'nowhere' is not defined"));
        let mut c = fsm2();
        c.states[3].next = "balancing".into();
        // two_feet is now unreachable.
        assert!(c
            .check()
            .unwrap_err()
            .to_string()
            .contains("'two_feet' is never reached"));
        let mut c = fsm2();
        c.states[1].when.com_error_below = Some(-0.025);
        assert!(c
            .check()
            .unwrap_err()
            .to_string()
            .contains("must be positive"));
        let mut c = fsm2();
        c.states[2].max_time = Some(1.0);
        c.states[2].min_time = 2.0;
        assert!(c.check().unwrap_err().to_string().contains("max_time"));
        let mut c = fsm2();
        c.states[2].name = "two_feet".into();
        assert!(c.check().unwrap_err().to_string().contains("two states"));
        // FSM #1's additions: a force threshold and a state's gain.
        for (set, expected) in [
            (
                0,
                "when.swing_force_below = -1: a threshold must be positive",
            ),
            (
                1,
                "fsm state 'stance_balancing': gain -5 must be finite and not negative",
            ),
        ] {
            let mut c = fsm2();
            match set {
                0 => c.states[1].when.swing_force_below = Some(-1.0),
                _ => c.states[2].gains.orientation = Some(-5.0),
            }
            let err = c.check().unwrap_err().to_string();
            assert!(err.contains(expected), "{err}");
        }
    }
}
