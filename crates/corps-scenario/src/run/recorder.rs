//! The run's observer: from each tick's true state, estimate, references and command it keeps
//! the metrics, builds the time-series row (handed to the sinks and the bounded series) and
//! decides the verdict.

use super::columns::push_stabilizer;
use super::contacts::{self, ContactSample, ZMP_MIN_FZ};
use super::RowSink;
use crate::controller::ScenarioController;
use crate::gait::PassivityGaitMeasure;
use crate::metrics::{Metrics, TickTimer};
use crate::series::PlotBuffer;
use crate::targets::Targets;
use crate::ScenarioError;
use corps_loop::verdict::{TickSample, Verdict, VerdictObserver};
use corps_loop::{Flow, Observer, Tick, Truth};
use corps_model::spatial::Se3;
use corps_model::Model;
use corps_model::STANDARD_GRAVITY as GRAVITY;
use nalgebra::Vector3;
use std::sync::Arc;

/// What the recorder knows of the robot and the run before the first tick.
pub(crate) struct RecorderSetup {
    pub model: Arc<Model>,
    /// Sole frames and the joints of the feet's bodies, left then right.
    pub soles: [usize; 2],
    pub foot_joints: [usize; 2],
    /// The body of a `[press]` tool, whose contact is meant.
    pub tool_joint: Option<usize>,
    /// Each ankle's (roll, pitch) joints as actuated indices, for the gait measure.
    pub ankles: [[usize; 2]; 2],
    pub base0: Vector3<f64>,
    /// The walk proper (s since the handover), if the motion walks.
    pub walking_window: Option<(f64, f64)>,
    pub stabilized: bool,
    pub dt: f64,
    pub columns: usize,
    /// Stop the run this long (s) after its first failure (None: run on to the end).
    pub stop_after_failure: Option<f64>,
    /// The run follows a person: the follow columns are logged.
    pub following: bool,
}

/// Observer of a scenario run.
pub(crate) struct Recorder<'s, 'k> {
    pub setup: RecorderSetup,
    pub metrics: Metrics,
    pub verdict: VerdictObserver,
    pub series: PlotBuffer,
    pub tick_time: TickTimer,
    pub pgm: PassivityGaitMeasure,
    pub force_sum: [f64; 2],
    pub estimator_errors: usize,
    pub first_estimator_error: Option<String>,
    /// The first error of a sink (the run stopped there).
    pub sink_error: Option<ScenarioError>,
    sinks: &'s mut [&'k mut dyn RowSink],
    contact_start: [Option<Vector3<f64>>; 2],
    row: Vec<f64>,
    /// Each foot's planned position at its last lift-off, while it swings.
    lift_off: [Option<Vector3<f64>>; 2],
}

impl<'s, 'k> Recorder<'s, 'k> {
    /// The follow columns and figures of a run with a person; the reason when the person is
    /// lost (the CoM farther than allowed from its point).
    fn follow(&mut self, truth: &Truth, targets: &Targets) -> Option<String> {
        let Some(f) = targets.follow else {
            self.row.extend([f64::NAN; 5]);
            return None;
        };
        let error = (truth.com.x - f.point[0]).hypot(truth.com.y - f.point[1]);
        self.row
            .extend([f.person[0], f.person[1], f.point[0], f.point[1], error]);
        let c = self.metrics.conav.get_or_insert_with(Default::default);
        c.error_sum += error;
        c.ticks += 1;
        c.mean_following_error_m = c.error_sum / c.ticks as f64;
        c.max_following_error_m = c.max_following_error_m.max(error);
        // Steps of the plan: each foot's lift-off and touchdown; sideways across the heading.
        let (sin, cos) = targets.waist_yaw.sin_cos();
        for (k, foot) in targets.feet.iter().enumerate() {
            let at = foot.reference.placement.translation;
            match (self.lift_off[k], foot.supporting) {
                (None, false) => self.lift_off[k] = Some(at),
                (Some(start), true) => {
                    let d = at - start;
                    let sideways = (-sin * d.x + cos * d.y).abs();
                    c.steps += 1;
                    c.max_lateral_step_m = c.max_lateral_step_m.max(sideways);
                    self.lift_off[k] = None;
                }
                _ => {}
            }
        }
        (error > f.lost_beyond).then(|| {
            format!(
                "the CoM {error:.2} m from the point it holds by the person (lost beyond {} m)",
                f.lost_beyond
            )
        })
    }

