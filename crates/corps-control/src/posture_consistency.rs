//! A posture reference consistent with the Cartesian tasks (seed 001 App. B.1, L9575–L9686).
//!
//! A posture task whose PD pulls towards a fixed posture fights the Cartesian tasks wherever
//! they need the joints elsewhere (a CoM over one foot needs the hips and ankles rolled); with
//! w_s ≪ w_T the fight leaves a steady error in the Cartesian tasks. Seed 001 replaces the
//! posture's reference acceleration by one that agrees with them: the accelerations the
//! Cartesian references imply, ν̇_T = J_T^†(v̇*_T − J̇_T ν) (B.1, with its sign slip
//! corrected), and the postural PD's, ν̇_s = [v̇*_B; s̈_ref] with v̇*_B = −k_B v_B driving the
//! base velocity to zero (B.2), are merged by a least squares over ν̇ = [v̇_B; s̈] (B.3), of
//! which the text lost the body. corps rebuilds B.3 as
//!
//! `ν̇* = argmin_ν̇ Σ_T w_T ‖J_T ν̇ − (v̇*_T − J̇_T ν)‖² + w_s ‖ν̇ − ν̇_s‖²`,
//!
//! i.e. the deviation from ν̇_T of B.4 measured through each task's Jacobian (in the range of
//! J_T, where B.4's joint-space deviation and this one agree) and the deviation from ν̇_s of
//! B.5 in joint space: the posture PD acts fully in the tasks' null space and is overridden in
//! their range as w_s / w_T → 0. Normal equations: `(Σ w_T J_TᵀJ_T + w_s 1) ν̇* =
//! Σ w_T J_Tᵀ b_T + w_s ν̇_s`; the posture task then tracks s̈* = the joint part of ν̇* with
//! no PD of its own.

use crate::error::{ControlError, Result};
use crate::tasks::TaskRows;
use nalgebra::{DMatrix, DVector};

/// Workspace and settings of the rebuilt Eq B.3 (module docs).
#[derive(Clone, Debug)]
pub struct ConsistentPosture {
    /// w_s of Eq B.3 (the Cartesian tasks weigh their QP weights).
    pub posture_weight: f64,
    /// k_B of the base's reference acceleration v̇*_B = −k_B v_B (1/s).
    pub base_gain: f64,
    normal: DMatrix<f64>,
    rhs: DVector<f64>,
}

impl ConsistentPosture {
    pub fn new(nv: usize, posture_weight: f64, base_gain: f64) -> Self {
        Self {
            posture_weight,
            base_gain,
            normal: DMatrix::zeros(nv, nv),
            rhs: DVector::zeros(nv),
        }
    }

    /// Starts a tick: the posture's share, with ν̇_s = [−k_B v_B; `joint_pd`] (`first` base
    /// dofs, then the joints' PD accelerations).
    pub fn begin(&mut self, v: &DVector<f64>, first: usize, joint_pd: &DVector<f64>) {
        let w = self.posture_weight;
        self.normal.fill(0.0);
        for k in 0..self.rhs.len() {
            self.normal[(k, k)] = w;
            self.rhs[k] = w * if k < first {
                -self.base_gain * v[k]
            } else {
                joint_pd[k - first]
            };
        }
    }

    /// Adds one Cartesian task's rows `J ν̇ = b` with weight `w`.
    pub fn add_task(&mut self, rows: &TaskRows, w: f64) {
        let (m, n) = (rows.rows(), self.rhs.len());
        for r in 0..m {
            let b = rows.b[r];
            for i in 0..n {
                let ai = rows.a[(r, i)];
                if ai == 0.0 {
                    continue;
                }
                self.rhs[i] += w * ai * b;
                for j in 0..n {
                    self.normal[(i, j)] += w * ai * rows.a[(r, j)];
                }
            }
        }
    }

