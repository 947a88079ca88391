//! Velocity-driven walking MPC with automatic footstep placement (Herdt, Perrin, Wieber et al.
//! 2010, "Online walking motion generation with automatic foot step placement"; the
//! formulation jrl-walkgen runs on TALOS, Naveau et al. 2017, seed 002 §4.4).
//!
//! Per horizontal axis the state is `[c, ċ, c̈]` and the input a piecewise-constant CoM jerk
//! over a horizon of `N = 16` samples of `T = 0.1 s` (seed 002 §4.4), re-planned every 5 ms.
//! The samples lie on a grid aligned with the step timing, so the first interval is the time
//! to the next grid point (≤ T), and support phases change exactly on samples. Decision
//! vector `U = [jerk_x(N), jerk_y(N), F_x(2), F_y(2)]`: jerks and the positions of the next
//! two footsteps (nf = 2 as in jrl-walkgen). Footstep yaws are computed beforehand from the
//! yaw-rate command (as Herdt 2010 does), which keeps the problem a QP.
//!
//! Cost (seed 002 eq. 8–12, weights of jrl-walkgen's `nmpc_generator.cpp` quoted in seed 002
//! §4.4: α = 5, β = 1e3, γ = 5e-4):
//!
//! ```text
//! α/2 Σ‖ċ_i − v*_i‖² + β/2 Σ‖z_i − z_centre,i(F)‖² + γ/2 Σ‖j_i − j*_i‖²
//! ```
//!
//! where `z_centre` is the support foot's centre in single support and moves linearly from the
//! previous to the next support foot in double support.
//!
//! References: seed 002 eq. 9 and 12 compare the velocity with the command,
//! `v*_i = R(θ_i) v_cmd`, and the jerk with zero. While walking, `v*` and `j*` are here the
//! CoM velocity and jerk of the periodic gait the command implies (`NominalGait`): the LIPM
//! whose ZMP is at `z_centre` at every sample, on footprints `P_k = k s ± a`, phase-aligned
//! with the step timing, where `s = R(θ) v_cmd (T_SS + T_DS)` is the stride (clamped to the
//! reachable region) and `a = R(θ) [0, (d + |s_y|)/2]` the alternation of the feet about their
//! mean line (`+` for a left support, `d` the double-support feet distance). That gait costs
//! nothing, so the closed loop settles on it. Standing and stopping keep the seed's references
//! with a zero command. With the seed's references every walking gait
//! pays for its CoM sway (forward its speed swings between about 0.55× and 1.8× its mean,
//! sideways it reverses at each step) and for the jerk of that sway; both grow with the stride
//! (sideways `a` grows with `|v_y|`), so the optimum walks slower than the command: 0.076 m/s
//! for 0.1 m/s forward and 0.0000 m/s for 0.05 m/s sideways; with `v*` alone 0.0963 and
//! 0.0418 m/s; with `v*` and `j*` 0.1000 and 0.0500 m/s.
//!
//! Constraints:
//! - ZMP at every sample (and at the end of the current 5 ms tick) inside the foot rectangle
//!   moved to `z_centre` and oriented like each foot involved. In double support this moving
//!   rectangle lies inside the convex hull of both feet, so the constraint is linear in `F`
//!   and conservative (seed 002 §4.2).
//! - each footstep inside a rectangle in the frame of the previous footprint (the reachable
//!   region, seed 002 §4.4 "Inequality 2").
//!
//! Gait: fixed timing with alternating feet, each step = double support then single support
//! (seed 002: DS 0.2 s, SS 1.0 s). A zero command stops the robot within two steps (seed 002
//! §4.4, `:numberstepsbeforestop 2`): the next step that has not lifted off yet lands beside the
//! support foot at the double-support feet distance, then the ZMP moves to the middle of the
//! feet and the robot stands. A non-zero command from standing starts walking.

use crate::lipm::{jerk_integrator, Lipm};
use crate::pose::{angle_difference, rotation, wrap_angle, Foot, FootPose, FootVelocity};
use crate::reference::{ContactPhase, WalkingReference};
use crate::support_polygon::FootGeometry;
use crate::swing_foot::Quintic;
use crate::WalkError;
use corps_qp::{ActiveSetSolver, QpProblem};
use nalgebra::{DMatrix, Vector2, Vector3};

/// Number of previewed footsteps (jrl-walkgen `nf_ = 2`, seed 002 §4.4).
pub const N_FOOTSTEPS: usize = 2;

/// Reachable region of a footstep in the frame of the previous footprint: `x ∈ [x_min, x_max]`
/// and `y ∈ [y_min, y_max]` for a left foot landing (left of a right footprint), mirrored for
/// a right foot.
#[derive(Debug, Clone, Copy, PartialEq, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ReachableRegion {
    /// Most backward step (m).
    pub x_min: f64,
    /// Most forward step (m).
    pub x_max: f64,
    /// Smallest lateral distance between the feet (m).
    pub y_min: f64,
    /// Largest lateral distance between the feet (m).
    pub y_max: f64,
}

/// Parameters of the MPC: a robot's settings, read from its configuration file (TALOS':
/// `config/talos/walk_mpc.toml`, seed 002 §4.4; unknown keys are errors).
#[derive(Debug, Clone, Copy, PartialEq, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MpcParams {
    /// The pendulum (TALOS: `z_c = 0.876681`, seed 002 §4.4).
    pub lipm: Lipm,
    /// Horizon sampling period `T` (0.1 s).
    pub sample_period: f64,
    /// Horizon samples `N` (16).
    pub horizon: usize,
    /// Re-planning period (5 ms, seed 002 §2).
    pub control_period: f64,
    /// Single-support duration (1.0 s, seed 002 §4.4).
    pub single_support: f64,
    /// Double-support duration (0.2 s, seed 002 §4.4).
    pub double_support: f64,
    /// CoM velocity weight α (5).
    pub alpha: f64,
    /// ZMP centring weight β (1e3).
    pub beta: f64,
    /// Jerk weight γ (5e-4).
    pub gamma: f64,
    /// ZMP rectangle about each foot centre (`:setfeetconstraint XY 0.091 0.0489`).
    pub zmp_rectangle: FootGeometry,
    /// Reachable region of the footsteps.
    pub reachable: ReachableRegion,
    /// Lateral feet distance when standing (0.162 m, `:setDSFeetDistance`).
    pub feet_distance: f64,
    /// Linear velocity saturation (0.3 m/s, seed 002 §4.4).
    pub max_speed: f64,
    /// Largest yaw difference between consecutive footprints (rad).
    pub max_relative_yaw: f64,
    /// The landing position is frozen when less than this remains of the swing (s).
    pub freeze_time: f64,
    /// Swing apex height (0.05 m, seed 002 §4.4).
    pub swing_height: f64,
    /// Double support of the first step from standing (s), a multiple of the sample period:
    /// the CoM must reach the support foot before lift-off, which the LIPM cannot do in a
    /// 0.2 s transfer (starting 8 cm off the support foot it would diverge by
    /// 0.032 · cosh(ω · 1.0 s) ≈ 0.45 m during the swing).
    pub start_double_support: f64,
}

