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
    let lowest = points
        .iter()
        .map(|p| data.o_m_i[p.joint].act_point(&p.local).z - p.radius)
        .fold(f64::INFINITY, f64::min);
    if !lowest.is_finite() {
        return Err(SimError::Setting {
            name: "initial placement".into(),
            reason: "the model has no collision box, cylinder or sphere".into(),
        });
    }
    let shift = height - lowest;
    q[2] += shift;
    Ok(shift)
}
