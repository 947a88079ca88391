//! `fitness.png`: the best fitness against the iteration, the mean over the repeats and the
//! band from the worst to the best repeat.

use anyhow::{anyhow, Result};
use corps_scenario::learning::campaign::Evaluation;
use plotters::prelude::*;
use std::collections::BTreeMap;
use std::path::Path;

pub fn fitness(
    path: &Path,
    title: &str,
    iterations: usize,
    rows: &BTreeMap<usize, BTreeMap<usize, Evaluation>>,
) -> Result<()> {
    // Per iteration: (min, mean, max) over repeats of the best fitness so far.
    let mut stats = Vec::with_capacity(iterations + 1);
    for it in 0..=iterations {
        let v: Vec<f64> = (rows.values())
            .filter_map(|r| r.get(&it).map(|e| e.best_fitness))
            .filter(|x| x.is_finite())
            .collect();
        if v.is_empty() {
            continue;
        }
        let mean = v.iter().sum::<f64>() / v.len() as f64;
        let lo = v.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = v.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        stats.push((it as f64, lo, mean, hi));
    }
    let (mut y0, mut y1) = stats
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), s| {
            (a.min(s.1), b.max(s.3))
        });
    if !(y0.is_finite() && y1.is_finite()) {
        (y0, y1) = (-1.0, 0.0);
    }
    let pad = ((y1 - y0) * 0.05).max(1e-9);
    crate::sim_cmd::plots::draw_png(path, (1000, 600), |root| {
        root.fill(&WHITE).map_err(|e| anyhow!("{e}"))?;
        let mut chart = ChartBuilder::on(root)
            .caption(
                format!("{title}: best fitness over the iterations"),
                ("sans-serif", 22),
            )
            .margin(12)
            .x_label_area_size(40)
            .y_label_area_size(70)
            .build_cartesian_2d(0f64..(iterations.max(1) as f64), (y0 - pad)..(y1 + pad))
            .map_err(|e| anyhow!("{e}"))?;
        chart
            .configure_mesh()
            .x_desc("iteration")
            .y_desc("best fitness ϕ")
            .light_line_style(RGBColor(235, 235, 235))
            .draw()
            .map_err(|e| anyhow!("{e}"))?;
        let blue = RGBColor(31, 119, 180);
        let band: Vec<(f64, f64)> = (stats.iter().map(|s| (s.0, s.3)))
            .chain(stats.iter().rev().map(|s| (s.0, s.1)))
            .collect();
        chart
            .draw_series(std::iter::once(Polygon::new(band, blue.mix(0.2).filled())))
            .map_err(|e| anyhow!("{e}"))?
            .label("worst to best repeat")
            .legend(move |(x, y)| {
                Rectangle::new([(x, y - 5), (x + 20, y + 5)], blue.mix(0.2).filled())
            });
        chart
            .draw_series(LineSeries::new(
                stats.iter().map(|s| (s.0, s.2)),
                blue.stroke_width(2),
            ))
            .map_err(|e| anyhow!("{e}"))?
            .label("mean over the repeats")
            .legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 20, y)], blue.stroke_width(2))
            });
        chart
            .configure_series_labels()
            .background_style(WHITE.mix(0.8))
            .border_style(BLACK)
            .position(SeriesLabelPosition::LowerRight)
            .draw()
            .map_err(|e| anyhow!("{e}"))?;
        Ok(())
    })
}
