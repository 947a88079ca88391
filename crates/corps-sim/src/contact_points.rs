//! Contact points sampled on the robot's collision primitives: a grid over each face of a
//! box (corners and edges included), rim points of cylinders, the centre of spheres. Meshes
//! are not used for contact (the TALOS `_box` model replaces the feet meshes by boxes).

use corps_model::{Model, Shape};
use nalgebra::Vector3;

/// A point rigidly attached to a body, where contact with the terrain is tested.
#[derive(Clone, Debug, PartialEq)]
pub struct ContactPoint {
    /// Joint whose body carries the point (None: the world, never in contact).
    pub joint: usize,
    /// Position in the joint frame.
    pub local: Vector3<f64>,
    /// Radius to subtract from the penetration (spheres), 0 for surface points.
    pub radius: f64,
    /// Surface area this point stands for (m²): the shape's area over its number of points.
    pub weight: f64,
    /// Index of the collision shape it came from.
    pub shape: usize,
}

/// Bounding sphere of a shape's points, for the broad phase.
#[derive(Clone, Debug, PartialEq)]
pub struct ShapeBound {
    pub joint: usize,
    pub center: Vector3<f64>,
    pub radius: f64,
    /// Range of this shape's points in the point list.
    pub points: std::ops::Range<usize>,
    pub link: String,
}

fn grid(n_for: impl Fn(f64) -> usize, a: f64, b: f64) -> Vec<(f64, f64)> {
    let (na, nb) = (n_for(a).max(2), n_for(b).max(2));
    let mut out = Vec::with_capacity(na * nb);
    for i in 0..na {
        for j in 0..nb {
            let u = -a / 2.0 + a * i as f64 / (na - 1) as f64;
            let v = -b / 2.0 + b * j as f64 / (nb - 1) as f64;
            out.push((u, v));
        }
    }
    out
}

/// Samples contact points on every box, cylinder and sphere of the model, with at most
/// `spacing` metres between neighbours on a face. Returns the points and one bound per shape.
pub fn sample_contact_points(model: &Model, spacing: f64) -> (Vec<ContactPoint>, Vec<ShapeBound>) {
    let n_for = |len: f64| (len / spacing).ceil() as usize + 1;
    let mut points = Vec::new();
    let mut bounds = Vec::new();
    for (s, geom) in model.collisions.iter().enumerate() {
        let Some(joint) = geom.parent_joint else {
            continue;
        };
        let start = points.len();
        // Points on the shape's surface (each location once) and the surface area.
        let (local, radius, area): (Vec<Vector3<f64>>, f64, f64) = match &geom.shape {
            Shape::Box { size } => {
                let h = size / 2.0;
                let mut pts: Vec<Vector3<f64>> = Vec::new();
                for axis in 0..3 {
                    let (i, j) = ((axis + 1) % 3, (axis + 2) % 3);
                    for sign in [-1.0, 1.0] {
                        for (u, v) in grid(n_for, size[i], size[j]) {
                            let mut p = Vector3::zeros();
                            p[axis] = sign * h[axis];
                            p[i] = u;
                            p[j] = v;
                            if !pts.iter().any(|o| (o - p).norm() < 1e-9) {
                                pts.push(p);
                            }
                        }
                    }
                }
                let area = 2.0 * (size.x * size.y + size.y * size.z + size.z * size.x);
                (pts, 0.0, area)
            }
            Shape::Cylinder { radius, length } => {
                let n = ((std::f64::consts::TAU * radius / spacing).ceil() as usize).max(8);
                let pts = [-length / 2.0, length / 2.0]
                    .into_iter()
                    .flat_map(|z| {
                        (0..n).map(move |k| {
                            let t = std::f64::consts::TAU * k as f64 / n as f64;
                            Vector3::new(radius * t.cos(), radius * t.sin(), z)
                        })
                    })
                    .collect();
                let area = std::f64::consts::TAU * radius * (radius + length);
                (pts, 0.0, area)
            }
            Shape::Sphere { radius } => (
                vec![Vector3::zeros()],
                *radius,
                4.0 * std::f64::consts::PI * radius * radius,
            ),
            Shape::Mesh { .. } => (vec![], 0.0, 0.0),
        };
        let share = if local.is_empty() {
            0.0
        } else {
            area / local.len() as f64
        };
        for p in local {
            points.push(ContactPoint {
                joint,
                local: geom.placement.act_point(&p),
                radius,
                weight: share,
                shape: s,
            });
        }
        if points.len() > start {
            let pts = &points[start..];
            let center = pts.iter().fold(Vector3::zeros(), |a, p| a + p.local) / pts.len() as f64;
            let radius = pts
                .iter()
                .map(|p| (p.local - center).norm() + p.radius)
                .fold(0.0, f64::max);
            bounds.push(ShapeBound {
                joint,
                center,
                radius,
                points: start..points.len(),
                link: geom.link.clone(),
            });
        }
    }
    (points, bounds)
}
