//! The metrics of a controller run (seed 000 §4.4.3): CoM, feet and ZMP tracking errors as
//! average / standard deviation / peak per axis, contact forces, base drift and foot slip,
//! mechanical work (Eq 4.16's E_m and E_m+), and the controller's time per tick.

use corps_loop::verdict::VerdictReport;
use serde::{Deserialize, Serialize};
use std::fmt;

/// Running average / standard deviation / peak of |e|.
#[derive(Clone, Copy, Debug, Default, Serialize)]
pub struct Stat {
    #[serde(skip)]
    n: usize,
    #[serde(skip)]
    sum: f64,
    #[serde(skip)]
    sum_sq: f64,
    pub avg: f64,
    pub std: f64,
    pub peak: f64,
}

impl Stat {
    pub fn push(&mut self, e: f64) {
        let a = e.abs();
        self.n += 1;
        self.sum += a;
        self.sum_sq += a * a;
        self.peak = self.peak.max(a);
        let n = self.n as f64;
        self.avg = self.sum / n;
        self.std = (self.sum_sq / n - self.avg * self.avg).max(0.0).sqrt();
    }
}

/// Per-axis statistics.
pub type Axes<const N: usize> = [Stat; N];

/// Time per control tick (µs).
#[derive(Clone, Debug, Default, Serialize)]
pub struct TickTime {
    pub avg_us: f64,
    pub median_us: f64,
    pub p99_us: f64,
    pub peak_us: f64,
}

impl TickTime {
    /// From the per-tick durations (µs), exactly (sorts them).
    pub fn from_samples(samples: &mut [f64]) -> Self {
        if samples.is_empty() {
            return Self::default();
        }
        samples.sort_by(f64::total_cmp);
        let n = samples.len();
        let at = |p: f64| samples[((n as f64 * p).ceil() as usize).clamp(1, n) - 1];
        Self {
            avg_us: samples.iter().sum::<f64>() / n as f64,
            median_us: at(0.5),
            p99_us: at(0.99),
            peak_us: samples[n - 1],
        }
    }
}

/// Tick times gathered online in fixed memory: the exact average and peak, and the median
/// and 99th percentile from a histogram of [`TickTimer::PER_DECADE`] logarithmic bins per decade
/// between 0.1 µs and 10 s (within 1.2 % of the order statistic).
#[derive(Clone, Debug)]
pub struct TickTimer {
    bins: Vec<u64>,
    n: u64,
    sum: f64,
    min: f64,
    peak: f64,
}

impl Default for TickTimer {
    fn default() -> Self {
        Self {
            bins: vec![0; Self::BINS],
            n: 0,
            sum: 0.0,
            min: f64::INFINITY,
            peak: 0.0,
        }
    }
}

impl TickTimer {
    const PER_DECADE: f64 = 100.0;
    const LOWEST_US: f64 = 0.1;
    const BINS: usize = 800;

    fn bin(us: f64) -> usize {
        let k = ((us / Self::LOWEST_US).log10() * Self::PER_DECADE).floor();
        if k.is_nan() || k < 0.0 {
            0
        } else {
            (k as usize).min(Self::BINS - 1)
        }
    }

    /// Records one tick's time (µs).
    pub fn push(&mut self, us: f64) {
        self.bins[Self::bin(us)] += 1;
        self.n += 1;
        self.sum += us;
        self.min = self.min.min(us);
        self.peak = self.peak.max(us);
    }

    /// The quantile `p` of the recorded times: the geometric middle of its bin, within the
    /// observed range.
    fn quantile(&self, p: f64) -> f64 {
        let rank = ((self.n as f64 * p).ceil() as u64).clamp(1, self.n);
        let mut seen = 0;
        let bin = (self.bins.iter().position(|c| {
            seen += c;
            seen >= rank
        }))
        .unwrap_or(Self::BINS - 1);
        let middle = Self::LOWEST_US * 10f64.powf((bin as f64 + 0.5) / Self::PER_DECADE);
        middle.clamp(self.min, self.peak)
    }