/// Velocity command `(v_x, v_y, ω)` in the robot (waist) frame, REP-103 signs (seed 002
/// §4.14: +y left, +yaw counter-clockwise).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct VelocityCommand {
    /// Forward velocity (m/s).
    pub vx: f64,
    /// Lateral velocity (m/s).
    pub vy: f64,
    /// Yaw rate (rad/s).
    pub yaw_rate: f64,
}

impl VelocityCommand {
    /// A command.
    pub fn new(vx: f64, vy: f64, yaw_rate: f64) -> Self {
        Self { vx, vy, yaw_rate }
    }

    fn is_zero(&self) -> bool {
        self.vx.abs() < 1e-9 && self.vy.abs() < 1e-9 && self.yaw_rate.abs() < 1e-9
    }
}

/// A footstep planned by the last solve.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlannedStep {
    /// Landing foot.
    pub foot: Foot,
    /// Landing pose.
    pub pose: FootPose,
    /// Time of touch-down from now (s).
    pub touchdown_in: f64,
}

/// One sample of the predicted horizon.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct HorizonSample {
    /// Time from now (s).
    pub time: f64,
    /// CoM `[c, ċ, c̈]` along x.
    pub x: Vector3<f64>,
    /// CoM `[c, ċ, c̈]` along y.
    pub y: Vector3<f64>,
    /// ZMP.
    pub zmp: Vector2<f64>,
    /// Contact phase.
    pub phase: ContactPhase,
}

#[derive(Debug, Clone, Copy, PartialEq)]
enum Gait {
    Standing,
    Walking {
        /// Index of the current step.
        step: u64,
        /// The foot that swings in the current step.
        swing: Foot,
        /// The current step starts from standing (its double support leaves the middle).
        from_standing: bool,
        /// Index of the closing step, when stopping.
        stop: Option<u64>,
    },
}

/// ZMP support description of one sample: weights of the four footprint slots
/// `[P_{c−1}, P_c, F_1, F_2]` in the centre, and the yaws of the feet involved.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Support {
    w: [f64; 4],
    /// Lateral extension of the rectangle (both sides) when the feet involved stand side by
    /// side at the double-support distance, so that the rectangle stays in their hull.
    ext: f64,
    yaws: [f64; 2],
    n_yaws: usize,
    phase: ContactPhase,
}

/// The MPC walking pattern generator.
#[derive(Debug)]
pub struct WalkingMpc {
    p: MpcParams,
    n: usize,
    // prediction matrices (per axis, shared): rows i = 1..N
    pz_s: DMatrix<f64>,
    pz_u: DMatrix<f64>,
    pv_s: DMatrix<f64>,
    pv_u: DMatrix<f64>,
    /// Reference CoM velocity of sample i (columns: x, y), see [`NominalGait`].
    v_ref: DMatrix<f64>,
    /// Reference jerk of interval i (columns: x, y), see [`NominalGait`].
    j_ref: DMatrix<f64>,
    nominal: NominalGait,
    pp_s: DMatrix<f64>,
    pp_u: DMatrix<f64>,
    pa_s: DMatrix<f64>,
    pa_u: DMatrix<f64>,
    tau: Vec<f64>,
    supports: Vec<Support>,
    qp: QpProblem,
    solver: ActiveSetSolver,
    // state
    time: f64,
    t_in_step: f64,
    com_x: Vector3<f64>,
    com_y: Vector3<f64>,
    yaw_ref: f64,
    left: FootPose,
    right: FootPose,
    left_vel: FootVelocity,
    right_vel: FootVelocity,
    swing_state: [Vector3<f64>; 3],
    gait: Gait,
    cmd: VelocityCommand,
    landing: [FootPose; N_FOOTSTEPS],
    frozen: Option<FootPose>,
    planned: [PlannedStep; N_FOOTSTEPS],
    n_planned: usize,
    horizon: Vec<HorizonSample>,
    last_jerk: Vector2<f64>,
    liftoff: FootPose,
    gam: DMatrix<f64>,
    used: [bool; N_FOOTSTEPS],
}

