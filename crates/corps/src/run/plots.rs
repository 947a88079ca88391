//! PNG plots of a controller run: CoM against its reference, ZMP against its reference, feet
//! heights and vertical forces, base position, controller time per tick; with a stabilizer,
//! the ankle admittance's offsets and rates and each foot's CoP against its target.

use super::Series;
use crate::sim_cmd::plots::{draw_figures, Figure, Panel};
use anyhow::Result;
use std::path::{Path, PathBuf};

/// At most this many points per series (longer runs are decimated).
const MAX_POINTS: usize = 20_000;

fn decimate(x: &[f64], stride: usize) -> Vec<f64> {
    x.iter().step_by(stride).copied().collect()
}

/// Writes the figures into `dir`; returns their paths.
pub fn write(dir: &Path, s: &Series, title: &str) -> Result<Vec<PathBuf>> {
    let stride = s.t.len().div_ceil(MAX_POINTS).max(1);
    let d = |x: &Vec<f64>| decimate(x, stride);
    let t = d(&s.t);
    let com = s.com.each_ref().map(d);
    let com_ref = s.com_ref.each_ref().map(d);
    let zmp = s.zmp.each_ref().map(d);
    let zmp_ref = s.zmp_ref.each_ref().map(d);
    let foot_z = s.foot_z.each_ref().map(d);
    let foot_z_ref = s.foot_z_ref.each_ref().map(d);
    let foot_fz = s.foot_fz.each_ref().map(d);
    let base = s.base.each_ref().map(d);
    let tick = d(&s.tick_us);
    let mut figures: Vec<Figure> = vec![];
    let mut figure = |name: &str, title: String, panels, cols: usize| {
        figures.push(Figure {
            path: dir.join(name),
            title,
            panels,
            cols,
        })
    };
    let axes = ["x", "y", "z"];

    let panels: Vec<Panel> = (0..3)
        .map(|k| {
            Panel::new(
                &format!("CoM {}", axes[k]),
                "m",
                vec![
                    ("measured".into(), &com[k]),
                    ("reference".into(), &com_ref[k]),
                ],
            )
        })
        .collect();
    figure("com.png", format!("{title}: centre of mass"), panels, 3);

    let panels: Vec<Panel> = (0..2)
        .map(|k| {
            Panel::new(
                &format!("ZMP {}", axes[k]),
                "m",
                vec![
                    ("measured".into(), &zmp[k]),
                    ("reference (LIPM)".into(), &zmp_ref[k]),
                ],
            )
        })
        .collect();
    figure("zmp.png", format!("{title}: zero-moment point"), panels, 2);

    let names = ["left", "right"];
    let mut panels: Vec<Panel> = (0..2)
        .map(|k| {
            Panel::new(
                &format!("{} sole height", names[k]),
                "m",
                vec![
                    ("measured".into(), &foot_z[k]),
                    ("reference".into(), &foot_z_ref[k]),
                ],
            )
        })
        .collect();
    panels.push(Panel::new(
        "vertical contact force",
        "N",
        vec![("left".into(), &foot_fz[0]), ("right".into(), &foot_fz[1])],
    ));
    panels.push(Panel::new(
        "base position",
        "m",
        vec![
            ("x".into(), &base[0]),
            ("y".into(), &base[1]),
            ("z".into(), &base[2]),
        ],
    ));
    figure("feet.png", format!("{title}: feet and base"), panels, 2);

    let panels = vec![Panel::new(
        "controller time per tick",
        "µs",
        vec![("tick".into(), &tick)],
    )];
    figure(
        "tick_time.png",
        format!("{title}: controller time"),
        panels,
        1,
    );

    // The stabilizer's series (empty without one), decimated here to outlive the figures.
    let st = &s.stabilizer;
    let dd = |x: &[Vec<f64>; 2]| x.each_ref().map(d);
    let offset = st.ankle_offset.each_ref().map(dd);
    let rate = st.ankle_rate.each_ref().map(dd);
    let cop = st.cop.each_ref().map(dd);
    let cop_des = st.cop_des.each_ref().map(dd);
    if !st.is_empty() {
        let mut panels = vec![];
        for f in 0..2 {
            panels.push(Panel::new(
                &format!("{} ankle offset", names[f]),
                "rad",
                vec![
                    ("roll".into(), &offset[f][0]),
                    ("pitch".into(), &offset[f][1]),
                ],
            ));
            panels.push(Panel::new(
                &format!("{} ankle rate", names[f]),
                "rad/s",
                vec![("roll".into(), &rate[f][0]), ("pitch".into(), &rate[f][1])],
            ));
        }
        for f in 0..2 {
            for k in 0..2 {
                panels.push(Panel::new(
                    &format!("{} CoP {} (sole frame)", names[f], axes[k]),
                    "m",
                    vec![
                        ("measured".into(), &cop[f][k]),
                        ("desired".into(), &cop_des[f][k]),
                    ],
                ));
            }
        }
        figure("ankle.png", format!("{title}: ankle admittance"), panels, 2);
    }
    draw_figures(&t, &figures)
}
