//! Wrench distribution between the two feet (seed 002 §4.9, after Caron et al. 2019):
//!
//! ```text
//! min  w_sum ‖G_L x_L + G_R x_R − w*‖²                          (net wrench at p*)
//!    + w_ankle Σ_i (T x_i)ᵀ diag(a) (T x_i)                       (ankle wrenches)
//!    + w_ratio ((1 − ρ) f_L,z − ρ f_R,z)²                         (double support only)
//! s.t. x_i ∈ CWC(sole, μ), f_i,z ≥ f_min   for a foot in contact,  x_i = 0 for a foot in the air
//! ```
//!
//! In single support the ankle and ratio terms are dropped for the stance foot, so its wrench is
//! the projection of `w*` onto its cone (seed 002 §4.9, SSP `saturateWrench`).
//!
//! `x_i = (f, τ)` is foot i's contact wrench in its sole frame about the sole origin, `G_i`
//! maps it to the world frame about the desired ZMP `p*`, `T` moves its moment to the ankle
//! (`τ_a = τ + h e_z × (−f)`), `a = (1, 1, 1e-4, 1, 1, 1e-4)`. Weights 1e4 / 10 / 1 and
//! `ρ = |p* − r| / |l − r|` clamped to [0, 1] (Eq 34, after Kajita 2010; taken as the
//! projection of p* on the feet segment, which equals Eq 34 on the segment). CWC: the
//! 16-row closed form for a rectangle (Caron et al. 2015): friction pyramid `|f_x|, |f_y| ≤ μ
//! f_z`, CoP in the sole `|τ_y| ≤ X f_z`, `|τ_x| ≤ Y f_z`, and the yaw-moment bounds. The
//! weights `a` are applied as given (not squared).
//!
//! When `p*` is outside the support polygon the net-wrench term cannot vanish and the QP
//! returns the feasible wrenches nearest to it in the weighted norm; the constraints are
//! always feasible (both feet loaded at their sole centres), so the solver only fails on
//! non-finite input.

use super::contact::{zmp_of, ContactPhase, Sole, Wrench, LEFT, RIGHT};
use crate::error::{ControlError, Result};
use corps_qp::{ActiveSetSolver, QpProblem};
use nalgebra::{Isometry3, Matrix6, Vector2, Vector3, Vector6};

/// Rows of the contact wrench cone per foot.
pub const CWC_ROWS: usize = 16;

/// Settings of [`WrenchDistribution`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DistributionSettings {
    /// Weight of the net-wrench error. Default 1e4 (seed 002 §4.9, wSum).
    pub weight_net_wrench: f64,
    /// Weight of the ankle-wrench norm. Default 10 (seed 002 §4.9, wNorm).
    pub weight_ankle: f64,
    /// Weight of the normal-force ratio term. Default 1 (seed 002 §4.9, wRatio).
    pub weight_ratio: f64,
    /// Per-component weights `a` of the ankle wrench (f_x, f_y, f_z, τ_x, τ_y, τ_z).
    /// Default (1, 1, 1e-4, 1, 1, 1e-4) (seed 002 §4.9, wAnkle).
    pub ankle_component_weights: [f64; 6],
    /// Minimum normal force of a foot in contact [N]. Default 15 (seed 002 §4.9, R L957).
    pub min_normal_force: f64,
}

impl Default for DistributionSettings {
    fn default() -> Self {
        Self {
            weight_net_wrench: 1e4,
            weight_ankle: 10.0,
            weight_ratio: 1.0,
            ankle_component_weights: [1.0, 1.0, 1e-4, 1.0, 1.0, 1e-4],
            min_normal_force: 15.0,
        }
    }
}

/// Result of one distribution.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Distribution {
    /// Per-foot contact wrench in its sole frame, about the sole origin (0 = left).
    pub wrenches: [Wrench; 2],
    /// Per-foot CoP in its sole frame (zero for an unloaded foot).
    pub cops: [Vector2<f64>; 2],
    /// Sum of the two wrenches in the world frame about the desired ZMP point.
    pub net: Wrench,
    /// ZMP of the distributed wrenches (equals p* when p* is feasible).
    pub zmp: Vector2<f64>,
    /// Left-foot ratio ρ used (meaningful in double support only).
    pub left_ratio: f64,
}