    pub(crate) fn new(
        setup: RecorderSetup,
        metrics: Metrics,
        verdict: VerdictObserver,
        sinks: &'s mut [&'k mut dyn RowSink],
    ) -> Self {
        let columns = setup.columns;
        Self {
            setup,
            metrics,
            verdict,
            series: PlotBuffer::new(columns),
            tick_time: TickTimer::default(),
            pgm: PassivityGaitMeasure::default(),
            force_sum: [0.0; 2],
            estimator_errors: 0,
            first_estimator_error: None,
            sink_error: None,
            sinks,
            contact_start: [None, None],
            lift_off: [None, None],
            row: Vec::with_capacity(columns),
        }
    }

    fn walking(&self, t: f64) -> bool {
        self.setup
            .walking_window
            .is_some_and(|(a, b)| t >= a && t < b)
    }
}

/// The height of the lower sole.
pub(crate) fn support(feet: &[Se3; 2]) -> f64 {
    feet[0].translation.z.min(feet[1].translation.z)
}

impl Observer<ScenarioController> for Recorder<'_, '_> {
    fn observe(&mut self, tick: &Tick<'_, ScenarioController>) -> Flow {
        let Some(truth) = &tick.sensed.truth else {
            // The metrics, the rows and the verdict compare with the true state: a plant
            // without one (a real robot) gets none of them from this recorder.
            return Flow::Continue;
        };
        let s = &self.setup;
        let t = tick.t;
        let placements = s.soles.map(|f| truth.frame_placement(&s.model, f));
        let mut contact = contacts::measure(truth, &s.foot_joints, s.tool_joint, &placements);
        let (w, w_pos, joint_power) = work(truth, &s.model, s.dt);
        let walking = self.walking(t);
        let m = &mut self.metrics;
        m.work += w;
        m.positive_work += w_pos;
        let targets: &Targets = tick.controller.tracked_targets().unwrap_or(tick.references);
        if walking {
            self.pgm.push(
                truth.applied_torques.as_slice(),
                &s.ankles,
                [targets.feet[0].supporting, targets.feet[1].supporting],
            );
        }
        let state_finite = truth.q.iter().chain(truth.v.iter()).all(|x| x.is_finite());
        let base_speed = Vector3::new(truth.v[0], truth.v[1], truth.v[2]).norm();
        let true_base = Vector3::new(truth.q[0], truth.q[1], truth.q[2]);
        if let Some(e) = tick.estimator_error {
            self.estimator_errors += 1;
            self.first_estimator_error
                .get_or_insert_with(|| format!("t = {t:.3} s: {e}"));
        }
        let est = tick.estimate;
        let base_estimate = Vector3::new(est.q[0], est.q[1], est.q[2]);
        m.estimate_error.push(
            (est.com - truth.com).norm(),
            (base_estimate - true_base).norm(),
        );
        // The ZMP as the thesis measured it, from the ankle F/T sensors' wrenches, placed at
        // the soles' true placements so that it compares with the world's reference (the
        // estimator's own ZMP is in its estimated world, for the controller).
        let sensed = [0, 1].map(|k| corps_estimation::FootEstimate {
            placement: placements[k],
            ..est.feet[k]
        });
        contact.zmp = corps_estimation::zmp_of_feet(&sensed).map(|p| [p.x, p.y]);
        let commanded = match corps_loop::Controller::command(tick.controller) {
            corps_loop::Command::Torque(t) => Some(t),
            _ => None,
        };
        sum_tick(
            m,
            &s.model,
            truth,
            commanded,
            targets,
            &placements,
            contact.zmp,
        );
        self.tick_time.push(tick.tick_us);
        if let Some(r) = tick.fallback {
            m.fallbacks += 1;
            m.first_fallback
                .get_or_insert_with(|| format!("t = {t:.3} s: {r}"));
        }
        for (sum, fz) in self.force_sum.iter_mut().zip(contact.foot_fz) {
            *sum += fz;
        }
        // Landings and the hold figures count until the run fails (a fallen robot's feet flail).
        let upright = self.verdict.failure().is_none();
        let end = self.metrics.duration;
        if !upright {
            self.metrics.hold = None;
        } else if t >= end - crate::metrics::HOLD_WINDOW - 1e-9 {
            let h = (self.metrics.hold).get_or_insert_with(|| crate::metrics::HoldFigures {
                from_t: t,
                ..Default::default()
            });
            let torque_x =
                [0, 1].map(|k| (contact.foot_fz[k] > ZMP_MIN_FZ).then_some(est.feet[k].wrench[3]));
            let own = tick.controller.controller_com();
            let offset = contact.zmp.map(|z| {
                [
                    [z[0] - truth.com.x, z[1] - truth.com.y],
                    [z[0] - own.x, z[1] - own.y],
                ]
            });
            h.push(torque_x, offset);
        }
        let m = &mut self.metrics;
        record(
            m,
            &mut self.row,
            Sample {
                upright,
                t,
                base: true_base,
                base0: s.base0,
                com: truth.com,
                feet: placements.map(|p| p.translation),
                targets,
                contact: &contact,
                tick_us: tick.tick_us,
                walking,
                com_estimate: est.com,
                base_estimate,
                joint_power,
            },
            &mut self.contact_start,
        );
        if s.stabilized {
            push_stabilizer(&mut self.row, tick.controller.stabilizer_output(), &contact);
        }
        let mut lost = None;
        if s.following {
            lost = self.follow(truth, targets);
        }
        tick.controller.push_channels(&mut self.row);
        self.series.push(&self.row);
        for sink in self.sinks.iter_mut() {
            let done = sink
                .row(tick.index, &self.row)
                .and_then(|()| sink.state(tick.index, truth));
            if let Err(e) = done {
                self.sink_error = Some(e);
                return Flow::Stop;
            }
        }
        let sample = TickSample {
            t,
            com_height: truth.com.z - support(&placements),
            base_speed,
            total_contact_force: contact.total,
            other_contact_force: contact.other,
            state_finite,
            safe_command: tick.fallback.is_some(),
        };
        if self.verdict.observe(&sample).is_some() {
            return Flow::Stop;
        }
        // Losing the person ends the run, unless an earlier failure already decides it.
        if let Some(reason) = lost.filter(|_| self.verdict.failure().is_none()) {
            self.verdict.task_failed(Verdict::LostHuman, t, reason);
            return Flow::Stop;
        }
        let failed_at = self.verdict.failure().and_then(|f| f.t);
        match (self.setup.stop_after_failure, failed_at) {
            (Some(grace), Some(at)) if t - at >= grace => Flow::Stop,
            _ => Flow::Continue,
        }
    }
}