impl WalkingMpc {
    /// A generator standing with the feet `feet_distance` apart about `(x, y)` facing `yaw`,
    /// the CoM at rest above the middle of the feet. Allocates every buffer.
    pub fn new(params: MpcParams, x: f64, y: f64, yaw: f64) -> Result<Self, WalkError> {
        let lipm = Lipm::new(params.lipm.com_height, params.lipm.gravity)?;
        let pos = |v: f64| v.is_finite() && v > 0.0;
        if !pos(params.sample_period) || !pos(params.control_period) || params.horizon < 2 {
            return Err(WalkError::InvalidParameter(
                "MPC periods must be > 0 and N ≥ 2",
            ));
        }
        if params.control_period > params.sample_period {
            return Err(WalkError::InvalidParameter(
                "control period must be ≤ sample period",
            ));
        }
        if !pos(params.single_support)
            || !pos(params.double_support)
            || !pos(params.start_double_support)
        {
            return Err(WalkError::InvalidParameter("step durations must be > 0"));
        }
        let horizon_time = params.sample_period * params.horizon as f64;
        if horizon_time
            > (N_FOOTSTEPS as f64 - 1.0) * (params.single_support + params.double_support)
                + params.single_support
                + 1e-9
        {
            return Err(WalkError::InvalidParameter(
                "horizon too long for 2 previewed footsteps (need N T ≤ 2 SS + DS)",
            ));
        }
        let step = (params.single_support + params.double_support) / params.sample_period;
        let per_step = step.round();
        if (step - per_step).abs() > 1e-9 {
            return Err(WalkError::InvalidParameter(
                "step period must be a multiple of the sample period",
            ));
        }
        let nominal = NominalGait::new(
            params.sample_period,
            per_step as usize,
            params.double_support,
            params.lipm.com_height / params.lipm.gravity,
        )?;
        let r = &params.reachable;
        if !(r.x_min < r.x_max && 0.0 < r.y_min && r.y_min < r.y_max) {
            return Err(WalkError::InvalidParameter(
                "reachable region must be non-empty with y_min > 0",
            ));
        }
        let n = params.horizon;
        let nv = 2 * n + 2 * N_FOOTSTEPS;
        let n_in = 4 * (n + 1) + 2 * N_FOOTSTEPS;
        let (l, rf) = stance(x, y, yaw, params.feet_distance);
        let mid = Vector2::new(x, y);
        let mut s = Self {
            p: MpcParams { lipm, ..params },
            n,
            pz_s: DMatrix::zeros(n, 3),
            pz_u: DMatrix::zeros(n, n),
            pv_s: DMatrix::zeros(n, 3),
            pv_u: DMatrix::zeros(n, n),
            v_ref: DMatrix::zeros(n, 2),
            j_ref: DMatrix::zeros(n, 2),
            nominal,
            pp_s: DMatrix::zeros(n, 3),
            pp_u: DMatrix::zeros(n, n),
            pa_s: DMatrix::zeros(n, 3),
            pa_u: DMatrix::zeros(n, n),
            tau: vec![0.0; n],
            supports: vec![
                Support {
                    w: [0.0; 4],
                    ext: 0.0,
                    yaws: [0.0; 2],
                    n_yaws: 0,
                    phase: ContactPhase::Double
                };
                n + 1
            ],
            qp: QpProblem::new(nv, 0, n_in),
            solver: ActiveSetSolver::new(nv, 0, n_in),
            time: 0.0,
            t_in_step: 0.0,
            com_x: Vector3::new(mid.x, 0.0, 0.0),
            com_y: Vector3::new(mid.y, 0.0, 0.0),
            yaw_ref: wrap_angle(yaw),
            left: l,
            right: rf,
            left_vel: FootVelocity::default(),
            right_vel: FootVelocity::default(),
            swing_state: [Vector3::zeros(); 3],
            gait: Gait::Standing,
            cmd: VelocityCommand::default(),
            landing: [l, rf],
            frozen: None,
            planned: [PlannedStep {
                foot: Foot::Left,
                pose: l,
                touchdown_in: 0.0,
            }; N_FOOTSTEPS],
            n_planned: 0,
            horizon: vec![HorizonSample::default(); n],
            last_jerk: Vector2::zeros(),
            liftoff: l,
            gam: DMatrix::zeros(0, 0),
            used: [false; N_FOOTSTEPS],
        };
        s.gam = DMatrix::zeros(3, n);
        Ok(s)
    }

    /// Parameters.
    pub fn params(&self) -> &MpcParams {
        &self.p
    }

    /// Time since start (s).
    pub fn time(&self) -> f64 {
        self.time
    }

    /// Overrides the CoM state (e.g. from an estimator): `[c, ċ, c̈]` per axis.
    pub fn set_com_state(&mut self, x: Vector3<f64>, y: Vector3<f64>) {
        self.com_x = x;
        self.com_y = y;
    }

    /// CoM state `([c, ċ, c̈]_x, [c, ċ, c̈]_y)`.
    pub fn com_state(&self) -> (Vector3<f64>, Vector3<f64>) {
        (self.com_x, self.com_y)
    }

    /// The jerk applied during the last tick.
    pub fn last_jerk(&self) -> Vector2<f64> {
        self.last_jerk
    }

    /// Footsteps planned by the last solve (landing pose and time to touch-down).
    pub fn planned_footsteps(&self) -> &[PlannedStep] {
        &self.planned[..self.n_planned]
    }

    /// The predicted horizon of the last solve.
    pub fn horizon(&self) -> &[HorizonSample] {
        &self.horizon
    }

    /// `true` when standing (not walking and not stopping).
    pub fn is_standing(&self) -> bool {
        self.gait == Gait::Standing
    }

    /// Yaw reference (integral of the yaw-rate command).
    pub fn yaw_reference(&self) -> f64 {
        self.yaw_ref
    }

    fn step_period(&self) -> f64 {
        self.p.single_support + self.p.double_support
    }

    /// Double-support duration of the current step.
    fn current_ds(&self) -> f64 {
        match self.gait {
            Gait::Walking {
                from_standing: true,
                ..
            } => self.p.start_double_support,
            _ => self.p.double_support,
        }
    }

    /// Duration of the current step.
    fn current_period(&self) -> f64 {
        self.current_ds() + self.p.single_support
    }

    /// Current contact phase.
    pub fn phase(&self) -> ContactPhase {
        match self.gait {
            Gait::Standing => ContactPhase::Double,
            Gait::Walking { swing, .. } => {
                if self.t_in_step < self.current_ds() {
                    ContactPhase::Double
                } else if swing == Foot::Left {
                    ContactPhase::RightSupport
                } else {
                    ContactPhase::LeftSupport
                }
            }
        }
    }

    fn foot(&self, f: Foot) -> FootPose {
        match f {
            Foot::Left => self.left,
            Foot::Right => self.right,
        }
    }

    /// The current reference sample.
    pub fn reference(&self) -> WalkingReference {
        let zc = self.p.lipm.com_height;
        let w2 = self.p.lipm.omega().powi(2);
        let mut r = WalkingReference {
            time: self.time,
            com: Vector3::new(self.com_x[0], self.com_y[0], zc),
            com_vel: Vector3::new(self.com_x[1], self.com_y[1], 0.0),
            com_acc: Vector3::new(self.com_x[2], self.com_y[2], 0.0),
            zmp: Vector3::new(
                self.com_x[0] - self.com_x[2] / w2,
                self.com_y[0] - self.com_y[2] / w2,
                0.0,
            ),
            left_foot: self.left,
            right_foot: self.right,
            left_foot_vel: self.left_vel,
            right_foot_vel: self.right_vel,
            phase: self.phase(),
            ..Default::default()
        };
        r.complete(self.p.lipm.omega());
        r
    }

