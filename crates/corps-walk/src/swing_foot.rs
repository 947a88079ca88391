//! Swing-foot trajectories.
//!
//! Horizontal position and yaw follow quintic polynomials with zero velocity and acceleration
//! at lift-off and touch-down (so that the foot lands with zero velocity, which limits the
//! impact, seed 002 §4.2 R L309); the height adds a bump `(h + |z₁ − z₀|/2) · 64 s³ (1 − s)³`
//! (s = t/T) to the quintic blend of the start and end heights: its value, slope and curvature
//! vanish at both ends and at mid-swing the foot is `h` above the higher of the two soles (on
//! flat ground the apex is exactly `h`: 5 cm by default, seed 002 §4.4 `:stepheight 0.05`; on
//! stairs the foot passes the stair edge height plus `h`). The yaw is interpolated along the
//! shortest arc; the roll and pitch of the sole (a foothold on a tilted surface) follow the
//! same rest-to-rest quintics, so the foot reaches the tilt of its landing pose with zero
//! angular velocity and acceleration.

use crate::min_jerk::min_jerk;
use crate::pose::{angle_difference, wrap_angle, FootPose, FootVelocity};

/// Default apex height of the swing foot (m): seed 002 §4.4 / §5 row 11.
pub const DEFAULT_APEX_HEIGHT: f64 = 0.05;

/// A quintic `p(t)`, `t ∈ [0, T]`, with prescribed position, velocity and acceleration at
/// both ends.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Quintic {
    coeffs: [f64; 6],
    duration: f64,
}

impl Quintic {
    /// The quintic from `(p0, v0, a0)` at `t = 0` to `(p1, v1, a1)` at `t = duration`.
    /// A non-positive duration gives the constant `p1`.
    pub fn new(p0: f64, v0: f64, a0: f64, p1: f64, v1: f64, a1: f64, duration: f64) -> Self {
        if duration <= 0.0 {
            return Self {
                coeffs: [p1, 0.0, 0.0, 0.0, 0.0, 0.0],
                duration: 0.0,
            };
        }
        let d = duration;
        let (c0, c1, c2) = (p0, v0 * d, 0.5 * a0 * d * d);
        // remaining gaps in normalized time s = t/T
        let h = p1 - c0 - c1 - c2;
        let dv = v1 * d - c1 - 2.0 * c2;
        let da = a1 * d * d - 2.0 * c2;
        let c3 = 10.0 * h - 4.0 * dv + 0.5 * da;
        let c4 = -15.0 * h + 7.0 * dv - da;
        let c5 = 6.0 * h - 3.0 * dv + 0.5 * da;
        Self {
            coeffs: [c0, c1, c2, c3, c4, c5],
            duration: d,
        }
    }

    /// Rest-to-rest quintic (minimum-jerk profile) from `p0` to `p1`.
    pub fn rest_to_rest(p0: f64, p1: f64, duration: f64) -> Self {
        Self::new(p0, 0.0, 0.0, p1, 0.0, 0.0, duration)
    }

    /// Duration `T`.
    pub fn duration(&self) -> f64 {
        self.duration
    }

    /// `(p, ṗ, p̈)` at time `t`, clamped to `[0, T]` (constant outside).
    pub fn sample(&self, t: f64) -> (f64, f64, f64) {
        let c = &self.coeffs;
        if self.duration <= 0.0 {
            return (c[0], 0.0, 0.0);
        }
        let s = (t / self.duration).clamp(0.0, 1.0);
        let p = c[0] + s * (c[1] + s * (c[2] + s * (c[3] + s * (c[4] + s * c[5]))));
        let dp = c[1] + s * (2.0 * c[2] + s * (3.0 * c[3] + s * (4.0 * c[4] + s * 5.0 * c[5])));
        let ddp = 2.0 * c[2] + s * (6.0 * c[3] + s * (12.0 * c[4] + s * 20.0 * c[5]));
        let (v, a) = if t < 0.0 || t > self.duration {
            (0.0, 0.0)
        } else {
            (dp / self.duration, ddp / (self.duration * self.duration))
        };
        (p, v, a)
    }
}

