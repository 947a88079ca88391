//! Rigid contacts (TSID `Contact6d` and `ContactPoint`): a set of contact points with one
//! force each (contact-frame coordinates), a linearized friction cone per point, bounds on the
//! total normal force, a motion constraint keeping the frame on its reference (LOCAL frame, as
//! TSID), and a force regularization on the contact wrench `T f`.
//! - **Surface** (a foot sole): four corners; the motion constraint holds the whole pose
//!   (6 rows); `T = [I I I I; [p₁]× [p₂]× [p₃]× [p₄]×]`.
//! - **Point** (a hand on a wall, a knee): one point at the frame origin; the motion
//!   constraint holds its position only (the 3 linear rows); `T = [I; 0]`.
//! - **Wrench** (seed 001 §2.4): one six-dimensional wrench about the frame origin, contact
//!   frame coordinates, bounded by [`WrenchLimits`] (unilateral, friction polygon, torsion,
//!   centre of pressure); `T = I`.
//!
//! The motion constraint is an equality (TSID) unless [`Contact::soft`] gives it a weight in
//! the cost (seed 001: the stance foot tracked softly, §2.4).

use super::WrenchLimits;
use crate::robot_state::RobotState;
use crate::tasks::{Se3Reference, Se3Task, TaskRows};
use corps_model::{Model, Result};
use nalgebra::{DMatrix, DVector, Vector3, Vector6};

#[derive(Clone, Debug)]
pub struct Contact {
    pub name: String,
    pub frame: usize,
    /// Contact points in the contact frame.
    points: Vec<Vector3<f64>>,
    /// Contact normal in the contact frame.
    pub normal: Vector3<f64>,
    pub mu: f64,
    pub fmin: f64,
    pub fmax: f64,
    /// Keeps the frame on its reference (a hard equality in the inverse-dynamics QP): all six
    /// rows for a surface contact, the three linear rows for a point contact.
    pub motion: Se3Task,
    /// Weight of the force regularization in the cost.
    pub force_reg_weight: f64,
    /// Per-component weights of the contact wrench in the regularization.
    pub force_reg_components: Vector6<f64>,
    /// Reference contact wrench [force; torque] about the frame origin, contact frame.
    pub force_reference: Vector6<f64>,
    /// Drops the friction pyramids (the per-point rows of [`Contact::force_constraints`]), so
    /// the contact wrench has no friction or centre-of-pressure bound; the bounds on the total
    /// normal force stay. For a model whose contact forces are never applied, such as TSID in
    /// position mode, where they would otherwise bend its motion (see `corps`'s TSID
    /// controller). Point forces only: a wrench contact keeps its limits. Default false.
    pub bilateral: bool,
    /// The motion rows as a cost of this weight instead of an equality (seed 001's soft
    /// stance-foot task); `None`: an equality. Only the [τ; f] formulation takes it.
    pub soft: Option<f64>,
    /// A wrench contact's limits (its force variables are the wrench); `None` for point forces.
    wrench: Option<WrenchLimits>,
    /// `Jc = Tᵀ J` (3 per point × nv): point Jacobians, LOCAL.
    pub jc: DMatrix<f64>,
    /// `T` (6 × 3 per point), refreshed by `compute`.
    pub t: DMatrix<f64>,
}

/// Rows of the friction pyramid per point (then one row for the total normal force).
pub const PYRAMID_ROWS: usize = 4;