    /// Updates the gait state machine for a new command.
    fn handle_command(&mut self) {
        let moving = !self.cmd.is_zero();
        let before_liftoff = self.t_in_step < self.current_ds();
        match &mut self.gait {
            Gait::Standing => {
                if moving {
                    let swing = if self.cmd.vy > 1e-9 {
                        Foot::Left
                    } else if self.cmd.vy < -1e-9
                        || (self.cmd.vy.abs() <= 1e-9 && self.cmd.yaw_rate < -1e-9)
                    {
                        Foot::Right
                    } else {
                        Foot::Left
                    };
                    self.gait = Gait::Walking {
                        step: 0,
                        swing,
                        from_standing: true,
                        stop: None,
                    };
                    self.t_in_step = 0.0;
                    self.frozen = None;
                }
            }
            Gait::Walking { step, stop, .. } => match (*stop, moving) {
                (None, false) => *stop = Some(if before_liftoff { *step } else { *step + 1 }),
                (Some(k), true) if *step < k || (*step == k && before_liftoff) => *stop = None,
                _ => {}
            },
        }
    }

    /// Support of the sample at time `tau` from now.
    fn support_at(&self, tau: f64) -> Support {
        let ds = self.p.double_support;
        let period = self.step_period();
        let mut out = Support {
            w: [0.0; 4],
            ext: 0.0,
            yaws: [0.0; 2],
            n_yaws: 0,
            phase: ContactPhase::Double,
        };
        let yaw_of = |slot: usize| -> f64 {
            match slot {
                0 | 1 => self.slot_fixed(slot).yaw,
                s => self.landing[s - 2].yaw,
            }
        };
        let Gait::Walking {
            step: c,
            swing,
            from_standing,
            stop,
        } = self.gait
        else {
            // standing: middle of the feet
            out.w = [0.5, 0.5, 0.0, 0.0];
            out.ext = 0.5 * self.p.feet_distance;
            out.yaws = [self.slot_fixed(0).yaw, self.slot_fixed(1).yaw];
            out.n_yaws = 2;
            return out;
        };
        let u = self.t_in_step + tau;
        let pc = self.current_period();
        let (rel, local) = if u < pc {
            (0u64, u)
        } else {
            let r = ((u - pc) / period).floor().max(0.0);
            (1 + r as u64, u - pc - r * period)
        };
        let ds_k = if rel == 0 { self.current_ds() } else { ds };
        // slot of footprint P_m, m = c − 1 + slot
        let slot = |m_rel: i64| -> usize { (m_rel + 1).clamp(0, 3) as usize };
        let add = |s: usize, w: f64, out: &mut Support| {
            out.w[s] += w;
        };
        if let Some(k) = stop {
            if c + rel > k {
                // after the closing step landed: to the middle of P_K and P_{K+1}, then stand
                // The closing step may have landed already (k < c): signed difference.
                let kr = k as i64 - c as i64;
                let after = u - pc - kr as f64 * period;
                let lam = (after / ds).clamp(0.0, 1.0);
                let (a, b) = (slot(kr), slot(kr + 1));
                add(a, 1.0 - 0.5 * lam, &mut out);
                add(b, 0.5 * lam, &mut out);
                out.ext = 0.5 * lam * self.p.feet_distance;
                out.yaws = [yaw_of(a), yaw_of(b)];
                out.n_yaws = 2;
                return out;
            }
        }
        let kr = rel as i64;
        let sup = slot(kr);
        // the foot swinging in step c + rel alternates
        let swing_k = if rel % 2 == 0 { swing } else { swing.other() };
        if local < ds_k {
            let prev = slot(kr - 1);
            let lam = local / ds_k;
            if rel == 0 && from_standing {
                add(0, 0.5 * (1.0 - lam), &mut out);
                add(1, 0.5 * (1.0 - lam), &mut out);
                out.ext = 0.5 * (1.0 - lam) * self.p.feet_distance;
            } else {
                add(prev, 1.0 - lam, &mut out);
            }
            add(sup, lam, &mut out);
            out.yaws = [yaw_of(prev), yaw_of(sup)];
            out.n_yaws = 2;
        } else {
            add(sup, 1.0, &mut out);
            out.yaws = [yaw_of(sup), 0.0];
            out.n_yaws = 1;
            out.phase = if swing_k == Foot::Left {
                ContactPhase::RightSupport
            } else {
                ContactPhase::LeftSupport
            };
        }
        out
    }

    /// Fixed footprints: slot 0 = P_{c−1} (the current step's swing foot before it lands),
    /// slot 1 = P_c (support). Standing: left, right.
    fn slot_fixed(&self, slot: usize) -> FootPose {
        match self.gait {
            Gait::Standing => {
                if slot == 0 {
                    self.left
                } else {
                    self.right
                }
            }
            Gait::Walking { swing, .. } => {
                if slot == 0 {
                    self.swing_liftoff(swing)
                } else {
                    self.foot(swing.other())
                }
            }
        }
    }

    fn swing_liftoff(&self, swing: Foot) -> FootPose {
        // before lift-off the swing foot is where it stands; during the swing its lift-off
        // pose is kept in `liftoff`
        if self.t_in_step < self.current_ds() {
            self.foot(swing)
        } else {
            self.liftoff
        }
    }
}

/// The periodic gait of the LIPM whose ZMP is at the support centre `z_centre` of the module
/// doc at every sample, on the sample grid of one regular step (`m` samples). By linearity it
/// is the sum of two unit responses per axis, scaled by the stride `s` and by the
/// alternation `±a` of the footprints about their mean line (`+` for a left support):
///
/// ```text
/// footprint P_k = s k ± a,   x(t + step) = x(t) + [s, 0, 0]ᵀ  (stride)
///                            x(t + step) = −x(t)               (alternation)
/// ```
///
/// Each response solves `m + 3` linear equations for `[x₀, j₀ … j_{m−1}]`: the ZMP
/// `[1, 0, −z_c/g] x_l = z_centre(l T)` at `l = 1 … m` (seed 002 eq. 5–7) and the periodicity.
#[derive(Debug, Clone)]
struct NominalGait {
    /// Samples per step.
    m: usize,
    /// CoM velocity at the grid points `l = 0 … m − 1` of a step (`[stride, alternation]`).
    vel: [Vec<f64>; 2],
    /// CoM jerk over the interval from grid point `l` to `l + 1`.
    jerk: [Vec<f64>; 2],
}

