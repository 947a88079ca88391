//! Convex polygons in the horizontal plane, stored inline (no heap) so that a control tick
//! can build and query them: support polygons (the ZMP lies in the convex hull of the
//! contacts, seed 000 §3.3, seed 002 §4.2).

use nalgebra::Vector2;

/// Most vertices a polygon keeps.
pub const MAX_VERTICES: usize = 16;

/// A convex polygon with counter-clockwise vertices (at most [`MAX_VERTICES`]); it may be
/// empty, a point or a segment.
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

/// (a − o) × (b − o): positive when o → a → b turns left.
fn cross(o: &Vector2<f64>, a: &Vector2<f64>, b: &Vector2<f64>) -> f64 {
    (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x)
}

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
    /// No vertex.
    pub const fn empty() -> Self {
        Self {
            vertices: [Vector2::new(0.0, 0.0); MAX_VERTICES],
            len: 0,
        }
    }

    /// Convex hull of `points` (Andrew's monotone chain); points beyond [`MAX_VERTICES`] are
    /// ignored, collinear points on the hull dropped; one or two points stay as they are
    /// (repeats removed).
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
        let m = (k - 1).min(MAX_VERTICES);
        out.vertices[..m].copy_from_slice(&h[..m]);
        out.len = m;
        out
    }

    /// Vertices, counter-clockwise.
    pub fn vertices(&self) -> &[Vector2<f64>] {
        &self.vertices[..self.len]
    }

    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// Half-space form of a polygon of three vertices or more: for each edge, the outward
    /// unit normal `n` and offset `d` with `nᵀ p ≤ d` inside (the rows of a ZMP constraint).
    /// A point or a segment has no interior and gives no rows: constrain a point to it with
    /// [`ConvexPolygon::closest_point`] instead.
    pub fn half_spaces(&self) -> impl Iterator<Item = (Vector2<f64>, f64)> + '_ {
        let n = if self.len >= 3 { self.len } else { 0 };
        (0..n).map(move |i| {
            let a = self.vertices[i];
            let b = self.vertices[(i + 1) % self.len];
            let e = (b - a).normalize();
            let n = Vector2::new(e.y, -e.x); // right of a CCW edge = outward
            (n, n.dot(&a))
        })
    }

    /// Signed distance from `p` to the boundary: negative inside (minus the distance to the
    /// nearest edge), positive outside (the Euclidean distance to the polygon); NaN for a
    /// point that is not finite, +∞ for an empty polygon.
    pub fn signed_distance(&self, p: &Vector2<f64>) -> f64 {
        if !(p.x.is_finite() && p.y.is_finite()) {
            return f64::NAN;
        }
        if self.len < 3 {
            return match self.len {
                0 => f64::INFINITY,
                _ => (self.closest_point(p) - p).norm(),
            };
        }
        let violation = self
            .half_spaces()
            .map(|(n, d)| n.dot(p) - d)
            .fold(f64::NEG_INFINITY, f64::max);
        if violation <= 0.0 {
            return violation;
        }
        (self.closest_point(p) - p).norm()
    }

    /// Whether `p` is inside or within `tolerance` of the polygon (never for an empty polygon
    /// or a point that is not finite).
    pub fn contains(&self, p: &Vector2<f64>, tolerance: f64) -> bool {
        self.signed_distance(p) <= tolerance
    }

    /// The point of the polygon nearest to `p` (`p` itself inside; `p` for an empty polygon).
    pub fn closest_point(&self, p: &Vector2<f64>) -> Vector2<f64> {
        match self.len {
            0 => *p,
            1 => self.vertices[0],
            2 => closest_on_segment(p, &self.vertices[0], &self.vertices[1]),
            n => {
                let inside =
                    (0..n).all(|i| cross(&self.vertices[i], &self.vertices[(i + 1) % n], p) >= 0.0);
                if inside {
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

    /// Area (shoelace formula).
    pub fn area(&self) -> f64 {
        let mut a = 0.0;
        for i in 0..self.len {
            let p = self.vertices[i];
            let q = self.vertices[(i + 1) % self.len];
            a += p.x * q.y - q.x * p.y;
        }
        0.5 * a
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn v(x: f64, y: f64) -> Vector2<f64> {
        Vector2::new(x, y)
    }

    #[test]
    fn the_hull_of_a_square_and_its_centre_is_the_square_counter_clockwise() {
        let p = ConvexPolygon::hull(&[
            v(1.0, 1.0),
            v(0.0, 0.0),
            v(0.5, 0.5),
            v(1.0, 0.0),
            v(0.0, 1.0),
        ]);
        assert_eq!(
            p.vertices(),
            &[v(0.0, 0.0), v(1.0, 0.0), v(1.0, 1.0), v(0.0, 1.0)]
        );
        assert!((p.area() - 1.0).abs() < 1e-15);
    }

    #[test]
    fn distances_inside_outside_and_near_a_corner() {
        let p = ConvexPolygon::hull(&[v(0.0, 0.0), v(2.0, 0.0), v(2.0, 1.0), v(0.0, 1.0)]);
        assert!((p.signed_distance(&v(1.0, 0.5)) + 0.5).abs() < 1e-15);
        assert!((p.signed_distance(&v(3.0, 0.5)) - 1.0).abs() < 1e-15);
        // Outside a corner the distance is Euclidean, not the largest edge violation.
        assert!((p.signed_distance(&v(3.0, 2.0)) - 2f64.sqrt()).abs() < 1e-15);
        assert!(!p.contains(&v(2.1, 1.1), 0.1));
        assert!(p.contains(&v(2.05, 1.05), 0.1));
        assert_eq!(p.closest_point(&v(1.0, 0.5)), v(1.0, 0.5));
        assert_eq!(p.closest_point(&v(3.0, 2.0)), v(2.0, 1.0));
        assert_eq!(p.closest_point(&v(1.0, -1.0)), v(1.0, 0.0));
        assert_eq!(p.half_spaces().count(), 4);
    }

    #[test]
    fn points_segments_and_empty_polygons_are_handled() {
        let e = ConvexPolygon::empty();
        assert!(e.is_empty() && !e.contains(&v(0.0, 0.0), 1.0));
        assert_eq!(e.closest_point(&v(1.0, 2.0)), v(1.0, 2.0));
        let point = ConvexPolygon::hull(&[v(1.0, 1.0), v(1.0, 1.0)]);
        assert_eq!(point.vertices().len(), 1);
        assert!((point.signed_distance(&v(1.0, 2.0)) - 1.0).abs() < 1e-15);
        let segment = ConvexPolygon::hull(&[v(0.0, 0.0), v(2.0, 0.0)]);
        assert_eq!(segment.closest_point(&v(1.0, 1.0)), v(1.0, 0.0));
        assert!(segment.contains(&v(1.0, 0.05), 0.1));
        assert_eq!(segment.half_spaces().count(), 0);
        let square = ConvexPolygon::hull(&[v(0.0, 0.0), v(1.0, 0.0), v(1.0, 1.0), v(0.0, 1.0)]);
        assert!(!square.contains(&v(f64::NAN, 0.5), 1.0));
        assert!(square.signed_distance(&v(0.5, f64::INFINITY)).is_nan());
    }
}
