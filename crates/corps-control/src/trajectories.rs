//! Reference trajectories: samples of position, velocity and acceleration at time t —
//! constant ([`Reference::constant`]), minimum-jerk segments, sinusoids, and splines through
//! samples read from a file.

use crate::error::{ControlError, Result};
use crate::tasks::Reference;
use nalgebra::DVector;

/// A minimum-jerk segment from `start` to `end` over `duration` seconds, beginning at `t0`:
/// s(τ) = 10τ³ − 15τ⁴ + 6τ⁵ with τ = (t − t0)/T (zero velocity and acceleration at both
/// ends; Flash & Hogan 1985). Before t0 it holds `start`, after t0 + T it holds `end`.
#[derive(Clone, Debug, PartialEq)]
pub struct MinJerk {
    pub start: DVector<f64>,
    pub end: DVector<f64>,
    pub t0: f64,
    pub duration: f64,
}

impl MinJerk {
    pub fn sample(&self, t: f64) -> Reference {
        let (s, ds, dds) = if t < self.t0 || t > self.t0 + self.duration || self.duration <= 0.0 {
            (if t < self.t0 { 0.0 } else { 1.0 }, 0.0, 0.0)
        } else {
            let d = self.duration;
            let [s, ds, dds] = corps_model::min_jerk::min_jerk((t - self.t0) / d);
            (s, ds / d, dds / (d * d))
        };
        let delta = &self.end - &self.start;
        Reference {
            pos: &self.start + &delta * s,
            vel: &delta * ds,
            acc: &delta * dds,
        }
    }
}

/// `center + amplitude · sin(2π f t)` per axis.
#[derive(Clone, Debug, PartialEq)]
pub struct Sinusoid {
    pub center: DVector<f64>,
    pub amplitude: DVector<f64>,
    pub frequency: f64,
}

impl Sinusoid {
    pub fn sample(&self, t: f64) -> Reference {
        let w = std::f64::consts::TAU * self.frequency;
        let (s, c) = (w * t).sin_cos();
        Reference {
            pos: &self.center + &self.amplitude * s,
            vel: &self.amplitude * (w * c),
            acc: &self.amplitude * (-w * w * s),
        }
    }
}

/// A trajectory through samples `(t_k, x_k)`: a natural cubic spline per component (continuous
/// position, velocity and acceleration; zero curvature at the ends). Before the first sample it
/// holds the first value, after the last the last, at rest.
#[derive(Clone, Debug, PartialEq)]
pub struct Sampled {
    times: Vec<f64>,
    values: Vec<DVector<f64>>,
    /// Second derivatives at the samples.
    curvature: Vec<DVector<f64>>,
}

impl Sampled {
    /// A spline through `values` at strictly increasing `times` (at least two samples, all of
    /// the same dimension, all finite).
    pub fn new(times: Vec<f64>, values: Vec<DVector<f64>>) -> Result<Self> {
        let bad = |reason: String| ControlError::Config {
            name: "sampled trajectory".into(),
            reason,
        };
        let n = times.len();
        if n < 2 || values.len() != n {
            return Err(bad(format!(
                "{n} times for {} samples (at least 2)",
                values.len()
            )));
        }
        let dim = values[0].len();
        for (k, (t, x)) in times.iter().zip(&values).enumerate() {
            if x.len() != dim {
                return Err(bad(format!("sample {k} has {} values, not {dim}", x.len())));
            }
            if !t.is_finite() || x.iter().any(|v| !v.is_finite()) {
                return Err(bad(format!("sample {k} is not finite")));
            }
            if k > 0 && *t <= times[k - 1] {
                return Err(bad(format!("time {t} at sample {k} does not increase")));
            }
        }
        // Natural spline: tridiagonal system for the interior second derivatives (Thomas).
        let mut curvature = vec![DVector::zeros(dim); n];
        let mut c_prime = vec![0.0; n];
        let mut d_prime = vec![DVector::zeros(dim); n];
        for k in 1..n - 1 {
            let (h0, h1) = (times[k] - times[k - 1], times[k + 1] - times[k]);
            let rhs = (&values[k + 1] - &values[k]) * (6.0 / h1)
                - (&values[k] - &values[k - 1]) * (6.0 / h0);
            let diag = 2.0 * (h0 + h1) - h0 * c_prime[k - 1];
            c_prime[k] = h1 / diag;
            d_prime[k] = (rhs - &d_prime[k - 1] * h0) / diag;
        }
        for k in (1..n - 1).rev() {
            curvature[k] = &d_prime[k] - &curvature[k + 1] * c_prime[k];
        }
        Ok(Self {
            times,
            values,
            curvature,
        })
    }

    /// Parses comma-separated rows `t, x₁, …, x_m` (lines starting with `#` and a header row
    /// whose first field is not a number are skipped).
    pub fn from_csv(text: &str) -> Result<Self> {
        let (mut times, mut values) = (vec![], vec![]);
        for (line_no, line) in text.lines().enumerate() {
            let line = line.trim();
            if line.is_empty() || line.starts_with('#') {
                continue;
            }
            let fields: Vec<&str> = line.split(',').map(str::trim).collect();
            let parsed: std::result::Result<Vec<f64>, _> =
                fields.iter().map(|f| f.parse::<f64>()).collect();
            match parsed {
                Ok(row) if row.len() >= 2 => {
                    times.push(row[0]);
                    values.push(DVector::from_column_slice(&row[1..]));
                }
                Err(_) if times.is_empty() && fields[0].parse::<f64>().is_err() => continue,
                _ => {
                    return Err(ControlError::Config {
                        name: "sampled trajectory".into(),
                        reason: format!("line {}: expected numbers `t, x1, ...`", line_no + 1),
                    })
                }
            }
        }
        Self::new(times, values)
    }

