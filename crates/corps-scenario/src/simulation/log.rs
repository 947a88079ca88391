//! The run's log: a CSV file with one row per control tick and every signal as a column, the
//! unit in the column name (`base_z_m`, `tau_leg_left_4_joint_Nm`). Ground truth first, then
//! the measured sensor readings (noise and bias added) under a `meas_` prefix. The rows are
//! streamed by [`crate::output::CsvLog`].

use crate::foot::Foot;
use corps_model::{JointKind, Model};
use corps_sim::{first_actuated, Readings};
use nalgebra::Vector3;

/// What one row holds besides the sensor readings.
pub struct Extra<'a> {
    pub com: &'a Vector3<f64>,
    pub com_velocity: &'a Vector3<f64>,
    /// Vertical contact force on each foot's body (N, world z).
    pub feet_fz: &'a [f64],
    /// Vertical contact force on the whole robot (N).
    pub total_fz: f64,
}

/// The column names, in row order.
pub fn columns(model: &Model, ft_names: &[String], feet: &[Foot]) -> Vec<String> {
    let mut c = vec!["t_s".to_string()];
    let readings = |c: &mut Vec<String>, p: &str| {
        for k in ["x_m", "y_m", "z_m", "qx", "qy", "qz", "qw"] {
            c.push(format!("{p}base_{k}"));
        }
        for k in [
            "vx_m_s", "vy_m_s", "vz_m_s", "wx_rad_s", "wy_rad_s", "wz_rad_s",
        ] {
            c.push(format!("{p}base_{k}"));
        }
        let joints = actuated_joints(model);
        for (n, prismatic) in &joints {
            c.push(format!("{p}q_{n}_{}", if *prismatic { "m" } else { "rad" }));
        }
        for (n, prismatic) in &joints {
            c.push(format!(
                "{p}v_{n}_{}",
                if *prismatic { "m_s" } else { "rad_s" }
            ));
        }
        for (n, prismatic) in &joints {
            c.push(format!(
                "{p}tau_{n}_{}",
                if *prismatic { "N" } else { "Nm" }
            ));
        }
        for s in ft_names {
            for k in ["fx_N", "fy_N", "fz_N", "tx_Nm", "ty_Nm", "tz_Nm"] {
                c.push(format!("{p}ft_{}_{k}", clean(s)));
            }
        }
        for k in [
            "qx", "qy", "qz", "qw", "wx_rad_s", "wy_rad_s", "wz_rad_s", "ax_m_s2", "ay_m_s2",
            "az_m_s2",
        ] {
            c.push(format!("{p}imu_{k}"));
        }
    };
    readings(&mut c, "");
    for k in ["x_m", "y_m", "z_m", "vx_m_s", "vy_m_s", "vz_m_s"] {
        c.push(format!("com_{k}"));
    }
    for f in feet {
        c.push(format!("contact_fz_{}_N", clean(&f.label)));
    }
    c.push("contact_fz_total_N".into());
    readings(&mut c, "meas_");
    c
}

/// Appends one row's values, in the order of [`columns`].
pub fn fill_row(row: &mut Vec<f64>, truth: &Readings, measured: &Readings, extra: &Extra) {
    row.clear();
    row.push(truth.time);
    let readings = |row: &mut Vec<f64>, r: &Readings| {
        row.extend_from_slice(&r.base_pose);
        row.extend_from_slice(&r.base_twist);
        row.extend(r.joint_positions.iter());
        row.extend(r.joint_velocities.iter());
        row.extend(r.joint_torques.iter());
        for w in &r.force_torque {
            row.extend_from_slice(w);
        }
        row.extend_from_slice(&r.imu.orientation);
        row.extend_from_slice(&r.imu.angular_velocity);
        row.extend_from_slice(&r.imu.linear_acceleration);
    };
    readings(row, truth);
    row.extend(extra.com.iter());
    row.extend(extra.com_velocity.iter());
    row.extend_from_slice(extra.feet_fz);
    row.push(extra.total_fz);
    readings(row, measured);
}

/// Actuated joints in velocity order, with whether each is prismatic (unit m instead of rad).
pub fn actuated_joints(model: &Model) -> Vec<(String, bool)> {
    let first = first_actuated(model);
    let mut joints: Vec<_> = model
        .joints
        .iter()
        .filter(|j| j.idx_v >= first)
        .map(|j| {
            (
                j.idx_v,
                clean(&j.name),
                matches!(j.kind, JointKind::Prismatic { .. }),
            )
        })
        .collect();
    joints.sort_by_key(|j| j.0);
    joints.into_iter().map(|(_, n, p)| (n, p)).collect()
}

/// A name safe inside a CSV header cell (no separators, quotes or spaces).
fn clean(name: &str) -> String {
    name.chars()
        .map(|c| {
            if c == ',' || c == '"' || c.is_whitespace() {
                '_'
            } else {
                c
            }
        })
        .collect()
}