impl Contact {
    /// A surface contact on four corners `points` of frame `frame` (TSID `Contact6d`).
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        model: &Model,
        name: &str,
        frame: usize,
        points: [Vector3<f64>; 4],
        normal: Vector3<f64>,
        mu: f64,
        (fmin, fmax): (f64, f64),
        kp: Vector6<f64>,
        kd: Vector6<f64>,
        reference: Se3Reference,
    ) -> Self {
        Self::with_points(
            model,
            name,
            frame,
            points.to_vec(),
            normal,
            mu,
            (fmin, fmax),
            Se3Task::new(model.nv, frame, kp, kd, reference),
        )
    }

    /// A point contact at the origin of frame `frame` (TSID `ContactPoint`): position PD
    /// gains `kp`, `kd` (the orientation is free).
    #[allow(clippy::too_many_arguments)]
    pub fn point(
        model: &Model,
        name: &str,
        frame: usize,
        normal: Vector3<f64>,
        mu: f64,
        (fmin, fmax): (f64, f64),
        kp: Vector3<f64>,
        kd: Vector3<f64>,
        reference: Se3Reference,
    ) -> Self {
        let six = |v: Vector3<f64>| Vector6::new(v.x, v.y, v.z, 0.0, 0.0, 0.0);
        let mut motion = Se3Task::new(model.nv, frame, six(kp), six(kd), reference);
        motion.mask = Vector6::new(1.0, 1.0, 1.0, 0.0, 0.0, 0.0);
        let mut c = Self::with_points(
            model,
            name,
            frame,
            vec![Vector3::zeros()],
            normal,
            mu,
            (fmin, fmax),
            motion,
        );
        // A point carries no moment: regularize the force only.
        c.force_reg_components = Vector6::new(1.0, 1.0, 1e-3, 0.0, 0.0, 0.0);
        c
    }

    /// A wrench contact on frame `frame`, its z axis the normal (seed 001 §2.4): one wrench
    /// about the frame origin bounded by `limits` and `fmin ≤ f_z ≤ fmax`; its motion task
    /// holds the whole pose with gains `kp`, `kd`. The wrench is not regularized (seed 001:
    /// only τ is, L1407–L1413).
    #[allow(clippy::too_many_arguments)]
    pub fn with_wrench(
        model: &Model,
        name: &str,
        frame: usize,
        limits: WrenchLimits,
        (fmin, fmax): (f64, f64),
        kp: Vector6<f64>,
        kd: Vector6<f64>,
        reference: Se3Reference,
    ) -> Self {
        let mut c = Self::with_points(
            model,
            name,
            frame,
            Vec::new(),
            Vector3::z(),
            limits.mu,
            (fmin, fmax),
            Se3Task::new(model.nv, frame, kp, kd, reference),
        );
        c.wrench = Some(limits);
        c.jc = DMatrix::zeros(6, model.nv);
        c.t = DMatrix::identity(6, 6);
        c.force_reg_weight = 0.0;
        c
    }

    #[allow(clippy::too_many_arguments)]
    fn with_points(
        model: &Model,
        name: &str,
        frame: usize,
        points: Vec<Vector3<f64>>,
        normal: Vector3<f64>,
        mu: f64,
        (fmin, fmax): (f64, f64),
        motion: Se3Task,
    ) -> Self {
        let nf = 3 * points.len();
        Self {
            name: name.to_string(),
            frame,
            points,
            normal,
            mu,
            fmin,
            fmax,
            motion,
            force_reg_weight: 1e-5,
            force_reg_components: Vector6::new(1.0, 1.0, 1e-3, 2.0, 2.0, 2.0),
            force_reference: Vector6::zeros(),
            bilateral: false,
            soft: None,
            wrench: None,
            jc: DMatrix::zeros(nf, model.nv),
            t: DMatrix::zeros(6, nf),
        }
    }

    /// The contact points in the contact frame.
    pub fn points(&self) -> &[Vector3<f64>] {
        &self.points
    }

    /// Force variables: 3 per point, or the 6 of a wrench.
    pub fn n_force(&self) -> usize {
        if self.wrench.is_some() {
            6
        } else {
            3 * self.points.len()
        }
    }

    /// Motion-constraint rows: 6 for a surface or a wrench, 3 for a point.
    pub fn n_motion(&self) -> usize {
        if self.points.len() == 1 {
            3
        } else {
            6
        }
    }

    /// Inequality rows: the friction pyramid of each point, then the total normal force; or
    /// a wrench's limits.
    pub fn n_rows(&self) -> usize {
        match &self.wrench {
            Some(limits) => limits.n_rows(),
            None => PYRAMID_ROWS * self.points.len() + 1,
        }
    }

    /// The contact wrench [force; torque about the frame origin] of the force variables `f`.
    pub fn wrench(&self, f: &[f64]) -> Vector6<f64> {
        if self.wrench.is_some() {
            return Vector6::from_column_slice(&f[..6]);
        }
        let mut w = Vector6::zeros();
        for (i, p) in self.points.iter().enumerate() {
            let fi = Vector3::new(f[3 * i], f[3 * i + 1], f[3 * i + 2]);
            let m = p.cross(&fi);
            for k in 0..3 {
                w[k] += fi[k];
                w[3 + k] += m[k];
            }
        }
        w
    }

    /// Total normal force of the force variables `f`.
    pub fn normal_force(&self, f: &[f64]) -> f64 {
        if self.wrench.is_some() {
            return f[2];
        }
        (0..self.points.len())
            .map(|i| {
                self.normal
                    .dot(&Vector3::new(f[3 * i], f[3 * i + 1], f[3 * i + 2]))
            })
            .sum()
    }

    /// Writes `T` (6 × 3 per point) into `t`.
    pub fn write_generator(&self, t: &mut DMatrix<f64>) {
        t.fill(0.0);
        if self.wrench.is_some() {
            t.fill_with_identity();
            return;
        }
        for (i, p) in self.points.iter().enumerate() {
            for k in 0..3 {
                t[(k, 3 * i + k)] = 1.0;
            }
            let px = corps_model::spatial::skew(p);
            for r in 0..3 {
                for c in 0..3 {
                    t[(3 + r, 3 * i + c)] = px[(r, c)];
                }
            }
        }
    }

    /// The motion rows computed by the last `compute` (use the first [`Self::n_motion`]).
    pub fn motion_rows(&self) -> &TaskRows {
        self.motion.rows()
    }

    /// Updates the motion rows and `Jc = Tᵀ J` at the state.
    pub fn compute(&mut self, model: &Model, s: &RobotState) -> Result<&TaskRows> {
        let mut t = std::mem::take(&mut self.t);
        self.write_generator(&mut t);
        self.t = t;
        // The point Jacobians need the angular rows even where the motion mask drops them.
        let mask = self.motion.mask;
        self.motion.mask = Vector6::repeat(1.0);
        let computed = self.motion.compute(model, s).map(|_| ());
        if computed.is_ok() && self.wrench.is_some() {
            self.jc.copy_from(&self.motion.rows().a);
        } else if computed.is_ok() {
            let rows = self.motion.rows();
            // Point i: velocity of p_i = J_lin − p_i × J_ang (column-wise).
            for (i, p) in self.points.iter().enumerate() {
                for c in 0..model.nv {
                    let lin = Vector3::new(rows.a[(0, c)], rows.a[(1, c)], rows.a[(2, c)]);
                    let ang = Vector3::new(rows.a[(3, c)], rows.a[(4, c)], rows.a[(5, c)]);
                    let v = lin - p.cross(&ang);
                    for k in 0..3 {
                        self.jc[(3 * i + k, c)] = v[k];
                    }
                }
            }
        }
        self.motion.mask = mask;
        computed?;
        Ok(self.motion.rows())
    }

    /// The friction pyramid and normal-force bounds on this contact's force variables:
    /// per point `[−t₁ − μn; t₁ − μn; −t₂ − μn; t₂ − μn]ᵀ f_i ≤ 0` with
    /// `t₁ = n × eₓ / ‖·‖`, `t₂ = n × t₁ / ‖·‖`, then `fmin ≤ Σ nᵀ f_i ≤ fmax`; a wrench
    /// contact's rows are its [`WrenchLimits`].
    pub fn force_constraints(
        &self,
        c: &mut DMatrix<f64>,
        l: &mut DVector<f64>,
        u: &mut DVector<f64>,
        row: usize,
        col: usize,
    ) {
        if let Some(limits) = &self.wrench {
            limits.write_rows(c, l, u, row, col, (self.fmin, self.fmax));
            return;
        }
        let n = self.normal;
        let t1 = n.cross(&Vector3::x()).normalize();
        let t2 = n.cross(&t1).normalize();
        let dirs = [
            -t1 - n * self.mu,
            t1 - n * self.mu,
            -t2 - n * self.mu,
            t2 - n * self.mu,
        ];
        let total = row + PYRAMID_ROWS * self.points.len();
        for i in 0..self.points.len() {
            for (k, d) in dirs.iter().enumerate() {
                let r = row + PYRAMID_ROWS * i + k;
                for j in 0..3 {
                    c[(r, col + 3 * i + j)] = d[j];
                }
                l[r] = -1e10;
                u[r] = if self.bilateral { 1e10 } else { 0.0 };
            }
            for j in 0..3 {
                c[(total, col + 3 * i + j)] = n[j];
            }
        }
        l[total] = self.fmin;
        u[total] = self.fmax;
    }
}
