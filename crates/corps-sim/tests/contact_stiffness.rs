//! The stiffness a flat box face gets from the sampled contact points: each point stands for
//! the box's whole surface area over its point count, so the bottom face's points of a box
//! thinner than the point spacing (its side faces sampled only along the top and bottom
//! edges, which the top and bottom grids already hold) carry half the surface,
//! `xy + z (x + y)`: the side faces' area folds onto the bottom. TALOS' sole box
//! (0.21 × 0.13 × 0.02 m) at the default 4·10⁷ N/m per m²: 1.364·10⁶ N/m per foot, not the
//! 1.092·10⁶ of the sole's own area.

mod common;

use corps_sim::{sample_contact_points, ContactParams};

#[test]
fn a_flat_sole_box_standing_has_the_stiffness_of_half_its_surface() {
    let [x, y, z] = [0.21, 0.13, 0.02];
    let model = common::box_body(1.0, [x, y, z]);
    let params = ContactParams::default();
    assert!(z <= params.point_spacing, "the formula is for thin boxes");
    let (points, _) = sample_contact_points(&model, params.point_spacing);
    let bottom: f64 = points
        .iter()
        .filter(|p| (p.local.z + z / 2.0).abs() < 1e-12)
        .map(|p| p.weight)
        .sum();
    let expected = x * y + z * (x + y);
    assert!(
        (bottom - expected).abs() < 1e-12,
        "bottom area {bottom} m², expected {expected} m²"
    );
    let stiffness = bottom * params.normal_stiffness;
    assert!((stiffness - 1.364e6).abs() < 1.0, "{stiffness} N/m");
}