/// `x_i ↦` world wrench about `o`: `[R 0; [s − o]× R  R]`.
fn world_map(pose: &Isometry3<f64>, o: &Vector3<f64>) -> Matrix6<f64> {
    let r = pose.rotation.to_rotation_matrix().into_inner();
    let s = pose.translation.vector - o;
    let sx = s.cross_matrix();
    let mut g = Matrix6::zeros();
    g.fixed_view_mut::<3, 3>(0, 0).copy_from(&r);
    g.fixed_view_mut::<3, 3>(3, 3).copy_from(&r);
    g.fixed_view_mut::<3, 3>(3, 0).copy_from(&(sx * r));
    g
}

/// The 16 CWC rows `C x ≤ 0` of a rectangle with half-sizes `x`, `y` and friction `mu`
/// (variables ordered f_x, f_y, f_z, τ_x, τ_y, τ_z).
pub fn cwc_rows(x: f64, y: f64, mu: f64) -> [[f64; 6]; CWC_ROWS] {
    let mut c = [[0.0; 6]; CWC_ROWS];
    c[0] = [1.0, 0.0, -mu, 0.0, 0.0, 0.0];
    c[1] = [-1.0, 0.0, -mu, 0.0, 0.0, 0.0];
    c[2] = [0.0, 1.0, -mu, 0.0, 0.0, 0.0];
    c[3] = [0.0, -1.0, -mu, 0.0, 0.0, 0.0];
    c[4] = [0.0, 0.0, -y, 1.0, 0.0, 0.0];
    c[5] = [0.0, 0.0, -y, -1.0, 0.0, 0.0];
    c[6] = [0.0, 0.0, -x, 0.0, 1.0, 0.0];
    c[7] = [0.0, 0.0, -x, 0.0, -1.0, 0.0];
    let mut k = 8;
    for s1 in [1.0, -1.0] {
        for s2 in [1.0, -1.0] {
            // τ_z ≥ −μ(X+Y)f_z + |Y f_x − μ τ_x| + |X f_y − μ τ_y|
            c[k] = [s1 * y, s2 * x, -mu * (x + y), -s1 * mu, -s2 * mu, -1.0];
            // τ_z ≤ μ(X+Y)f_z − |Y f_x + μ τ_x| − |X f_y + μ τ_y|
            c[k + 1] = [s1 * y, s2 * x, -mu * (x + y), s1 * mu, s2 * mu, 1.0];
            k += 2;
        }
    }
    c
}

/// Left-foot ratio (seed 002 Eq 34) from the feet's (x, y) and the ZMP.
pub fn left_foot_ratio(zmp: &Vector2<f64>, left: &Vector2<f64>, right: &Vector2<f64>) -> f64 {
    let d = left - right;
    let l2 = d.norm_squared();
    if l2 <= 1e-12 {
        return 0.5;
    }
    ((zmp - right).dot(&d) / l2).clamp(0.0, 1.0)
}

/// The distribution QP and its solver (12 variables, 32 inequality rows), allocated once.
#[derive(Clone, Debug)]
pub struct WrenchDistribution {
    pub settings: DistributionSettings,
    pub sole: Sole,
    problem: QpProblem,
    solver: ActiveSetSolver,
}

impl WrenchDistribution {
    pub fn new(settings: DistributionSettings, sole: Sole) -> Self {
        let mut problem = QpProblem::new(12, 0, 2 * CWC_ROWS);
        let rows = cwc_rows(sole.half_length, sole.half_width, sole.friction);
        for foot in 0..2 {
            for (r, row) in rows.iter().enumerate() {
                for (j, v) in row.iter().enumerate() {
                    problem.c[(foot * CWC_ROWS + r, 6 * foot + j)] = *v;
                }
                problem.u[foot * CWC_ROWS + r] = 0.0;
            }
        }
        Self {
            settings,
            sole,
            problem,
            solver: ActiveSetSolver::new(12, 0, 2 * CWC_ROWS),
        }
    }

