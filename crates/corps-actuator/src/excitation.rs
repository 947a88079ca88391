//! The exciting trajectory of seed 000 §6 step 3: double S-curves over the whole range of
//! the joint, the acceleration, constant-velocity and deceleration phases of equal duration,
//! the velocity plateau rising in 20 % steps up to the maximum. Each move of length `L` at
//! plateau `v` lasts `3T` with `T = L/(2v)`; the velocity rises as `v (1 − cos(πt/T))/2`
//! (continuous acceleration, zero at both ends of the phase). Each level goes there and back
//! with a rest at either end.

use std::f64::consts::PI;

/// The trajectory's design.
#[derive(Clone, Debug, PartialEq)]
pub struct Excitation {
    /// The positions swept, rad (the joint's range less a margin).
    pub range: [f64; 2],
    /// Highest plateau velocity, rad/s.
    pub max_velocity: f64,
    /// Plateau velocities as fractions of the maximum (the thesis: 0.2, 0.4, … 1.0).
    pub levels: Vec<f64>,
    /// Rest at either end, s.
    pub rest_s: f64,
    /// How many there-and-back moves per level.
    pub repeats: usize,
}

/// `(q, q̇, q̈)` samples at a fixed rate.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Motion {
    pub t: Vec<f64>,
    pub q: Vec<f64>,
    pub v: Vec<f64>,
    pub a: Vec<f64>,
}

impl Excitation {
    /// The thesis's design over `range` up to `max_velocity`.
    pub fn thesis(range: [f64; 2], max_velocity: f64) -> Self {
        Self {
            range,
            max_velocity,
            levels: vec![0.2, 0.4, 0.6, 0.8, 1.0],
            rest_s: 0.5,
            repeats: 2,
        }
    }

    /// Samples the trajectory at `sample_hz`, starting at rest at the range's lower end.
    pub fn sample(&self, sample_hz: f64) -> Motion {
        let mut pieces: Vec<(f64, f64, f64, f64)> = Vec::new(); // (duration, from, to, v)
        let [lo, hi] = self.range;
        for &level in &self.levels {
            let v = level * self.max_velocity;
            for _ in 0..self.repeats {
                pieces.push((self.rest_s, lo, lo, 0.0));
                pieces.push((3.0 * (hi - lo) / (2.0 * v), lo, hi, v));
                pieces.push((self.rest_s, hi, hi, 0.0));
                pieces.push((3.0 * (hi - lo) / (2.0 * v), hi, lo, v));
            }
        }
        pieces.push((self.rest_s, lo, lo, 0.0));
        let total: f64 = pieces.iter().map(|p| p.0).sum();
        let n = (total * sample_hz).floor() as usize + 1;
        let mut m = Motion::default();
        let (mut start, mut index) = (0.0, 0);
        for k in 0..n {
            let t = k as f64 / sample_hz;
            while index + 1 < pieces.len() && t >= start + pieces[index].0 {
                start += pieces[index].0;
                index += 1;
            }
            let (duration, from, to, v) = pieces[index];
            let (q, qd, qdd) = if v == 0.0 {
                (from, 0.0, 0.0)
            } else {
                let s = (to - from).signum();
                let (d, vd, ad) = s_curve((t - start).min(duration), duration / 3.0, v);
                (from + s * d, s * vd, s * ad)
            };
            m.t.push(t);
            m.q.push(q);
            m.v.push(qd);
            m.a.push(qdd);
        }
        m
    }
}

/// Distance, velocity and acceleration at `t` into a move of three phases of length `p` with
/// plateau `v`.
fn s_curve(t: f64, p: f64, v: f64) -> (f64, f64, f64) {
    let w = PI / p;
    if t < p {
        (
            0.5 * v * (t - (w * t).sin() / w),
            0.5 * v * (1.0 - (w * t).cos()),
            0.5 * v * w * (w * t).sin(),
        )
    } else if t < 2.0 * p {
        (0.5 * v * p + v * (t - p), v, 0.0)
    } else {
        let r = (3.0 * p - t).max(0.0);
        let (d, vd, ad) = s_curve(r, p, v);
        (2.0 * v * p - d, vd, -ad)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_trajectory_is_consistent_and_sweeps_the_range() {
        let e = Excitation::thesis([-2.3, -0.05], 4.0);
        let fs = 1000.0;
        let m = e.sample(fs);
        let (min, max) =
            m.q.iter()
                .fold((f64::MAX, f64::MIN), |(a, b), &q| (a.min(q), b.max(q)));
        assert!((min + 2.3).abs() < 1e-9 && (max + 0.05).abs() < 1e-9);
        let vmax = m.v.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        assert!((vmax - 4.0).abs() < 1e-9);
        // Velocity and acceleration are the derivatives of position (centred differences).
        for k in 1..m.q.len() - 1 {
            let v = (m.q[k + 1] - m.q[k - 1]) * fs / 2.0;
            assert!((v - m.v[k]).abs() < 1e-3, "{k}");
            let a = (m.v[k + 1] - m.v[k - 1]) * fs / 2.0;
            assert!((a - m.a[k]).abs() < 0.2, "{k}: {a} vs {}", m.a[k]);
        }
    }
}
