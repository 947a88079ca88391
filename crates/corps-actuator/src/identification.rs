//! Identification of the drive model of [`crate::elbow`] by total least squares with the
//! gains inside (seed 000 §6, Eq 3.9–3.12; Gautier & Jubien): unknowns
//! `Φ = [φ; R K_m; K_j; φ_up; φ_kp]` with `φ = [M_X, M_Y, I_m, F_Vm, F_Sm, Off_m, I_j, F_Vj,
//! F_Sj, Off_j]`, payload parameters `φ_up = [I_L, L_X]` unknown and `φ_kp = L_Y` known.
//! Each sample gives a motor row `R K_m i − [g cos q, g sin q, D, D] φ (− W_p φ_p) = 0` and a
//! joint row `K_j τ_js − [g cos q, g sin q, 0, D] φ (− W_p φ_p) = 0`, `D = [q̈, q̇, sign q̇, 1]`,
//! `W_p = [q̈, g cos q, g sin q]` on the samples taken with the payload. `Φ̂` is the right
//! singular vector of the smallest singular value of the stacked matrix, scaled so that
//! `L_Y` equals its known value; a second pass weights each block of rows (motor/joint,
//! with/without payload) by the inverse of its residual's standard deviation.
//!
//! Pre-processing (step 4): `q` through a zero-phase Butterworth at `derivative_hz`, `q̇` and
//! `q̈` by centred differences, `sign q̇` zero inside a dead band; then every column (and the
//! current and torque) through the same zero-phase Butterworth (order 5, 5 Hz) — parallel
//! filtering, which keeps the rows' linear relation — and decimation, keeping samples where
//! `|q̇|` exceeds a threshold. Standard deviations: the equivalent least-squares problem with
//! `L_Y` moved to the right-hand side, `σ²_ρ = ‖ρ‖²/(r − c)`, `C = σ²_ρ (AᵀA)⁻¹`,
//! `σ%_i = 100 √C_ii / |Φ_i|` (Pressé & Gautier).

use crate::butterworth::Butterworth;
use crate::elbow::G;
use crate::error::ActuatorError;
use nalgebra::{DMatrix, DVector};

/// The parameters identified, in the order of `Φ` (the known `L_Y` last).
pub const PARAMETER_NAMES: [&str; 15] = [
    "M_X", "M_Y", "I_m", "F_Vm", "F_Sm", "Off_m", "I_j", "F_Vj", "F_Sj", "Off_j", "RK_m", "K_j",
    "I_L", "L_X", "L_Y",
];

/// One experiment: time (s), joint position (rad), motor current (A) and the joint torque
/// sensor's reading (N·m), with or without the payload.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Segment {
    pub t: Vec<f64>,
    pub q: Vec<f64>,
    pub current: Vec<f64>,
    pub torque_sensor: Vec<f64>,
    pub payload: bool,
}

/// The experiments and the payload's known first moment `L_Y` (kg·m).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct IdentificationData {
    pub segments: Vec<Segment>,
    pub payload_moment: f64,
}

/// Pre-processing choices.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct IdentificationSettings {
    /// Order and cut-off of the zero-phase low-pass (seed 000: 5, 5 Hz).
    pub order: usize,
    pub cutoff_hz: f64,
    /// Cut-off of the filter on `q` before differentiation.
    pub derivative_hz: f64,
    /// Rate after decimation: twice the cut-off, the filtered signal's Nyquist rate, so that
    /// the residuals are nearly uncorrelated as the σ formula assumes.
    pub decimated_hz: f64,
    /// Samples closer than one period of the cut-off to a sample with `|q̇|` below this are
    /// dropped (friction's sign is undefined at rest and smeared by the filter), rad/s.
    pub velocity_threshold: f64,
    /// `sign q̇` is zero below this, rad/s.
    pub sign_deadband: f64,
    /// Samples this close to either end of an experiment are dropped, s.
    pub edge_s: f64,
}

impl Default for IdentificationSettings {
    fn default() -> Self {
        Self {
            order: 5,
            cutoff_hz: 5.0,
            derivative_hz: 50.0,
            decimated_hz: 10.0,
            velocity_threshold: 0.1,
            sign_deadband: 0.01,
            edge_s: 0.5,
        }
    }
}

/// The result.
#[derive(Clone, Debug, PartialEq)]
pub struct Identified {
    /// `Φ̂` in the order of [`PARAMETER_NAMES`] (the last is the known `L_Y`).
    pub values: Vec<f64>,
    /// σ% of each (0 for the known `L_Y`).
    pub sigma_percent: Vec<f64>,
    /// RMS of `R K_m i − W_m φ` on the raw samples without payload, N·m.
    pub rmsd_nm: f64,
    /// Condition number of the column-normalised base regressor `[W_m; W_j]` (φ's columns).
    pub cond: f64,
    /// Decimated samples used (each gives two rows).
    pub samples: usize,
}