    /// The average, the median and 99th percentile (within 1.2 %) and the peak.
    pub fn summary(&self) -> TickTime {
        if self.n == 0 {
            return TickTime::default();
        }
        TickTime {
            avg_us: self.sum / self.n as f64,
            median_us: self.quantile(0.5),
            p99_us: self.quantile(0.99),
            peak_us: self.peak,
        }
    }
}

/// One foot's figures.
#[derive(Clone, Debug, Default, Serialize)]
pub struct FootMetrics {
    pub label: String,
    /// Position tracking error of the sole (m), x y z.
    pub error: Axes<3>,
    /// Largest horizontal displacement while in contact, from where the contact began (m).
    pub slip: f64,
    /// Peak and mean vertical contact force (N).
    pub force_peak: f64,
    pub force_mean: f64,
    /// Landings: contacts that begin after the plan lifted the foot. The landing error is
    /// the horizontal distance from the true sole to its planned place when the contact
    /// begins (m): seed 000 §4.6.1.c's "feet landing up to 5 cm off".
    pub landings: usize,
    pub landing_error_mean: f64,
    pub landing_error_max: f64,
    /// The plan has lifted this foot since its last landing.
    #[serde(skip)]
    pub(crate) swung: bool,
}

/// The documents' figures for an experiment (`[thesis]` of a scenario), each as
/// `[average, standard deviation, peak]` in metres, and the costs of transport.
#[derive(Clone, Debug, Default, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct ThesisFigures {
    /// Where the figures come from, e.g. "seed 000 Table 4.4, TSID torque".
    pub source: String,
    pub com_x: Option<[f64; 3]>,
    pub com_y: Option<[f64; 3]>,
    pub zmp_x: Option<[f64; 3]>,
    pub zmp_y: Option<[f64; 3]>,
    pub left_foot_x: Option<[f64; 3]>,
    pub left_foot_y: Option<[f64; 3]>,
    pub right_foot_x: Option<[f64; 3]>,
    pub right_foot_y: Option<[f64; 3]>,
    pub cost_of_transport: Option<f64>,
    pub mechanical_cost_of_transport: Option<f64>,
    /// Passivity gait measure: double support, single support, flying foot.
    pub passivity_gait_measure: Option<[f64; 3]>,
}

impl ThesisFigures {
    /// The figures of a table row ("CoM", "x"), if given.
    fn get(&self, name: &str, axis: &str) -> Option<[f64; 3]> {
        match (name, axis) {
            ("CoM", "x") => self.com_x,
            ("CoM", "y") => self.com_y,
            ("ZMP", "x") => self.zmp_x,
            ("ZMP", "y") => self.zmp_y,
            ("left foot", "x") => self.left_foot_x,
            ("left foot", "y") => self.left_foot_y,
            ("right foot", "x") => self.right_foot_x,
            ("right foot", "y") => self.right_foot_y,
            _ => None,
        }
    }
}

/// One of the documents' figures beside corps' (m for errors; a ratio for costs).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Comparison {
    /// "ZMP x peak", "cost of transport C_et", …
    pub figure: String,
    pub corps: f64,
    pub thesis: f64,
    /// Whether corps is worse (a larger error or cost).
    pub worse: bool,
}

/// The rows of an error table: the row's name and its axes.
type ErrorTable<'a> = Vec<(String, Vec<(&'static str, &'a Stat)>)>;

/// The CoM, ZMP and feet (label, errors) rows of one table.
fn error_table<'a>(
    com: &'a Axes<3>,
    zmp: &'a Axes<2>,
    feet: impl Iterator<Item = (&'a str, &'a Axes<3>)>,
) -> ErrorTable<'a> {
    let mut rows = vec![
        (
            "CoM".to_string(),
            vec![("x", &com[0]), ("y", &com[1]), ("z", &com[2])],
        ),
        ("ZMP".to_string(), vec![("x", &zmp[0]), ("y", &zmp[1])]),
    ];
    for (label, e) in feet {
        let axes = vec![("x", &e[0]), ("y", &e[1]), ("z", &e[2])];
        rows.push((format!("{label} foot"), axes));
    }
    rows
}

