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
use crate::preview_control::{PreviewAxis, PreviewController, PreviewParams};
use crate::reference::WalkingReference;
use crate::WalkError;
use nalgebra::Vector3;

/// Preview-control walking pattern generator over a footstep plan.
#[derive(Debug, Clone)]
pub struct PreviewWalk {
    plan: FootstepPlan,
    controller: PreviewController,
    params: PreviewParams,
    x: PreviewAxis,
    y: PreviewAxis,
    tick: u64,
    /// The ZMP reference over the preview window, `buf[j]` at plan time `tp + j T`; slid by
    /// one sample per step, so each step samples the plan once instead of `N + 1` times.
    buf_x: Vec<f64>,
    buf_y: Vec<f64>,
    /// Whether the window holds the samples for the current tick.
    window_filled: bool,
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
            x: PreviewAxis::at_rest(start.x),
            y: PreviewAxis::at_rest(start.y),
            tick: 0,
            buf_x: vec![0.0; n + 1],
            buf_y: vec![0.0; n + 1],
            window_filled: false,
        })
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
        let n = self.buf_x.len();
        if self.window_filled {
            self.buf_x.copy_within(1.., 0);
            self.buf_y.copy_within(1.., 0);
            let (z, _) = self.plan.zmp_at(tp + (n - 1) as f64 * dt);
            (self.buf_x[n - 1], self.buf_y[n - 1]) = (z.x, z.y);
        } else {
            for j in 0..n {
                let (z, _) = self.plan.zmp_at(tp + j as f64 * dt);
                (self.buf_x[j], self.buf_y[j]) = (z.x, z.y);
            }
            self.window_filled = true;
        }
        let s = self.plan.sample(tp);
        let [gz, gz_rate, gz_acc] = self.plan.com_ground(tp);
        let m = &self.controller.model;
        let zc = self.params.lipm.com_height;
        let mut r = WalkingReference {
            time: t,
            com: Vector3::new(self.x.x[0], self.y.x[0], gz + zc),
            com_vel: Vector3::new(self.x.x[1], self.y.x[1], gz_rate),
            com_acc: Vector3::new(self.x.x[2], self.y.x[2], gz_acc),
            zmp: Vector3::new(m.zmp(&self.x.x), m.zmp(&self.y.x), s.zmp.z),
            left_foot: s.left,
            right_foot: s.right,
            left_foot_vel: s.left_vel,
            right_foot_vel: s.right_vel,
            phase: s.phase,
            ..Default::default()
        };
        r.complete(self.params.lipm.omega());
        self.controller.step(&mut self.x, &self.buf_x)?;
        self.controller.step(&mut self.y, &self.buf_y)?;
        self.tick += 1;
        Ok(r)
    }
}