impl NominalGait {
    fn new(t: f64, m: usize, ds: f64, h: f64) -> Result<Self, WalkError> {
        let (a, b) = jerk_integrator(t);
        let dim = m + 3;
        let mut vel = [vec![0.0; m], vec![0.0; m]];
        let mut jerk = [vec![0.0; m], vec![0.0; m]];
        for (r, (prev, sign)) in [(0.0, 1.0), (-1.0, -1.0)].into_iter().enumerate() {
            // x_l = Φ_l [x₀; j], Φ_l a 3 × dim block
            let mut phi = nalgebra::Matrix3xX::<f64>::zeros(dim);
            phi.view_mut((0, 0), (3, 3)).fill_with_identity();
            let mut lhs = DMatrix::<f64>::zeros(dim, dim);
            let mut rhs = nalgebra::DVector::<f64>::zeros(dim);
            for l in 1..=m {
                let mut next = a * &phi;
                for c in 0..3 {
                    next[(c, 3 + l - 1)] += b[c];
                }
                phi = next;
                let local = l as f64 * t;
                let centre = if local < ds {
                    prev + (1.0 - prev) * local / ds
                } else {
                    1.0
                };
                for c in 0..dim {
                    lhs[(l - 1, c)] = phi[(0, c)] - h * phi[(2, c)];
                }
                rhs[l - 1] = centre;
            }
            // x_m − sign x₀ = [1 + prev, 0, 0]: the stride shifts by 1, the alternation flips
            for c in 0..3 {
                for col in 0..dim {
                    lhs[(m + c, col)] = phi[(c, col)];
                }
                lhs[(m + c, c)] -= sign;
            }
            rhs[m] = 1.0 + prev;
            let y = lhs.lu().solve(&rhs).ok_or(WalkError::InvalidParameter(
                "no periodic gait on the sample grid",
            ))?;
            let mut x = Vector3::new(y[0], y[1], y[2]);
            for l in 0..m {
                vel[r][l] = x[1];
                jerk[r][l] = y[3 + l];
                x = a * x + b * y[3 + l];
            }
        }
        Ok(Self { m, vel, jerk })
    }
}

fn stance(x: f64, y: f64, yaw: f64, d: f64) -> (FootPose, FootPose) {
    let off = rotation(yaw) * Vector2::new(0.0, 0.5 * d);
    (
        FootPose::new(x + off.x, y + off.y, 0.0, yaw),
        FootPose::new(x - off.x, y - off.y, 0.0, yaw),
    )
}

impl WalkingMpc {
    /// One re-planning tick: takes the command (saturated to `max_speed`), solves the QP,
    /// applies the first jerk for one control period, advances the gait and the feet, and
    /// returns the reference at the new time. Never allocates. On a QP failure the state is
    /// not advanced and the error is returned (the caller keeps the previous reference).
    pub fn tick(&mut self, cmd: VelocityCommand) -> Result<WalkingReference, WalkError> {
        let mut cmd = cmd;
        let v = (cmd.vx * cmd.vx + cmd.vy * cmd.vy).sqrt();
        if v > self.p.max_speed {
            cmd.vx *= self.p.max_speed / v;
            cmd.vy *= self.p.max_speed / v;
        }
        if !(cmd.vx.is_finite() && cmd.vy.is_finite() && cmd.yaw_rate.is_finite()) {
            return Err(WalkError::InvalidParameter(
                "velocity command must be finite",
            ));
        }
        self.cmd = cmd;
        self.handle_command();
        self.build_predictions();
        self.build_references();
        self.plan_footstep_yaws();
        self.build_qp();
        let sol = self.solver.solve(&self.qp)?;
        let n = self.n;
        let u = Vector2::new(sol.x[0], sol.x[n]);
        for j in 0..N_FOOTSTEPS {
            if self.used[j] {
                self.landing[j].x = sol.x[2 * n + j];
                self.landing[j].y = sol.x[2 * n + N_FOOTSTEPS + j];
            }
        }
        self.fill_horizon();
        self.advance(u);
        Ok(self.reference())
    }

    /// Prediction matrices on the step-aligned grid.
    fn build_predictions(&mut self) {
        let (n, t) = (self.n, self.p.sample_period);
        let rem = self.t_in_step % t;
        let on_grid = t - rem < 1e-9 || rem < 1e-9;
        let tau1 = if on_grid { t } else { t - rem };
        let h = self.p.lipm.com_height / self.p.lipm.gravity;
        let (a1, b1) = jerk_integrator(tau1);
        let (at, bt) = jerk_integrator(t);
        let mut phi = a1;
        self.gam.fill(0.0);
        self.gam.set_column(0, &b1);
        for i in 0..n {
            self.tau[i] = tau1 + i as f64 * t;
            for c in 0..3 {
                self.pp_s[(i, c)] = phi[(0, c)];
                self.pv_s[(i, c)] = phi[(1, c)];
                self.pa_s[(i, c)] = phi[(2, c)];
                self.pz_s[(i, c)] = phi[(0, c)] - h * phi[(2, c)];
            }
            for j in 0..n {
                let g = (self.gam[(0, j)], self.gam[(1, j)], self.gam[(2, j)]);
                self.pp_u[(i, j)] = g.0;
                self.pv_u[(i, j)] = g.1;
                self.pa_u[(i, j)] = g.2;
                self.pz_u[(i, j)] = g.0 - h * g.2;
            }
            // propagate one sample
            phi = at * phi;
            for j in 0..=i {
                let col = Vector3::new(self.gam[(0, j)], self.gam[(1, j)], self.gam[(2, j)]);
                self.gam.set_column(j, &(at * col));
            }
            if i + 1 < n {
                self.gam.set_column(i + 1, &bt);
            }
        }
        for i in 0..n {
            self.supports[i] = self.support_at(self.tau[i]);
        }
        self.supports[n] = self.support_at(self.p.control_period);
    }

