//! Footstep-driven pattern generator: Kajita 2003 preview control of the LIPM tracking the
//! piecewise-linear ZMP reference of a [`FootstepPlan`], producing a [`WalkingReference`] per
//! control period.
//!
//! The plan starts after a standing phase as long as the preview window (`N T`, 1.6 s by
//! default): the controller must see the first ZMP transfer a whole window ahead, otherwise the
//! non-minimum-phase cart-table has to throw its ZMP far outside the feet to catch up (measured:
//! 0.84 m at the first tick when the plan starts at t = 0). Plan time is generator time minus
//! [`PreviewWalk::lead_time`].
//!
//! The CoM height is `z_c` above the support height, which changes smoothly over the step
//! period after each touch-down ([`FootstepPlan::com_ground`]), so that on stairs the CoM
//! climbs with the support foot; the preview control itself keeps the LIPM's constant height.

use crate::footsteps::FootstepPlan;
use crate::min_jerk::min_jerk;
use crate::preview_control::{PreviewAxis, PreviewController, PreviewParams};
use crate::reference::WalkingReference;
use crate::WalkError;
use nalgebra::Vector3;

/// The fraction of the standing window over which a walk that starts off the middle of the
/// feet moves its ZMP reference to the plan ([`PreviewWalk::starting_at`]). Measured on the
/// 20 cm plan with the CoM 27 mm ahead: a move over the last quarter (0.4 s) changes the
/// LIPM's ZMP by at most 4.5 mm per 5 ms tick and pushes it 4.9 mm forward first; over the
/// last half, 14.5 and 15.9 mm; over the whole window, starting at once, 0.10 m.
pub const START_BLEND: f64 = 0.25;

/// Preview-control walking pattern generator over a footstep plan.
#[derive(Debug, Clone)]
pub struct PreviewWalk {
    plan: FootstepPlan,
    controller: PreviewController,
    params: PreviewParams,
    /// The LIPM per axis, relative to `origin`.
    x: PreviewAxis,
    y: PreviewAxis,
    /// Where the preview control's coordinates start (the CoM at rest at the first tick): a
    /// finite window makes the control slightly position-dependent (its gains give
    /// `G_x[0] + Σ G_d ≠ 0`), so a robot at rest at the origin of these coordinates gets no
    /// command until the reference moves.
    origin: (f64, f64),
    tick: u64,
    /// The ZMP reference over the preview window, per axis.
    window_x: PreviewWindow,
    window_y: PreviewWindow,
    /// Whether the windows hold the samples for the current tick.
    window_filled: bool,
    /// Where the CoM stands before the plan, if not above the middle of the feet.
    start: Option<(f64, f64)>,
}

/// A sliding window of `len` samples kept contiguous without shifting: every sample is
/// stored twice, at slot `s` and `s + len` of a `2 len` buffer, so the window starting at
/// `head` is always `buf[head..head + len]`. Each tick writes one new sample.
#[derive(Debug, Clone)]
struct PreviewWindow {
    buf: Vec<f64>,
    head: usize,
}

impl PreviewWindow {
    fn new(len: usize) -> Self {
        Self {
            buf: vec![0.0; 2 * len],
            head: 0,
        }
    }

    fn len(&self) -> usize {
        self.buf.len() / 2
    }

    /// Sets sample `j` of the current window.
    fn set(&mut self, j: usize, value: f64) {
        let n = self.len();
        let slot = (self.head + j) % n;
        self.buf[slot] = value;
        self.buf[slot + n] = value;
    }

    /// Drops the oldest sample and appends `value` as the newest.
    fn slide(&mut self, value: f64) {
        let n = self.len();
        self.head = (self.head + 1) % n;
        self.set(n - 1, value);
    }

    fn samples(&self) -> &[f64] {
        &self.buf[self.head..self.head + self.len()]
    }
}

impl PreviewWalk {
    /// A generator for `plan` with preview control of parameters `params` (with integral
    /// action), the CoM starting at rest above the middle of the initial feet.
    pub fn new(plan: FootstepPlan, params: PreviewParams) -> Result<Self, WalkError> {
        let controller = PreviewController::with_integral(&params)?;
        let n = controller.horizon();
        let start = plan.sample(0.0).zmp;
        Ok(Self {
            plan,
            controller,
            params,
            x: PreviewAxis::at_rest(0.0),
            y: PreviewAxis::at_rest(0.0),
            origin: (start.x, start.y),
            tick: 0,
            window_x: PreviewWindow::new(n + 1),
            window_y: PreviewWindow::new(n + 1),
            window_filled: false,
            start: None,
        })
    }

