//! 6D surface contact (a foot sole): four corner forces `f_i` (sole frame) with a linearized
//! friction cone per corner, bounds on the total normal force, a motion constraint keeping
//! the sole on its reference (LOCAL frame, as TSID `Contact6d`), and a force regularization on
//! the sole wrench `T f`, with `T = [I I I I; [p₁]× [p₂]× [p₃]× [p₄]×]`.

use crate::robot_state::RobotState;
use crate::tasks::{Se3Reference, Se3Task, TaskRows};
use corps_model::{Model, Result};
use nalgebra::{DMatrix, DVector, Vector3, Vector6};

#[derive(Clone, Debug)]
pub struct Contact6d {
    pub name: String,
    pub frame: usize,
    /// Corner positions in the sole frame.
    pub points: [Vector3<f64>; 4],
    /// Contact normal in the sole frame.
    pub normal: Vector3<f64>,
    pub mu: f64,
    pub fmin: f64,
    pub fmax: f64,
    /// Keeps the sole on its reference (a hard equality in the inverse-dynamics QP).
    pub motion: Se3Task,
    /// Weight of the force regularization in the cost.
    pub force_reg_weight: f64,
    /// Per-component weights of the sole wrench in the regularization.
    pub force_reg_components: Vector6<f64>,
    /// Reference sole wrench [force; torque] about the sole origin, sole frame.
    pub force_reference: Vector6<f64>,
    /// `Jc = Tᵀ J` (12 × nv): corner point Jacobians, LOCAL.
    pub jc: DMatrix<f64>,
    /// `T` (6 × 12), refreshed by `compute` from `points`.
    pub t: DMatrix<f64>,
}

/// Rows of the friction pyramid per corner, then one row for the total normal force.
pub const FORCE_ROWS: usize = 17;
/// Force variables of a 6D contact.
pub const FORCE_VARS: usize = 12;

impl Contact6d {
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
        Self {
            name: name.to_string(),
            frame,
            points,
            normal,
            mu,
            fmin,
            fmax,
            motion: Se3Task::new(model.nv, frame, kp, kd, reference),
            force_reg_weight: 1e-5,
            force_reg_components: Vector6::new(1.0, 1.0, 1e-3, 2.0, 2.0, 2.0),
            force_reference: Vector6::zeros(),
            jc: DMatrix::zeros(FORCE_VARS, model.nv),
            t: DMatrix::zeros(6, FORCE_VARS),
        }
    }

    /// The sole wrench [force; torque about the sole origin] of corner forces `f` (12).
    pub fn wrench(&self, f: &[f64]) -> Vector6<f64> {
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

    /// Writes `T` (6 × 12) into `t`.
    pub fn write_generator(&self, t: &mut DMatrix<f64>) {
        t.fill(0.0);
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

    /// The motion rows computed by the last `compute`.
    pub fn motion_rows(&self) -> &TaskRows {
        self.motion.rows()
    }

    /// Updates the motion rows and `Jc = Tᵀ J` at the state.
    pub fn compute(&mut self, model: &Model, s: &RobotState) -> Result<&TaskRows> {
        let mut t = std::mem::take(&mut self.t);
        self.write_generator(&mut t);
        self.t = t;
        let rows = self.motion.compute(model, s)?;
        // Corner i: velocity of point p_i = J_lin − p_i × J_ang (column-wise).
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
        Ok(rows)
    }

    /// The friction pyramid and normal-force bounds on this contact's 12 force variables:
    /// per corner `[−t₁ − μn; t₁ − μn; −t₂ − μn; t₂ − μn]ᵀ f_i ≤ 0` with
    /// `t₁ = n × eₓ / ‖·‖`, `t₂ = n × t₁ / ‖·‖`, then `fmin ≤ Σ nᵀ f_i ≤ fmax`.
    pub fn force_constraints(
        &self,
        c: &mut DMatrix<f64>,
        l: &mut DVector<f64>,
        u: &mut DVector<f64>,
        row: usize,
        col: usize,
    ) {
        let n = self.normal;
        let t1 = n.cross(&Vector3::x()).normalize();
        let t2 = n.cross(&t1).normalize();
        let dirs = [
            -t1 - n * self.mu,
            t1 - n * self.mu,
            -t2 - n * self.mu,
            t2 - n * self.mu,
        ];
        for i in 0..4 {
            for (k, d) in dirs.iter().enumerate() {
                let r = row + 4 * i + k;
                for j in 0..3 {
                    c[(r, col + 3 * i + j)] = d[j];
                }
                l[r] = -1e10;
                u[r] = 0.0;
            }
            for j in 0..3 {
                c[(row + 16, col + 3 * i + j)] = n[j];
            }
        }
        l[row + 16] = self.fmin;
        u[row + 16] = self.fmax;
    }
}