/// Mechanical work of the joints over one step and their power: (Σ|τ q̇| dt,
/// Σ max(τ q̇, 0) dt, q̇ᵀτ).
fn work(truth: &Truth, model: &Model, dt: f64) -> (f64, f64, f64) {
    let tau = &truth.applied_torques;
    let v = &truth.v;
    let first = model.nv - tau.len();
    (0..tau.len()).fold((0.0, 0.0, 0.0), |(a, p, total), k| {
        let power = tau[k] * v[first + k];
        (a + power.abs() * dt, p + power.max(0.0) * dt, total + power)
    })
}

struct Sample<'a> {
    /// The run has not failed yet.
    upright: bool,
    t: f64,
    base: Vector3<f64>,
    base0: Vector3<f64>,
    com: Vector3<f64>,
    feet: [Vector3<f64>; 2],
    targets: &'a Targets,
    contact: &'a ContactSample,
    tick_us: f64,
    /// Within the walk proper (the walking statistics count this tick).
    walking: bool,
    /// The controller's estimate of the CoM and base position.
    com_estimate: Vector3<f64>,
    base_estimate: Vector3<f64>,
    /// q̇ᵀτ of the torques the joints applied (W).
    joint_power: f64,
}

/// Updates the metrics with one tick and fills `row` with its tracked signals, in
/// [`log_columns`]' order (without the stabilizer's).
fn record(
    m: &mut Metrics,
    row: &mut Vec<f64>,
    s: Sample,
    contact_start: &mut [Option<Vector3<f64>>; 2],
) {
    let c_ref = &s.targets.com;
    // Reference ZMP of the CoM reference on the measured contact plane.
    let zmp_ref = s.targets.reference_zmp(s.contact.plane_z, GRAVITY);
    let mut walking = m.while_walking.as_mut().filter(|_| s.walking);
    for k in 0..3 {
        let e = s.com[k] - c_ref.pos[k];
        m.com_error[k].push(e);
        if let Some(w) = walking.as_deref_mut() {
            w.com_error[k].push(e);
        }
    }
    if let Some(p) = s.contact.zmp {
        for k in 0..2 {
            let e = p[k] - zmp_ref[k];
            m.zmp_error[k].push(e);
            if let Some(w) = walking.as_deref_mut() {
                w.zmp_error[k].push(e);
            }
        }
    }
    row.clear();
    row.push(s.t);
    row.extend(s.com.iter());
    row.extend(c_ref.pos.iter());
    let zmp = s.contact.zmp.unwrap_or([f64::NAN; 2]);
    row.extend(zmp);
    row.extend([zmp_ref[0], zmp_ref[1]]);
    for (k, foot) in m.feet.iter_mut().enumerate() {
        let target = &s.targets.feet[k];
        let r = target.reference.placement.translation;
        for (a, stat) in foot.error.iter_mut().enumerate() {
            let e = s.feet[k][a] - r[a];
            stat.push(e);
            if let Some(w) = walking.as_deref_mut() {
                w.feet_error[k][a].push(e);
            }
        }
        foot.force_peak = foot.force_peak.max(s.contact.foot_fz[k]);
        // Slip: horizontal motion while the plan has the foot on the ground and it is loaded.
        foot.swung |= !target.supporting;
        if target.supporting && s.contact.foot_fz[k] > ZMP_MIN_FZ {
            if contact_start[k].is_none() && std::mem::take(&mut foot.swung) && s.upright {
                let error = (s.feet[k] - r).xy().norm();
                foot.landings += 1;
                foot.landing_error_mean += (error - foot.landing_error_mean) / foot.landings as f64;
                foot.landing_error_max = foot.landing_error_max.max(error);
            }
            let start = *contact_start[k].get_or_insert(s.feet[k]);
            foot.slip = foot.slip.max((s.feet[k] - start).xy().norm());
        } else {
            contact_start[k] = None;
        }
        row.extend([s.feet[k].z, r.z]);
    }
    row.extend(s.contact.foot_fz);
    row.extend(s.base.iter());
    row.extend(s.com_estimate.iter());
    row.extend(s.base_estimate.iter());
    row.push(s.joint_power);
    row.push(s.tick_us);
    let drift = (s.base - s.base0).norm();
    m.base_drift = drift;
    m.base_drift_peak = m.base_drift_peak.max(drift);
    m.min_base_height = m.min_base_height.min(s.base.z);
    m.other_contact_peak = m.other_contact_peak.max(s.contact.other);
}