    /// Step of the sample grid point at time `tau` from now: `(k, l)` with `k` steps after the
    /// current one and `l` sample periods into the regular part of that step (`None` inside
    /// the extra double support of a step from standing).
    fn grid_phase(&self, tau: f64) -> Option<(u64, usize)> {
        let (t, m) = (self.p.sample_period, self.nominal.m);
        let u = self.t_in_step + tau;
        let pc = self.current_period();
        let (mut k, local) = if u < pc - 0.5 * t {
            (0u64, u - (pc - self.step_period()))
        } else {
            let r = ((u - pc) / self.step_period() + 1e-9).floor().max(0.0);
            (1 + r as u64, u - pc - r * self.step_period())
        };
        if local < -0.5 * t {
            return None;
        }
        let mut l = (local / t).round().max(0.0) as usize;
        if l >= m {
            k += 1;
            l -= m;
        }
        Some((k, l))
    }

    /// References of the velocity and jerk terms (module doc): the velocity `v*` at each
    /// sample and the jerk `j*` over each interval of the periodic gait the command implies,
    /// phase-aligned with the step timing. Zero when standing or stopping, and during the extra
    /// double support of a step from standing.
    fn build_references(&mut self) {
        self.v_ref.fill(0.0);
        self.j_ref.fill(0.0);
        let Gait::Walking {
            swing, stop: None, ..
        } = self.gait
        else {
            return;
        };
        let (n, t) = (self.n, self.p.sample_period);
        let (period, r) = (self.step_period(), self.p.reachable);
        // stride per step and mean lateral feet distance in the robot frame, inside the
        // reachable region (seed 002 §5: stride = v × step period)
        let d0 = self.p.feet_distance.max(r.y_min);
        let fwd = (self.cmd.vx * period).clamp(r.x_min, r.x_max);
        let lat_max = (0.5 * (r.y_max - d0)).max(0.0);
        let lat = (self.cmd.vy * period).clamp(-lat_max, lat_max);
        let stride = Vector2::new(fwd, lat);
        let half_width = Vector2::new(0.0, 0.5 * (d0 + lat.abs()));
        let om = self.cmd.yaw_rate;
        // side of the support foot of step c + k: the current support foot for even k
        let side = |k: u64| {
            let sup = if k.is_multiple_of(2) {
                swing.other()
            } else {
                swing
            };
            sup.side()
        };
        for i in 0..n {
            let rot = rotation(self.yaw_ref + om * self.tau[i]);
            let (s, a) = (rot * stride, rot * half_width);
            if let Some((k, l)) = self.grid_phase(self.tau[i]) {
                let (vd, va) = (self.nominal.vel[0][l], self.nominal.vel[1][l]);
                let v = s * vd + a * (side(k) * va);
                self.v_ref.set_row(i, &v.transpose());
            }
            if let Some((k, l)) = self.grid_phase(self.tau[i] - t) {
                let (jd, ja) = (self.nominal.jerk[0][l], self.nominal.jerk[1][l]);
                let j = s * jd + a * (side(k) * ja);
                self.j_ref.set_row(i, &j.transpose());
            }
        }
    }

    /// Landing yaws from the yaw-rate command (Herdt 2010 computes orientations first).
    fn plan_footstep_yaws(&mut self) {
        self.n_planned = 0;
        self.used = [false; N_FOOTSTEPS];
        let Gait::Walking {
            step, swing, stop, ..
        } = self.gait
        else {
            return;
        };
        let period = self.step_period();
        let omega = if stop.is_some() {
            0.0
        } else {
            self.cmd.yaw_rate
        };
        let mut prev = self.slot_fixed(1);
        let mut foot = swing;
        for j in 0..N_FOOTSTEPS {
            let td = self.current_period() - self.t_in_step + j as f64 * period;
            let closing = stop == Some(step + j as u64);
            let after_stop = matches!(stop, Some(k) if step + j as u64 > k);
            let yaw = if j == 0 && self.frozen.is_some() {
                self.frozen.map(|f| f.yaw).unwrap_or(prev.yaw)
            } else if closing || after_stop {
                prev.yaw
            } else {
                let want = self.yaw_ref + omega * td;
                let d = angle_difference(want, prev.yaw)
                    .clamp(-self.p.max_relative_yaw, self.p.max_relative_yaw);
                wrap_angle(prev.yaw + d)
            };
            self.landing[j].yaw = yaw;
            self.used[j] = self.supports.iter().any(|s| s.w[2 + j] > 1e-12);
            if !after_stop {
                self.planned[self.n_planned] = PlannedStep {
                    foot,
                    pose: self.landing[j],
                    touchdown_in: td,
                };
                self.n_planned += 1;
            }
            prev = self.landing[j];
            foot = foot.other();
        }
    }

