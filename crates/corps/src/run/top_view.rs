//! A top view (world x, y, equal scales) of paths: a walk with a person drawn as the person's
//! path, the point the robot should hold and the robot's CoM.

use anyhow::{anyhow, Result};
use plotters::prelude::*;
use std::path::Path;

/// A named path: (x, y) points, NaN where it is absent.
pub struct TopPath<'a> {
    pub label: &'a str,
    pub x: &'a [f64],
    pub y: &'a [f64],
}

/// Draws `paths` into `path` (PNG) with `title`, through a temporary file renamed at the end.
pub fn draw(path: &Path, title: &str, paths: &[TopPath<'_>]) -> Result<()> {
    let points = |p: &TopPath<'_>| -> Vec<(f64, f64)> {
        p.x.iter()
            .zip(p.y)
            .filter(|(x, y)| x.is_finite() && y.is_finite())
            .map(|(x, y)| (*x, *y))
            .collect()
    };
    let all: Vec<(f64, f64)> = paths.iter().flat_map(points).collect();
    let (mut x0, mut x1, mut y0, mut y1) = all.iter().fold(
        (
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::INFINITY,
            f64::NEG_INFINITY,
        ),
        |(a, b, c, d), (x, y)| (a.min(*x), b.max(*x), c.min(*y), d.max(*y)),
    );
    if !x0.is_finite() {
        (x0, x1, y0, y1) = (-1.0, 1.0, -1.0, 1.0);
    }
    // Equal scales: the larger span on both axes, with a margin.
    let span = (x1 - x0).max(y1 - y0).max(0.5) * 1.1;
    let (cx, cy) = ((x0 + x1) / 2.0, (y0 + y1) / 2.0);
    crate::sim_cmd::plots::draw_png(path, (900, 900), |root| {
        root.fill(&WHITE).map_err(|e| anyhow!("{e}"))?;
        let mut chart = ChartBuilder::on(root)
            .caption(title, ("sans-serif", 22))
            .margin(12)
            .x_label_area_size(40)
            .y_label_area_size(60)
            .build_cartesian_2d(
                (cx - span / 2.0)..(cx + span / 2.0),
                (cy - span / 2.0)..(cy + span / 2.0),
            )
            .map_err(|e| anyhow!("{e}"))?;
        chart
            .configure_mesh()
            .x_desc("x (m)")
            .y_desc("y (m)")
            .light_line_style(RGBColor(235, 235, 235))
            .draw()
            .map_err(|e| anyhow!("{e}"))?;
        let colors = [
            RGBColor(214, 39, 40),
            RGBColor(44, 160, 44),
            RGBColor(31, 119, 180),
        ];
        for (k, p) in paths.iter().enumerate() {
            let style = ShapeStyle::from(&colors[k % colors.len()]).stroke_width(2);
            let pts = points(p);
            if let Some(&first) = pts.first() {
                chart
                    .draw_series(std::iter::once(Circle::new(first, 5, style.filled())))
                    .map_err(|e| anyhow!("{e}"))?;
            }
            chart
                .draw_series(LineSeries::new(pts, style))
                .map_err(|e| anyhow!("{e}"))?
                .label(p.label)
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], style));
        }
        chart
            .configure_series_labels()
            .background_style(WHITE.mix(0.85))
            .border_style(RGBColor(180, 180, 180))
            .position(SeriesLabelPosition::UpperLeft)
            .draw()
            .map_err(|e| anyhow!("{e}"))?;
        Ok(())
    })
}