/// Folds one tick into [`crate::metrics::RunSums`].
fn sum_tick(
    m: &mut Metrics,
    model: &Model,
    truth: &Truth,
    commanded: Option<&nalgebra::DVector<f64>>,
    targets: &Targets,
    placements: &[Se3; 2],
    zmp: Option<[f64; 2]>,
) {
    let sums = &mut m.sums;
    sums.samples += 1;
    let com_ref = &targets.com.pos;
    let mut e2 = (0..3)
        .map(|a| (truth.com[a] - com_ref[a]).powi(2))
        .sum::<f64>();
    for (k, p) in placements.iter().enumerate() {
        e2 += (p.translation - targets.feet[k].reference.placement.translation).norm_squared();
    }
    sums.task_error_square_sum += e2;
    // The controller's torques where it commands torques (the motors' effort), else the
    // joints' applied torques.
    let tau = commanded.unwrap_or(&truth.applied_torques);
    sums.torque_square_sum += tau.norm_squared();
    sums.torque_peak = sums.torque_peak.max(tau.amax());
    let (mut centre, mut n) = (nalgebra::Vector2::zeros(), 0.0);
    for (k, p) in placements.iter().enumerate() {
        if targets.feet[k].supporting {
            centre += p.translation.xy();
            n += 1.0;
        }
    }
    if let (Some([x, y]), true) = (zmp, n > 0.0) {
        centre /= n;
        sums.zmp_support_square_sum += (x - centre.x).powi(2) + (y - centre.y).powi(2);
    }
    for joint in &model.joints {
        if joint.nq() != 1 || joint.idx_v < model.first_actuated() {
            continue;
        }
        let (q, i) = (truth.q[joint.idx_q], joint.idx_q);
        let excess = (q - model.upper_position_limit[i]).max(model.lower_position_limit[i] - q);
        if excess > sums.joint_limit_excess {
            sums.joint_limit_excess = excess;
            // A new worst joint: rare, and only then is its name copied.
            if sums.joint_limit_excess_joint.as_deref() != Some(joint.name.as_str()) {
                sums.joint_limit_excess_joint = Some(joint.name.clone());
            }
        }
    }
}