    /// Distribute `desired` (world frame, moment about `point` = the desired ZMP on the
    /// ground) over the feet with sole frames `feet` in `phase`.
    pub fn solve(
        &mut self,
        desired: &Wrench,
        point: &Vector3<f64>,
        feet: &[Isometry3<f64>; 2],
        phase: ContactPhase,
    ) -> Result<Distribution> {
        let s = &self.settings;
        let g = [
            world_map(&feet[LEFT], point),
            world_map(&feet[RIGHT], point),
        ];
        // Ankle map T and its weighted Gram TᵀAT.
        let h = self.sole.ankle_height;
        let mut t = Matrix6::<f64>::identity();
        t[(3, 1)] = h; // τ_a,x = τ_x + h f_y
        t[(4, 0)] = -h; // τ_a,y = τ_y − h f_x
        let a = Matrix6::from_diagonal(&Vector6::from_row_slice(&s.ankle_component_weights));
        let ankle = t.transpose() * a * t * s.weight_ankle;
        let w = Vector6::new(
            desired.force.x,
            desired.force.y,
            desired.force.z,
            desired.torque.x,
            desired.torque.y,
            desired.torque.z,
        );
        let feet_xy = [
            feet[LEFT].translation.vector.xy(),
            feet[RIGHT].translation.vector.xy(),
        ];
        let rho = left_foot_ratio(&point.xy(), &feet_xy[LEFT], &feet_xy[RIGHT]);
        let w_ratio = if phase == ContactPhase::Double {
            s.weight_ratio
        } else {
            0.0
        };
        // r·x = (1 − ρ) f_L,z − ρ f_R,z; its coefficients sit at indices 2 and 8.
        let ratio = [(2usize, 1.0 - rho), (8usize, -rho)];
        for i in 0..2 {
            for j in 0..2 {
                let block: Matrix6<f64> = g[i].transpose() * g[j] * s.weight_net_wrench;
                for r in 0..6 {
                    for c in 0..6 {
                        let mut v = block[(r, c)];
                        // In single support the stance foot's wrench is the projection of
                        // w* on its cone (seed 002 §4.9, SSP): no ankle term on it.
                        if i == j && (phase == ContactPhase::Double || !phase.in_contact(i)) {
                            v += ankle[(r, c)];
                        }
                        self.problem.h[(6 * i + r, 6 * j + c)] = 2.0 * v;
                    }
                }
            }
            let gi = g[i].transpose() * w * (-2.0 * s.weight_net_wrench);
            for r in 0..6 {
                self.problem.g[6 * i + r] = gi[r];
            }
        }
        for (ia, ca) in ratio {
            for (ib, cb) in ratio {
                self.problem.h[(ia, ib)] += 2.0 * w_ratio * ca * cb;
            }
        }
        for i in 0..2 {
            let contact = phase.in_contact(i);
            for r in 0..6 {
                let (lo, hi) = if !contact {
                    (0.0, 0.0)
                } else if r == 2 {
                    (s.min_normal_force, f64::INFINITY)
                } else {
                    (f64::NEG_INFINITY, f64::INFINITY)
                };
                self.problem.lx[6 * i + r] = lo;
                self.problem.ux[6 * i + r] = hi;
            }
        }
        let sol = self.solver.solve(&self.problem).map_err(ControlError::Qp)?;
        let mut out = Distribution {
            left_ratio: rho,
            ..Default::default()
        };
        #[allow(clippy::needless_range_loop)] // per-foot arrays in step
        for i in 0..2 {
            if !phase.in_contact(i) {
                // Fixed to zero by its bounds (up to the solver's 1e-9 tolerance): make it exact.
                continue;
            }
            let x = sol.x.fixed_rows::<6>(6 * i);
            out.wrenches[i] = Wrench::new(
                Vector3::new(x[0], x[1], x[2]),
                Vector3::new(x[3], x[4], x[5]),
            );
            out.cops[i] = out.wrenches[i].cop();
            let wi = out.wrenches[i].sole_to_world(&feet[i], point);
            out.net.force += wi.force;
            out.net.torque += wi.torque;
        }
        out.zmp = zmp_of(&out.net, point).ok_or(ControlError::NonFinite("distributed wrench"))?;
        Ok(out)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{Translation3, UnitQuaternion};

    const M: f64 = 90.2722; // seed 002 §2
    const G: f64 = 9.81;

    fn feet() -> [Isometry3<f64>; 2] {
        // Feet 0.162 m apart (seed 002 §2, setDSFeetDistance), left one yawed by 0.1 rad.
        [
            Isometry3::from_parts(
                Translation3::new(0.02, 0.081, 0.0),
                UnitQuaternion::from_euler_angles(0.0, 0.0, 0.1),
            ),
            Isometry3::from_parts(
                Translation3::new(0.0, -0.081, 0.0),
                UnitQuaternion::identity(),
            ),
        ]
    }

    fn weight_at(p: &Vector2<f64>) -> (Wrench, Vector3<f64>) {
        // Static LIPM: force m g, zero moment about p*.
        (
            Wrench::new(Vector3::new(0.0, 0.0, M * G), Vector3::zeros()),
            Vector3::new(p.x, p.y, 0.0),
        )
    }

    #[test]
    fn cwc_contains_every_wrench_of_corner_forces_in_the_pyramid() {
        let (x, y, mu) = (0.1, 0.06, 0.7);
        let rows = cwc_rows(x, y, mu);
        let corners = [(x, y), (-x, y), (-x, -y), (x, -y)];
        // Deterministic pseudo-random corner forces inside the pyramid.
        let mut seed = 12345u64;
        let mut rnd = || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        let mut worst = f64::NEG_INFINITY;
        for _ in 0..2000 {
            let mut w = [0.0; 6];
            for (cx, cy) in corners {
                let fz = rnd() * 100.0;
                let fx = (2.0 * rnd() - 1.0) * mu * fz;
                let fy = (2.0 * rnd() - 1.0) * mu * fz;
                let t = Vector3::new(cx, cy, 0.0).cross(&Vector3::new(fx, fy, fz));
                for (k, v) in [fx, fy, fz, t.x, t.y, t.z].iter().enumerate() {
                    w[k] += v;
                }
            }
            for r in rows.iter() {
                let v: f64 = r.iter().zip(w.iter()).map(|(a, b)| a * b).sum();
                worst = worst.max(v);
            }
        }
        assert!(worst <= 1e-9, "a CWC row is violated by {worst}");
        // And the yaw bound is tight: pure yaw μ(X+Y)f_z sits on the boundary.
        let fz = 100.0;
        let w = [0.0, 0.0, fz, 0.0, 0.0, mu * (x + y) * fz];
        let max = rows
            .iter()
            .map(|r| r.iter().zip(w.iter()).map(|(a, b)| a * b).sum::<f64>())
            .fold(f64::NEG_INFINITY, f64::max);
        assert!(max.abs() < 1e-9);
    }

    #[test]
    fn double_support_splits_the_weight_by_the_lever_rule() {
        let f = feet();
        let l = f[LEFT].translation.vector.xy();
        let r = f[RIGHT].translation.vector.xy();
        let mut d = WrenchDistribution::new(
            DistributionSettings::default(),
            Sole::new(0.10, 0.06, 0.107),
        );
        for rho in [0.3, 0.5, 0.8] {
            let p = r + (l - r) * rho;
            let (w, o) = weight_at(&p);
            let out = d.solve(&w, &o, &f, ContactPhase::Double).unwrap();
            // Σ wrenches about p*: zero x/y moment, i.e. the ZMP of the result is p*.
            let net = out.net;
            println!(
                "rho {rho}: fz L {:.3} R {:.3}, net τ about p* {:.2e} {:.2e}, zmp err {:.2e}",
                out.wrenches[0].force.z,
                out.wrenches[1].force.z,
                net.torque.x,
                net.torque.y,
                (out.zmp - p).norm()
            );
            // The net wrench is a 1e4-weighted cost, not a constraint: the residual is the
            // trade-off with the 10-weighted ankle term (≈ 1e-3 relative), here µN·m.
            assert!(net.torque.x.abs() < 1e-3 && net.torque.y.abs() < 1e-3);
            assert!((out.zmp - p).norm() < 1e-6);
            assert!((net.force.z - M * G).abs() < 1e-3);
            assert!((out.left_ratio - rho).abs() < 1e-12);
            // Proportional split: f_L = ρ m g.
            let share = out.wrenches[LEFT].force.z / (M * G);
            assert!((share - rho).abs() < 1e-3, "share {share} vs ρ {rho}");
            // Each CoP near its sole centre (the ankle term), well inside the sole.
            for c in out.cops {
                assert!(c.norm() < 1e-3, "cop {c}");
            }
        }
    }

    #[test]
    fn single_support_puts_everything_on_the_stance_foot() {
        let f = feet();
        let mut d = WrenchDistribution::new(
            DistributionSettings::default(),
            Sole::new(0.10, 0.06, 0.107),
        );
        // p* 3 cm ahead and 1 cm inside of the right sole centre.
        let p = f[RIGHT].translation.vector.xy() + Vector2::new(0.03, 0.01);
        let (w, o) = weight_at(&p);
        let out = d.solve(&w, &o, &f, ContactPhase::RightSupport).unwrap();
        assert_eq!(out.wrenches[LEFT], Wrench::default());
        assert!((out.wrenches[RIGHT].force.z - M * G).abs() < 1e-3);
        let cop = out.cops[RIGHT];
        println!(
            "single support: cop {cop:?}, fz {}",
            out.wrenches[RIGHT].force.z
        );
        assert!((cop - Vector2::new(0.03, 0.01)).norm() < 1e-6, "{cop}");
        assert!((out.zmp - p).norm() < 1e-6);
        // Same for the left foot, whose sole frame is yawed.
        let p = f[LEFT].translation.vector.xy() + Vector2::new(-0.02, 0.0);
        let (w, o) = weight_at(&p);
        let out = d.solve(&w, &o, &f, ContactPhase::LeftSupport).unwrap();
        assert_eq!(out.wrenches[RIGHT], Wrench::default());
        assert!((out.zmp - p).norm() < 1e-6);
    }

    #[test]
    fn infeasible_zmp_gives_the_nearest_feasible_wrench() {
        let f = feet();
        let mut d = WrenchDistribution::new(
            DistributionSettings::default(),
            Sole::new(0.10, 0.06, 0.107),
        );
        // 30 cm ahead of the feet (sole half-length 0.10): no contact wrench has this ZMP.
        let p = Vector2::new(0.30, 0.0);
        let (w, o) = weight_at(&p);
        let out = d.solve(&w, &o, &f, ContactPhase::Double).unwrap();
        // The ZMP lands on the front edge of the support polygon, the CoPs on the toes.
        println!(
            "outside: zmp {:?}, cops {:?} {:?}",
            out.zmp, out.cops[0], out.cops[1]
        );
        for (i, c) in out.cops.iter().enumerate() {
            assert!((c.x - 0.10).abs() < 1e-6, "foot {i} cop {c}");
            assert!(c.y.abs() <= 0.06 + 1e-9);
            assert!(out.wrenches[i].force.z >= 15.0 - 1e-9);
        }
        // Single support with p* beside the stance foot: CoP on the inner edge.
        let p = Vector2::new(0.0, 0.0);
        let (w, o) = weight_at(&p);
        let out = d.solve(&w, &o, &f, ContactPhase::RightSupport).unwrap();
        assert!(
            (out.cops[RIGHT].y - 0.06).abs() < 1e-6,
            "{}",
            out.cops[RIGHT]
        );
        assert!(out.wrenches[RIGHT].force.z > 0.5 * M * G);
        // Non-finite input is an error, not a panic.
        let bad = Wrench::new(Vector3::new(f64::NAN, 0.0, 1.0), Vector3::zeros());
        assert!(d.solve(&bad, &o, &f, ContactPhase::Double).is_err());
    }
}
