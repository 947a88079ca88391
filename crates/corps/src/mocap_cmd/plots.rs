//! `joints.png`: each mapped joint's angle asked by the operator (Eq 6.1–6.2, dashed) and the
//! robot's after clipping (solid) with its limits, like seed 001 Fig 6.10; `steps.png`: the
//! operator's step lengths and heights and the robot's (Eq 6.6–6.7), like Fig 6.12.

use anyhow::{anyhow, Result};
use corps_mocap::replay::Retargeted;
use corps_mocap::retarget::Mapping;
use plotters::prelude::*;
use std::path::Path;

const BLUE: RGBColor = RGBColor(31, 119, 180);
const ORANGE: RGBColor = RGBColor(255, 127, 14);
const GREY: RGBColor = RGBColor(150, 150, 150);

pub fn joints(path: &Path, clip: &str, r: &Retargeted) -> Result<()> {
    let n = r.joints.len().max(1);
    let cols = 4;
    let rows = n.div_ceil(cols);
    let t1 = r.time.last().copied().unwrap_or(1.0).max(1e-3);
    crate::sim_cmd::plots::draw_png(path, (1600, 300 * rows as u32 + 60), |root| {
        root.fill(&WHITE).map_err(|e| anyhow!("{e}"))?;
        let title = format!(
            "{clip} onto {}: operator (dashed) and robot (solid, clipped to the limits, grey), degrees",
            r.robot
        );
        let root = root
            .titled(&title, ("sans-serif", 24))
            .map_err(|e| anyhow!("{e}"))?;
        let areas = root.split_evenly((rows, cols));
        for (i, j) in r.joints.iter().enumerate() {
            let op: Vec<(f64, f64)> = (r.time.iter().zip(&r.operator))
                .map(|(t, o)| (*t, o[i].to_degrees()))
                .collect();
            let cl: Vec<(f64, f64)> = (r.time.iter().zip(&r.clipped))
                .map(|(t, c)| (*t, c[i].to_degrees()))
                .collect();
            let (lo, hi) = (op.iter().chain(&cl))
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| {
                    (a.min(p.1), b.max(p.1))
                });
            let (lo, hi) = (
                lo.min(j.lower.to_degrees().max(lo - 20.0)),
                hi.max(j.upper.to_degrees().min(hi + 20.0)),
            );
            let pad = ((hi - lo) * 0.08).max(1.0);
            let mut chart = ChartBuilder::on(&areas[i])
                .caption(&j.name, ("sans-serif", 18))
                .margin(8)
                .x_label_area_size(28)
                .y_label_area_size(44)
                .build_cartesian_2d(0.0..t1, (lo - pad)..(hi + pad))
                .map_err(|e| anyhow!("{e}"))?;
            chart
                .configure_mesh()
                .x_desc("t (s)")
                .light_line_style(RGBColor(238, 238, 238))
                .draw()
                .map_err(|e| anyhow!("{e}"))?;
            for limit in [j.lower.to_degrees(), j.upper.to_degrees()] {
                if limit > lo - pad && limit < hi + pad {
                    chart
                        .draw_series(LineSeries::new([(0.0, limit), (t1, limit)], GREY))
                        .map_err(|e| anyhow!("{e}"))?;
                }
            }
            chart
                .draw_series(DashedLineSeries::new(op, 6, 4, ORANGE.stroke_width(2)))
                .map_err(|e| anyhow!("{e}"))?;
            chart
                .draw_series(LineSeries::new(cl, BLUE.stroke_width(2)))
                .map_err(|e| anyhow!("{e}"))?;
        }
        Ok(())
    })
}

pub fn steps(path: &Path, clip: &str, r: &Retargeted, mapping: &Mapping) -> Result<()> {
    let s = &mapping.spec.steps;
    let n = r.steps.len().max(1) as f64;
    crate::sim_cmd::plots::draw_png(path, (1000, 700), |root| {
        root.fill(&WHITE).map_err(|e| anyhow!("{e}"))?;
        let root = root
            .titled(
                &format!("{clip} onto {}: footsteps (Eq 6.6–6.7)", r.robot),
                ("sans-serif", 22),
            )
            .map_err(|e| anyhow!("{e}"))?;
        let panels = root.split_evenly((2, 1));
        for (k, (who, range_len, range_h)) in [
            ("operator", s.human_length, s.human_height),
            (r.robot.as_str(), s.robot_length, s.robot_height),
        ]
        .into_iter()
        .enumerate()
        {
            let points: Vec<(f64, f64, f64)> = (r.steps.iter().enumerate())
                .map(|(i, st)| {
                    let (l, h) = if k == 0 {
                        (st.human_travel.norm(), st.human_height)
                    } else {
                        (st.robot_travel.norm(), st.robot_height)
                    };
                    (i as f64 + 1.0, l, h)
                })
                .collect();
            let top = range_len[1].max(range_h[1]) * 1.1;
            let mut chart = ChartBuilder::on(&panels[k])
                .caption(
                    format!(
                        "{who}: step length (blue) and height (orange), m; range {:.2}–{:.2} / {:.2}–{:.2}",
                        range_len[0], range_len[1], range_h[0], range_h[1]
                    ),
                    ("sans-serif", 18),
                )
                .margin(10)
                .x_label_area_size(32)
                .y_label_area_size(56)
                .build_cartesian_2d(0.5..(n + 0.5), 0.0..top)
                .map_err(|e| anyhow!("{e}"))?;
            chart
                .configure_mesh()
                .x_desc("step")
                .light_line_style(RGBColor(238, 238, 238))
                .draw()
                .map_err(|e| anyhow!("{e}"))?;
            chart
                .draw_series(LineSeries::new(
                    [(0.5, range_len[1]), (n + 0.5, range_len[1])],
                    GREY,
                ))
                .map_err(|e| anyhow!("{e}"))?;
            chart
                .draw_series(
                    points
                        .iter()
                        .map(|p| Circle::new((p.0, p.1), 5, BLUE.filled())),
                )
                .map_err(|e| anyhow!("{e}"))?;
            chart
                .draw_series(
                    points
                        .iter()
                        .map(|p| TriangleMarker::new((p.0, p.2), 6, ORANGE.filled())),
                )
                .map_err(|e| anyhow!("{e}"))?;
        }
        Ok(())
    })
}
