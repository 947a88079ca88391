//! `drilling.png`: the clamping force against its bounds with the drill's thrust (top), the
//! tank's energy (middle) and its valves β and γ (bottom), over the cycle.

use anyhow::{anyhow, Result};
use corps_scenario::drilling::DrillingScenario;
use plotters::prelude::*;
use std::path::Path;

const BLUE: RGBColor = RGBColor(31, 119, 180);
const ORANGE: RGBColor = RGBColor(255, 127, 14);
const GREEN: RGBColor = RGBColor(44, 160, 44);
const RED: RGBColor = RGBColor(214, 39, 40);
const GREY: RGBColor = RGBColor(120, 120, 120);

/// Points drawn per curve at most (the log keeps every row).
const MAX_POINTS: usize = 4000;

/// The columns the plot shows, by name.
const COLUMNS: [&str; 9] = [
    "t",
    "clamp_N",
    "force_ref_N",
    "f_min_N",
    "f_max_N",
    "thrust_N",
    "tank_energy_J",
    "beta",
    "gamma",
];

/// The logged rows' plotted columns.
pub struct Series {
    at: [usize; COLUMNS.len()],
    rows: Vec<[f64; COLUMNS.len()]>,
}

impl Series {
    pub fn new(header: &[String]) -> Result<Self> {
        let mut at = [0; COLUMNS.len()];
        for (k, name) in COLUMNS.iter().enumerate() {
            at[k] = crate::output::column(header, name)?;
        }
        Ok(Self {
            at,
            rows: Vec::new(),
        })
    }

    pub fn push(&mut self, row: &[f64]) {
        self.rows.push(self.at.map(|k| row[k]));
    }

    /// Column `k` against time, every n-th row so that at most [`MAX_POINTS`] remain; NaN
    /// values split the curve.
    fn curves(&self, k: usize) -> Vec<Vec<(f64, f64)>> {
        let stride = self.rows.len().div_ceil(MAX_POINTS).max(1);
        let mut out = vec![Vec::new()];
        for r in self.rows.iter().step_by(stride) {
            if r[k].is_finite() {
                out.last_mut().expect("a curve").push((r[0], r[k]));
            } else if !out.last().expect("a curve").is_empty() {
                out.push(Vec::new());
            }
        }
        out.retain(|c| !c.is_empty());
        out
    }

    fn range(&self, ks: &[usize]) -> (f64, f64) {
        let (lo, hi) = self
            .rows
            .iter()
            .flat_map(|r| ks.iter().map(move |k| r[*k]))
            .filter(|x| x.is_finite())
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| {
                (a.min(x), b.max(x))
            });
        if lo.is_finite() && hi.is_finite() {
            let pad = ((hi - lo) * 0.08).max(0.05);
            (lo - pad, hi + pad)
        } else {
            (0.0, 1.0)
        }
    }
}

type Panel<'a> = (&'a str, &'a [(usize, RGBColor, &'a str)]);

pub fn draw(path: &Path, name: &str, s: &Series, scenario: &DrillingScenario) -> Result<()> {
    let t1 = s.rows.last().map_or(1.0, |r| r[0]).max(1e-3);
    let c = &scenario.clamp;
    let title = format!(
        "{name}: clamping force (bounds {}–{} N while held), drill thrust {} N, energy tank",
        c.f_min, c.f_max, scenario.cycle.thrust
    );
    let panels: [Panel; 3] = [
        (
            "force on the tool (N)",
            &[
                (1, BLUE, "clamp (true)"),
                (2, ORANGE, "reference"),
                (3, GREY, "F_min"),
                (4, GREY, "F_max"),
                (5, GREEN, "thrust"),
            ],
        ),
        ("tank energy (J)", &[(6, RED, "E_tank")]),
        ("valves", &[(7, BLUE, "β"), (8, ORANGE, "γ")]),
    ];
    crate::sim_cmd::plots::draw_png(path, (1600, 1000), |root| {
        root.fill(&WHITE).map_err(|e| anyhow!("{e}"))?;
        let root = root
            .titled(&title, ("sans-serif", 24))
            .map_err(|e| anyhow!("{e}"))?;
        let areas = root.split_evenly((panels.len(), 1));
        for ((label, curves), area) in panels.iter().zip(&areas) {
            let ks: Vec<usize> = curves.iter().map(|c| c.0).collect();
            let (lo, hi) = s.range(&ks);
            let mut chart = ChartBuilder::on(area)
                .margin(10)
                .x_label_area_size(30)
                .y_label_area_size(60)
                .build_cartesian_2d(0.0..t1, lo..hi)
                .map_err(|e| anyhow!("{e}"))?;
            chart
                .configure_mesh()
                .x_desc("t (s)")
                .y_desc(*label)
                .draw()
                .map_err(|e| anyhow!("{e}"))?;
            for (k, color, legend) in curves.iter() {
                let mut first = true;
                for curve in s.curves(*k) {
                    let series = chart
                        .draw_series(LineSeries::new(curve, color.stroke_width(2)))
                        .map_err(|e| anyhow!("{e}"))?;
                    if first {
                        let color = *color;
                        series
                            .label(*legend)
                            .legend(move |(x, y)| PathElement::new([(x, y), (x + 20, y)], color));
                        first = false;
                    }
                }
            }
            chart
                .configure_series_labels()
                .background_style(WHITE.mix(0.8))
                .border_style(BLACK)
                .draw()
                .map_err(|e| anyhow!("{e}"))?;
        }
        Ok(())
    })
}
