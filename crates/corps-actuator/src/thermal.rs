//! The motor's first-order thermal model (seed 000 Eq 3.6–3.8):
//! winding resistance `R = R_TA (1 + α_Cu (T − T_A))`, Joule losses `P_J = R i²`, and
//! `C_th Ṫ = P_J + P_0 − (T − T_A)/R_th`. `P_0` is the constant heat the drives put into the
//! casing: the thesis's motor sits at ~43 °C unused in a 26 °C room (§4.1), so
//! `P_0 = (T_idle − T_A)/R_th`.
//!
//! Identification fits `C_th`, `R_th` and `P_0` to a heating record: a start by linear least
//! squares on the integrated model `C_th (T(t) − T(t₀)) = ∫P_J + P_0 (t − t₀) − ∫(T − T_A)/R_th`
//! (no derivative of the noisy temperature), then the output-error fit (the model simulated
//! along the record's current against the measured temperature, Gauss–Newton), whose
//! residuals are the sensor's noise and give the parameters' standard deviations.

use crate::error::ActuatorError;
use nalgebra::{DMatrix, DVector};
use serde::Deserialize;

/// Thermal parameters of one motor.
#[derive(Clone, Copy, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ThermalParameters {
    /// Room temperature `T_A`, °C.
    pub ambient_c: f64,
    /// Casing temperature with no current, °C (sets `P_0`).
    pub idle_c: f64,
    /// Winding resistance at `T_A`, Ω.
    pub winding_resistance_ohm: f64,
    /// Copper's temperature coefficient, 1/K.
    pub alpha_cu: f64,
    /// `C_th`, J/K.
    pub heat_capacity_j_per_k: f64,
    /// `R_th`, K/W.
    pub thermal_resistance_k_per_w: f64,
    /// The highest admissible winding temperature, °C.
    pub max_temperature_c: f64,
}

impl ThermalParameters {
    pub(crate) fn validate(&self) -> Result<(), ActuatorError> {
        let positive = [
            ("winding_resistance_ohm", self.winding_resistance_ohm),
            ("heat_capacity_j_per_k", self.heat_capacity_j_per_k),
            (
                "thermal_resistance_k_per_w",
                self.thermal_resistance_k_per_w,
            ),
        ];
        for (name, v) in positive {
            if !(v.is_finite() && v > 0.0) {
                return Err(ActuatorError::Description(format!(
                    "thermal {name} = {v} must be positive"
                )));
            }
        }
        if !(self.idle_c >= self.ambient_c && self.max_temperature_c > self.idle_c) {
            return Err(ActuatorError::Description(format!(
                "thermal temperatures must satisfy ambient ({}) ≤ idle ({}) < max ({})",
                self.ambient_c, self.idle_c, self.max_temperature_c
            )));
        }
        Ok(())
    }

    /// The drives' heat `P_0`, W.
    pub fn idle_power(&self) -> f64 {
        (self.idle_c - self.ambient_c) / self.thermal_resistance_k_per_w
    }

    /// Joule losses at temperature `t` and current `i` (Eq 3.7), W.
    pub fn joule(&self, t: f64, i: f64) -> f64 {
        self.winding_resistance_ohm * (1.0 + self.alpha_cu * (t - self.ambient_c)) * i * i
    }

    /// `Ṫ` of Eq 3.8, K/s.
    pub fn rate(&self, t: f64, i: f64) -> f64 {
        (self.joule(t, i) + self.idle_power()
            - (t - self.ambient_c) / self.thermal_resistance_k_per_w)
            / self.heat_capacity_j_per_k
    }

