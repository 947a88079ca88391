//! What a state of the machine sets beside its set-points (seed 001 App. A.1): its gains
//! (Tables A.4–A.5) and its postural set-point (Table A.7). Every switch is smoothed: the
//! gains blend from their values at the switch to the new state's by the minimum-jerk
//! fraction over t_smooth, the postural reference follows a quintic
//! ([`super::posture_law::PostureLaw::go_to`]). With `fsm.legs_from_kinematics` the legs'
//! set-points come from [`super::stance_ik`], one per state and stance foot. The legs' joint
//! errors, which FSM #1's conditions read, are distances to the state's set-point.

use super::config::SoftTasksConfig;
use super::fsm::StateMachine;
use super::posture_law::PostureLaw;
use super::smoothing::min_jerk_fraction;
use super::stance_ik::{self, chain_to, StanceGoal};
use crate::error::{bail, Result};
use crate::gains::PostureGains;
use crate::targets::Side;
use corps_model::spatial::Se3;
use corps_model::Model;
use nalgebra::{DVector, Vector3};

/// The proportional gains of one state (D = 2√P throughout).
#[derive(Clone, Debug, PartialEq)]
pub struct GainSet {
    pub com: Vector3<f64>,
    /// [linear, angular] of the stance foot and of the swing foot.
    pub stance: [f64; 2],
    pub swing: [f64; 2],
    pub orientation: f64,
    pub posture: DVector<f64>,
}

impl GainSet {
    /// `self ← other`, without allocating.
    fn copy_from(&mut self, other: &GainSet) {
        self.com = other.com;
        self.stance = other.stance;
        self.swing = other.swing;
        self.orientation = other.orientation;
        self.posture.copy_from(&other.posture);
    }

    /// `self ← from + s (to − from)`, without allocating.
    fn blend(&mut self, from: &GainSet, to: &GainSet, s: f64) {
        let mix = |a: f64, b: f64| a + s * (b - a);
        self.com = from.com + (to.com - from.com) * s;
        for k in 0..2 {
            self.stance[k] = mix(from.stance[k], to.stance[k]);
            self.swing[k] = mix(from.swing[k], to.swing[k]);
        }
        self.orientation = mix(from.orientation, to.orientation);
        for ((o, a), b) in self.posture.iter_mut().zip(&from.posture).zip(&to.posture) {
            *o = mix(*a, *b);
        }
    }
}

/// What the settings are computed from: the model and the controller's file, its posture law,
/// the soles' frames (left, right), the state machine and the configuration at the handover.
#[derive(Clone, Copy)]
pub struct Handover<'a> {
    pub model: &'a Model,
    pub config: &'a SoftTasksConfig,
    pub law: &'a PostureLaw,
    pub soles: [usize; 2],
    pub fsm: &'a StateMachine,
    pub q: &'a DVector<f64>,
}

/// Per state: gains and postural set-point; the blend under way; the legs' joints.
pub struct StateSettings {
    gains: Vec<GainSet>,
    /// Per stance foot (left, right), per state.
    set_points: [Vec<Vec<f64>>; 2],
    /// Whether any state gives gains (else the file's gains, with their own Kd, stay).
    pub varies: bool,
    from: GainSet,
    pub now: GainSet,
    switched_at: f64,
    state: usize,
    stance: Side,
    /// The law's indices of the joints between the base and each sole, left then right.
    legs: [Vec<usize>; 2],
}

