//! Foot soles, support polygons and ZMP containment.
//!
//! The ZMP must lie in the support polygon: the support sole in single support, the convex
//! hull of both soles in double support (seed 002 §4.2, after Wieber 2002 and Caron et al.
//! 2015). Polygons here have a fixed capacity and live on the stack, so that checks in a
//! control tick never allocate.

use crate::pose::FootPose;
use nalgebra::Vector2;

/// Maximum number of vertices of a [`ConvexPolygon`].
pub const MAX_VERTICES: usize = 16;

/// A rectangular sole, given by the distances from the foot frame origin to its four edges,
/// in the foot frame (x forward, y left).
#[derive(Debug, Clone, Copy, PartialEq, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FootGeometry {
    /// Distance to the front (toe) edge, m.
    pub front: f64,
    /// Distance to the back (heel) edge, m.
    pub back: f64,
    /// Distance to the left edge, m.
    pub left: f64,
    /// Distance to the right edge, m.
    pub right: f64,
}

impl FootGeometry {
    /// A rectangle centred on the foot frame with the given half length and half width.
    pub fn centered(half_length: f64, half_width: f64) -> Self {
        Self {
            front: half_length,
            back: half_length,
            left: half_width,
            right: half_width,
        }
    }

    /// The four corners in the foot frame, counter-clockwise from the back-right one.
    pub fn corners(&self) -> [Vector2<f64>; 4] {
        [
            Vector2::new(-self.back, -self.right),
            Vector2::new(self.front, -self.right),
            Vector2::new(self.front, self.left),
            Vector2::new(-self.back, self.left),
        ]
    }
}

/// A convex polygon with counter-clockwise vertices (at most [`MAX_VERTICES`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ConvexPolygon {
    vertices: [Vector2<f64>; MAX_VERTICES],
    len: usize,
}

impl ConvexPolygon {
    /// Convex hull of `points` (Andrew's monotone chain); points beyond [`MAX_VERTICES`] are
    /// ignored. Collinear points on the hull are dropped.
    pub fn hull(points: &[Vector2<f64>]) -> Self {
        let n = points.len().min(MAX_VERTICES);
        let mut p = [Vector2::zeros(); MAX_VERTICES];
        p[..n].copy_from_slice(&points[..n]);
        p[..n].sort_unstable_by(|a, b| a.x.total_cmp(&b.x).then(a.y.total_cmp(&b.y)));
        let cross = |o: &Vector2<f64>, a: &Vector2<f64>, b: &Vector2<f64>| {
            (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x)
        };
        let mut h = [Vector2::zeros(); 2 * MAX_VERTICES];
        let mut k = 0;
        for q in &p[..n] {
            while k >= 2 && cross(&h[k - 2], &h[k - 1], q) <= 0.0 {
                k -= 1;
            }
            h[k] = *q;
            k += 1;
        }
        let lower = k + 1;
        for i in (0..n.saturating_sub(1)).rev() {
            while k >= lower && cross(&h[k - 2], &h[k - 1], &p[i]) <= 0.0 {
                k -= 1;
            }
            h[k] = p[i];
            k += 1;
        }
        let len = if n > 1 { k - 1 } else { n };
        let mut vertices = [Vector2::zeros(); MAX_VERTICES];
        vertices[..len].copy_from_slice(&h[..len]);
        Self { vertices, len }
    }

    /// The sole of a foot at `pose`.
    pub fn foot(pose: &FootPose, geometry: &FootGeometry) -> Self {
        let c = geometry.corners();
        Self::hull(&c.map(|v| pose.transform(&v)))
    }

    /// Double-support polygon: the convex hull of both soles.
    pub fn double_support(left: &FootPose, right: &FootPose, geometry: &FootGeometry) -> Self {
        let (l, r) = (geometry.corners(), geometry.corners());
        let mut pts = [Vector2::zeros(); 8];
        for i in 0..4 {
            pts[i] = left.transform(&l[i]);
            pts[i + 4] = right.transform(&r[i]);
        }
        Self::hull(&pts)
    }

    /// Vertices, counter-clockwise.
    pub fn vertices(&self) -> &[Vector2<f64>] {
        &self.vertices[..self.len]
    }

