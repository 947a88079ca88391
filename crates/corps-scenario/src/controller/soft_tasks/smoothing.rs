//! Minimum-jerk smoothing of set-point changes (seed 001 §2.7, after Pattacini 2010): a
//! change starts a quintic from the reference's current position, velocity and acceleration
//! to the new set-point at rest, over `t_smooth`, so that a change in the middle of a move
//! keeps the reference twice differentiable.

use nalgebra::Vector3;

/// One 3-D reference and the quintic it follows.
#[derive(Clone, Debug)]
pub struct Smoothed {
    start: f64,
    duration: f64,
    /// Coefficients c0…c5 of p(τ) = Σ c_k τ^k, τ = t − start.
    c: [Vector3<f64>; 6],
    target: Vector3<f64>,
}

impl Smoothed {
    /// At rest at `p`.
    pub fn at(p: Vector3<f64>) -> Self {
        let z = Vector3::zeros();
        Self {
            start: 0.0,
            duration: 0.0,
            c: [p, z, z, z, z, z],
            target: p,
        }
    }

    /// The set-point it is heading to.
    pub fn target(&self) -> Vector3<f64> {
        self.target
    }

    /// Position, velocity, acceleration at `t`.
    pub fn sample(&self, t: f64) -> [Vector3<f64>; 3] {
        let tau = (t - self.start).clamp(0.0, self.duration);
        if self.duration <= 0.0 {
            return [self.target, Vector3::zeros(), Vector3::zeros()];
        }
        if t - self.start >= self.duration {
            return [self.target, Vector3::zeros(), Vector3::zeros()];
        }
        let c = &self.c;
        let p = c[0] + tau * (c[1] + tau * (c[2] + tau * (c[3] + tau * (c[4] + tau * c[5]))));
        let v =
            c[1] + tau * (2.0 * c[2] + tau * (3.0 * c[3] + tau * (4.0 * c[4] + tau * 5.0 * c[5])));
        let a = 2.0 * c[2] + tau * (6.0 * c[3] + tau * (12.0 * c[4] + tau * 20.0 * c[5]));
        [p, v, a]
    }

    /// Heads to `target` from `t`, over `duration` (0: a jump).
    pub fn go_to(&mut self, t: f64, target: Vector3<f64>, duration: f64) {
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
            (20.0 * dp - 12.0 * v0 * d - 3.0 * a0 * d * d) / (2.0 * d.powi(3)),
            (-30.0 * dp + 16.0 * v0 * d + 3.0 * a0 * d * d) / (2.0 * d.powi(4)),
            (12.0 * dp - 6.0 * v0 * d - a0 * d * d) / (2.0 * d.powi(5)),
        ];
    }
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
        assert!((end[0] - Vector3::new(0.0, 1.0, 0.0)).norm() < 1e-12);
        // Finite differences of the position give the velocity and acceleration.
        let h = 1e-5;
        let [p0, v, a] = s.sample(3.0);
        let (pp, pm) = (s.sample(3.0 + h)[0], s.sample(3.0 - h)[0]);
        assert!(((pp - pm) / (2.0 * h) - v).norm() < 1e-8);
        assert!(((pp - 2.0 * p0 + pm) / (h * h) - a).norm() < 1e-4);
    }
}
