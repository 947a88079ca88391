//! Small convex polygon in the horizontal plane, stored inline (no heap), for the support
//! polygon the desired ZMP is clamped into (seed 000 §3.3: the ZMP lies in the convex hull of
//! the contacts).

use nalgebra::Vector2;

/// Largest number of hull vertices kept (two rectangular soles give at most 8).
pub const MAX_VERTICES: usize = 16;

/// Convex polygon with counter-clockwise vertices, built as the convex hull of points.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ConvexPolygon {
    vertices: [Vector2<f64>; MAX_VERTICES],
    len: usize,
}

impl Default for ConvexPolygon {
    fn default() -> Self {
        Self::empty()
    }
}

fn cross(o: &Vector2<f64>, a: &Vector2<f64>, b: &Vector2<f64>) -> f64 {
    (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x)
}

/// Closest point to `p` on the segment `[a, b]`.
fn closest_on_segment(p: &Vector2<f64>, a: &Vector2<f64>, b: &Vector2<f64>) -> Vector2<f64> {
    let d = b - a;
    let l2 = d.norm_squared();
    if l2 <= 0.0 {
        return *a;
    }
    let t = ((p - a).dot(&d) / l2).clamp(0.0, 1.0);
    a + d * t
}

impl ConvexPolygon {
    /// A polygon with no vertex (contains nothing; projection returns the input).
    pub const fn empty() -> Self {
        Self {
            vertices: [Vector2::new(0.0, 0.0); MAX_VERTICES],
            len: 0,
        }
    }

    /// Convex hull of `points` (Andrew's monotone chain; collinear points dropped). At most
    /// [`MAX_VERTICES`] input points are used; the rest are ignored. Sorting is done in a
    /// stack buffer, so this does not allocate.
    pub fn hull(points: &[Vector2<f64>]) -> Self {
        let n = points.len().min(MAX_VERTICES);
        let mut pts = [Vector2::zeros(); MAX_VERTICES];
        pts[..n].copy_from_slice(&points[..n]);
        let pts = &mut pts[..n];
        pts.sort_unstable_by(|a, b| a.x.total_cmp(&b.x).then(a.y.total_cmp(&b.y)));
        let mut out = Self::empty();
        if n <= 2 {
            for p in pts.iter() {
                if out.len == 0 || out.vertices[out.len - 1] != *p {
                    out.vertices[out.len] = *p;
                    out.len += 1;
                }
            }
            return out;
        }
        // Lower then upper chain into a buffer of 2n.
        let mut h = [Vector2::zeros(); 2 * MAX_VERTICES];
        let mut k = 0;
        for p in pts.iter() {
            while k >= 2 && cross(&h[k - 2], &h[k - 1], p) <= 0.0 {
                k -= 1;
            }
            h[k] = *p;
            k += 1;
        }
        let lower = k + 1;
        for p in pts.iter().rev().skip(1) {
            while k >= lower && cross(&h[k - 2], &h[k - 1], p) <= 0.0 {
                k -= 1;
            }
            h[k] = *p;
            k += 1;
        }
        // The last point repeats the first.
        let m = (k - 1).min(MAX_VERTICES);
        out.vertices[..m].copy_from_slice(&h[..m]);
        out.len = m;
        out
    }

    /// Counter-clockwise vertices.
    pub fn vertices(&self) -> &[Vector2<f64>] {
        &self.vertices[..self.len]
    }

    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// Whether `p` is inside or on the boundary (within `tol`).
    pub fn contains(&self, p: &Vector2<f64>, tol: f64) -> bool {
        match self.len {
            0 => false,
            1 | 2 => (self.closest_point(p) - p).norm() <= tol,
            n => (0..n).all(|i| {
                let a = &self.vertices[i];
                let b = &self.vertices[(i + 1) % n];
                // Signed distance to the edge's supporting line, positive inside (CCW).
                cross(a, b, p) / (b - a).norm() >= -tol
            }),
        }
    }

    /// The point of the polygon nearest to `p` (`p` itself when inside).
    pub fn closest_point(&self, p: &Vector2<f64>) -> Vector2<f64> {
        match self.len {
            0 => *p,
            1 => self.vertices[0],
            2 => closest_on_segment(p, &self.vertices[0], &self.vertices[1]),
            n => {
                if self.contains(p, 0.0) {
                    return *p;
                }
                let mut best = self.vertices[0];
                let mut best_d = f64::INFINITY;
                for i in 0..n {
                    let q = closest_on_segment(p, &self.vertices[i], &self.vertices[(i + 1) % n]);
                    let d = (q - p).norm_squared();
                    if d < best_d {
                        best_d = d;
                        best = q;
                    }
                }
                best
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn v(x: f64, y: f64) -> Vector2<f64> {
        Vector2::new(x, y)
    }

    #[test]
    fn hull_of_two_rectangles_is_their_convex_envelope() {
        // Two 0.2 × 0.12 soles at y = ±0.081 (seed 002 §2: feet distance 0.162 m).
        let mut pts = [Vector2::zeros(); 8];
        for (k, cy) in [0.081, -0.081].iter().enumerate() {
            for (j, (sx, sy)) in [(1.0, 1.0), (-1.0, 1.0), (-1.0, -1.0), (1.0, -1.0)]
                .iter()
                .enumerate()
            {
                pts[4 * k + j] = v(0.1 * sx, cy + 0.06 * sy);
            }
        }
        let h = ConvexPolygon::hull(&pts);
        // Aligned feet: the hull is the bounding rectangle, 4 vertices.
        assert_eq!(h.vertices().len(), 4);
        assert!(h.contains(&v(0.0, 0.0), 0.0));
        assert!(h.contains(&v(0.1, 0.141), 1e-12));
        assert!(!h.contains(&v(0.0, 0.15), 1e-9));
        let q = h.closest_point(&v(0.3, 0.0));
        assert!((q - v(0.1, 0.0)).norm() < 1e-12);
        let q = h.closest_point(&v(0.3, 0.3));
        assert!((q - v(0.1, 0.141)).norm() < 1e-12);
    }

    #[test]
    fn hull_drops_interior_points_and_orders_ccw() {
        let h = ConvexPolygon::hull(&[
            v(0.0, 0.0),
            v(1.0, 0.0),
            v(0.5, 0.2),
            v(1.0, 1.0),
            v(0.0, 1.0),
        ]);
        assert_eq!(h.vertices().len(), 4);
        let vs = h.vertices();
        let mut area = 0.0;
        for i in 0..vs.len() {
            let (a, b) = (vs[i], vs[(i + 1) % vs.len()]);
            area += a.x * b.y - b.x * a.y;
        }
        assert!((0.5 * area - 1.0).abs() < 1e-12, "CCW area {}", 0.5 * area);
    }
}