impl Identified {
    pub fn value(&self, name: &str) -> Option<f64> {
        PARAMETER_NAMES
            .iter()
            .position(|n| *n == name)
            .map(|i| self.values[i])
    }
}

/// Filtered base signals of one experiment: `[q̈, q̇, sign q̇, 1, g cos q, g sin q, i, τ]`
/// and the velocity used to select samples.
struct Signals {
    columns: [Vec<f64>; 8],
    velocity: Vec<f64>,
    raw: [Vec<f64>; 8],
    sample_hz: f64,
}

const MIN_SAMPLES_PER_EXPERIMENT: usize = 100;

fn check_segment(index: usize, s: &Segment) -> Result<f64, ActuatorError> {
    let n = s.t.len();
    let name = format!(
        "experiment {} ({} payload)",
        index + 1,
        if s.payload { "with" } else { "without" }
    );
    if s.q.len() != n || s.current.len() != n || s.torque_sensor.len() != n {
        return Err(ActuatorError::Data(format!(
            "{name}: columns of unequal length"
        )));
    }
    if n < MIN_SAMPLES_PER_EXPERIMENT {
        return Err(ActuatorError::Data(format!(
            "{name}: {n} samples, too few to filter (at least {MIN_SAMPLES_PER_EXPERIMENT})"
        )));
    }
    for k in 0..n {
        let row = [s.t[k], s.q[k], s.current[k], s.torque_sensor[k]];
        if row.iter().any(|v| !v.is_finite()) {
            return Err(ActuatorError::Data(format!(
                "{name}: sample {} holds a non-finite value",
                k + 1
            )));
        }
        if k > 0 && s.t[k] <= s.t[k - 1] {
            return Err(ActuatorError::Data(format!(
                "{name}: time is not increasing at sample {} ({} s after {} s)",
                k + 1,
                s.t[k],
                s.t[k - 1]
            )));
        }
    }
    let mut steps: Vec<f64> = s.t.windows(2).map(|w| w[1] - w[0]).collect();
    steps.sort_by(f64::total_cmp);
    let median = steps[steps.len() / 2];
    if steps[steps.len() - 1] > 2.0 * median || steps[0] < 0.5 * median {
        return Err(ActuatorError::Data(format!(
            "{name}: the sampling is not uniform (steps from {:.3e} to {:.3e} s); resample it",
            steps[0],
            steps[steps.len() - 1]
        )));
    }
    Ok(1.0 / median)
}

fn signals(
    s: &Segment,
    sample_hz: f64,
    set: &IdentificationSettings,
) -> Result<Signals, ActuatorError> {
    let filter_error = |what: &str, hz: f64| {
        ActuatorError::Data(format!(
            "the {what} cut-off {hz} Hz is not below the Nyquist rate {} Hz",
            0.5 * sample_hz
        ))
    };
    let derivative = Butterworth::low_pass(set.order, set.derivative_hz, sample_hz)
        .ok_or_else(|| filter_error("derivative filter's", set.derivative_hz))?;
    let low = Butterworth::low_pass(set.order, set.cutoff_hz, sample_hz)
        .ok_or_else(|| filter_error("low-pass", set.cutoff_hz))?;
    let pad = (3.0 * sample_hz / set.cutoff_hz) as usize;
    let q = derivative.filtfilt(&s.q, pad);
    let v = centred(&q, sample_hz);
    let a = centred(&v, sample_hz);
    let sign: Vec<f64> = v
        .iter()
        .map(|&x| {
            if x.abs() < set.sign_deadband {
                0.0
            } else {
                x.signum()
            }
        })
        .collect();
    let raw = [
        a,
        v,
        sign,
        vec![1.0; q.len()],
        q.iter().map(|x| G * x.cos()).collect(),
        q.iter().map(|x| G * x.sin()).collect(),
        s.current.clone(),
        s.torque_sensor.clone(),
    ];
    let columns = raw.clone().map(|c| low.filtfilt(&c, pad));
    Ok(Signals {
        velocity: columns[1].clone(),
        columns,
        raw,
        sample_hz,
    })
}

fn centred(x: &[f64], hz: f64) -> Vec<f64> {
    let n = x.len();
    (0..n)
        .map(|k| {
            let (i, j) = (k.saturating_sub(1), (k + 1).min(n - 1));
            (x[j] - x[i]) * hz / (j - i) as f64
        })
        .collect()
}