impl Metrics {
    /// The tracking-error tables, each with the suffix its figures take: the whole run's
    /// (`""`), then the walk proper's (`" while walking"`) when there is one.
    fn error_tables(&self) -> Vec<(&'static str, ErrorTable<'_>)> {
        let labels = self.feet.iter().map(|f| f.label.as_str());
        let whole = labels.clone().zip(self.feet.iter().map(|f| &f.error));
        let mut tables = vec![("", error_table(&self.com_error, &self.zmp_error, whole))];
        if let Some(w) = &self.while_walking {
            let feet = labels.zip(w.feet_error.iter());
            tables.push((
                " while walking",
                error_table(&w.com_error, &w.zmp_error, feet),
            ));
        }
        tables
    }

    /// Every figure the scenario's `[thesis]` gives, beside corps' own: the average and peak
    /// of each error row (the standard deviation describes a spread, not a bound), and the
    /// costs of transport. Lower is better for all of them.
    pub fn thesis_comparison(&self) -> Vec<Comparison> {
        let Some(t) = &self.thesis else {
            return vec![];
        };
        let mut rows = vec![];
        let mut add = |figure: String, corps: f64, thesis: f64| {
            rows.push(Comparison {
                figure,
                corps,
                thesis,
                worse: corps > thesis,
            })
        };
        for (when, table) in self.error_tables() {
            for (name, axes) in table {
                for (axis, stat) in axes {
                    if let Some([avg, _, peak]) = t.get(&name, axis) {
                        add(format!("{name} {axis} average{when}"), stat.avg, avg);
                        add(format!("{name} {axis} peak{when}"), stat.peak, peak);
                    }
                }
            }
        }
        if let Some(w) = &self.walk {
            if let Some(c) = t.cost_of_transport {
                add("cost of transport C_et".into(), w.cost_of_transport, c);
            }
            if let Some(c) = t.mechanical_cost_of_transport {
                add(
                    "cost of transport C_mt".into(),
                    w.mechanical_cost_of_transport,
                    c,
                );
            }
        }
        rows
    }
}

/// The tracking errors over the walk proper ([`crate::walk::WalkMotion::walking_window`]):
/// the whole run's averages are diluted by the standing before and after, and its peaks may
/// come from the hand-over to walking.
#[derive(Clone, Debug, Default, Serialize)]
pub struct WalkingErrors {
    /// The window, in seconds of controlled time.
    pub start: f64,
    pub end: f64,
    pub com_error: Axes<3>,
    pub zmp_error: Axes<2>,
    /// Left then right foot.
    pub feet_error: [Axes<3>; 2],
}

/// The figures of a walk.
#[derive(Clone, Debug, Default, Serialize)]
pub struct WalkMetrics {
    /// Horizontal distance travelled by the base (m).
    pub distance: f64,
    /// Horizontal distance between the final base and where the plan puts it (m).
    pub final_base_error: f64,
    /// Costs of transport C_et = E_m/(m g D) and C_mt = E_m+/(m g D) (seed 000 Eq 4.16).
    pub cost_of_transport: f64,
    pub mechanical_cost_of_transport: f64,
    /// Passivity gait measure (seed 000 Eq 4.17–4.18) in double support, single support and
    /// for the flying foot.
    pub passivity_gait_measure: [Option<f64>; 3],
    /// The dynamic filter's pass on the plan, when it ran.
    pub dynamic_filter: Option<DynamicFilterMetrics>,
}

/// What one dynamic filter pass did to the plan (`crate::dynamic_filter`): its multibody
/// ZMP error (kinematic replay) before and after, and the correction.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct DynamicFilterMetrics {
    /// RMS and peak of |p_ref − p_MB| per axis (m), x then y.
    pub before: [(f64, f64); 2],
    pub after: [(f64, f64); 2],
    /// Largest CoM correction |Δc| per axis (m).
    pub max_correction: [f64; 2],
}

