//! Compliant contact with stiction: a spring–damper along the normal and an anchored
//! tangential spring–damper, projected onto the Coulomb cone (the anchor slides with the point
//! when the cone is reached). Chosen over a complementarity solve because it is explicit, cheap
//! per point, exactly static at rest (the anchor removes creep), and its parameters are two
//! stiffnesses and two dampings per shape face; `tests/validation.rs` measures it against the
//! static, sliding and resting-robot cases of the issue.

use crate::terrain::Terrain;
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

/// Contact parameters, per unit of contact area: a sample point carries the area it stands
/// for, so a fully touching face of area A has stiffness `A · normal_stiffness` whatever the
/// sampling. Damping is stiffness times a time constant, which keeps every contact mode,
/// however light the body, inside the integrator's stability region.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ContactParams {
    /// Normal stiffness per contact area (N/m per m²). The default gives a TALOS sole
    /// (0.21 × 0.13 m) about 1.1·10⁶ N/m: 0.4 mm sinking under the robot's weight.
    pub normal_stiffness: f64,
    /// Damping time constant (s): normal damping = stiffness × this.
    pub normal_damping_time: f64,
    /// Tangential (anchor) stiffness per contact area (N/m per m²).
    pub tangential_stiffness: f64,
    /// Tangential damping time constant (s).
    pub tangential_damping_time: f64,
    /// Largest distance between neighbouring sample points on a face (m).
    pub point_spacing: f64,
}

impl Default for ContactParams {
    fn default() -> Self {
        Self {
            normal_stiffness: 4.0e7,
            normal_damping_time: 5e-4,
            tangential_stiffness: 4.0e7,
            tangential_damping_time: 5e-4,
            point_spacing: 0.03,
        }
    }
}

/// Per-point contact state carried across steps: where the tangential spring is anchored.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Anchor {
    /// World point the tangential spring pulls towards (valid while `active`).
    pub position: Vector3<f64>,
    pub active: bool,
}

/// The force on one point, and what the anchor should become if the step is accepted.
#[derive(Clone, Copy, Debug)]
pub struct PointForce {
    pub force: Vector3<f64>,
    pub normal_force: f64,
    pub next_anchor: Anchor,
    pub surface: usize,
}

/// Force on a world point at `p` (area share `w`, sphere radius `r`); `velocity` gives the
/// point's velocity and is called only if the point penetrates a surface.
#[inline]
pub fn point_force(
    terrain: &Terrain,
    params: &ContactParams,
    p: &Vector3<f64>,
    velocity: impl FnOnce() -> Vector3<f64>,
    r: f64,
    w: f64,
    anchor: &Anchor,
) -> Option<PointForce> {
    for (s, surface) in terrain.surfaces.iter().enumerate() {
        // A sphere is probed at its lowest point along the surface's up direction.
        let probe = if r > 0.0 { p - surface.up() * r } else { *p };
        let Some(pen) = surface.penetration(&probe) else {
            continue;
        };
        let n = pen.normal;
        let v = velocity();
        let vn = n.dot(&v);
        let kn = params.normal_stiffness * w;
        let fn_ = (kn * (pen.depth - params.normal_damping_time * vn)).max(0.0);
        if fn_ == 0.0 {
            return Some(PointForce {
                force: Vector3::zeros(),
                normal_force: 0.0,
                next_anchor: Anchor::default(),
                surface: s,
            });
        }
        let vt = v - n * vn;
        let anchor_pos = if anchor.active { anchor.position } else { *p };
        let mut dt = p - anchor_pos;
        dt -= n * n.dot(&dt);
        let kt = params.tangential_stiffness * w;
        let mut ft = -(dt + vt * params.tangential_damping_time) * kt;
        let limit = pen.mu * fn_;
        let mut next = Anchor {
            position: anchor_pos,
            active: true,
        };
        let norm = ft.norm();
        if norm > limit {
            // Sliding: the force sits on the cone; the anchor moves so the spring alone gives it.
            ft *= limit / norm;
            next.position = p + ft / kt;
            next.position -= n * n.dot(&(next.position - p));
        }
        return Some(PointForce {
            force: n * fn_ + ft,
            normal_force: fn_,
            next_anchor: next,
            surface: s,
        });
    }
    None
}