    /// The temperature after `duration` s at constant current `i` from `t0` (RK4 steps of
    /// 1 s, or of `duration`/10⁷ beyond 10⁷ s — still far inside RK4's stability for the
    /// model's time constant `C_th R_th` when that is minutes or more).
    pub fn predict(&self, t0: f64, i: f64, duration: f64) -> f64 {
        let steps = duration.max(0.0).ceil().clamp(1.0, 1e7) as usize;
        let h = duration.max(0.0) / steps as f64;
        let mut t = t0;
        for _ in 0..steps {
            let k1 = self.rate(t, i);
            let k2 = self.rate(t + 0.5 * h * k1, i);
            let k3 = self.rate(t + 0.5 * h * k2, i);
            let k4 = self.rate(t + h * k3, i);
            t += h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
        }
        t
    }

    /// The equilibrium temperature at constant current `i`, or None when the resistance's
    /// growth outruns the cooling (no equilibrium: thermal runaway). From Eq 3.8 with Ṫ = 0:
    /// `ΔT = R_th (P_0 + R_TA i²) / (1 − R_th R_TA α_Cu i²)`.
    pub fn steady_state(&self, i: f64) -> Option<f64> {
        let r = self.thermal_resistance_k_per_w;
        let denominator = 1.0 - r * self.winding_resistance_ohm * self.alpha_cu * i * i;
        (denominator > 0.0).then(|| {
            self.ambient_c
                + r * (self.idle_power() + self.winding_resistance_ohm * i * i) / denominator
        })
    }
}

/// A heating record: time (s), motor current (A, the RMS over the interval that ends at the
/// sample: what heats the winding; the current itself when sampled fast) and casing
/// temperature (°C).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct HeatingRecord {
    pub t: Vec<f64>,
    pub current: Vec<f64>,
    pub temperature: Vec<f64>,
}

/// The columns of a heating record's CSV file.
pub const CSV_COLUMNS: [&str; 3] = ["t_s", "current_A", "temperature_C"];

impl HeatingRecord {
    /// Reads a CSV file with the columns [`CSV_COLUMNS`] (in any order, by header name);
    /// [`identify_thermal`] checks the values.
    pub fn read_csv(text: &str) -> Result<Self, ActuatorError> {
        let mut r = Self::default();
        crate::csv_rows::read_rows(text, CSV_COLUMNS, |_, [t, current, temperature]| {
            r.t.push(t);
            r.current.push(current);
            r.temperature.push(temperature);
            Ok(())
        })?;
        Ok(r)
    }
}

/// Fitted `C_th`, `R_th`, `P_0` with their relative standard deviations (%) and the fit's
/// temperature RMSD (K) when the identified model is simulated along the record.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ThermalFit {
    pub heat_capacity_j_per_k: f64,
    pub thermal_resistance_k_per_w: f64,
    pub idle_power_w: f64,
    pub sigma_percent: [f64; 3],
    pub rmsd_k: f64,
}