    /// Half-space form: for each edge, the outward unit normal `n` and offset `d` with
    /// `nᵀ p ≤ d` for every point of the polygon (the rows of a ZMP constraint in a QP).
    pub fn half_spaces(&self) -> impl Iterator<Item = (Vector2<f64>, f64)> + '_ {
        (0..self.len).map(move |i| {
            let a = self.vertices[i];
            let b = self.vertices[(i + 1) % self.len];
            let e = (b - a).normalize();
            let n = Vector2::new(e.y, -e.x); // right of a CCW edge = outward
            (n, n.dot(&a))
        })
    }

    /// Signed distance from `p` to the boundary: negative inside (minus the distance to the
    /// nearest edge), positive outside (Euclidean distance to the polygon).
    pub fn signed_distance(&self, p: &Vector2<f64>) -> f64 {
        let mut max_violation = f64::NEG_INFINITY;
        for (n, d) in self.half_spaces() {
            max_violation = max_violation.max(n.dot(p) - d);
        }
        if max_violation <= 0.0 {
            return max_violation;
        }
        let mut best = f64::INFINITY;
        for i in 0..self.len {
            let a = self.vertices[i];
            let b = self.vertices[(i + 1) % self.len];
            let ab = b - a;
            let s = ((p - a).dot(&ab) / ab.norm_squared()).clamp(0.0, 1.0);
            best = best.min((a + ab * s - p).norm());
        }
        best
    }

    /// `true` when `p` is inside or within `tolerance` outside.
    pub fn contains(&self, p: &Vector2<f64>, tolerance: f64) -> bool {
        self.signed_distance(p) <= tolerance
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
    use proptest::prelude::*;

    #[test]
    fn talos_sole_rectangle() {
        let g = crate::test_fixtures::TALOS_SOLE;
        let poly = ConvexPolygon::foot(&FootPose::new(1.0, 2.0, 0.0, 0.0), &g);
        assert_eq!(poly.vertices().len(), 4);
        assert!((poly.area() - 0.21 * 0.138).abs() < 1e-12);
        // centre of the sole rectangle is 5 mm behind the ankle; its distance to the nearest
        // (side) edge is 0.069
        let d = poly.signed_distance(&Vector2::new(0.995, 2.0));
        assert!((d + 0.069).abs() < 1e-12);
        // 1 cm beyond the toe
        assert!((poly.signed_distance(&Vector2::new(1.11, 2.0)) - 0.01).abs() < 1e-12);
        // beyond a corner: Euclidean distance to the corner
        let d = poly.signed_distance(&Vector2::new(1.13, 2.069 + 0.04));
        assert!((d - 0.05).abs() < 1e-12);
    }

    #[test]
    fn double_support_hull_of_two_feet() {
        let g = FootGeometry::centered(0.1, 0.05);
        let l = FootPose::new(0.0, 0.1, 0.0, 0.0);
        let r = FootPose::new(0.0, -0.1, 0.0, 0.0);
        let poly = ConvexPolygon::double_support(&l, &r, &g);
        assert_eq!(poly.vertices().len(), 4);
        assert!((poly.area() - 0.2 * 0.3).abs() < 1e-12);
        assert!(poly.contains(&Vector2::new(0.0, 0.0), 0.0));
        // staggered feet: 6-vertex hull
        let l2 = FootPose::new(0.2, 0.1, 0.0, 0.0);
        let poly = ConvexPolygon::double_support(&l2, &r, &g);
        assert_eq!(poly.vertices().len(), 6);
        // vertices (−.1,−.15) (.1,−.15) (.3,.05) (.3,.15) (.1,.15) (−.1,−.05): shoelace area 0.08
        assert!((poly.area() - 0.08).abs() < 1e-12);
        assert!(poly.contains(&Vector2::new(0.1, 0.0), 0.0));
        assert!(!poly.contains(&Vector2::new(0.25, -0.1), 1e-9));
    }

    proptest! {
        #[test]
        fn half_spaces_agree_with_signed_distance(
            x in -0.5f64..0.5, y in -0.5f64..0.5, yaw in -3.2f64..3.2,
            lx in 0.0f64..0.3, ly in -0.3f64..0.3, lyaw in -1.0f64..1.0,
        ) {
            let g = crate::test_fixtures::TALOS_SOLE;
            let r = FootPose::new(0.0, 0.0, 0.0, yaw);
            let l = FootPose::new(lx, ly, 0.0, lyaw);
            let poly = ConvexPolygon::double_support(&l, &r, &g);
            let p = Vector2::new(x, y);
            let inside = poly.half_spaces().all(|(n, d)| n.dot(&p) <= d);
            prop_assert_eq!(inside, poly.signed_distance(&p) <= 0.0);
            // every sole corner lies in the hull
            for c in g.corners() {
                prop_assert!(poly.signed_distance(&l.transform(&c)) <= 1e-12);
                prop_assert!(poly.signed_distance(&r.transform(&c)) <= 1e-12);
            }
            prop_assert!(poly.area() > 0.0);
        }
    }
}
