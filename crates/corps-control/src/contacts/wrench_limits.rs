//! Limits on one contact wrench w = [f; τ] in the contact frame, z along the normal, taken
//! about the contact frame's origin (seed 001 §2.4, Eq 2.32–2.36):
//! - unilateral: `f_min ≤ f_z ≤ f_max` (2.32);
//! - friction: the circle `|f_t| ≤ μ f_z` replaced by an inscribed regular polygon of
//!   `4 (n_v − 1)` edges, `n_v` vertices per quadrant (2.33; the polygon of robotology's
//!   `computeRigidContactConstraints.m`, 12 edges for the thesis's n_v = 4);
//! - torsion: `|τ_z| ≤ μ_t f_z` (2.34);
//! - centre of pressure inside the foot: `x_min ≤ −τ_y / f_z ≤ x_max`,
//!   `y_min ≤ τ_x / f_z ≤ y_max` (2.35), written linearly as they are for `f_z > 0`.

use nalgebra::{DMatrix, DVector};

/// The foot's rectangle about the contact frame's origin (m), `min < 0 < max` on each axis.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CopBox {
    pub x_min: f64,
    pub x_max: f64,
    pub y_min: f64,
    pub y_max: f64,
}

/// The wrench limits of one contact (see the module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WrenchLimits {
    /// Friction coefficient μ_c.
    pub mu: f64,
    /// Torsional coefficient μ_t (m).
    pub mu_torsion: f64,
    /// Vertices per quadrant of the friction polygon (≥ 2).
    pub vertices_per_quadrant: usize,
    pub cop: CopBox,
}

/// Sentinel for a one-sided row.
const FREE: f64 = 1e10;

impl WrenchLimits {
    /// Edges of the friction polygon.
    pub fn friction_edges(&self) -> usize {
        4 * (self.vertices_per_quadrant.max(2) - 1)
    }

    /// Inequality rows: friction edges, 2 torsion, 4 centre of pressure, 1 normal force.
    pub fn n_rows(&self) -> usize {
        self.friction_edges() + 7
    }

    /// Checks the numbers: μ > 0, μ_t ≥ 0, a box around the origin, at least 2 vertices.
    pub fn check(&self) -> Result<(), String> {
        let c = &self.cop;
        if !(self.mu > 0.0 && self.mu.is_finite()) {
            return Err(format!("friction coefficient must be > 0, got {}", self.mu));
        }
        if !(self.mu_torsion >= 0.0 && self.mu_torsion.is_finite()) {
            return Err(format!(
                "torsional friction must be ≥ 0, got {}",
                self.mu_torsion
            ));
        }
        if self.vertices_per_quadrant < 2 {
            return Err(format!(
                "the friction polygon needs at least 2 vertices per quadrant, got {}",
                self.vertices_per_quadrant
            ));
        }
        let finite = [c.x_min, c.x_max, c.y_min, c.y_max]
            .iter()
            .all(|v| v.is_finite());
        let around_origin = c.x_min < 0.0 && c.x_max > 0.0 && c.y_min < 0.0 && c.y_max > 0.0;
        if !finite || !around_origin {
            return Err(format!(
                "the centre-of-pressure box must contain the contact frame's origin, got x [{}, {}], y [{}, {}]",
                c.x_min, c.x_max, c.y_min, c.y_max
            ));
        }
        Ok(())
    }