/// Fits `C_th`, `R_th`, `P_0` to `record`, with `ambient_c`, the winding resistance and
/// α_Cu of `known` taken as known.
pub fn identify_thermal(
    record: &HeatingRecord,
    known: &ThermalParameters,
) -> Result<ThermalFit, ActuatorError> {
    let n = record.t.len();
    if record.current.len() != n || record.temperature.len() != n {
        return Err(ActuatorError::Data("columns of unequal length".into()));
    }
    if n < 10 {
        return Err(ActuatorError::Data(format!(
            "{n} samples: a thermal fit needs at least 10"
        )));
    }
    for k in 0..n {
        if !(record.t[k].is_finite()
            && record.current[k].is_finite()
            && record.temperature[k].is_finite())
        {
            return Err(ActuatorError::Data(format!(
                "row {} holds a non-finite value",
                k + 1
            )));
        }
        if k > 0 && record.t[k] <= record.t[k - 1] {
            return Err(ActuatorError::Data(format!(
                "time does not increase at row {} ({} after {})",
                k + 1,
                record.t[k],
                record.t[k - 1]
            )));
        }
    }
    // Integrated model, unknowns θ = [C_th, P_0, 1/R_th]:
    // C_th ΔT_k − P_0 (t_k − t_0) + (1/R_th) ∫(T − T_A) = ∫P_J.
    let mut a = DMatrix::zeros(n - 1, 3);
    let mut y = DVector::zeros(n - 1);
    let (mut int_pj, mut int_dt) = (0.0, 0.0);
    for k in 1..n {
        let h = record.t[k] - record.t[k - 1];
        let mean_t = 0.5 * (record.temperature[k] + record.temperature[k - 1]);
        int_pj += h * known.joule(mean_t, record.current[k]);
        int_dt +=
            0.5 * h * (record.temperature[k] + record.temperature[k - 1] - 2.0 * known.ambient_c);
        a[(k - 1, 0)] = record.temperature[k] - record.temperature[0];
        a[(k - 1, 1)] = -(record.t[k] - record.t[0]);
        a[(k - 1, 2)] = int_dt;
        y[k - 1] = int_pj;
    }
    let svd = a.clone().svd(true, true);
    let cond = svd.singular_values.max() / svd.singular_values.min();
    if cond.is_nan() || cond >= 1e12 {
        return Err(ActuatorError::RankDeficient {
            cond,
            cause: "the record does not separate heating, drive heat and cooling (it needs \
                    a change of current long enough to change the temperature)"
                .into(),
        });
    }
    let theta = svd
        .solve(&y, 0.0)
        .map_err(|e| ActuatorError::Data(e.to_string()))?;
    let (c, p0, inv_r) = (theta[0], theta[1], theta[2]);
    if !(c > 0.0 && inv_r > 0.0) {
        return Err(ActuatorError::Data(format!(
            "the fit is not physical (C_th = {c:.3e} J/K, 1/R_th = {inv_r:.3e} W/K): the \
             record does not heat and cool the motor"
        )));
    }
    output_error_fit(record, known, [c, inv_r, p0, record.temperature[0]])
}

/// The temperatures the model predicts along `record` for `θ = [C_th, 1/R_th, P_0, T(t₀)]`.
fn simulate(record: &HeatingRecord, known: &ThermalParameters, theta: &[f64; 4], out: &mut [f64]) {
    let model = ThermalParameters {
        heat_capacity_j_per_k: theta[0],
        thermal_resistance_k_per_w: 1.0 / theta[1],
        idle_c: known.ambient_c + theta[2] / theta[1],
        ..*known
    };
    out[0] = theta[3];
    for k in 1..record.t.len() {
        out[k] = model.predict(out[k - 1], record.current[k], record.t[k] - record.t[k - 1]);
    }
}

/// Output-error refinement by Gauss–Newton from `theta`: the simulated temperature against
/// the measured one, whose residuals are the sensor's white noise, so that the covariance
/// `σ² (JᵀJ)⁻¹` holds (the integrated least squares only starts it: its residuals are
/// cumulative sums).
fn output_error_fit(
    record: &HeatingRecord,
    known: &ThermalParameters,
    mut theta: [f64; 4],
) -> Result<ThermalFit, ActuatorError> {
    let n = record.t.len();
    let mut sim = vec![0.0; n];
    let mut plus = vec![0.0; n];
    let mut minus = vec![0.0; n];
    let mut jac = DMatrix::zeros(n, 4);
    let mut residual = DVector::zeros(n);
    for _ in 0..50 {
        simulate(record, known, &theta, &mut sim);
        for k in 0..n {
            residual[k] = record.temperature[k] - sim[k];
        }
        for j in 0..4 {
            let h = 1e-6 * theta[j].abs().max(1e-3);
            let (mut tp, mut tm) = (theta, theta);
            tp[j] += h;
            tm[j] -= h;
            simulate(record, known, &tp, &mut plus);
            simulate(record, known, &tm, &mut minus);
            for k in 0..n {
                jac[(k, j)] = (plus[k] - minus[k]) / (2.0 * h);
            }
        }
        let step = (jac.transpose() * &jac)
            .lu()
            .solve(&(jac.transpose() * &residual))
            .ok_or_else(|| ActuatorError::RankDeficient {
                cond: f64::INFINITY,
                cause: "the thermal parameters are not separable on this record".into(),
            })?;
        let mut largest = 0.0f64;
        for j in 0..4 {
            theta[j] += step[j];
            largest = largest.max((step[j] / theta[j].abs().max(1e-12)).abs());
        }
        if !(theta[0] > 0.0 && theta[1] > 0.0) {
            return Err(ActuatorError::Data(
                "the fit is not physical: the record does not heat and cool the motor".into(),
            ));
        }
        if largest < 1e-10 {
            break;
        }
    }
    simulate(record, known, &theta, &mut sim);
    for k in 0..n {
        residual[k] = record.temperature[k] - sim[k];
    }
    let s2 = residual.norm_squared() / (n - 4) as f64;
    let cov =
        (jac.transpose() * &jac)
            .try_inverse()
            .ok_or_else(|| ActuatorError::RankDeficient {
                cond: f64::INFINITY,
                cause: "singular normal matrix".into(),
            })?
            * s2;
    let sigma = |i: usize| 100.0 * cov[(i, i)].sqrt() / theta[i].abs();
    // σ% of R_th equals that of 1/R_th to first order.
    Ok(ThermalFit {
        heat_capacity_j_per_k: theta[0],
        thermal_resistance_k_per_w: 1.0 / theta[1],
        idle_power_w: theta[2],
        sigma_percent: [sigma(0), sigma(1), sigma(2)],
        rmsd_k: (residual.norm_squared() / n as f64).sqrt(),
    })
}

