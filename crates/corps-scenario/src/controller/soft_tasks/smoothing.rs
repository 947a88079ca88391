//! Minimum-jerk smoothing of set-point changes (seed 001 §2.7, after Pattacini 2010): a
//! change starts a quintic from the reference's current position, velocity and acceleration
//! to the new set-point at rest, over `t_smooth`, so that a change in the middle of a move
//! keeps the reference twice differentiable.

use nalgebra::Vector3;
use std::ops::{Add, Div, Mul, Sub};

/// What a reference can be: a point (`Vector3`) or one joint's angle (`f64`).
pub trait Point:
    Copy
    + PartialEq
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<f64, Output = Self>
    + Div<f64, Output = Self>
{
}
impl<T> Point for T where
    T: Copy
        + PartialEq
        + Add<Output = T>
        + Sub<Output = T>
        + Mul<f64, Output = T>
        + Div<f64, Output = T>
{
}

/// T's zero (+0 in every component).
#[allow(clippy::eq_op)]
fn zero<T: Point>(x: T) -> T {
    x - x
}

/// One reference and the quintic it follows.
#[derive(Clone, Debug)]
pub struct Smoothed<T: Point = Vector3<f64>> {
    start: f64,
    duration: f64,
    /// Coefficients c0…c5 of p(τ) = Σ c_k τ^k, τ = t − start.
    c: [T; 6],
    target: T,
}

impl<T: Point> Smoothed<T> {
    /// At rest at `p`.
    pub fn at(p: T) -> Self {
        let z = zero(p);
        Self {
            start: 0.0,
            duration: 0.0,
            c: [p, z, z, z, z, z],
            target: p,
        }
    }

    /// The set-point it is heading to.
    pub fn target(&self) -> T {
        self.target
    }

    /// Position, velocity, acceleration at `t`.
    pub fn sample(&self, t: f64) -> [T; 3] {
        let z = zero(self.target);
        if self.duration <= 0.0 || t - self.start >= self.duration {
            return [self.target, z, z];
        }
        let tau = (t - self.start).max(0.0);
        let c = &self.c;
        let p = c[0] + (c[1] + (c[2] + (c[3] + (c[4] + c[5] * tau) * tau) * tau) * tau) * tau;
        let v = c[1]
            + (c[2] * 2.0 + (c[3] * 3.0 + (c[4] * 4.0 + c[5] * (5.0 * tau)) * tau) * tau) * tau;
        let a = c[2] * 2.0 + (c[3] * 6.0 + (c[4] * 12.0 + c[5] * (20.0 * tau)) * tau) * tau;
        [p, v, a]
    }

    /// Heads to `target` from `t`, over `duration` (0: a jump).
    pub fn go_to(&mut self, t: f64, target: T, duration: f64) {
        if target == self.target {
            return;
        }
        let [p0, v0, a0] = self.sample(t);
        let d = duration;
        self.start = t;
        self.duration = d;
        self.target = target;
        if d <= 0.0 {
            return;
        }
        let dp = target - p0;
        self.c = [
            p0,
            v0,
            a0 / 2.0,
            (dp * 20.0 - v0 * 12.0 * d - a0 * 3.0 * d * d) / (2.0 * d.powi(3)),
            (dp * -30.0 + v0 * 16.0 * d + a0 * 3.0 * d * d) / (2.0 * d.powi(4)),
            (dp * 12.0 - v0 * 6.0 * d - a0 * d * d) / (2.0 * d.powi(5)),
        ];
    }
}

/// The minimum-jerk blend `10x³ − 15x⁴ + 6x⁵` of `x = elapsed / duration` clamped to [0, 1]
/// (1 for a duration ≤ 0): how far a gain switch has gone.
pub fn min_jerk_fraction(elapsed: f64, duration: f64) -> f64 {
    if duration <= 0.0 {
        return 1.0;
    }
    let x = (elapsed / duration).clamp(0.0, 1.0);
    x * x * x * (10.0 + x * (6.0 * x - 15.0))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ends_at_rest_on_the_target_and_is_continuous_through_a_change_of_mind() {
        let mut s = Smoothed::at(Vector3::zeros());
        s.go_to(1.0, Vector3::new(1.0, 0.0, 0.0), 2.0);
        let mid = s.sample(2.0);
        assert!((mid[0].x - 0.5).abs() < 1e-12, "half-way at half time");
        let before = s.sample(2.2);
        s.go_to(2.2, Vector3::new(0.0, 1.0, 0.0), 2.0);
        let after = s.sample(2.2);
        for k in 0..3 {
            assert!(
                (before[k] - after[k]).norm() < 1e-12,
                "derivative {k} jumps"
            );
        }
        let end = s.sample(4.2);
        let mut angle = Smoothed::at(0.0);
        angle.go_to(1.0, 1.0, 2.0);
        assert!((angle.sample(2.0)[0] - 0.5).abs() < 1e-12);
        assert!((min_jerk_fraction(1.0, 2.0) - 0.5).abs() < 1e-12);
        assert_eq!(min_jerk_fraction(3.0, 2.0), 1.0);
        assert!((end[0] - Vector3::new(0.0, 1.0, 0.0)).norm() < 1e-12);
        // Finite differences of the position give the velocity and acceleration.
        let h = 1e-5;
        let [p0, v, a] = s.sample(3.0);
        let (pp, pm) = (s.sample(3.0 + h)[0], s.sample(3.0 - h)[0]);
        assert!(((pp - pm) / (2.0 * h) - v).norm() < 1e-8);
        assert!(((pp - 2.0 * p0 + pm) / (h * h) - a).norm() < 1e-4);
    }
}
