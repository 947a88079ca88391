//! Foot soles, support polygons and ZMP containment.
//!
//! The ZMP must lie in the support polygon: the support sole in single support, the convex
//! hull of both soles in double support (seed 002 §4.2, after Wieber 2002 and Caron et al.
//! 2015). The polygons are corps-model's [`ConvexPolygon`]: on the stack, so that checks in
//! a control tick never allocate.

use crate::pose::FootPose;
use nalgebra::Vector2;

pub use corps_model::support::{ConvexPolygon, MAX_VERTICES};

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

    /// The sole of a foot at `pose`.
    pub fn sole_polygon(&self, pose: &FootPose) -> ConvexPolygon {
        ConvexPolygon::hull(&self.corners().map(|v| pose.transform(&v)))
    }

    /// Double-support polygon: the convex hull of both soles.
    pub fn double_support(&self, left: &FootPose, right: &FootPose) -> ConvexPolygon {
        let c = self.corners();
        let mut pts = [Vector2::zeros(); 8];
        for i in 0..4 {
            pts[i] = left.transform(&c[i]);
            pts[i + 4] = right.transform(&c[i]);
        }
        ConvexPolygon::hull(&pts)
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

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn talos_sole_rectangle() {
        let g = crate::test_fixtures::TALOS_SOLE;
        let poly = g.sole_polygon(&FootPose::new(1.0, 2.0, 0.0, 0.0));
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
        let poly = g.double_support(&l, &r);
        assert_eq!(poly.vertices().len(), 4);
        assert!((poly.area() - 0.2 * 0.3).abs() < 1e-12);
        assert!(poly.contains(&Vector2::new(0.0, 0.0), 0.0));
        // staggered feet: 6-vertex hull
        let l2 = FootPose::new(0.2, 0.1, 0.0, 0.0);
        let poly = g.double_support(&l2, &r);
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
            let poly = g.double_support(&l, &r);
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
