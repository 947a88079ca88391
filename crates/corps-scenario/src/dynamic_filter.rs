//! The dynamic filter in the loop for footstep-list walks (seed 002 §2.2.2, §4.5, after
//! Kajita et al. 2003): the LIPM plan ignores the limbs' momentum, so the whole body following
//! it puts its ZMP `p_MB` elsewhere than the plan's LIPM ZMP `p_ref`. Before the run, the plan
//! is replayed through the kinematic IK (seed 000's controller A without the simulator), `p_MB`
//! is taken from the whole body's centroidal momentum rate, and
//! [`corps_walk::dynamic_filter::DynamicFilter`] turns `Δp = p_ref − p_MB` into a CoM
//! correction `Δc` (one pass, as in jrl-walkgen). A second replay of the corrected plan
//! measures what the pass achieved.
//!
//! ZMP of the whole body on the ground plane `z = z₀` (from the Newton–Euler equations about
//! the CoM: the ground wrench is `f = ṗ + m g e_z` and its moment about `c` is `L̇`):
//! `p_x = c_x − ((c_z − z₀) f_x + L̇_y) / f_z`,  `p_y = c_y − ((c_z − z₀) f_y − L̇_x) / f_z`.

use crate::controller::{IkController, Measured, WholeBodyController};
use crate::error::{bail, Context, Result};
use crate::gains;
use crate::metrics::DynamicFilterMetrics;
use crate::motion::{MotionPlan, Targets};
use corps_control::stabilizer::Wrench;
use corps_model::{compute_centroidal_momentum, difference_to, Data};
use corps_robot::Robot;
use corps_sim::Command;
use corps_walk::dynamic_filter::DynamicFilter;
use nalgebra::{DVector, Isometry3, Vector2, Vector3};
use std::path::Path;

/// Ticks of the IK at the first target before the replay is recorded.
const WARM_UP_TICKS: usize = 2000;

/// The multibody ZMP error of a plan: `p_ref − p_MB` per tick, world x and y.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ZmpError {
    pub x: Vec<f64>,
    pub y: Vec<f64>,
}

impl ZmpError {
    /// Root mean square and peak of |Δp| per axis [m].
    pub fn rms_and_peak(&self) -> [(f64, f64); 2] {
        [&self.x, &self.y].map(|e| {
            let n = e.len().max(1) as f64;
            let rms = (e.iter().map(|v| v * v).sum::<f64>() / n).sqrt();
            let peak = e.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            (rms, peak)
        })
    }
}