impl StateSettings {
    /// Every state's gains and set-point at the handover `h`; the first state's are in force.
    pub fn new(h: &Handover<'_>) -> Result<Self> {
        let (model, config, law, soles) = (h.model, h.config, h.law, h.soles);
        let base_posture = config.posture.kp_per_joint(model)?;
        let file = GainSet {
            com: Vector3::repeat(config.com.kp),
            stance: [config.feet.linear.kp, config.feet.angular.kp],
            swing: [config.feet.linear.kp, config.feet.angular.kp],
            orientation: config.neck.kp,
            posture: base_posture,
        };
        let chains = soles.map(|frame| chain_to(model, frame));
        let legs = chains.clone().map(|joints| {
            (joints.iter())
                .filter_map(|&j| law.index_of(&model.joints[j].name))
                .collect::<Vec<_>>()
        });
        if legs.iter().any(Vec::is_empty) {
            bail!("the soles' frames hang from no actuated joint: no legs to watch");
        }
        // The velocities the inverse kinematics frees: the legs' joints.
        let free: Vec<usize> = (chains.iter().flatten())
            .map(|&j| model.joints[j].idx_v)
            .collect();
        let mut gains = Vec::with_capacity(config.fsm.states.len());
        let mut set_points = [Vec::new(), Vec::new()];
        for (k, s) in config.fsm.states.iter().enumerate() {
            let g = &s.gains;
            let posture = if g.posture.is_empty() {
                file.posture.clone()
            } else {
                let mut groups = config.posture.groups.clone();
                groups.extend(g.posture.clone());
                let merged = PostureGains {
                    kp: config.posture.kp,
                    groups,
                    weight: config.posture.weight,
                };
                merged
                    .kp_per_joint(model)
                    .map_err(|e| crate::error::invalid!("fsm state '{}': {e}", s.name))?
            };
            gains.push(GainSet {
                com: g.com.map_or(file.com, Vector3::from),
                stance: g.stance.unwrap_or(file.stance),
                swing: g.swing.unwrap_or(file.swing),
                orientation: g.orientation.unwrap_or(file.orientation),
                posture,
            });
            let at = law
                .set_point(&s.posture_deg)
                .map_err(|e| crate::error::invalid!("fsm state '{}': {e}", s.name))?;
            for stance in [Side::Left, Side::Right] {
                let mut point = at.clone();
                if config.fsm.legs_from_kinematics {
                    let legs_q = legs_by_kinematics(h, &free, &at, (k, stance))
                        .map_err(|e| crate::error::invalid!("fsm state '{}': {e}", s.name))?;
                    for &i in legs.iter().flatten() {
                        point[i] = legs_q[law.q_index(i)];
                    }
                    law.check_inside(&point)
                        .map_err(|e| crate::error::invalid!("fsm state '{}': {e}", s.name))?;
                }
                set_points[stance.index()].push(point);
            }
        }
        let varies = config
            .fsm
            .states
            .iter()
            .any(|s| s.gains != Default::default());
        let first = gains[0].clone();
        Ok(Self {
            gains,
            set_points,
            varies,
            from: first.clone(),
            now: first,
            switched_at: 0.0,
            state: 0,
            stance: h.fsm.stance(),
            legs,
        })
    }

    /// Starts the switch to state `k` at `t` if it is not the one in force: the gains blend
    /// from where they are, the posture heads to the state's set-point.
    pub fn enter(&mut self, k: usize, stance: Side, t: f64, t_smooth: f64, law: &mut PostureLaw) {
        if k == self.state && stance == self.stance {
            return;
        }
        self.from.copy_from(&self.now);
        if stance != self.stance {
            // The feet exchange roles: each keeps blending from the gains it had.
            std::mem::swap(&mut self.from.stance, &mut self.from.swing);
        }
        (self.state, self.stance) = (k, stance);
        self.switched_at = t;
        law.go_to(t, &self.set_points[stance.index()][k], t_smooth);
    }

    /// The gains at `t`.
    pub fn update(&mut self, t: f64, t_smooth: f64) {
        let s = min_jerk_fraction(t - self.switched_at, t_smooth);
        let (from, to) = (&self.from, &self.gains[self.state]);
        self.now.blend(from, to, s);
    }

    /// Each leg's largest joint distance to the state's postural set-point at `q` (rad).
    pub fn leg_errors(&self, q: &[f64], law: &PostureLaw) -> [f64; 2] {
        let set_point = &self.set_points[self.stance.index()][self.state];
        [0, 1].map(|k| {
            (self.legs[k].iter())
                .map(|&i| law.error(q, i, set_point[i]))
                .fold(0.0, f64::max)
        })
    }
}

/// The configuration whose legs (the velocities `free`) realise state `k`'s set-points with
/// `stance` standing, the other joints at `set_point` (the law's order), from the handover's
/// configuration.
fn legs_by_kinematics(
    h: &Handover<'_>,
    free: &[usize],
    set_point: &[f64],
    (k, stance): (usize, Side),
) -> Result<DVector<f64>> {
    let Handover {
        model,
        config,
        law,
        soles,
        fsm,
        q,
    } = *h;
    let mut q = q.clone();
    for (i, x) in set_point.iter().enumerate() {
        q[law.q_index(i)] = *x;
    }
    let swing = stance.other();
    let mut data = corps_model::Data::new(model);
    corps_model::forward_kinematics_placements(model, &mut data, q.as_slice())?;
    let placed = |frame| corps_model::frame_placement(model, &data, frame);
    let (com, swing_at) = fsm.planned(k, stance);
    let feet0 = fsm.initial_feet();
    let stance_frame = soles[stance.index()];
    let swing_frame = soles[swing.index()];
    let orientation = model.frame_id(&config.neck.frame)?;
    let goal = StanceGoal {
        stance: (
            stance_frame,
            Se3::new(placed(stance_frame)?.rotation, feet0[stance.index()]),
        ),
        swing: (
            swing_frame,
            Se3::new(placed(swing_frame)?.rotation, swing_at),
        ),
        com,
        orientation: (orientation, placed(orientation)?.rotation),
    };
    stance_ik::solve(model, &q, free, &goal)
}