/// Whether each sample is more than `window` samples away from any sample slower than
/// `threshold`: there the sign of `q̇` holds over the low-pass filter's support, so that the
/// filtered friction column is exact.
fn far_from_slow(v: &[f64], threshold: f64, window: f64) -> Vec<bool> {
    let n = v.len();
    let mut distance = vec![f64::INFINITY; n];
    let mut last = f64::NEG_INFINITY;
    for k in 0..n {
        if v[k].abs() <= threshold {
            last = k as f64;
        }
        distance[k] = k as f64 - last;
    }
    let mut next = f64::INFINITY;
    for k in (0..n).rev() {
        if v[k].abs() <= threshold {
            next = k as f64;
        }
        distance[k] = distance[k].min(next - k as f64);
    }
    distance.iter().map(|&d| d > window).collect()
}

/// Writes the motor and joint rows of sample `k` of `c` into `w` at rows `r`, `r + 1`.
fn rows(w: &mut DMatrix<f64>, r: usize, c: &[Vec<f64>; 8], k: usize, payload: bool) {
    let d = [c[0][k], c[1][k], c[2][k], c[3][k]];
    for row in [r, r + 1] {
        w[(row, 0)] = -c[4][k];
        w[(row, 1)] = -c[5][k];
    }
    for j in 0..4 {
        w[(r, 2 + j)] = -d[j];
        w[(r, 6 + j)] = -d[j];
        w[(r + 1, 6 + j)] = -d[j];
    }
    w[(r, 10)] = c[6][k];
    w[(r + 1, 11)] = c[7][k];
    if payload {
        for row in [r, r + 1] {
            w[(row, 12)] = -c[0][k];
            w[(row, 13)] = -c[4][k];
            w[(row, 14)] = -c[5][k];
        }
    }
}

/// Identifies the drive's parameters from `data`.
pub fn identify(
    data: &IdentificationData,
    settings: &IdentificationSettings,
) -> Result<Identified, ActuatorError> {
    if !data.segments.iter().any(|s| s.payload) {
        return Err(ActuatorError::Data(
            "no experiment with the payload: the gains R K_m and K_j cannot be scaled \
             without a known payload"
                .into(),
        ));
    }
    if !data.segments.iter().any(|s| !s.payload) {
        return Err(ActuatorError::Data(
            "no experiment without the payload".into(),
        ));
    }
    if !(data.payload_moment.is_finite() && data.payload_moment != 0.0) {
        return Err(ActuatorError::Data(format!(
            "the payload's known first moment L_Y = {} kg·m must be finite and non-zero",
            data.payload_moment
        )));
    }
    let mut all = Vec::new();
    for (i, s) in data.segments.iter().enumerate() {
        let hz = check_segment(i, s)?;
        all.push((signals(s, hz, settings)?, s.payload));
    }
    // Decimated, moving samples.
    let mut picks: Vec<(usize, usize)> = Vec::new();
    for (si, (sig, _)) in all.iter().enumerate() {
        let n = sig.velocity.len();
        let step = ((sig.sample_hz / settings.decimated_hz).round() as usize).max(1);
        let edge = (settings.edge_s * sig.sample_hz) as usize;
        let far = far_from_slow(
            &sig.raw[1],
            settings.velocity_threshold,
            sig.sample_hz / settings.cutoff_hz,
        );
        let mut k = edge;
        while k + edge < n {
            if far[k] {
                picks.push((si, k));
            }
            k += step;
        }
    }
    let unknowns = PARAMETER_NAMES.len();
    if picks.len() < 3 * unknowns {
        return Err(ActuatorError::Data(format!(
            "{} usable samples (moving faster than {} rad/s, after decimation to {} Hz); at \
             least {} are needed",
            picks.len(),
            settings.velocity_threshold,
            settings.decimated_hz,
            3 * unknowns
        )));
    }
    let r = 2 * picks.len();
    let mut w = DMatrix::zeros(r, unknowns);
    let mut block = vec![0usize; r];
    for (p, &(si, k)) in picks.iter().enumerate() {
        let (sig, payload) = &all[si];
        rows(&mut w, 2 * p, &sig.columns, k, *payload);
        let b = 2 * usize::from(*payload);
        block[2 * p] = b;
        block[2 * p + 1] = b + 1;
    }
    // Excitation: the column-normalised regressor of the unknowns (L_Y to the right).
    let a = w.columns(0, unknowns - 1).into_owned();
    let (cond_all, weakest) = normalised_condition(&a);
    if cond_all.is_nan() || cond_all >= 1e8 {
        let names: Vec<&str> = weakest.iter().map(|&i| PARAMETER_NAMES[i]).collect();
        return Err(ActuatorError::RankDeficient {
            cond: cond_all,
            cause: format!(
                "the trajectory does not excite {} (the regressor's weakest direction)",
                names.join(", ")
            ),
        });
    }
    let cond = normalised_condition(&w.columns(0, 10).into_owned()).0;
    // Total least squares, then weighted by each block's residual.
    let phi = tls(&w, data.payload_moment)?;
    let residual = &w * &phi;
    let mut weight = [0.0; 4];
    for (b, weight) in weight.iter_mut().enumerate() {
        let (sum, count) = (0..r)
            .filter(|&i| block[i] == b)
            .fold((0.0, 0usize), |(s, c), i| {
                (s + residual[i] * residual[i], c + 1)
            });
        *weight = if count > 0 && sum > 0.0 {
            1.0 / (sum / count as f64).sqrt()
        } else {
            1.0
        };
    }
    for i in 0..r {
        w.row_mut(i).scale_mut(weight[block[i]]);
    }
    let phi = tls(&w, data.payload_moment)?;
    // Standard deviations of the equivalent least-squares problem.
    let a = w.columns(0, unknowns - 1).into_owned();
    let rho = &w * &phi;
    let s2 = rho.norm_squared() / (r - (unknowns - 1)) as f64;
    let cov = (a.transpose() * &a)
        .try_inverse()
        .ok_or_else(|| ActuatorError::RankDeficient {
            cond: cond_all,
            cause: "singular normal matrix".into(),
        })?
        * s2;
    let mut sigma: Vec<f64> = (0..unknowns - 1)
        .map(|i| 100.0 * cov[(i, i)].sqrt() / phi[i].abs())
        .collect();
    sigma.push(0.0);
    Ok(Identified {
        values: phi.iter().copied().collect(),
        sigma_percent: sigma,
        rmsd_nm: rmsd(&all, &phi, settings),
        cond,
        samples: picks.len(),
    })
}