/// Distance between the estimated and the true CoM and base position (m): mean and peak.
#[derive(Clone, Copy, Debug, Default, Serialize)]
pub struct EstimateError {
    pub com_mean: f64,
    pub com_peak: f64,
    pub base_mean: f64,
    pub base_peak: f64,
    #[serde(skip)]
    samples: usize,
}

impl EstimateError {
    /// Adds one tick's CoM and base position errors.
    pub fn push(&mut self, com: f64, base: f64) {
        self.samples += 1;
        let n = self.samples as f64;
        self.com_mean += (com - self.com_mean) / n;
        self.base_mean += (base - self.base_mean) / n;
        self.com_peak = self.com_peak.max(com);
        self.base_peak = self.base_peak.max(base);
    }
}

/// Everything measured during a run.
#[derive(Clone, Debug, Default, Serialize)]
pub struct Metrics {
    pub scenario: String,
    pub controller: String,
    /// Controlled time (s).
    pub duration: f64,
    /// CoM tracking error (m), x y z.
    pub com_error: Axes<3>,
    /// ZMP (from the simulated contact forces) against the reference ZMP (m), x y.
    pub zmp_error: Axes<2>,
    pub feet: Vec<FootMetrics>,
    /// Base displacement at the end and its peak over the run (m, 3D).
    pub base_drift: f64,
    pub base_drift_peak: f64,
    /// Lowest base height (m).
    pub min_base_height: f64,
    /// Peak force on bodies other than the feet (N): a fall or a knee on the ground.
    pub other_contact_peak: f64,
    /// Mechanical work Σ|τ·q̇| and its positive part (J), seed 000 Eq 4.16.
    pub work: f64,
    pub positive_work: f64,
    /// Controller time per tick.
    pub tick_time: TickTime,
    /// Ticks whose simulator preparation ran on the second thread.
    pub overlapped_ticks: u64,
    /// Ticks that used the safe command, and the first reason.
    pub fallbacks: usize,
    pub first_fallback: Option<String>,
    /// For a walk.
    pub walk: Option<WalkMetrics>,
    /// The same errors over the walk proper (walks only).
    pub while_walking: Option<WalkingErrors>,
    /// The documents' figures, printed beside ours.
    pub thesis: Option<ThesisFigures>,
    /// How the run ended.
    pub verdict: VerdictReport,
    /// The documents' figures beside corps' ([`Metrics::thesis_comparison`], filled at the
    /// end of the run; printed and written from here).
    pub against_thesis: Vec<Comparison>,
    /// What fed the controller, and the readings it could not use (the estimate was held).
    pub estimator: crate::estimation::EstimatorKind,
    /// The sensors' noise: `noiseless`, the scenario's `[noise]`, or a profile's file.
    pub sensor_noise: String,
    /// How far the controller's estimate was from the simulator's state.
    pub estimate_error: EstimateError,
    pub estimator_errors: usize,
    pub first_estimator_error: Option<String>,
    /// Controlled time reached when Ctrl-C stopped the run (s); the log ends there.
    pub interrupted_at: Option<f64>,
    /// The controller's own figures of the run (a state machine's cycles, say), with the
    /// documents' beside them.
    pub controller_report: Vec<ReportLine>,
    /// Walking with a person (co-navigation): how well the robot held its point.
    #[serde(flatten)]
    pub conav: Option<ConavMetrics>,
    /// Teleoperation: the operator's steps and the robot's, the upper body's tracking.
    #[serde(flatten)]
    pub teleop: Option<TeleopMetrics>,
    /// Sums over every tick that fitness functions are made of (seed 001 Eq 5.17–5.18).
    pub sums: RunSums,
    /// The last [`HOLD_WINDOW`] of the run, the robot standing: the balance the feet's F/T
    /// sensors measure (seed 000 App. 4's one-leg CoP/CoM test). None if the run failed.
    pub hold: Option<HoldFigures>,
}