    /// Writes the rows `l ≤ C w ≤ u` for the wrench at columns `col..col + 6`, from row `row`,
    /// the normal force bounded by `[f_min, f_max]`.
    #[allow(clippy::too_many_arguments)]
    pub fn write_rows(
        &self,
        c: &mut DMatrix<f64>,
        l: &mut DVector<f64>,
        u: &mut DVector<f64>,
        row: usize,
        col: usize,
        (f_min, f_max): (f64, f64),
    ) {
        let edges = self.friction_edges();
        // Edge k joins the vertices at angles 2πk/N and 2π(k+1)/N of the circle of radius
        // μ f_z: its outward normal is at the mid angle, at distance μ f_z cos(π/N).
        let half = std::f64::consts::PI / edges as f64;
        let reach = self.mu * half.cos();
        let mut r = row;
        let mut put = |r: usize, coeffs: [f64; 6]| {
            for (j, v) in coeffs.iter().enumerate() {
                c[(r, col + j)] = *v;
            }
            l[r] = -FREE;
            u[r] = 0.0;
        };
        for k in 0..edges {
            let phi = (2 * k + 1) as f64 * half;
            put(r, [phi.cos(), phi.sin(), -reach, 0.0, 0.0, 0.0]);
            r += 1;
        }
        let mt = self.mu_torsion;
        put(r, [0.0, 0.0, -mt, 0.0, 0.0, 1.0]);
        put(r + 1, [0.0, 0.0, -mt, 0.0, 0.0, -1.0]);
        let b = &self.cop;
        // −τ_y ≤ x_max f_z, x_min f_z ≤ −τ_y, τ_x ≤ y_max f_z, y_min f_z ≤ τ_x.
        put(r + 2, [0.0, 0.0, -b.x_max, 0.0, -1.0, 0.0]);
        put(r + 3, [0.0, 0.0, b.x_min, 0.0, 1.0, 0.0]);
        put(r + 4, [0.0, 0.0, -b.y_max, 1.0, 0.0, 0.0]);
        put(r + 5, [0.0, 0.0, b.y_min, -1.0, 0.0, 0.0]);
        r += 6;
        for j in 0..6 {
            c[(r, col + j)] = if j == 2 { 1.0 } else { 0.0 };
        }
        l[r] = f_min;
        u[r] = f_max;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn limits() -> WrenchLimits {
        WrenchLimits {
            mu: 1.0,
            mu_torsion: 1.0 / 75.0,
            vertices_per_quadrant: 4,
            cop: CopBox {
                x_min: -0.07,
                x_max: 0.07,
                y_min: -0.03,
                y_max: 0.03,
            },
        }
    }

    fn holds(w: [f64; 6]) -> bool {
        let lim = limits();
        let n = lim.n_rows();
        let (mut c, mut l, mut u) = (DMatrix::zeros(n, 6), DVector::zeros(n), DVector::zeros(n));
        lim.write_rows(&mut c, &mut l, &mut u, 0, 0, (10.0, 1000.0));
        let cw = &c * DVector::from_row_slice(&w);
        (0..n).all(|r| cw[r] >= l[r] - 1e-12 && cw[r] <= u[r] + 1e-12)
    }

    #[test]
    fn the_thesis_polygon_has_twelve_edges_and_nineteen_rows() {
        assert_eq!(limits().friction_edges(), 12);
        assert_eq!(limits().n_rows(), 19);
    }

    #[test]
    fn wrenches_inside_pass_and_each_limit_is_enforced() {
        // 100 N down, friction inside the inscribed circle, CoP (2, 1) cm, a small twist.
        assert!(holds([50.0, -40.0, 100.0, 1.0, -2.0, 1.0]));
        // The polygon's vertices touch the circle, its edge midpoints are inside it.
        assert!(holds([100.0, 0.0, 100.0, 0.0, 0.0, 0.0]));
        let mid = std::f64::consts::PI / 12.0;
        assert!(!holds([
            100.0 * mid.cos(),
            100.0 * mid.sin(),
            100.0,
            0.0,
            0.0,
            0.0
        ]));
        // Torsion beyond f_z / 75, CoP beyond the box on each side, f_z under f_min.
        assert!(!holds([0.0, 0.0, 150.0, 0.0, 0.0, 2.1]));
        assert!(!holds([0.0, 0.0, 100.0, 0.0, -7.1, 0.0]));
        assert!(!holds([0.0, 0.0, 100.0, 0.0, 7.1, 0.0]));
        assert!(!holds([0.0, 0.0, 100.0, 3.1, 0.0, 0.0]));
        assert!(!holds([0.0, 0.0, 100.0, -3.1, 0.0, 0.0]));
        assert!(!holds([0.0, 0.0, 9.0, 0.0, 0.0, 0.0]));
    }

    #[test]
    fn bad_numbers_are_refused() {
        let mut l = limits();
        l.mu = 0.0;
        assert!(l.check().is_err());
        let mut l = limits();
        l.cop.x_min = 0.01;
        assert!(l.check().unwrap_err().contains("centre-of-pressure"));
        let mut l = limits();
        l.vertices_per_quadrant = 1;
        assert!(l.check().is_err());
        assert!(limits().check().is_ok());
    }
}