    fn build_qp(&mut self) {
        let n = self.n;
        let p = self.p;
        let (alpha, beta, gamma) = (p.alpha, p.beta, p.gamma);
        let nf = N_FOOTSTEPS;
        let fx = 2 * n;
        let fy = 2 * n + nf;
        let fixed = [self.slot_fixed(0), self.slot_fixed(1)];
        let qp = &mut self.qp;
        qp.h.fill(0.0);
        qp.g.fill(0.0);
        qp.c.fill(0.0);
        qp.l.fill(f64::NEG_INFINITY);
        qp.u.fill(f64::INFINITY);
        qp.lx.fill(f64::NEG_INFINITY);
        qp.ux.fill(f64::INFINITY);
        // jerk blocks: α Pvuᵀ Pvu + β Pzuᵀ Pzu + γ I (same for both axes); gradients
        // α Pvuᵀ (Pvs x₀ − v*) + β Pzuᵀ (Pzs x₀ − z_centre) − γ j* (module doc)
        for a in 0..n {
            for b in 0..=a {
                let mut s = 0.0;
                for i in 0..n {
                    s += alpha * self.pv_u[(i, a)] * self.pv_u[(i, b)]
                        + beta * self.pz_u[(i, a)] * self.pz_u[(i, b)];
                }
                if a == b {
                    s += gamma;
                }
                for o in [0, n] {
                    qp.h[(o + a, o + b)] = s;
                    qp.h[(o + b, o + a)] = s;
                }
            }
        }
        let x0 = [self.com_x, self.com_y];
        for i in 0..n {
            let sup = self.supports[i];
            for (ax, x0a) in x0.iter().enumerate() {
                let (ou, of) = if ax == 0 { (0, fx) } else { (n, fy) };
                let fc = sup.w[0] * coord(&fixed[0], ax) + sup.w[1] * coord(&fixed[1], ax);
                let d = row3(&self.pz_s, i).dot(x0a) - fc;
                let dv = row3(&self.pv_s, i).dot(x0a) - self.v_ref[(i, ax)];
                for a in 0..n {
                    qp.g[ou + a] += beta * self.pz_u[(i, a)] * d + alpha * self.pv_u[(i, a)] * dv;
                }
                qp.g[ou + i] -= gamma * self.j_ref[(i, ax)];
                for j in 0..nf {
                    let wj = sup.w[2 + j];
                    if wj == 0.0 {
                        continue;
                    }
                    qp.g[of + j] -= beta * wj * d;
                    for a in 0..n {
                        let v = -beta * wj * self.pz_u[(i, a)];
                        qp.h[(ou + a, of + j)] += v;
                        qp.h[(of + j, ou + a)] += v;
                    }
                    for k in 0..nf {
                        qp.h[(of + j, of + k)] += beta * wj * sup.w[2 + k];
                    }
                }
            }
        }
        // ZMP rows: samples 0..n−1 and the end of the current tick (index n)
        let dt = p.control_period;
        let extra = dt < self.tau[0] - 1e-9;
        let (adt, bdt) = jerk_integrator(dt);
        let hh = p.lipm.com_height / p.lipm.gravity;
        let zb = bdt[0] - hh * bdt[2];
        let rect = p.zmp_rectangle;
        for i in 0..=n {
            if i == n && !extra {
                continue;
            }
            let sup = self.supports[i];
            let fcx = sup.w[0] * fixed[0].x + sup.w[1] * fixed[1].x;
            let fcy = sup.w[0] * fixed[0].y + sup.w[1] * fixed[1].y;
            let (zsx, zsy) = if i < n {
                (
                    row3(&self.pz_s, i).dot(&x0[0]),
                    row3(&self.pz_s, i).dot(&x0[1]),
                )
            } else {
                let zs = |x: &Vector3<f64>| {
                    let y = adt * x;
                    y[0] - hh * y[2]
                };
                (zs(&x0[0]), zs(&x0[1]))
            };
            for q in 0..sup.n_yaws {
                let (s, c) = sup.yaws[q].sin_cos();
                let side = [
                    (c, s, -rect.back, rect.front),
                    (-s, c, -rect.right - sup.ext, rect.left + sup.ext),
                ];
                for (r, (ca, cb, lo, hi)) in side.into_iter().enumerate() {
                    let row = 4 * i + 2 * q + r;
                    if i < n {
                        for a in 0..n {
                            qp.c[(row, a)] = ca * self.pz_u[(i, a)];
                            qp.c[(row, n + a)] = cb * self.pz_u[(i, a)];
                        }
                    } else {
                        qp.c[(row, 0)] = ca * zb;
                        qp.c[(row, n)] = cb * zb;
                    }
                    for j in 0..nf {
                        qp.c[(row, fx + j)] = -ca * sup.w[2 + j];
                        qp.c[(row, fy + j)] = -cb * sup.w[2 + j];
                    }
                    let k = ca * (zsx - fcx) + cb * (zsy - fcy);
                    qp.l[row] = lo - k;
                    qp.u[row] = hi - k;
                }
            }
        }
        // footsteps
        let base = 4 * (n + 1);
        if let Gait::Walking {
            step, swing, stop, ..
        } = self.gait
        {
            let r = p.reachable;
            let mut foot = swing;
            for j in 0..nf {
                let prev = if j == 0 {
                    fixed[1]
                } else {
                    self.landing[j - 1]
                };
                let side = foot.side();
                let nominal = prev.transform(&Vector2::new(0.0, side * p.feet_distance));
                if !self.used[j] {
                    qp.h[(fx + j, fx + j)] += 1.0;
                    qp.h[(fy + j, fy + j)] += 1.0;
                    qp.g[fx + j] -= nominal.x;
                    qp.g[fy + j] -= nominal.y;
                    foot = foot.other();
                    continue;
                }
                let (s, c) = prev.yaw.sin_cos();
                let closing = stop == Some(step + j as u64);
                let (xl, xu) = if closing {
                    (0.0, 0.0)
                } else {
                    (r.x_min, r.x_max)
                };
                let (yl, yu) = if closing {
                    (side * p.feet_distance, side * p.feet_distance)
                } else if side > 0.0 {
                    (r.y_min, r.y_max)
                } else {
                    (-r.y_max, -r.y_min)
                };
                for (k, (ca, cb, lo, hi)) in
                    [(c, s, xl, xu), (-s, c, yl, yu)].into_iter().enumerate()
                {
                    let row = base + 2 * j + k;
                    qp.c[(row, fx + j)] = ca;
                    qp.c[(row, fy + j)] = cb;
                    let mut off = 0.0;
                    if j == 0 {
                        off = ca * prev.x + cb * prev.y;
                    } else {
                        qp.c[(row, fx + j - 1)] = -ca;
                        qp.c[(row, fy + j - 1)] = -cb;
                    }
                    qp.l[row] = lo + off;
                    qp.u[row] = hi + off;
                }
                foot = foot.other();
            }
            if let Some(f) = self.frozen {
                qp.lx[fx] = f.x;
                qp.ux[fx] = f.x;
                qp.lx[fy] = f.y;
                qp.ux[fy] = f.y;
            }
        } else {
            for j in 0..nf {
                qp.h[(fx + j, fx + j)] += 1.0;
                qp.h[(fy + j, fy + j)] += 1.0;
            }
        }
    }

    fn fill_horizon(&mut self) {
        let n = self.n;
        let w2 = self.p.lipm.omega().powi(2);
        let x = &self.solver.solution().x;
        for i in 0..n {
            let mut sx = Vector3::new(
                row3(&self.pp_s, i).dot(&self.com_x),
                row3(&self.pv_s, i).dot(&self.com_x),
                row3(&self.pa_s, i).dot(&self.com_x),
            );
            let mut sy = Vector3::new(
                row3(&self.pp_s, i).dot(&self.com_y),
                row3(&self.pv_s, i).dot(&self.com_y),
                row3(&self.pa_s, i).dot(&self.com_y),
            );
            for j in 0..=i {
                let (ux, uy) = (x[j], x[n + j]);
                sx += Vector3::new(self.pp_u[(i, j)], self.pv_u[(i, j)], self.pa_u[(i, j)]) * ux;
                sy += Vector3::new(self.pp_u[(i, j)], self.pv_u[(i, j)], self.pa_u[(i, j)]) * uy;
            }
            self.horizon[i] = HorizonSample {
                time: self.tau[i],
                x: sx,
                y: sy,
                zmp: Vector2::new(sx[0] - sx[2] / w2, sy[0] - sy[2] / w2),
                phase: self.supports[i].phase,
            };
        }
    }