    /// Duration from the first to the last sample.
    pub fn duration(&self) -> f64 {
        self.times[self.times.len() - 1] - self.times[0]
    }

    pub fn sample(&self, t: f64) -> Reference {
        let n = self.times.len();
        if t <= self.times[0] || t >= self.times[n - 1] {
            let x = if t <= self.times[0] {
                &self.values[0]
            } else {
                &self.values[n - 1]
            };
            return Reference::constant(x.clone());
        }
        let k = self.times.partition_point(|tk| *tk <= t) - 1;
        let h = self.times[k + 1] - self.times[k];
        let (a, b) = ((self.times[k + 1] - t) / h, (t - self.times[k]) / h);
        let (x0, x1) = (&self.values[k], &self.values[k + 1]);
        let (m0, m1) = (&self.curvature[k], &self.curvature[k + 1]);
        Reference {
            pos: x0 * a + x1 * b + (m0 * (a * a * a - a) + m1 * (b * b * b - b)) * (h * h / 6.0),
            vel: (x1 - x0) / h + (m1 * (3.0 * b * b - 1.0) - m0 * (3.0 * a * a - 1.0)) * (h / 6.0),
            acc: m0 * a + m1 * b,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn min_jerk_derivatives_match_finite_differences_and_end_at_rest() {
        let mj = MinJerk {
            start: DVector::from_vec(vec![0.0, 1.0]),
            end: DVector::from_vec(vec![0.3, -1.0]),
            t0: 0.5,
            duration: 2.0,
        };
        let h = 1e-6;
        for k in 1..40 {
            let t = 0.5 + 2.0 * k as f64 / 40.0;
            let (a, b, c) = (mj.sample(t - h), mj.sample(t), mj.sample(t + h));
            let vel_fd = (&c.pos - &a.pos) / (2.0 * h);
            let acc_fd = (&c.vel - &a.vel) / (2.0 * h);
            assert!((vel_fd - &b.vel).amax() < 1e-6);
            assert!((acc_fd - &b.acc).amax() < 1e-5);
        }
        let end = mj.sample(2.5);
        assert!(
            (end.pos - &mj.end).amax() < 1e-15 && end.vel.amax() < 1e-15 && end.acc.amax() < 1e-12
        );
        assert_eq!(mj.sample(0.0).pos, mj.start);
    }

    #[test]
    fn sinusoid_derivatives_are_consistent() {
        let s = Sinusoid {
            center: DVector::zeros(1),
            amplitude: DVector::from_vec(vec![0.03]),
            frequency: 0.5,
        };
        let h = 1e-6;
        let (a, b, c) = (s.sample(0.7 - h), s.sample(0.7), s.sample(0.7 + h));
        assert!(((&c.pos - &a.pos) / (2.0 * h) - &b.vel).amax() < 1e-8);
        assert!(((&c.vel - &a.vel) / (2.0 * h) - &b.acc).amax() < 1e-8);
    }

    #[test]
    fn a_spline_through_samples_of_a_sine_interpolates_and_differentiates_consistently() {
        // Samples of sin(t) every 0.1 s: the spline's value, velocity and acceleration match
        // sin, cos, −sin away from the (natural) ends, and its derivatives match finite
        // differences of itself.
        let times: Vec<f64> = (0..=60).map(|k| 0.1 * k as f64).collect();
        let values = times
            .iter()
            .map(|t| DVector::from_element(1, t.sin()))
            .collect();
        let s = Sampled::new(times, values).unwrap();
        for t in [1.03, 2.5, 3.77, 4.91] {
            let r = s.sample(t);
            assert!((r.pos[0] - t.sin()).abs() < 1e-5, "pos at {t}");
            assert!((r.vel[0] - t.cos()).abs() < 1e-3, "vel at {t}");
            assert!((r.acc[0] + t.sin()).abs() < 2e-2, "acc at {t}");
            let e = 1e-6;
            let fd = (s.sample(t + e).pos[0] - s.sample(t - e).pos[0]) / (2.0 * e);
            assert!((fd - r.vel[0]).abs() < 1e-6);
            let fd = (s.sample(t + e).vel[0] - s.sample(t - e).vel[0]) / (2.0 * e);
            assert!((fd - r.acc[0]).abs() < 1e-5);
        }
        assert_eq!(s.sample(-1.0).pos[0], 0.0);
        assert_eq!(s.sample(10.0).vel[0], 0.0);
    }

    #[test]
    fn csv_samples_parse_with_a_header_and_bad_rows_are_errors() {
        let s = Sampled::from_csv("t, x, y\n0, 0, 1\n# comment\n1, 2, 3\n2, 4, 5\n").unwrap();
        assert!((s.duration() - 2.0).abs() < 1e-12);
        assert!((s.sample(1.0).pos[1] - 3.0).abs() < 1e-12);
        let e = Sampled::from_csv("0, 0\n1, x\n").unwrap_err().to_string();
        assert!(e.contains("line 2"), "{e}");
        let e = Sampled::from_csv("0, 0\n0, 1\n").unwrap_err().to_string();
        assert!(e.contains("does not increase"), "{e}");
    }
}
