//! Reference trajectories: samples of position, velocity and acceleration at time t.

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
        let tau = ((t - self.t0) / self.duration).clamp(0.0, 1.0);
        let (s, ds, dds) = if t < self.t0 || t > self.t0 + self.duration || self.duration <= 0.0 {
            (if t < self.t0 { 0.0 } else { 1.0 }, 0.0, 0.0)
        } else {
            let t2 = tau * tau;
            let d = self.duration;
            (
                t2 * tau * (10.0 - 15.0 * tau + 6.0 * t2),
                30.0 * t2 * (1.0 - 2.0 * tau + t2) / d,
                60.0 * tau * (1.0 - 3.0 * tau + 2.0 * t2) / (d * d),
            )
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
}