/// Replays `ticks` ticks of `plan` (period `dt`) through the kinematic IK from the
/// configuration `q0` (posture task towards `posture`) with the robot's `ik_position` gains
/// and returns `p_ref − p_MB` per tick.
pub fn multibody_zmp_error(
    robot: &Robot,
    q0: &DVector<f64>,
    posture: &DVector<f64>,
    plan: &mut MotionPlan,
    ticks: usize,
    dt: f64,
    gravity: f64,
) -> Result<ZmpError> {
    let source = gains::GainsSource::resolve(None, "ik_position", robot, Path::new("."))?;
    let gains: gains::IkGainsFile =
        gains::load(&source, &toml::Table::new()).context("IK gains")?;
    let mut ik = IkController::new(robot, gains, dt, q0, posture)?;
    let model = &robot.model;
    let measured = Measured {
        com: Vector3::zeros(),
        com_velocity: Vector3::zeros(),
        zmp: None,
        hands: &[],
        feet: [Isometry3::identity(); 2],
        foot_wrenches: [Wrench::default(); 2],
    };
    let mut targets: Targets = plan.initial_targets();
    let mut data = Data::new(model);
    let (nq, nv) = (model.nq, model.nv);
    let mut q_prev = q0.clone();
    let mut v = DVector::zeros(nv);
    // Per tick: CoM, linear momentum, angular momentum about the CoM, LIPM ZMP, ground.
    let mut com = Vec::with_capacity(ticks);
    let mut lin = Vec::with_capacity(ticks);
    let mut ang = Vec::with_capacity(ticks);
    let mut zmp_ref = Vec::with_capacity(ticks);
    let mut ground = Vec::with_capacity(ticks);
    let empty: [f64; 0] = [];
    // The IK first pulls the handover state onto the targets (a few mm, within ≈ 0.3 s at its
    // gains): done at t = 0 before recording, or that transient's momentum rate would count
    // as ZMP error.
    plan.sample(0.0, &mut targets);
    for _ in 0..WARM_UP_TICKS {
        if let Some(reason) = ik.tick(0.0, &empty, &empty, &targets, &measured) {
            bail!("the IK replay failed at its start: {reason}");
        }
    }
    if let Command::Position { q_ref, .. } = ik.command() {
        q_prev.copy_from(q_ref);
    }
    for tick in 0..ticks {
        let t = tick as f64 * dt;
        plan.sample(t, &mut targets);
        if let Some(reason) = ik.tick(t, &empty, &empty, &targets, &measured) {
            bail!("the IK replay failed at t = {t:.3} s: {reason}");
        }
        let Command::Position { q_ref, .. } = ik.command() else {
            unreachable!("the IK commands positions")
        };
        debug_assert_eq!(q_ref.len(), nq);
        difference_to(model, q_prev.as_slice(), q_ref.as_slice(), v.as_mut_slice())?;
        v /= dt;
        let h = compute_centroidal_momentum(model, &mut data, q_ref.as_slice(), v.as_slice())?;
        com.push(data.com);
        lin.push(h.linear);
        ang.push(h.angular);
        let z0 = targets.contact_ground();
        zmp_ref.push(targets.reference_zmp(z0, gravity));
        ground.push(z0);
        q_prev.copy_from(q_ref);
    }
    let mass = model.total_mass();
    let mut err = ZmpError {
        x: Vec::with_capacity(ticks),
        y: Vec::with_capacity(ticks),
    };
    for k in 0..ticks {
        // Central differences of the momenta (one-sided at the ends); the velocities are
        // backward differences, so the rate at k is centred on k − ½ … k + ½.
        let (a, b) = (k.saturating_sub(1), (k + 1).min(ticks - 1));
        let span = (b - a).max(1) as f64 * dt;
        let f = (lin[b] - lin[a]) / span + Vector3::new(0.0, 0.0, mass * gravity);
        let dl = (ang[b] - ang[a]) / span;
        let c = com[k];
        let h = c.z - ground[k];
        let p = Vector2::new(c.x - (h * f.x + dl.y) / f.z, c.y - (h * f.y - dl.x) / f.z);
        err.x.push(zmp_ref[k][0] - p.x);
        err.y.push(zmp_ref[k][1] - p.y);
    }
    Ok(err)
}

/// One pass of the dynamic filter on the footstep-list walk of `plan` (`ticks` periods):
/// replays it, corrects its CoM with the preview control that planned it (same period, LIPM
/// and horizon), replays the corrected plan and reports both errors.
pub fn filter_walk(
    robot: &Robot,
    q0: &DVector<f64>,
    posture: &DVector<f64>,
    plan: &mut MotionPlan,
    ticks: usize,
) -> Result<DynamicFilterMetrics> {
    let Some(params) = plan.walk().and_then(|w| w.preview_params()).copied() else {
        bail!("the dynamic filter needs a walk planned by preview control (kind = \"walk\")");
    };
    let (dt, gravity) = (params.period, params.lipm.gravity);
    let before = multibody_zmp_error(robot, q0, posture, plan, ticks, dt, gravity)?;
    let mut filter = DynamicFilter::new(&params).context("dynamic filter")?;
    let n = filter.horizon();
    // The error held at its last value past the end, so that every tick's window is a slice.
    let padded = |e: &[f64]| {
        let last = e.last().copied().unwrap_or(0.0);
        let mut p = Vec::with_capacity(e.len() + n);
        p.extend_from_slice(e);
        p.resize(e.len() + n, last);
        p
    };
    let (ex, ey) = (padded(&before.x), padded(&before.y));
    let mut dx = Vec::with_capacity(ticks);
    let mut dy = Vec::with_capacity(ticks);
    for k in 0..ticks {
        // The correction at tick k is the filter's state there (as the pattern generator's
        // CoM), then the filter advances over the window starting at k.
        let (cx, cy) = filter.correction();
        dx.push(cx);
        dy.push(cy);
        filter
            .step(&ex[k..=k + n], &ey[k..=k + n])
            .context("dynamic filter")?;
    }
    let max_correction = [&dx, &dy].map(|d| d.iter().fold(0.0f64, |m, c| m.max(c[0].abs())));
    if let Some(walk) = plan.walk_mut() {
        walk.correct_com(&dx, &dy);
    }
    let after = multibody_zmp_error(robot, q0, posture, plan, ticks, dt, gravity)?;
    Ok(DynamicFilterMetrics {
        before: before.rms_and_peak(),
        after: after.rms_and_peak(),
        max_correction,
    })
}
