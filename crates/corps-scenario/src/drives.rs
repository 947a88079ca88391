//! The flexible joint drives a scenario simulates (`[actuation] drives = true`), built from the
//! robot description's `[drives]` for each actuated joint of the model.

use crate::error::{bail, Result};
use crate::scenario::DriveOverrides;
use corps_model::Model;
use corps_robot::Robot;
use corps_sim::{first_actuated, FlexibleDrive};

/// One entry per actuated joint of `model`: a flexible drive, or None for the joints the
/// description keeps ideal. The current limit defaults to each joint's effort limit over the
/// drive gain, so that the motor's torque limit is the URDF's. The drives act on torque
/// commands (a torque controller's); position and velocity commands (the settling hold, the
/// position controllers) keep the ideal joint servo. `overrides` replace the description's
/// values.
pub fn for_model(
    model: &Model,
    robot: Option<&Robot>,
    overrides: &DriveOverrides,
) -> Result<Vec<Option<FlexibleDrive>>> {
    let Some(described) = robot.and_then(|r| r.drives.as_ref()) else {
        bail!("actuation.drives: the robot description has no [drives] section");
    };
    let mut spec = described.clone();
    let o = overrides;
    let pick = |x: &mut f64, y: Option<f64>| {
        if let Some(y) = y {
            *x = y;
        }
    };
    pick(&mut spec.motor_inertia, o.motor_inertia);
    pick(&mut spec.stiffness, o.stiffness);
    pick(&mut spec.damping, o.damping);
    pick(&mut spec.viscous_friction, o.viscous_friction);
    pick(&mut spec.dry_friction, o.dry_friction);
    pick(&mut spec.friction_velocity, o.friction_velocity);
    pick(&mut spec.drive_gain, o.drive_gain);
    pick(&mut spec.bandwidth_hz, o.bandwidth_hz);
    spec.current_limit = o.current_limit.or(spec.current_limit);
    spec.delay_periods = o.delay_periods.unwrap_or(spec.delay_periods);
    let first = first_actuated(model);
    Ok((first..model.nv)
        .map(|dof| {
            let joint = &model.joints[model.dof_joint[dof]];
            if spec.ideal.contains(&joint.name) {
                return None;
            }
            let effort = model.effort_limit[dof];
            let current_limit = spec.current_limit.unwrap_or(if effort.is_finite() {
                effort / spec.drive_gain
            } else {
                f64::MAX
            });
            Some(FlexibleDrive {
                motor_inertia: spec.motor_inertia,
                stiffness: spec.stiffness,
                damping: spec.damping,
                viscous_friction: spec.viscous_friction,
                dry_friction: spec.dry_friction,
                friction_velocity: spec.friction_velocity,
                drive_gain: spec.drive_gain,
                current_limit,
                bandwidth_hz: spec.bandwidth_hz,
                delay_periods: spec.delay_periods,
            })
        })
        .collect())
}