    /// The same generator starting from a robot at rest with its CoM at `(x, y)` instead of
    /// above the middle of its feet (TALOS' settled half-sitting stands 27 mm ahead of it).
    /// The ZMP reference stays at `(x, y)` for most of the standing window
    /// ([`PreviewWalk::lead_time`]) and moves to the plan's first ZMP by min-jerk over its
    /// last [`START_BLEND`], so the reference begins where the robot stands and the preview
    /// control, seeing the move a whole window ahead, shifts the CoM without a jerk.
    pub fn starting_at(mut self, x: f64, y: f64) -> Self {
        self.x = PreviewAxis::at_rest(0.0);
        self.y = PreviewAxis::at_rest(0.0);
        self.origin = (x, y);
        self.start = Some((x, y));
        self.window_filled = false;
        self
    }

    /// The ZMP reference (x, y) at plan time `tp`, relative to the origin.
    fn reference_zmp(&self, tp: f64) -> (f64, f64) {
        let (z, _) = self.plan.zmp_at(tp);
        let (ox, oy) = self.origin;
        match self.start {
            Some((x0, y0)) if tp < 0.0 => {
                let blend = START_BLEND * self.lead_time();
                let lam = (tp + blend) / blend;
                let x = min_jerk(x0, z.x, lam, blend)[0];
                let y = min_jerk(y0, z.y, lam, blend)[0];
                (x - ox, y - oy)
            }
            _ => (z.x - ox, z.y - oy),
        }
    }

    /// The plan.
    pub fn plan(&self) -> &FootstepPlan {
        &self.plan
    }

    /// The preview controller (gains).
    pub fn controller(&self) -> &PreviewController {
        &self.controller
    }

    /// Current time `k T` (plan time plus [`PreviewWalk::lead_time`]).
    pub fn time(&self) -> f64 {
        self.tick as f64 * self.params.period
    }

    /// Standing time before the plan starts: the preview window `N T`.
    pub fn lead_time(&self) -> f64 {
        self.controller.horizon() as f64 * self.params.period
    }

    /// Time of the plan corresponding to generator time `t`.
    pub fn plan_time(&self, t: f64) -> f64 {
        t - self.lead_time()
    }

    /// `true` once the plan is over.
    pub fn finished(&self) -> bool {
        self.plan_time(self.time()) > self.plan.duration()
    }

    /// The reference at the current time, then one control period of preview control.
    /// Never allocates.
    pub fn step(&mut self) -> Result<WalkingReference, WalkError> {
        let t = self.time();
        let tp = self.plan_time(t);
        let dt = self.params.period;
        let n = self.window_x.len();
        if self.window_filled {
            let (x, y) = self.reference_zmp(tp + (n - 1) as f64 * dt);
            self.window_x.slide(x);
            self.window_y.slide(y);
        } else {
            for j in 0..n {
                let (x, y) = self.reference_zmp(tp + j as f64 * dt);
                self.window_x.set(j, x);
                self.window_y.set(j, y);
            }
            self.window_filled = true;
        }
        let s = self.plan.sample(tp);
        let [gz, gz_rate, gz_acc] = self.plan.com_ground(tp);
        let m = &self.controller.model;
        let (ox, oy) = self.origin;
        let zc = self.params.lipm.com_height;
        let mut r = WalkingReference {
            time: t,
            com: Vector3::new(ox + self.x.x[0], oy + self.y.x[0], gz + zc),
            com_vel: Vector3::new(self.x.x[1], self.y.x[1], gz_rate),
            com_acc: Vector3::new(self.x.x[2], self.y.x[2], gz_acc),
            zmp: Vector3::new(ox + m.zmp(&self.x.x), oy + m.zmp(&self.y.x), s.zmp.z),
            left_foot: s.left,
            right_foot: s.right,
            left_foot_vel: s.left_vel,
            right_foot_vel: s.right_vel,
            phase: s.phase,
            ..Default::default()
        };
        r.complete(self.params.lipm.omega());
        self.controller.step(&mut self.x, self.window_x.samples())?;
        self.controller.step(&mut self.y, self.window_y.samples())?;
        self.tick += 1;
        Ok(r)
    }
}