/// The vertical bump `64 s³ (1 − s)³` and its first two derivatives with respect to `s`.
fn bump(s: f64) -> (f64, f64, f64) {
    let r = 1.0 - s;
    (
        64.0 * s.powi(3) * r.powi(3),
        192.0 * s * s * r * r * (1.0 - 2.0 * s),
        384.0 * s * r * ((1.0 - 2.0 * s).powi(2) - s * r),
    )
}

/// Height of the swing at normalized time `s`: the quintic blend from `z0` to `z1` plus the
/// bump of amplitude `apex`.
fn swing_height(z0: f64, z1: f64, apex: f64, s: f64) -> f64 {
    min_jerk(z0, z1, s, 1.0)[0] + apex * bump(s).0
}

/// The normalized window `[a, b]` of the horizontal motion: `a` the first `s` at which the
/// swing reaches `(z0 + z1)/2` when stepping up, `b` the last at which it is still there when
/// stepping down (bisection on the monotone half of the height profile; the apex at `s = ½`
/// is above both soles). Height changes under 1 mm count as flat: `[0, 1]`.
fn horizontal_window(z0: f64, z1: f64, apex: f64) -> (f64, f64) {
    const FLAT: f64 = 1e-3;
    let crossing = |level: f64, lo: f64, hi: f64, rising: bool| {
        let (mut lo, mut hi) = (lo, hi);
        for _ in 0..50 {
            let mid = 0.5 * (lo + hi);
            if (swing_height(z0, z1, apex, mid) >= level) == rising {
                hi = mid;
            } else {
                lo = mid;
            }
        }
        if rising {
            hi
        } else {
            lo
        }
    };
    let middle = 0.5 * (z0 + z1);
    if z1 > z0 + FLAT {
        (crossing(middle, 0.0, 0.5, true), 1.0)
    } else if z0 > z1 + FLAT {
        (0.0, crossing(middle, 0.5, 1.0, false))
    } else {
        (0.0, 1.0)
    }
}

/// A swing-foot trajectory from `start` (lift-off) to `end` (touch-down).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SwingTrajectory {
    x: Quintic,
    y: Quintic,
    z: Quintic,
    yaw: Quintic,
    roll: Quintic,
    pitch: Quintic,
    apex: f64,
    duration: f64,
    /// Start of the horizontal motion (s after lift-off); the `x`, `y` quintics run from here.
    horizontal_start: f64,
}

impl SwingTrajectory {
    /// Rest-to-rest swing of `duration` seconds passing `apex` above the higher of the two
    /// soles at mid-swing.
    ///
    /// On a height change the horizontal motion waits for the sole to rise halfway: up a step
    /// it starts once the sole is halfway to the landing height, down a step it ends when the
    /// sole comes down through halfway. With both feet moving two treads per step, halfway is
    /// the top of the riser in between, which is 4 cm in front of TALOS' toe from the middle
    /// of a 30 cm tread: with one timing for all axes the toe struck it (a −570 N sole force
    /// and a 0.48 m ZMP spike on the TSID torque stairs walk). Waiting for the full landing
    /// height instead made the IK's swing leg fold too far and TALOS fell. The rest-to-rest
    /// quintics of x and y run over the rest of the swing; on flat ground, the whole swing.
    pub fn new(start: &FootPose, end: &FootPose, duration: f64, apex: f64) -> Self {
        let dyaw = angle_difference(end.yaw, start.yaw);
        let apex = apex + 0.5 * (end.z - start.z).abs();
        let duration = duration.max(0.0);
        let (a, b) = horizontal_window(start.z, end.z, apex);
        let (t_a, t_b) = (a * duration, b * duration);
        Self {
            x: Quintic::rest_to_rest(start.x, end.x, t_b - t_a),
            y: Quintic::rest_to_rest(start.y, end.y, t_b - t_a),
            z: Quintic::rest_to_rest(start.z, end.z, duration),
            yaw: Quintic::rest_to_rest(start.yaw, start.yaw + dyaw, duration),
            roll: Quintic::rest_to_rest(start.roll, end.roll, duration),
            pitch: Quintic::rest_to_rest(start.pitch, end.pitch, duration),
            apex,
            duration,
            horizontal_start: t_a,
        }
    }