/// Sums over the run's ticks (true state against the tracked references) and the peaks that
/// a learning problem's fitness and constraints read (seed 001 §5.3.2, Eq 5.17–5.18).
#[derive(Clone, Debug, Default, Serialize)]
pub struct RunSums {
    /// Ticks summed (n_s).
    pub samples: usize,
    /// Σ_t (|CoM − CoM*|² + Σ_feet |p − p*|²), m².
    pub task_error_square_sum: f64,
    /// Σ_t |τ|², N²·m²: the controller's torque command (its applied torques for a
    /// controller of positions or velocities).
    pub torque_square_sum: f64,
    /// Σ_t |ZMP − support polygon centre|² over the ticks with a ZMP, m².
    pub zmp_support_square_sum: f64,
    /// Largest |τ_i| of the same, N·m.
    pub torque_peak: f64,
    /// Largest excursion of a joint beyond its URDF position limits, rad (0: never), and
    /// that joint's name.
    pub joint_limit_excess: f64,
    pub joint_limit_excess_joint: Option<String>,
}

/// The window of [`HoldFigures`], s: long enough to average a standing robot's sway
/// (TALOS on its flexible hips sways at about 0.55 Hz) over more than one period.
pub const HOLD_WINDOW: f64 = 5.0;

/// Means over the last [`HOLD_WINDOW`] of a run: each foot's F/T moment about its sole's x axis
/// (ground on foot, about the sole origin) while it carries load; the ZMP of the F/T sensors
/// minus the true CoM's ground projection, and minus the CoM of the state the controller
/// works on (world x, y): where the CoP is against where the controller put the CoM.
#[derive(Clone, Debug, Default, Serialize)]
pub struct HoldFigures {
    pub from_t: f64,
    pub ankle_torque_x_nm: [f64; 2],
    pub zmp_minus_com_m: [f64; 2],
    pub zmp_minus_controller_com_m: [f64; 2],
    #[serde(skip)]
    pub(crate) samples: [usize; 3],
}

impl HoldFigures {
    /// Folds in one tick: feet moments (None: that foot unloaded) and the ZMP − CoM offset.
    pub(crate) fn push(
        &mut self,
        torque_x: [Option<f64>; 2],
        zmp_minus_com: Option<[[f64; 2]; 2]>,
    ) {
        for (k, t) in torque_x.iter().enumerate() {
            if let Some(t) = t {
                self.samples[k] += 1;
                self.ankle_torque_x_nm[k] +=
                    (t - self.ankle_torque_x_nm[k]) / self.samples[k] as f64;
            }
        }
        if let Some([d, c]) = zmp_minus_com {
            self.samples[2] += 1;
            let n = self.samples[2] as f64;
            for a in 0..2 {
                self.zmp_minus_com_m[a] += (d[a] - self.zmp_minus_com_m[a]) / n;
                self.zmp_minus_controller_com_m[a] +=
                    (c[a] - self.zmp_minus_controller_com_m[a]) / n;
            }
        }
    }
}

/// How a robot walking with a person did: its CoM against the point it should hold relative
/// to them, over every tick; its steps (touchdowns of the plan) and the widest sideways one
/// (the foot's displacement from lift-off to touchdown across the plan's heading).
#[derive(Clone, Debug, Default, Serialize)]
pub struct ConavMetrics {
    pub mean_following_error_m: f64,
    pub max_following_error_m: f64,
    pub steps: usize,
    pub max_lateral_step_m: f64,
    #[serde(skip)]
    pub(crate) error_sum: f64,
    #[serde(skip)]
    pub(crate) ticks: usize,
}

