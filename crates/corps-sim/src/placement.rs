//! Initial placement: lift or lower the floating base so the robot's lowest contact point
//! touches the ground plane z = 0.

use crate::contact_points::sample_contact_points;
use crate::error::{Result, SimError};
use corps_model::{forward_kinematics_placements, Data, Model};

/// Shifts the base height in `q` (free-flyer models) so that the lowest contact point sits at
/// z = `height`. Returns the shift applied (m).
pub fn place_on_ground(model: &Model, q: &mut [f64], height: f64) -> Result<f64> {
    if !model.has_free_flyer() {
        return Err(SimError::Setting {
            name: "initial placement".into(),
            reason: "needs a free-flyer base".into(),
        });
    }
    let mut data = Data::new(model);
    forward_kinematics_placements(model, &mut data, q)?;
    let (points, _) = sample_contact_points(model, 0.05);
    let (lowest, shape) = points
        .iter()
        .map(|p| {
            (
                data.o_m_i[p.joint].act_point(&p.local).z - p.radius,
                p.shape,
            )
        })
        .fold(
            (f64::INFINITY, usize::MAX),
            |a, b| if b.0 < a.0 { b } else { a },
        );
    if !lowest.is_finite() {
        return Err(SimError::Setting {
            name: "initial placement".into(),
            reason: "the model has no collision box, cylinder or sphere".into(),
        });
    }
    if let Some(link) = resting_on_base(model, shape) {
        return Err(SimError::Setting {
            name: "initial placement".into(),
            reason: format!(
                "the lowest collision shape is on the base link '{link}', so the robot would \
                 rest on its base instead of its feet; give the feet collision boxes, cylinders \
                 or spheres (meshes are not simulated) or place the robot yourself"
            ),
        });
    }
    let shift = height - lowest;
    q[2] += shift;
    Ok(shift)
}

/// The base link's name when `shape`, the lowest one, moves with the free-flyer itself on a
/// robot that has other bodies: such a robot would stand on its trunk (simple_humanoid's
/// 1 m test cylinder on its waist is its only simulated shape).
fn resting_on_base(model: &Model, shape: usize) -> Option<&str> {
    let geometry = model.collisions.get(shape)?;
    let on_root = geometry.parent_joint == Some(0);
    (on_root && model.njoints() > 1).then_some(geometry.link.as_str())
}