    /// Duration (s).
    pub fn duration(&self) -> f64 {
        self.duration
    }

    /// Pose and velocity at time `t` (clamped to the swing).
    pub fn sample(&self, t: f64) -> (FootPose, FootVelocity) {
        let (x, vx, _) = self.x.sample(t - self.horizontal_start);
        let (y, vy, _) = self.y.sample(t - self.horizontal_start);
        let (mut z, mut vz, _) = self.z.sample(t);
        let (yaw, vyaw, _) = self.yaw.sample(t);
        let (roll, vroll, _) = self.roll.sample(t);
        let (pitch, vpitch, _) = self.pitch.sample(t);
        if self.duration > 0.0 && t > 0.0 && t < self.duration {
            let s = t / self.duration;
            let (b, db, _) = bump(s);
            z += self.apex * b;
            vz += self.apex * db / self.duration;
        }
        (
            FootPose {
                x,
                y,
                z,
                yaw: wrap_angle(yaw),
                roll,
                pitch,
            },
            FootVelocity {
                x: vx,
                y: vy,
                z: vz,
                yaw: vyaw,
                roll: vroll,
                pitch: vpitch,
            },
        )
    }

    /// Vertical acceleration at time `t` (for checks and feed-forward).
    pub fn vertical_acceleration(&self, t: f64) -> f64 {
        let (_, _, az) = self.z.sample(t);
        if self.duration > 0.0 && t > 0.0 && t < self.duration {
            let (_, _, ddb) = bump(t / self.duration);
            az + self.apex * ddb / (self.duration * self.duration)
        } else {
            az
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    fn fd_pose(tr: &SwingTrajectory, t: f64, h: f64) -> [f64; 4] {
        let (a, _) = tr.sample(t - h);
        let (b, _) = tr.sample(t + h);
        [
            (b.x - a.x) / (2.0 * h),
            (b.y - a.y) / (2.0 * h),
            (b.z - a.z) / (2.0 * h),
            angle_difference(b.yaw, a.yaw) / (2.0 * h),
        ]
    }

    /// Up and down two treads (seed 000 §4.2: 10 cm risers, 30 cm treads): the foot moves
    /// 0.6 m and 0.2 m in height, from the middle of a tread, with the next riser 4 cm in front
    /// of TALOS' toe (0.11 m ahead of the sole centre). The toe never meets a riser, and the
    /// foot still lands at rest on the target.
    #[test]
    fn stair_swings_clear_the_risers_and_land_at_rest() {
        let (lo, hi) = (
            FootPose::new(0.0, 0.1, 0.1, 0.0),
            FootPose::new(0.6, 0.1, 0.3, 0.0),
        );
        let toe = 0.11;
        // Risers in front of the lower foot: at 0.15 (top 0.2) and 0.45 (top 0.3).
        let risers = [(0.15, 0.2), (0.45, 0.3)];
        let up = SwingTrajectory::new(&lo, &hi, 0.9, DEFAULT_APEX_HEIGHT);
        let down = SwingTrajectory::new(&hi, &lo, 0.9, DEFAULT_APEX_HEIGHT);
        // Going down (backwards here), the sole is over the upper tread while its trailing toe
        // is past the nose at x: the same bound as the leading toe going up.
        for k in 0..=900 {
            let t = k as f64 * 1e-3;
            for (name, swing) in [("up", &up), ("down", &down)] {
                let (p, _) = swing.sample(t);
                for (x, top) in risers {
                    if p.x + toe > x {
                        assert!(
                            p.z >= top - 1e-9,
                            "{name}: toe past the riser at {x} with the sole at {}",
                            p.z
                        );
                    }
                }
            }
        }
        for (tr, end) in [(&up, &hi), (&down, &lo)] {
            let (p, v) = tr.sample(0.9);
            assert!((p.x - end.x).abs() < 1e-12 && (p.z - end.z).abs() < 1e-12);
            assert!(v.x.abs() < 1e-12 && v.z.abs() < 1e-12);
        }
        // Horizontal velocities agree with finite differences inside the window.
        for &t in &[0.3, 0.5, 0.8] {
            let fd = fd_pose(&up, t, 1e-6);
            assert!((fd[0] - up.sample(t).1.x).abs() < 1e-6);
        }
    }

    #[test]
    fn quintic_boundary_conditions() {
        let q = Quintic::new(0.1, -0.2, 0.3, 1.0, 0.5, -0.4, 0.8);
        let (p, v, a) = q.sample(0.0);
        assert!((p - 0.1).abs() < 1e-14 && (v + 0.2).abs() < 1e-13 && (a - 0.3).abs() < 1e-12);
        let (p, v, a) = q.sample(0.8);
        assert!((p - 1.0).abs() < 1e-13 && (v - 0.5).abs() < 1e-12 && (a + 0.4).abs() < 1e-11);
        // derivative consistency by finite differences inside
        let h = 1e-6;
        for &t in &[0.1, 0.4, 0.7] {
            let fd_v = (q.sample(t + h).0 - q.sample(t - h).0) / (2.0 * h);
            let fd_a = (q.sample(t + h).1 - q.sample(t - h).1) / (2.0 * h);
            assert!((fd_v - q.sample(t).1).abs() < 1e-7);
            assert!((fd_a - q.sample(t).2).abs() < 1e-6);
        }
    }

    #[test]
    fn swing_lands_with_zero_velocity_and_acceleration() {
        let s = FootPose::new(0.0, 0.1, 0.0, 0.0);
        let e = FootPose::new(0.2, 0.12, 0.0, 0.3);
        let tr = SwingTrajectory::new(&s, &e, 0.9, DEFAULT_APEX_HEIGHT);
        let h = 1e-5;
        // one-sided finite differences at the ends: velocity O(h²)-small, acceleration small
        for &(t0, sign) in &[(0.0, 1.0), (0.9, -1.0)] {
            let (p0, v0) = tr.sample(t0);
            let (p1, _) = tr.sample(t0 + sign * h);
            let (p2, _) = tr.sample(t0 + sign * 2.0 * h);
            for (a, b, c) in [
                (p0.x, p1.x, p2.x),
                (p0.y, p1.y, p2.y),
                (p0.z, p1.z, p2.z),
                (p0.yaw, p1.yaw, p2.yaw),
            ] {
                assert!(((b - a) / h).abs() < 1e-8, "velocity at {t0}");
                assert!(
                    ((c - 2.0 * b + a) / (h * h)).abs() < 1e-3,
                    "acceleration at {t0}"
                );
            }
            for v in [v0.x, v0.y, v0.z, v0.yaw] {
                assert!(v.abs() < 1e-14);
            }
            assert!(tr.vertical_acceleration(t0).abs() < 1e-12);
        }
        assert_eq!(tr.sample(0.0).0, s);
        let end = tr.sample(0.9).0;
        assert!(
            (end.x - e.x).abs() < 1e-12 && (end.yaw - e.yaw).abs() < 1e-12 && end.z.abs() < 1e-12
        );
        // analytic velocities agree with finite differences mid-swing
        for &t in &[0.2, 0.45, 0.7] {
            let fd = fd_pose(&tr, t, 1e-6);
            let (_, v) = tr.sample(t);
            for (a, b) in fd.iter().zip([v.x, v.y, v.z, v.yaw]) {
                assert!((a - b).abs() < 1e-7);
            }
            let fd_az = (tr.sample(t + 1e-5).1.z - tr.sample(t - 1e-5).1.z) / 2e-5;
            assert!((fd_az - tr.vertical_acceleration(t)).abs() < 1e-5);
        }
    }

    #[test]
    fn swing_lands_on_a_tilted_foothold_at_rest() {
        use nalgebra::Vector3;
        let s = FootPose::new(0.0, -0.085, 0.0, 0.0);
        let n = Vector3::new(0.0, 10f64.to_radians().sin(), 10f64.to_radians().cos());
        let e = FootPose::on_surface(0.5, -0.085, 0.035, 0.1, &n).unwrap();
        let tr = SwingTrajectory::new(&s, &e, 0.9, DEFAULT_APEX_HEIGHT);
        let (end, v) = tr.sample(0.9);
        assert!((end.sole_normal() - n).norm() < 1e-12);
        assert!((end.position() - e.position()).norm() < 1e-12);
        assert!(v.linear().norm() < 1e-14 && v.angular(&end).norm() < 1e-14);
        // one-sided differences: the tilt comes to rest (velocity and acceleration vanish)
        let h = 1e-5;
        let (p1, _) = tr.sample(0.9 - h);
        let (p2, _) = tr.sample(0.9 - 2.0 * h);
        for (a, b, c) in [
            (end.roll, p1.roll, p2.roll),
            (end.pitch, p1.pitch, p2.pitch),
        ] {
            assert!(((a - b) / h).abs() < 1e-8);
            assert!(((a - 2.0 * b + c) / (h * h)).abs() < 1e-3);
        }
        // the Euler rates are the derivatives of the angles mid-swing
        for &t in &[0.2, 0.45, 0.7] {
            let (a, _) = tr.sample(t - 1e-6);
            let (b, _) = tr.sample(t + 1e-6);
            let (_, v) = tr.sample(t);
            assert!(((b.roll - a.roll) / 2e-6 - v.roll).abs() < 1e-7);
            assert!(((b.pitch - a.pitch) / 2e-6 - v.pitch).abs() < 1e-7);
        }
        // and the lift-off keeps the flat start at rest
        let (start, v0) = tr.sample(0.0);
        assert_eq!(start, s);
        assert!(v0.angular(&start).norm() < 1e-14);
    }

    #[test]
    fn apex_height_on_flat_ground() {
        let s = FootPose::new(0.0, -0.1, 0.0, 0.0);
        let e = FootPose::new(0.4, -0.1, 0.0, 0.0);
        let tr = SwingTrajectory::new(&s, &e, 1.0, 0.05);
        let max = (0..=1000)
            .map(|i| tr.sample(i as f64 / 1000.0).0.z)
            .fold(0.0, f64::max);
        assert!((max - 0.05).abs() < 1e-12);
        assert!((tr.sample(0.5).0.z - 0.05).abs() < 1e-15);
        assert!(tr.sample(0.5).1.z.abs() < 1e-12);
        // a 10 cm stair: mid-swing 5 cm above the upper sole
        let up = FootPose::new(0.3, -0.1, 0.1, 0.0);
        let tr = SwingTrajectory::new(&s, &up, 1.0, 0.05);
        assert!((tr.sample(0.5).0.z - 0.15).abs() < 1e-15);
    }

    #[test]
    fn yaw_takes_the_short_way_across_pi() {
        let s = FootPose::new(0.0, 0.0, 0.0, PI - 0.1);
        let e = FootPose::new(0.0, 0.0, 0.0, -PI + 0.1);
        let tr = SwingTrajectory::new(&s, &e, 1.0, 0.05);
        for i in 0..=100 {
            let (p, v) = tr.sample(i as f64 / 100.0);
            // stays within 0.1 rad of ±π and turns counter-clockwise
            assert!(p.yaw.abs() >= PI - 0.1 - 1e-12, "{}", p.yaw);
            assert!(v.yaw >= 0.0);
            assert!(p.yaw > -PI && p.yaw <= PI);
        }
        assert!((tr.sample(1.0).0.yaw - (-PI + 0.1)).abs() < 1e-12);
    }
}