/// `Φ̂` from the smallest singular value's right vector, scaled to `L_Y = moment`.
fn tls(w: &DMatrix<f64>, moment: f64) -> Result<DVector<f64>, ActuatorError> {
    let svd = w.clone().svd(false, true);
    let vt = svd
        .v_t
        .ok_or_else(|| ActuatorError::Data("SVD failed".into()))?;
    let smallest = svd
        .singular_values
        .iter()
        .enumerate()
        .min_by(|a, b| a.1.total_cmp(b.1))
        .map(|(i, _)| i)
        .unwrap_or(0);
    let v = vt.row(smallest).transpose();
    let last = v[v.len() - 1];
    if last.abs() < 1e-300 {
        return Err(ActuatorError::Data(
            "the payload's parameter vanishes from the solution: the payload does not act".into(),
        ));
    }
    Ok(v * (moment / last))
}

/// Condition number of `a` with unit-norm columns, and the parameters it does not
/// determine: those whose column is zero, else those that weigh in its weakest direction.
fn normalised_condition(a: &DMatrix<f64>) -> (f64, Vec<usize>) {
    let mut a = a.clone();
    let largest = a.column_iter().map(|c| c.norm()).fold(0.0, f64::max);
    let mut zero = Vec::new();
    for (i, mut c) in a.column_iter_mut().enumerate() {
        let n = c.norm();
        if n > 1e-12 * largest {
            c /= n;
        } else {
            zero.push(i);
        }
    }
    if !zero.is_empty() {
        return (f64::INFINITY, zero);
    }
    let svd = a.svd(false, true);
    let s = &svd.singular_values;
    let (imin, smin) = s
        .iter()
        .enumerate()
        .min_by(|x, y| x.1.total_cmp(y.1))
        .map(|(i, v)| (i, *v))
        .unwrap_or((0, 0.0));
    let weakest = svd
        .v_t
        .map(|vt| {
            vt.row(imin)
                .iter()
                .enumerate()
                .filter(|(_, v)| v.abs() > 0.3)
                .map(|(i, _)| i)
                .collect()
        })
        .unwrap_or_default();
    (s.max() / smin, weakest)
}

/// RMS of the motor rows' residual on the raw samples of the experiments without payload.
fn rmsd(all: &[(Signals, bool)], phi: &DVector<f64>, settings: &IdentificationSettings) -> f64 {
    let (mut sum, mut count) = (0.0, 0usize);
    for (sig, payload) in all.iter().filter(|(_, p)| !p) {
        let n = sig.velocity.len();
        let edge = (settings.edge_s * sig.sample_hz) as usize;
        let mut w = DMatrix::zeros(2, PARAMETER_NAMES.len());
        for k in edge..n.saturating_sub(edge) {
            if sig.raw[1][k].abs() <= settings.velocity_threshold {
                continue;
            }
            rows(&mut w, 0, &sig.raw, k, *payload);
            let e = (w.row(0) * phi)[0];
            sum += e * e;
            count += 1;
        }
    }
    (sum / count.max(1) as f64).sqrt()
}
