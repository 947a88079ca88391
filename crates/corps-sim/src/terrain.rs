//! Terrain: half-spaces and boxes with a friction coefficient each, and the documents'
//! scenario presets.

use corps_model::spatial::{rotation::rpy_to_matrix, Se3};
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

/// One rigid surface of the world.
#[derive(Clone, Debug, PartialEq)]
pub enum Surface {
    /// The half-space below the plane through `point` with upward unit `normal`.
    Plane {
        point: Vector3<f64>,
        normal: Vector3<f64>,
        mu: f64,
    },
    /// A solid box with placement `pose` (centre and axes) and half side lengths.
    Box {
        pose: Se3,
        half_extents: Vector3<f64>,
        mu: f64,
    },
}

/// Where a point touches a surface: penetration depth (> 0 inside), outward normal and the
/// surface point.
#[derive(Clone, Copy, Debug)]
pub struct Penetration {
    pub depth: f64,
    pub normal: Vector3<f64>,
    pub mu: f64,
}

impl Surface {
    /// Friction coefficient.
    pub fn mu(&self) -> f64 {
        match self {
            Surface::Plane { mu, .. } | Surface::Box { mu, .. } => *mu,
        }
    }

    /// Penetration of world point `p`, if it is inside the surface's solid.
    #[inline]
    pub fn penetration(&self, p: &Vector3<f64>) -> Option<Penetration> {
        match self {
            Surface::Plane { point, normal, mu } => {
                let depth = normal.dot(&(point - p));
                (depth > 0.0).then_some(Penetration {
                    depth,
                    normal: *normal,
                    mu: *mu,
                })
            }
            Surface::Box {
                pose,
                half_extents,
                mu,
            } => {
                let local = pose.act_inv_point(p);
                let mut best: Option<(f64, usize, f64)> = None;
                for k in 0..3 {
                    let d = half_extents[k] - local[k].abs();
                    if d <= 0.0 {
                        return None;
                    }
                    if best.is_none_or(|(bd, _, _)| d < bd) {
                        best = Some((d, k, local[k].signum()));
                    }
                }
                let (depth, k, sign) = best?;
                let mut n = Vector3::zeros();
                n[k] = sign;
                Some(Penetration {
                    depth,
                    normal: pose.rotation * n,
                    mu: *mu,
                })
            }
        }
    }

    /// The surface's up direction: a plane's normal, a box's local z axis.
    pub fn up(&self) -> Vector3<f64> {
        match self {
            Surface::Plane { normal, .. } => *normal,
            Surface::Box { pose, .. } => pose.rotation.column(2).into(),
        }
    }

    /// Signed distance from `p` to the surface's solid, for broad-phase culling (a lower
    /// bound for boxes: distance to the bounding sphere).
    pub fn distance_bound(&self, p: &Vector3<f64>) -> f64 {
        match self {
            Surface::Plane { point, normal, .. } => normal.dot(&(p - point)),
            Surface::Box {
                pose, half_extents, ..
            } => (p - pose.translation).norm() - half_extents.norm(),
        }
    }
}

/// The world's surfaces.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Terrain {
    pub surfaces: Vec<Surface>,
}

/// Named terrains of the documents' scenarios.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum TerrainPreset {
    /// A horizontal ground plane at z = 0.
    Flat,
    /// Flat ground and 6 steps, 10 cm high and 30 cm deep, starting 0.3 m ahead (seed 000 §4.2).
    Stairs,
    /// Two platforms tilted ±15° about x under the feet (seed 000 ch. 4 multi-contact scenario).
    TiltedPlatforms,
    /// Flat ground with a 4 mm high, 3 cm wide stick 25 cm ahead of the feet (seed 002 §4.2).
    Stick,
    /// Nothing (free fall / free floating).
    None,
}

impl Terrain {
    /// Builds a preset with friction coefficient `mu` on every surface.
    pub fn preset(p: TerrainPreset, mu: f64) -> Terrain {
        let ground = Surface::Plane {
            point: Vector3::zeros(),
            normal: Vector3::z(),
            mu,
        };
        let boxed = |center: Vector3<f64>, rpy: Vector3<f64>, half: Vector3<f64>| Surface::Box {
            pose: Se3::new(rpy_to_matrix(rpy.x, rpy.y, rpy.z), center),
            half_extents: half,
            mu,
        };
        let surfaces = match p {
            TerrainPreset::None => vec![],
            TerrainPreset::Flat => vec![ground],
            TerrainPreset::Stairs => {
                let (rise, run, first) = (0.10, 0.30, 0.30);
                let mut s = vec![ground];
                for k in 0..6 {
                    let h = rise * (k + 1) as f64;
                    // Each step is a block from the ground to its tread, running to the top.
                    let x0 = first + run * k as f64;
                    let len = run * (6 - k) as f64 + 1.0;
                    s.push(boxed(
                        Vector3::new(x0 + len / 2.0, 0.0, h / 2.0),
                        Vector3::zeros(),
                        Vector3::new(len / 2.0, 1.0, h / 2.0),
                    ));
                }
                s
            }
            TerrainPreset::TiltedPlatforms => {
                let tilt = 15f64.to_radians();
                vec![
                    ground,
                    boxed(
                        Vector3::new(0.0, 0.25, 0.0),
                        Vector3::new(-tilt, 0.0, 0.0),
                        Vector3::new(0.4, 0.15, 0.05),
                    ),
                    boxed(
                        Vector3::new(0.0, -0.25, 0.0),
                        Vector3::new(tilt, 0.0, 0.0),
                        Vector3::new(0.4, 0.15, 0.05),
                    ),
                ]
            }
            TerrainPreset::Stick => vec![
                ground,
                boxed(
                    Vector3::new(0.25, 0.0, 0.002),
                    Vector3::zeros(),
                    Vector3::new(0.015, 0.5, 0.002),
                ),
            ],
        };
        Terrain { surfaces }
    }
}
