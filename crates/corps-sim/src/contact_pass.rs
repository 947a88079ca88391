//! The narrow phase shared by every integrator: walks the sampled points of the shapes that
//! may touch the terrain and computes each touching point's force.

use crate::contact::{point_force, Anchor, ContactParams, PointForce};
use crate::contact_points::{ContactPoint, ShapeBound};
use crate::terrain::{Surface, Terrain};
use corps_model::spatial::{Motion, Se3};
use nalgebra::Vector3;

/// Planes tested in each body's frame (larger terrains fall back to world-frame tests).
const MAX_LOCAL_PLANES: usize = 8;

/// One sample point as the pass saw it.
pub(crate) struct PointVisit<'a> {
    /// Index in the point list.
    pub index: usize,
    /// Joint whose body carries the point.
    pub joint: usize,
    /// World position.
    pub position: Vector3<f64>,
    /// The contact force, or `None` when the point does not penetrate any surface.
    pub force: Option<PointForce>,
    /// The point's tangential anchor, for the caller to move when it accepts the step.
    pub anchor: &'a mut Anchor,
}

/// The shapes' sample points against the terrain, at body placements `o_m_i` and world
/// twists `ov`. Every point that may touch a surface is visited with its force (or none);
/// with `visit_clear`, so is every other point (with no force), for callers that record.
#[allow(clippy::too_many_arguments)]
pub(crate) fn contact_pass(
    terrain: &Terrain,
    params: &ContactParams,
    points: &[ContactPoint],
    bounds: &[ShapeBound],
    anchors: &mut [Anchor],
    o_m_i: &[Se3],
    ov: &[Motion],
    visit_clear: bool,
    mut visit: impl FnMut(PointVisit),
) {
    for b in bounds {
        let m = &o_m_i[b.joint];
        let center = m.act_point(&b.center);
        if terrain
            .surfaces
            .iter()
            .all(|s| s.distance_bound(&center) > b.radius)
        {
            if visit_clear {
                for k in b.points.clone() {
                    visit(PointVisit {
                        index: k,
                        joint: b.joint,
                        position: m.act_point(&points[k].local),
                        force: None,
                        anchor: &mut anchors[k],
                    });
                }
            }
            continue;
        }
        let twist = &ov[b.joint];
        // Planes in the body frame: a point can touch plane (n, p₀) only if
        // d − n_l·p_l > −r with n_l = Rᵀn, d = n·(p₀ − t); one dot product per point
        // instead of a transform. Boxes are tested in the world.
        let mut planes = [(Vector3::zeros(), 0.0); MAX_LOCAL_PLANES];
        let mut n_planes = 0;
        let mut needs_world_test = terrain.surfaces.len() > MAX_LOCAL_PLANES;
        for surface in &terrain.surfaces {
            match surface {
                Surface::Plane { point, normal, .. } if n_planes < MAX_LOCAL_PLANES => {
                    planes[n_planes] = (
                        m.rotation.tr_mul(normal),
                        normal.dot(&(point - m.translation)),
                    );
                    n_planes += 1;
                }
                _ => needs_world_test = true,
            }
        }
        for k in b.points.clone() {
            let pt = &points[k];
            let near = needs_world_test
                || planes[..n_planes]
                    .iter()
                    .any(|(n, d)| d - n.dot(&pt.local) > -pt.radius);
            if !near && !visit_clear {
                continue;
            }
            let p = m.act_point(&pt.local);
            let force = if near {
                point_force(
                    terrain,
                    params,
                    &p,
                    || twist.point_velocity(&p),
                    pt.radius,
                    pt.weight,
                    &anchors[k],
                )
            } else {
                None
            };
            visit(PointVisit {
                index: k,
                joint: b.joint,
                position: p,
                force,
                anchor: &mut anchors[k],
            });
        }
    }
}