/// A teleoperation run (seed 001 §6.2, S12): steps of the operator and of the robot, the
/// measured upper body against the retargeted references (after mapping and clipping), and
/// the ticks with a joint past its limits.
#[derive(Clone, Debug, Default, Serialize)]
pub struct TeleopMetrics {
    pub operator_steps: usize,
    pub robot_steps: usize,
    pub upper_body_rms_deg: f64,
    pub upper_body_max_deg: f64,
    pub joint_limit_violations: usize,
    /// Control ticks without a live operator pose (the references held).
    pub feed_lost_ticks: usize,
    /// Steps the walking state machine made to the end (Fig 6.6's swap of the feet).
    pub steps_walked: usize,
    /// Steps never walked: the queue of pending steps was full (or a step was not valid).
    pub steps_dropped: usize,
    /// Each step made: its planned length (Eq 6.6–6.7, or the scenario's footsteps, a turning
    /// step's swing included) and the measured one (m).
    pub step_lengths: Vec<StepLength>,
    /// Mean |measured − planned| step length (mm); 0 without a step.
    pub step_length_error_mm: f64,
    /// The robot's turn about the vertical, planned (the mean of the soles' planned turns)
    /// and measured (the mean turn of the estimator's soles), at the end (degrees).
    pub turn_planned_deg: f64,
    pub turn_walked_deg: f64,
    pub upper_body: Vec<JointTracking>,
}

/// One robot step's length.
#[derive(Clone, Debug, Default, Serialize)]
pub struct StepLength {
    pub planned_m: f64,
    pub walked_m: f64,
}

/// One retargeted joint's tracking.
#[derive(Clone, Debug, Default, Serialize)]
pub struct JointTracking {
    pub joint: String,
    pub rms_deg: f64,
    pub max_deg: f64,
    /// Operator frames whose angle went past the joint's limits (clipped).
    pub clipped_frames: usize,
}

/// One figure a controller reports about its run.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ReportLine {
    pub figure: String,
    pub value: f64,
    pub unit: String,
    /// The documents' figure or bound, as text with its source ("< 0.01 (seed 001 L3031)").
    pub thesis: Option<String>,
    /// Whether corps meets it, where it is a bound.
    pub met: Option<bool>,
}

fn row(
    f: &mut fmt::Formatter<'_>,
    thesis: Option<&ThesisFigures>,
    name: &str,
    axes: &[(&str, &Stat)],
) -> fmt::Result {
    for (axis, s) in axes {
        write!(
            f,
            "  {name:<14} {axis}  {:>7.1} {:>7.1} {:>7.1}",
            s.avg * 1e3,
            s.std * 1e3,
            s.peak * 1e3
        )?;
        match thesis.and_then(|t| t.get(name, axis)) {
            Some([a, sd, p]) => {
                writeln!(f, "    {:>7.1} {:>7.1} {:>7.1}", a * 1e3, sd * 1e3, p * 1e3)?
            }
            None => writeln!(f)?,
        }
    }
    Ok(())
}