    fn set_foot(&mut self, f: Foot, pose: FootPose, vel: FootVelocity) {
        match f {
            Foot::Left => {
                self.left = pose;
                self.left_vel = vel;
            }
            Foot::Right => {
                self.right = pose;
                self.right_vel = vel;
            }
        }
    }

    fn advance(&mut self, u: Vector2<f64>) {
        let dt = self.p.control_period;
        let (a, b) = jerk_integrator(dt);
        self.com_x = a * self.com_x + b * u.x;
        self.com_y = a * self.com_y + b * u.y;
        self.last_jerk = u;
        self.time += dt;
        let prev_t = self.t_in_step;
        self.t_in_step += dt;
        let ds = self.current_ds();
        let period = self.current_period();
        let Gait::Walking {
            step,
            swing,
            from_standing,
            stop,
        } = self.gait
        else {
            return;
        };
        if stop.is_none() {
            self.yaw_ref = wrap_angle(self.yaw_ref + self.cmd.yaw_rate * dt);
        }
        if let Some(k) = stop {
            if step == k + 1 && self.t_in_step >= self.p.double_support - 1e-9 {
                self.gait = Gait::Standing;
                self.t_in_step -= self.p.double_support;
                self.frozen = None;
                return;
            }
        }
        if prev_t < ds - 1e-9 && self.t_in_step >= ds - 1e-9 {
            let f = self.foot(swing);
            self.liftoff = f;
            self.swing_state = [
                Vector3::new(f.x, f.y, f.yaw),
                Vector3::zeros(),
                Vector3::zeros(),
            ];
        }
        if self.t_in_step > ds - 1e-9 {
            let remaining = period - prev_t;
            let target = self.landing[0];
            let cur = self.swing_state[0];
            let goal = Vector3::new(
                target.x,
                target.y,
                cur.z + angle_difference(target.yaw, cur.z),
            );
            let (mut pos, mut vel, mut acc) = (goal, Vector3::zeros(), Vector3::zeros());
            if remaining > dt + 1e-9 {
                for c in 0..3 {
                    let q = Quintic::new(
                        self.swing_state[0][c],
                        self.swing_state[1][c],
                        self.swing_state[2][c],
                        goal[c],
                        0.0,
                        0.0,
                        remaining,
                    );
                    (pos[c], vel[c], acc[c]) = q.sample(dt);
                }
            }
            self.swing_state = [pos, vel, acc];
            let ts = (self.t_in_step - ds).min(self.p.single_support);
            let vertical = crate::swing_foot::SwingTrajectory::new(
                &FootPose::default(),
                &FootPose::default(),
                self.p.single_support,
                self.p.swing_height,
            );
            let (zp, zv) = vertical.sample(ts);
            let ground = self.liftoff.z;
            self.set_foot(
                swing,
                FootPose::new(pos.x, pos.y, ground + zp.z, pos.z),
                FootVelocity {
                    x: vel.x,
                    y: vel.y,
                    z: zv.z,
                    yaw: vel.z,
                    ..Default::default()
                },
            );
            if self.frozen.is_none() && period - self.t_in_step <= self.p.freeze_time + 1e-9 {
                self.frozen = Some(self.landing[0]);
            }
        }
        if self.t_in_step >= period - 1e-9 {
            let landed = self.frozen.unwrap_or(self.landing[0]);
            self.set_foot(
                swing,
                FootPose {
                    z: self.liftoff.z,
                    ..landed
                },
                FootVelocity::default(),
            );
            self.t_in_step -= period;
            self.frozen = None;
            self.landing[0] = self.landing[1];
            let _ = from_standing;
            self.gait = Gait::Walking {
                step: step + 1,
                swing: swing.other(),
                from_standing: false,
                stop,
            };
        }
    }
}

fn coord(p: &FootPose, axis: usize) -> f64 {
    if axis == 0 {
        p.x
    } else {
        p.y
    }
}

fn row3(m: &DMatrix<f64>, i: usize) -> Vector3<f64> {
    Vector3::new(m[(i, 0)], m[(i, 1)], m[(i, 2)])
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Re-simulates both unit responses of the TALOS gait from their grid velocities and jerks:
    /// the ZMP lies on `z_centre` at every sample and the step closes periodically.
    #[test]
    fn nominal_gait_tracks_the_support_centres() {
        let p = crate::test_fixtures::talos_mpc();
        let (t, ds) = (p.sample_period, p.double_support);
        let h = p.lipm.com_height / p.lipm.gravity;
        let g = NominalGait::new(t, 12, ds, h).unwrap();
        let (a, b) = jerk_integrator(t);
        for (r, prev, sign) in [(0, 0.0, 1.0), (1, -1.0, -1.0)] {
            // position and acceleration at l = 0 from the ZMP and velocity relations
            let (v0, v1) = (g.vel[r][0], g.vel[r][1]);
            let j0 = g.jerk[r][0];
            let acc0 = (v1 - v0 - j0 * t * t / 2.0) / t;
            let mut x = Vector3::new(prev + h * acc0, v0, acc0);
            let x0 = x;
            for l in 0..12 {
                assert!((x[1] - g.vel[r][l]).abs() < 1e-9, "{r} {l}");
                x = a * x + b * g.jerk[r][l];
                let local = (l + 1) as f64 * t;
                let centre = if local < ds {
                    prev + (1.0 - prev) * local / ds
                } else {
                    1.0
                };
                assert!((x[0] - h * x[2] - centre).abs() < 1e-9, "{r} {l}");
            }
            let shift = Vector3::new(1.0 + prev, 0.0, 0.0);
            assert!((x - sign * x0 - shift).norm() < 1e-9, "{r}");
        }
    }
}
