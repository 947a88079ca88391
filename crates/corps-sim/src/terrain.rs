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

    /// Where the vertical line through `(x, y)` leaves the solid upwards: the height of that
    /// point and the outward unit normal of the face it crosses (`None` when the line misses
    /// the solid, or the plane is vertical). A plane `n·(p − p₀) = 0` gives
    /// `z = z₀ − (n_x (x − x₀) + n_y (y − y₀)) / n_z`; a box is clipped slab by slab in its own
    /// frame (`o + t d`, `o = Rᵀ((x, y, 0) − c)`, `d = Rᵀ e_z`) and the exit is the smallest
    /// of the slabs' exits.
    pub fn top_at(&self, x: f64, y: f64) -> Option<(f64, Vector3<f64>)> {
        const PARALLEL: f64 = 1e-12;
        match self {
            Surface::Plane { point, normal, .. } => (normal.z > PARALLEL).then(|| {
                let z = point.z - (normal.x * (x - point.x) + normal.y * (y - point.y)) / normal.z;
                (z, *normal)
            }),
            Surface::Box {
                pose, half_extents, ..
            } => {
                let rt = pose.rotation.transpose();
                let o = rt * (Vector3::new(x, y, 0.0) - pose.translation);
                let d = rt * Vector3::z();
                let (mut enter, mut exit, mut face) = (f64::NEG_INFINITY, f64::INFINITY, None);
                for k in 0..3 {
                    let h = half_extents[k];
                    if d[k].abs() < PARALLEL {
                        if o[k].abs() > h {
                            return None;
                        }
                        continue;
                    }
                    let (a, b) = ((-h - o[k]) / d[k], (h - o[k]) / d[k]);
                    enter = enter.max(a.min(b));
                    if a.max(b) < exit {
                        exit = a.max(b);
                        face = Some((k, d[k].signum()));
                    }
                }
                let (k, sign) = face?;
                if enter > exit {
                    return None;
                }
                let mut n = Vector3::zeros();
                n[k] = sign;
                Some((exit, pose.rotation * n))
            }
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

impl Terrain {
    /// The highest surface above `(x, y)`: its height and upward unit normal there (`None`
    /// where no surface is under the point).
    pub fn surface_at(&self, x: f64, y: f64) -> Option<(f64, Vector3<f64>)> {
        self.surfaces
            .iter()
            .filter_map(|s| s.top_at(x, y))
            .max_by(|a, b| a.0.total_cmp(&b.0))
    }
}

/// The tilted-platforms preset (ours: seed 000's platforms come from an offline planner's
/// file we do not have). Two platforms side by side, each under one foot of TALOS standing at
/// the origin facing +x (soles at y ≈ ±0.085 m, 3 cm apart): each spans from
/// `|y| = PLATFORM_INNER_Y` outwards over `PLATFORM_WIDTH` and is rolled by `PLATFORM_ROLL`
/// about x so that it rises outwards (a valley: the left sole rolls by +10°, the right by
/// −10°, seed 002's target slope for such stabilizers), its top `PLATFORM_HEIGHT` above the
/// ground on the soles' line `|y| = PLATFORM_FOOT_Y`. The left one spans x ∈ [0.30, 1.20] m,
/// the right one x ∈ [0.45, 1.05] m, so that a walk of 25 cm steps starting with the right
/// foot puts the left foot on its platform at x = 0.5 and 1.0 m and the right foot on its
/// platform at x = 0.75 m, each sole ≥ 9 cm from the platform's ends, and the flat footholds
/// at x = 0.25, 1.25 (right) and 0, 1.5 m (left) ≥ 9 cm clear of them.
pub mod platforms {
    /// Roll of the platforms' top (rad): 10°.
    pub const PLATFORM_ROLL: f64 = 10.0 * std::f64::consts::PI / 180.0;
    /// Height of the top on the soles' line (m).
    pub const PLATFORM_HEIGHT: f64 = 0.035;
    /// Lateral position of the soles' line (m).
    pub const PLATFORM_FOOT_Y: f64 = 0.085;
    /// Inner edge of each platform (m from the centre line).
    pub const PLATFORM_INNER_Y: f64 = 0.005;
    /// Width of each platform across y, horizontally (m).
    pub const PLATFORM_WIDTH: f64 = 0.3;
    /// Thickness of the slabs (m): enough for their bottom to reach below the ground.
    pub const PLATFORM_THICKNESS: f64 = 0.12;
    /// x extent of the left platform (m).
    pub const LEFT_X: [f64; 2] = [0.30, 1.20];
    /// x extent of the right platform (m).
    pub const RIGHT_X: [f64; 2] = [0.45, 1.05];
}

/// Named terrains of the documents' scenarios.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum TerrainPreset {
    /// A horizontal ground plane at z = 0.
    Flat,
    /// Flat ground and 6 steps, 10 cm high and 30 cm deep, starting 0.3 m ahead (seed 000 §4.2).
    Stairs,
    /// Flat ground and two platforms side by side, rolled ±10° about x, one under each foot's
    /// line ahead of the robot (seed 000 §4.2 "tilted platforms"; our geometry, see
    /// [`platforms`]).
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
                use platforms::*;
                let (tan, cos) = (PLATFORM_ROLL.tan(), PLATFORM_ROLL.cos());
                let mut s = vec![ground];
                for (side, [x0, x1]) in [(1.0, LEFT_X), (-1.0, RIGHT_X)] {
                    // Top face: centre line at |y| = inner + width/2, rising outwards.
                    let y_mid = PLATFORM_INNER_Y + PLATFORM_WIDTH / 2.0;
                    let z_mid = PLATFORM_HEIGHT + tan * (y_mid - PLATFORM_FOOT_Y);
                    let roll = side * PLATFORM_ROLL;
                    let rotation = rpy_to_matrix(roll, 0.0, 0.0);
                    let top = Vector3::new((x0 + x1) / 2.0, side * y_mid, z_mid);
                    let half_thickness = PLATFORM_THICKNESS / 2.0;
                    s.push(boxed(
                        top - rotation.column(2) * half_thickness,
                        Vector3::new(roll, 0.0, 0.0),
                        Vector3::new((x1 - x0) / 2.0, PLATFORM_WIDTH / 2.0 / cos, half_thickness),
                    ));
                }
                s
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

#[cfg(test)]
mod tests {
    use super::platforms::*;
    use super::*;

    #[test]
    fn the_platforms_are_rolled_under_the_soles_and_clear_between_them() {
        let t = Terrain::preset(TerrainPreset::TiltedPlatforms, 0.8);
        let roll = PLATFORM_ROLL;
        for (side, x) in [(1.0, 0.5), (1.0, 1.0), (-1.0, 0.75)] {
            let (z, n) = t.surface_at(x, side * PLATFORM_FOOT_Y).unwrap();
            assert!((z - PLATFORM_HEIGHT).abs() < 1e-12, "{z}");
            // a valley: the left top's normal leans to −y, the right's to +y
            let expected = Vector3::new(0.0, -side * roll.sin(), roll.cos());
            assert!((n - expected).norm() < 1e-12, "{n:?}");
            // the solid is just below the top, not just above it
            let p = Vector3::new(x, side * PLATFORM_FOOT_Y, z);
            assert!(t
                .surfaces
                .iter()
                .any(|s| s.penetration(&(p - Vector3::z() * 1e-4)).is_some()));
            assert!(t
                .surfaces
                .iter()
                .all(|s| s.penetration(&(p + Vector3::z() * 1e-4)).is_none()));
        }
        // rising outwards by tan(10°) per metre, from the inner edge
        let (z_in, _) = t.surface_at(0.75, -(PLATFORM_INNER_Y + 1e-3)).unwrap();
        let (z_out, _) = t
            .surface_at(0.75, -(PLATFORM_INNER_Y + PLATFORM_WIDTH - 1e-3))
            .unwrap();
        assert!((z_out - z_in - (PLATFORM_WIDTH - 2e-3) * roll.tan()).abs() < 1e-12);
        // flat ground between them, before, beside and after
        for (x, y) in [
            (0.75, 0.0),
            (0.0, 0.085),
            (0.25, -0.085),
            (1.25, -0.085),
            (1.5, 0.085),
        ] {
            let (z, n) = t.surface_at(x, y).unwrap();
            assert!(z == 0.0 && n == Vector3::z(), "({x}, {y})");
        }
        // the slabs reach below the ground at their outer edges
        for s in &t.surfaces[1..] {
            let Surface::Box {
                pose, half_extents, ..
            } = s
            else {
                panic!("a box")
            };
            for sy in [-1.0, 1.0] {
                let corner =
                    pose.act_point(&Vector3::new(0.0, sy * half_extents.y, -half_extents.z));
                assert!(corner.z < 0.0, "{corner:?}");
            }
        }
    }

    #[test]
    fn the_top_of_a_stair_and_of_nothing() {
        let t = Terrain::preset(TerrainPreset::Stairs, 0.8);
        let (z, n) = t.surface_at(0.45, 0.0).unwrap();
        assert!((z - 0.1).abs() < 1e-12 && (n - Vector3::z()).norm() < 1e-12);
        let (z, _) = t.surface_at(1.95, 0.3).unwrap();
        assert!((z - 0.6).abs() < 1e-12);
        assert!(Terrain::preset(TerrainPreset::None, 0.8)
            .surface_at(0.0, 0.0)
            .is_none());
    }
}
