//! The columns of a run's time series, and the stabilizer's part of each row.

use super::contacts::{ContactSample, ZMP_MIN_FZ};
use corps_control::stabilizer::StabilizerOutput;

/// The columns, in row order: the tracked signals (`joint_power_W`: q̇ᵀτ of the torques the
/// joints applied, true state), then with a stabilizer each foot's
/// ankle admittance (roll, pitch) offset and rate, measured and desired CoP in the sole frame,
/// and the DCM controller's desired ZMP (world x, y).
pub fn log_columns(stabilized: bool) -> Vec<String> {
    let mut header: Vec<String> = [
        "t",
        "com_x",
        "com_y",
        "com_z",
        "com_ref_x",
        "com_ref_y",
        "com_ref_z",
        "zmp_x",
        "zmp_y",
        "zmp_ref_x",
        "zmp_ref_y",
        "left_foot_z",
        "left_foot_z_ref",
        "right_foot_z",
        "right_foot_z_ref",
        "left_foot_fz",
        "right_foot_fz",
        "base_x",
        "base_y",
        "base_z",
        "com_est_x",
        "com_est_y",
        "com_est_z",
        "base_est_x",
        "base_est_y",
        "base_est_z",
        "joint_power_W",
        "tick_us",
    ]
    .map(String::from)
    .to_vec();
    if stabilized {
        for foot in ["left", "right"] {
            for (signal, axes) in [
                ("ankle", ["roll", "pitch"]),
                ("ankle_rate", ["roll", "pitch"]),
                ("cop", ["x", "y"]),
                ("cop_des", ["x", "y"]),
            ] {
                header.extend(axes.map(|a| format!("{foot}_{signal}_{a}")));
            }
        }
        header.extend(["zmp_des_x", "zmp_des_y"].map(String::from));
    }
    header
}

/// The columns of a run with a person (co-navigation), after the stabilizer's: the person's
/// position, the point the robot should hold (world x, y) and the CoM's distance from it.
pub const FOLLOW_COLUMNS: [&str; 5] = [
    "human_x",
    "human_y",
    "follow_x",
    "follow_y",
    "follow_error_m",
];

/// Appends the stabilizer's signals of one tick to `row` (NaN where it failed or a foot is
/// unloaded), in [`log_columns`]' order.
pub(crate) fn push_stabilizer(
    row: &mut Vec<f64>,
    out: Option<&StabilizerOutput>,
    contact: &ContactSample,
) {
    let nan2 = nalgebra::Vector2::repeat(f64::NAN);
    for f in 0..2 {
        let a = out.map(|o| o.ankle[f]);
        let cop = if contact.foot_fz[f] >= ZMP_MIN_FZ {
            contact.foot_wrenches[f].cop()
        } else {
            nan2
        };
        let cop_des = out.map_or(nan2, |o| o.foot_cops[f]);
        row.extend((0..2).map(|k| a.map_or(f64::NAN, |a| a.offset[k])));
        row.extend((0..2).map(|k| a.map_or(f64::NAN, |a| a.velocity[k])));
        row.extend((0..2).map(|k| cop[k]));
        row.extend((0..2).map(|k| cop_des[k]));
    }
    row.extend((0..2).map(|k| out.map_or(f64::NAN, |o| o.zmp_des[k])));
}
