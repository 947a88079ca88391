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
    /// Normal stiffness per contact area (N/m per m²). A flat face's stiffness is this times
    /// the area its touching points stand for: for a box thinner than `point_spacing`, the
    /// bottom face's points carry half the box's surface, `xy + z (x + y)`, because its side
    /// faces are sampled only along the top and bottom edges. The default gives TALOS' sole
    /// box (0.21 × 0.13 × 0.02 m) 4·10⁷ × 0.0341 = 1.364·10⁶ N/m per foot: 0.32 mm sinking
    /// under the robot's weight on two feet (`tests/contact_stiffness.rs`).
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
    /// Surface normal at the point.
    pub normal: Vector3<f64>,
    /// Whether the tangential force sits on the friction cone (the point slides).
    pub sliding: bool,
    /// The point's velocity the force was computed with.
    pub velocity: Vector3<f64>,
}

/// A point force's linearization about the current state: ∂f/∂x = −K and ∂f/∂ẋ = −D with
/// `K = k_n nnᵀ + k_t (I − nnᵀ)` and `D = d_n nnᵀ + d_t (I − nnᵀ)`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PointLinearization {
    pub normal: Vector3<f64>,
    pub normal_stiffness: f64,
    pub normal_damping: f64,
    pub tangential_stiffness: f64,
    pub tangential_damping: f64,
}

/// `(a nnᵀ + b (I − nnᵀ)) x`.
#[inline]
pub(crate) fn split_times(n: &Vector3<f64>, a: f64, b: f64, x: &Vector3<f64>) -> Vector3<f64> {
    x * b + n * ((a - b) * n.dot(x))
}

/// `a nnᵀ + b (I − nnᵀ)` as a matrix (tests check the vector forms against it).
#[cfg(test)]
pub(crate) fn split_matrix(n: &Vector3<f64>, a: f64, b: f64) -> nalgebra::Matrix3<f64> {
    nalgebra::Matrix3::identity() * b + n * n.transpose() * (a - b)
}

impl PointLinearization {
    /// `K x`.
    pub fn stiffness_times(&self, x: &Vector3<f64>) -> Vector3<f64> {
        split_times(
            &self.normal,
            self.normal_stiffness,
            self.tangential_stiffness,
            x,
        )
    }
    /// `D x`.
    pub fn damping_times(&self, x: &Vector3<f64>) -> Vector3<f64> {
        split_times(
            &self.normal,
            self.normal_damping,
            self.tangential_damping,
            x,
        )
    }
}

impl PointForce {
    /// The force's linearization for a point of area share `w`: while pushing, the normal
    /// spring–damper; a sticking point adds its tangential spring–damper; a sliding point's
    /// friction force is held constant (its size follows the normal force, its direction the
    /// slip: neither is linear). Zero when not pushing.
    pub fn linearization(&self, params: &ContactParams, w: f64) -> PointLinearization {
        if self.normal_force <= 0.0 {
            return PointLinearization::default();
        }
        let kn = params.normal_stiffness * w;
        let kt = if self.sliding {
            0.0
        } else {
            params.tangential_stiffness * w
        };
        PointLinearization {
            normal: self.normal,
            normal_stiffness: kn,
            normal_damping: kn * params.normal_damping_time,
            tangential_stiffness: kt,
            tangential_damping: kt * params.tangential_damping_time,
        }
    }
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
                normal: n,
                sliding: false,
                velocity: v,
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
        let sliding = norm > limit;
        if sliding {
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
            normal: n,
            sliding,
            velocity: v,
        });
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::terrain::{Terrain, TerrainPreset};

    /// The linearization against central differences of the force in position and velocity,
    /// for a sticking point (anchor 0.2 mm behind) and a sliding one (anchor 5 cm behind).
    #[test]
    fn linearization_matches_finite_differences() {
        let terrain = Terrain::preset(TerrainPreset::Flat, 0.8);
        let params = ContactParams::default();
        let w = 1e-3;
        let p0 = Vector3::new(0.1, -0.2, -4e-4);
        let v0 = Vector3::new(0.003, -0.002, -0.001);
        for (offset, sliding) in [(2e-4, false), (0.05, true)] {
            let anchor = Anchor {
                position: p0 - Vector3::new(offset, 0.0, 0.0),
                active: true,
            };
            let force = |p: Vector3<f64>, v: Vector3<f64>| {
                point_force(&terrain, &params, &p, || v, 0.0, w, &anchor).unwrap()
            };
            let at = force(p0, v0);
            assert_eq!(at.sliding, sliding);
            let lin = at.linearization(&params, w);
            let k = split_matrix(&lin.normal, lin.normal_stiffness, lin.tangential_stiffness);
            let d = split_matrix(&lin.normal, lin.normal_damping, lin.tangential_damping);
            let h = 1e-9;
            for i in 0..3 {
                let e = Vector3::ith(i, h);
                let dfdx = (force(p0 + e, v0).force - force(p0 - e, v0).force) / (2.0 * h);
                let dfdv = (force(p0, v0 + e).force - force(p0, v0 - e).force) / (2.0 * h);
                let scale = params.normal_stiffness * w;
                // A sliding point's friction does change with x and v; the linearization
                // holds it constant, so compare the normal row there.
                let rows = if sliding { 2..3 } else { 0..3 };
                for r in rows {
                    assert!(
                        (dfdx[r] + k[(r, i)]).abs() < 1e-4 * scale,
                        "sliding {sliding}: ∂f{r}/∂x{i} {} vs {}",
                        dfdx[r],
                        -k[(r, i)]
                    );
                    assert!(
                        (dfdv[r] + d[(r, i)]).abs() < 1e-4 * scale * params.normal_damping_time,
                        "sliding {sliding}: ∂f{r}/∂v{i} {} vs {}",
                        dfdv[r],
                        -d[(r, i)]
                    );
                }
            }
            let x = Vector3::new(0.3, -0.7, 1.1);
            assert!((lin.stiffness_times(&x) - k * x).norm() < 1e-9 * k.norm());
            assert!((lin.damping_times(&x) - d * x).norm() < 1e-9 * d.norm());
        }
    }
}