/// A simulated heating run (seed 000 §4.1: position control, a sinusoidal elbow motion with
/// a heavy load): `heating_s` of a current `amplitude |sin(2πt/period)|`-shaped profile, then
/// `cooling_s` without current, the temperature sampled at 1 Hz with Gaussian noise.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HeatingSimulation {
    pub amplitude_a: f64,
    pub period_s: f64,
    pub heating_s: f64,
    pub cooling_s: f64,
    pub noise_c: f64,
    pub seed: u64,
}

impl Default for HeatingSimulation {
    fn default() -> Self {
        Self {
            amplitude_a: 5.0,
            period_s: 2.0,
            heating_s: 1800.0,
            cooling_s: 1800.0,
            noise_c: 0.1,
            seed: 1,
        }
    }
}

impl HeatingSimulation {
    /// The record, from the idle temperature, integrated by RK4 at 0.05 s.
    pub fn run(&self, truth: &ThermalParameters) -> HeatingRecord {
        use rand::SeedableRng;
        use rand_distr::{Distribution, Normal};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(self.seed);
        let noise = Normal::new(0.0, self.noise_c.max(0.0)).expect("σ ≥ 0");
        let current = |t: f64| {
            if t < self.heating_s {
                self.amplitude_a * (2.0 * std::f64::consts::PI * t / self.period_s).sin().abs()
            } else {
                0.0
            }
        };
        let (h, per_sample) = (0.05, 20);
        let mut temperature = truth.idle_c;
        let mut record = HeatingRecord::default();
        let samples = (self.heating_s + self.cooling_s) as usize;
        record.t.push(0.0);
        record.current.push(0.0);
        record
            .temperature
            .push(temperature + noise.sample(&mut rng));
        for s in 0..samples {
            let mut sq = 0.0;
            for j in 0..per_sample {
                let t = s as f64 + j as f64 * h;
                let (i0, im, i1) = (current(t), current(t + 0.5 * h), current(t + h));
                sq += (i0 * i0 + 4.0 * im * im + i1 * i1) / 6.0;
                let k1 = truth.rate(temperature, i0);
                let k2 = truth.rate(temperature + 0.5 * h * k1, im);
                let k3 = truth.rate(temperature + 0.5 * h * k2, im);
                let k4 = truth.rate(temperature + h * k3, i1);
                temperature += h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
            }
            record.t.push((s + 1) as f64);
            record.current.push((sq / per_sample as f64).sqrt());
            record
                .temperature
                .push(temperature + noise.sample(&mut rng));
        }
        record
    }
}