impl fmt::Display for Metrics {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "{} — {} — {:.2} s controlled",
            self.scenario, self.controller, self.duration
        )?;
        let th = self.thesis.as_ref();
        write!(f, "  error (mm)            avg     std    peak")?;
        match th {
            Some(t) => writeln!(f, "    thesis: {}", t.source)?,
            None => writeln!(f)?,
        }
        for (when, table) in self.error_tables() {
            if let Some(w) = self.while_walking.as_ref().filter(|_| !when.is_empty()) {
                writeln!(
                    f,
                    "  while walking, t = {:.2}–{:.2} s (first lift-off to last touchdown):",
                    w.start, w.end
                )?;
            }
            for (name, axes) in table {
                row(f, th, &name, &axes)?;
            }
        }
        for foot in &self.feet {
            writeln!(
                f,
                "  {} foot: slip {:.2} mm, vertical force mean {:.0} N, peak {:.0} N{}",
                foot.label,
                foot.slip * 1e3,
                foot.force_mean,
                foot.force_peak,
                if foot.landings > 0 {
                    format!(
                        "; {} landings, landing error mean {:.1} mm, max {:.1} mm",
                        foot.landings,
                        foot.landing_error_mean * 1e3,
                        foot.landing_error_max * 1e3
                    )
                } else {
                    String::new()
                }
            )?;
        }
        writeln!(
            f,
            "  base: drift {:.2} mm at the end, {:.2} mm peak; lowest height {:.3} m",
            self.base_drift * 1e3,
            self.base_drift_peak * 1e3,
            self.min_base_height
        )?;
        if self.other_contact_peak > 0.0 {
            writeln!(
                f,
                "  contact on other bodies: peak {:.0} N",
                self.other_contact_peak
            )?;
        }
        writeln!(
            f,
            "  mechanical work {:.1} J (positive {:.1} J)",
            self.work, self.positive_work
        )?;
        if let Some(h) = &self.hold {
            writeln!(
                f,
                "  hold, t ≥ {:.2} s: F/T moment about the sole x, left {:.2} N·m, right {:.2} N·m; ZMP − CoM x {:.2} mm, y {:.2} mm; ZMP − the controller's CoM x {:.2} mm, y {:.2} mm",
                h.from_t,
                h.ankle_torque_x_nm[0],
                h.ankle_torque_x_nm[1],
                h.zmp_minus_com_m[0] * 1e3,
                h.zmp_minus_com_m[1] * 1e3,
                h.zmp_minus_controller_com_m[0] * 1e3,
                h.zmp_minus_controller_com_m[1] * 1e3
            )?;
        }
        if let Some(t) = &self.teleop {
            writeln!(
                f,
                "  teleoperation: operator steps {}, robot steps {} (F/T), {} walked, {} dropped (step length error {:.1} mm); upper body vs retargeted references RMS {:.2}°, max {:.2}°; {} ticks with a joint past its limits; {} ticks without a live pose",
                t.operator_steps,
                t.robot_steps,
                t.steps_walked,
                t.steps_dropped,
                t.step_length_error_mm,
                t.upper_body_rms_deg,
                t.upper_body_max_deg,
                t.joint_limit_violations,
                t.feed_lost_ticks
            )?;
        }
        if let Some(c) = &self.conav {
            writeln!(
                f,
                "  with the person: following error mean {:.1} mm, max {:.1} mm; {} steps, widest sideways {:.1} mm",
                c.mean_following_error_m * 1e3,
                c.max_following_error_m * 1e3,
                c.steps,
                c.max_lateral_step_m * 1e3
            )?;
        }
        if let Some(w) = &self.walk {
            writeln!(
                f,
                "  walk: {:.3} m travelled, final base {:.1} mm from the plan",
                w.distance,
                w.final_base_error * 1e3
            )?;
            if let Some(d) = &w.dynamic_filter {
                writeln!(
                    f,
                    "  dynamic filter: plan's multibody ZMP error RMS/peak x {:.1}/{:.1}, y {:.1}/{:.1} mm → x {:.1}/{:.1}, y {:.1}/{:.1} mm; CoM corrected by up to {:.1} / {:.1} mm",
                    d.before[0].0 * 1e3,
                    d.before[0].1 * 1e3,
                    d.before[1].0 * 1e3,
                    d.before[1].1 * 1e3,
                    d.after[0].0 * 1e3,
                    d.after[0].1 * 1e3,
                    d.after[1].0 * 1e3,
                    d.after[1].1 * 1e3,
                    d.max_correction[0] * 1e3,
                    d.max_correction[1] * 1e3
                )?;
            }
            write!(
                f,
                "  cost of transport C_et {:.2}, C_mt {:.2}",
                w.cost_of_transport, w.mechanical_cost_of_transport
            )?;
            match th.map(|t| (t.cost_of_transport, t.mechanical_cost_of_transport)) {
                Some((Some(et), Some(mt))) => writeln!(f, "   (thesis {et:.2}, {mt:.2})")?,
                _ => writeln!(f)?,
            }
            let show = |x: Option<f64>| x.map_or("–".to_string(), |v| format!("{v:.2}"));
            let [ds, ss, fly] = w.passivity_gait_measure;
            write!(
                f,
                "  passivity gait measure DS {}, SS {}, flying foot {}",
                show(ds),
                show(ss),
                show(fly)
            )?;
            match th.and_then(|t| t.passivity_gait_measure) {
                Some([a, b, c]) => writeln!(f, "   (thesis {a:.2}, {b:.2}, {c:.2})")?,
                None => writeln!(f)?,
            }
        }
        let t = &self.tick_time;
        writeln!(
            f,
            "  controller time per tick: avg {:.1} µs, median {:.1} µs, p99 {:.1} µs, peak {:.1} µs",
            t.avg_us, t.median_us, t.p99_us, t.peak_us
        )?;
        match &self.first_fallback {
            None => writeln!(f, "  safe command: never used")?,
            Some(r) => writeln!(
                f,
                "  safe command used on {} ticks; first: {r}",
                self.fallbacks
            )?,
        }
        for line in &self.controller_report {
            write!(f, "  {}: {:.4} {}", line.figure, line.value, line.unit)?;
            match (&line.thesis, line.met) {
                (Some(t), Some(met)) => {
                    writeln!(f, "   (thesis {t}: {})", if met { "met" } else { "MISSED" })?
                }
                (Some(t), None) => writeln!(f, "   (thesis {t})")?,
                _ => writeln!(f)?,
            }
        }
        for c in self.against_thesis.iter().filter(|c| c.worse) {
            let (scale, unit) = if c.figure.starts_with("cost") {
                (1.0, "")
            } else {
                (1e3, " mm")
            };
            writeln!(
                f,
                "  short of the thesis: {} {:.2}{unit} (thesis {:.2}{unit})",
                c.figure,
                c.corps * scale,
                c.thesis * scale
            )?;
        }
        let source = match self.estimator {
            crate::estimation::EstimatorKind::LegOdometry => {
                "leg odometry + IMU + ankle F/T (the sensors)"
            }
            crate::estimation::EstimatorKind::GroundTruth => {
                "ground truth (the simulator's exact state)"
            }
        };
        let e = &self.estimate_error;
        writeln!(
            f,
            "  state estimate: {source}, {}; error CoM {:.1} mm mean, {:.1} peak; base {:.1} mean, {:.1} peak",
            self.sensor_noise,
            e.com_mean * 1e3,
            e.com_peak * 1e3,
            e.base_mean * 1e3,
            e.base_peak * 1e3
        )?;
        if let Some(e) = &self.first_estimator_error {
            writeln!(
                f,
                "  estimator held its estimate on {} ticks; first: {e}",
                self.estimator_errors
            )?;
        }
        writeln!(f, "  verdict: {}", self.verdict)?;
        if let Some(t) = self.interrupted_at {
            writeln!(f, "  interrupted at t = {t:.3} s: the log ends there")?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stat_gives_mean_std_and_peak_of_the_magnitude() {
        let mut s = Stat::default();
        for e in [1.0, -3.0, 2.0] {
            s.push(e);
        }
        assert!((s.avg - 2.0).abs() < 1e-12);
        assert!((s.std - (2.0f64 / 3.0).sqrt()).abs() < 1e-12);
        assert_eq!(s.peak, 3.0);
    }

    #[test]
    fn tick_time_percentile_is_an_order_statistic() {
        let mut v: Vec<f64> = (1..=200).rev().map(f64::from).collect();
        let t = TickTime::from_samples(&mut v);
        assert_eq!(t.p99_us, 198.0);
        assert_eq!(t.peak_us, 200.0);
        assert!((t.avg_us - 100.5).abs() < 1e-12);
    }

    #[test]
    fn online_tick_time_matches_the_order_statistic_within_its_bin() {
        let mut v: Vec<f64> = (0..100_000)
            .map(|k| 40.0 + (k * 7919 % 1000) as f64 * 0.1)
            .collect();
        v.extend([500.0, 2_000.0]);
        let mut timer = TickTimer::default();
        for x in &v {
            timer.push(*x);
        }
        let online = timer.summary();
        let exact = TickTime::from_samples(&mut v);
        assert!((online.avg_us - exact.avg_us).abs() < 1e-9 * exact.avg_us);
        assert_eq!(online.peak_us, exact.peak_us);
        assert!(
            (online.p99_us / exact.p99_us - 1.0).abs() < 0.012,
            "{} vs {}",
            online.p99_us,
            exact.p99_us
        );
    }
}
