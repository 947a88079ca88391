//! PNG plots of a controller run: CoM against its reference, ZMP against its reference, feet
//! heights and vertical forces, base position, controller time per tick; with a stabilizer,
//! the ankle admittance's offsets and rates and each foot's CoP against its target; with an
//! energy tank, its energy, its valves and the power bound (seed 000 §4.5's figures); with a
//! stepping state machine, its state and the feet's desired and measured forces; with a person
//! to walk with, the following error and a top view of the paths (`top_view`).

use crate::sim_cmd::plots::{draw_figures, Figure, Panel};
use anyhow::{anyhow, Result};
use corps_scenario::series::PlotBuffer;
use std::path::{Path, PathBuf};

/// Writes the figures of the signals in `buffer` (columns named by `header`, the log's) into
/// `dir`; returns their paths.
pub fn write(
    dir: &Path,
    buffer: &PlotBuffer,
    header: &[String],
    title: &str,
) -> Result<Vec<PathBuf>> {
    let column = |name: &str| -> Result<&Vec<f64>> {
        let k = header
            .iter()
            .position(|h| h == name)
            .ok_or_else(|| anyhow!("plots: no signal {name}"))?;
        Ok(&buffer.columns()[k])
    };
    let xyz = |prefix: &str, n: usize| -> Result<Vec<&Vec<f64>>> {
        ["x", "y", "z"][..n]
            .iter()
            .map(|a| column(&format!("{prefix}_{a}")))
            .collect()
    };
    let t = column("t")?;
    let com = xyz("com", 3)?;
    let com_ref = xyz("com_ref", 3)?;
    let zmp = xyz("zmp", 2)?;
    let zmp_ref = xyz("zmp_ref", 2)?;
    let foot_z = [column("left_foot_z")?, column("right_foot_z")?];
    let foot_z_ref = [column("left_foot_z_ref")?, column("right_foot_z_ref")?];
    let foot_fz = [column("left_foot_fz")?, column("right_foot_fz")?];
    let base = xyz("base", 3)?;
    let tick = column("tick_us")?;
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
                    ("measured".into(), com[k]),
                    ("reference".into(), com_ref[k]),
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
                    ("measured".into(), zmp[k]),
                    ("reference (LIPM)".into(), zmp_ref[k]),
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
                    ("measured".into(), foot_z[k]),
                    ("reference".into(), foot_z_ref[k]),
                ],
            )
        })
        .collect();
    panels.push(Panel::new(
        "vertical contact force",
        "N",
        vec![("left".into(), foot_fz[0]), ("right".into(), foot_fz[1])],
    ));
    panels.push(Panel::new(
        "base position",
        "m",
        vec![
            ("x".into(), base[0]),
            ("y".into(), base[1]),
            ("z".into(), base[2]),
        ],
    ));
    figure("feet.png", format!("{title}: feet and base"), panels, 2);

    let panels = vec![Panel::new(
        "controller time per tick",
        "µs",
        vec![("tick".into(), tick)],
    )];
    figure(
        "tick_time.png",
        format!("{title}: controller time"),
        panels,
        1,
    );

    // The stabilizer's signals (absent without one).
    if header.iter().any(|h| h == "zmp_des_x") {
        let pair = |foot: &str, signal: &str, axes: [&str; 2]| -> Result<[&Vec<f64>; 2]> {
            Ok([
                column(&format!("{foot}_{signal}_{}", axes[0]))?,
                column(&format!("{foot}_{signal}_{}", axes[1]))?,
            ])
        };
        let mut panels = vec![];
        for name in names {
            let offset = pair(name, "ankle", ["roll", "pitch"])?;
            let rate = pair(name, "ankle_rate", ["roll", "pitch"])?;
            panels.push(Panel::new(
                &format!("{name} ankle offset"),
                "rad",
                vec![("roll".into(), offset[0]), ("pitch".into(), offset[1])],
            ));
            panels.push(Panel::new(
                &format!("{name} ankle rate"),
                "rad/s",
                vec![("roll".into(), rate[0]), ("pitch".into(), rate[1])],
            ));
        }
        for name in names {
            let cop = pair(name, "cop", ["x", "y"])?;
            let cop_des = pair(name, "cop_des", ["x", "y"])?;
            for k in 0..2 {
                panels.push(Panel::new(
                    &format!("{name} CoP {} (sole frame)", axes[k]),
                    "m",
                    vec![("measured".into(), cop[k]), ("desired".into(), cop_des[k])],
                ));
            }
        }
        figure("ankle.png", format!("{title}: ankle admittance"), panels, 2);
    }
    // The energy tank's signals (absent without one).
    if header.iter().any(|h| h == "tank_energy_J") {
        let panels = vec![
            Panel::new(
                "tank energy",
                "J",
                vec![("E_tank".into(), column("tank_energy_J")?)],
            ),
            Panel::new(
                "valves",
                "",
                vec![
                    ("alpha".into(), column("alpha")?),
                    ("beta".into(), column("beta")?),
                    ("gamma".into(), column("gamma")?),
                    ("beta_phi".into(), column("beta_phi")?),
                ],
            ),
            Panel::new(
                "storage rate and its bound",
                "W",
                vec![
                    ("dH/dt".into(), column("h_dot_W")?),
                    ("-qdot^T tau (bound)".into(), column("passivity_bound_W")?),
                ],
            ),
            Panel::new(
                "tank power",
                "W",
                vec![
                    ("B_sigma".into(), column("b_sigma_W")?),
                    ("B_phi".into(), column("b_phi_W")?),
                ],
            ),
        ];
        figure("tank.png", format!("{title}: energy tank"), panels, 2);
    }
    // A stepping state machine's run (seed 001 Figs 2.5–2.8: FSM state, forces desired and
    // measured).
    if header.iter().any(|h| h == "fsm_state") {
        let mut panels = vec![Panel::new(
            "state machine",
            "",
            vec![
                ("state (file order)".into(), column("fsm_state")?),
                ("stance left".into(), column("stance_left")?),
            ],
        )];
        for (k, side) in ["left", "right"].iter().enumerate() {
            panels.push(Panel::new(
                &format!("{side} foot normal force"),
                "N",
                vec![
                    (
                        "QP desired".into(),
                        column(&format!("force_desired_{side}_z_N"))?,
                    ),
                    ("contact (simulator)".into(), foot_fz[k]),
                ],
            ));
        }
        panels.push(Panel::new(
            "|measured (F/T) - desired| contact force",
            "N",
            vec![
                ("left".into(), column("force_error_left_N")?),
                ("right".into(), column("force_error_right_N")?),
            ],
        ));
        figure("stepping.png", format!("{title}: stepping"), panels, 2);
    }
    // A hand's force task (a `[press]` scenario; seed 000 Fig 5.4).
    if header.iter().any(|h| h == "hand_force_N") {
        let panels = vec![
            Panel::new(
                "hand force along the contact normal",
                "N",
                vec![
                    ("reference F*".into(), column("hand_force_ref_N")?),
                    ("measured (filtered)".into(), column("hand_force_N")?),
                    ("asked of the QP".into(), column("hand_force_desired_N")?),
                    ("QP's solution".into(), column("hand_force_qp_N")?),
                ],
            ),
            Panel::new(
                "tool tip below its contact point (< 0: above)",
                "m",
                vec![("drop".into(), column("tool_drop_m")?)],
            ),
            Panel::new(
                "hand contact held",
                "",
                vec![("contact".into(), column("hand_contact")?)],
            ),
        ];
        figure(
            "hand_force.png",
            format!("{title}: hand force task"),
            panels,
            1,
        );
    }
    // Walking with a person: the following error over time, and a top view of the paths.
    let mut written = Vec::new();
    if header.iter().any(|h| h == "follow_error_m") {
        let panels = vec![
            Panel::new(
                "CoM distance from the point to hold",
                "m",
                vec![("following error".into(), column("follow_error_m")?)],
            ),
            Panel::new(
                "x",
                "m",
                vec![
                    ("person".into(), column("human_x")?),
                    ("point to hold".into(), column("follow_x")?),
                    ("CoM".into(), com[0]),
                ],
            ),
            Panel::new(
                "y",
                "m",
                vec![
                    ("person".into(), column("human_y")?),
                    ("point to hold".into(), column("follow_y")?),
                    ("CoM".into(), com[1]),
                ],
            ),
        ];
        figure(
            "following.png",
            format!("{title}: with the person"),
            panels,
            1,
        );
        let top = dir.join("paths.png");
        super::top_view::draw(
            &top,
            &format!("{title}: paths seen from above (dots: start)"),
            &[
                super::top_view::TopPath {
                    label: "person",
                    x: column("human_x")?,
                    y: column("human_y")?,
                },
                super::top_view::TopPath {
                    label: "point to hold",
                    x: column("follow_x")?,
                    y: column("follow_y")?,
                },
                super::top_view::TopPath {
                    label: "robot CoM",
                    x: com[0],
                    y: com[1],
                },
            ],
        )?;
        written.push(top);
    }
    let mut files = draw_figures(t, &figures)?;
    files.extend(written);
    Ok(files)
}