    /// Solves the normal equations in place and writes the joint part of ν̇* (from dof
    /// `first`) to `out`. An error if the system is not positive definite (w_s ≤ 0).
    pub fn solve(&mut self, first: usize, out: &mut DVector<f64>) -> Result<()> {
        cholesky_solve(&mut self.normal, &mut self.rhs).map_err(|pivot| ControlError::Config {
            name: "posture consistency".into(),
            reason: format!("the normal equations are not positive definite (pivot {pivot:e})"),
        })?;
        out.copy_from(&self.rhs.rows(first, out.len()));
        Ok(())
    }
}

/// Solves `A x = b` for symmetric positive definite `A` by an in-place Cholesky (lower
/// triangle overwritten), `b` replaced by `x`; the first non-positive pivot on failure.
fn cholesky_solve(a: &mut DMatrix<f64>, b: &mut DVector<f64>) -> std::result::Result<(), f64> {
    let n = b.len();
    for j in 0..n {
        let mut d = a[(j, j)];
        for k in 0..j {
            d -= a[(j, k)] * a[(j, k)];
        }
        if d.is_nan() || d <= 0.0 {
            return Err(d);
        }
        let d = d.sqrt();
        a[(j, j)] = d;
        for i in j + 1..n {
            let mut s = a[(i, j)];
            for k in 0..j {
                s -= a[(i, k)] * a[(j, k)];
            }
            a[(i, j)] = s / d;
        }
    }
    for i in 0..n {
        let mut s = b[i];
        for k in 0..i {
            s -= a[(i, k)] * b[k];
        }
        b[i] = s / a[(i, i)];
    }
    for i in (0..n).rev() {
        let mut s = b[i];
        for k in i + 1..n {
            s -= a[(k, i)] * b[k];
        }
        b[i] = s / a[(i, i)];
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// With a tiny w_s the result meets the tasks and, in their null space, equals the
    /// posture's acceleration (a projected posture); with a large w_s it is the posture's.
    #[test]
    fn tasks_win_in_their_range_and_the_posture_in_their_null_space() {
        let n = 6;
        let mut rows = TaskRows::new(2, n);
        for c in 0..n {
            rows.a[(0, c)] = 1.0 + c as f64;
            rows.a[(1, c)] = (c as f64 * 0.7).sin();
        }
        rows.b[0] = 0.3;
        rows.b[1] = -1.1;
        let v = DVector::from_fn(n, |k, _| 0.1 * k as f64);
        let pd = DVector::from_fn(n - 1, |k, _| 0.2 - 0.05 * k as f64);
        let mut p = ConsistentPosture::new(n, 1e-9, 2.0);
        p.begin(&v, 1, &pd);
        p.add_task(&rows, 1.0);
        let mut out = DVector::zeros(n - 1);
        // Recover the whole ν̇* from the joint part and check the task rows.
        p.solve(1, &mut out).unwrap();
        let x = p.rhs.clone();
        let res = &rows.a * &x - &rows.b;
        assert!(res.norm() < 1e-6, "task residual {}", res.norm());
        // The null-space component of x equals that of ν̇_s.
        let mut nu_s = DVector::zeros(n);
        nu_s[0] = -2.0 * v[0];
        nu_s.rows_mut(1, n - 1).copy_from(&pd);
        let a = &rows.a;
        let proj = DMatrix::identity(n, n)
            - a.transpose() * (a * a.transpose()).try_inverse().unwrap() * a;
        assert!((&proj * (&x - &nu_s)).norm() < 1e-6);

        let mut p = ConsistentPosture::new(n, 1e9, 2.0);
        p.begin(&v, 1, &pd);
        p.add_task(&rows, 1.0);
        p.solve(1, &mut out).unwrap();
        assert!((&out - &pd).norm() < 1e-6);
    }

    #[test]
    fn a_zero_posture_weight_without_tasks_is_refused() {
        let mut p = ConsistentPosture::new(3, 0.0, 1.0);
        p.begin(&DVector::zeros(3), 0, &DVector::zeros(3));
        assert!(p.solve(0, &mut DVector::zeros(3)).is_err());
    }
}
