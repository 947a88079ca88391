//! PNG plots of a run (plotters' bitmap backend, text in an embedded DejaVu Sans subset so
//! nothing is needed from the system): base height, centre of mass, centre of pressure per
//! foot, vertical contact forces, joint torques. One file per plot.

use anyhow::{anyhow, Context, Result};
use plotters::prelude::*;
use plotters::style::FontStyle;
use std::path::{Path, PathBuf};
use std::sync::Once;

/// DejaVu Sans reduced to Latin, Greek and a few symbols (Bitstream Vera license, see
/// `assets/fonts/LICENSE`).
const FONT: &[u8] = include_bytes!("../../assets/fonts/DejaVuSans-subset.ttf");

/// At most this many samples per series are kept (longer runs are decimated).
const MAX_SAMPLES: usize = 20_000;

/// Vertical force (N) below which a foot's centre of pressure is not defined.
pub const COP_MIN_FZ: f64 = 10.0;

/// One foot's traces.
struct FootTrace {
    label: String,
    fz: Vec<f64>,
    /// CoP x and y in the F/T sensor (sole) frame; NaN while the foot is unloaded.
    cop: [Vec<f64>; 2],
}

/// The values of one tick that the plots show.
pub use corps_scenario::simulation::Signals as Sample;

/// Time series kept for the plots.
pub struct Traces {
    stride: usize,
    t: Vec<f64>,
    base_z: Vec<f64>,
    com: [Vec<f64>; 3],
    feet: Vec<FootTrace>,
    total_fz: Vec<f64>,
    tau: Vec<Vec<f64>>,
    joints: Vec<String>,
}

/// Centre of pressure (x, y) from a force/torque reading in a frame on the sole:
/// (−τy/fz, τx/fz), or None when fz ≤ [`COP_MIN_FZ`].
pub fn center_of_pressure(ft: &[f64; 6]) -> Option<[f64; 2]> {
    let fz = ft[2];
    (fz > COP_MIN_FZ).then(|| [-ft[4] / fz, ft[3] / fz])
}

impl Traces {
    /// Empty traces for a run of `ticks` ticks with these feet and actuated joints.
    pub fn new(ticks: usize, feet: &[String], joints: &[String]) -> Self {
        Self {
            stride: ticks.div_ceil(MAX_SAMPLES).max(1),
            t: vec![],
            base_z: vec![],
            com: Default::default(),
            feet: feet
                .iter()
                .map(|l| FootTrace {
                    label: l.clone(),
                    fz: vec![],
                    cop: Default::default(),
                })
                .collect(),
            total_fz: vec![],
            tau: vec![vec![]; joints.len()],
            joints: joints.to_vec(),
        }
    }

    /// Records tick `tick` (kept if it falls on the decimation stride).
    pub fn push(&mut self, tick: usize, s: &Sample) {
        if !tick.is_multiple_of(self.stride) {
            return;
        }
        self.t.push(s.t);
        self.base_z.push(s.base_z);
        for (k, c) in self.com.iter_mut().enumerate() {
            c.push(s.com[k]);
        }
        for (k, foot) in self.feet.iter_mut().enumerate() {
            foot.fz.push(s.feet_fz[k]);
            let cop = center_of_pressure(&s.feet_ft[k]).unwrap_or([f64::NAN; 2]);
            foot.cop[0].push(cop[0]);
            foot.cop[1].push(cop[1]);
        }
        self.total_fz.push(s.total_fz);
        for (trace, x) in self.tau.iter_mut().zip(s.tau) {
            trace.push(*x);
        }
    }

    /// Writes every plot into `dir`; returns the files written.
    pub fn write_pngs(&self, dir: &Path) -> Result<Vec<PathBuf>> {
        let mut figures: Vec<Figure> = vec![];
        let mut figure = |name: &str, title: &str, panels, cols: usize| {
            figures.push(Figure {
                path: dir.join(name),
                title: title.into(),
                panels,
                cols,
            });
        };
        figure(
            "base_height.png",
            "Base height",
            vec![Panel::new("base z", "m", vec![("z".into(), &self.base_z)])],
            1,
        );
        let com = ["x", "y", "z"]
            .iter()
            .zip(&self.com)
            .map(|(a, c)| Panel::new(&format!("CoM {a}"), "m", vec![((*a).into(), c)]))
            .collect();
        figure("com.png", "Centre of mass (world)", com, 1);
        if !self.feet.is_empty() {
            let cop = ["x", "y"]
                .iter()
                .enumerate()
                .map(|(k, a)| {
                    Panel::new(
                        &format!("CoP {a} in the sole frame (where fz > {COP_MIN_FZ} N)"),
                        "m",
                        self.feet
                            .iter()
                            .map(|f| (f.label.clone(), &f.cop[k]))
                            .collect(),
                    )
                })
                .collect();
            figure(
                "cop.png",
                "Centre of pressure per foot (from the measured F/T readings)",
                cop,
                1,
            );
        }
        let mut forces: Vec<(String, &Vec<f64>)> =
            self.feet.iter().map(|f| (f.label.clone(), &f.fz)).collect();
        forces.push(("total".into(), &self.total_fz));
        figure(
            "contact_forces.png",
            "Vertical contact forces",
            vec![Panel::new("fz", "N", forces)],
            1,
        );
        if !self.joints.is_empty() {
            figure(
                "joint_torques.png",
                "Applied joint torques",
                self.torque_panels(),
                2,
            );
        }
        draw_figures(&self.t, &figures)
    }

    /// One panel per joint group (`leg_left_4_joint` belongs to `leg_left`).
    fn torque_panels(&self) -> Vec<Panel<'_>> {
        let mut groups: Vec<(String, Series<'_>)> = vec![];
        for (name, trace) in self.joints.iter().zip(&self.tau) {
            let short = name.strip_suffix("_joint").unwrap_or(name);
            let group = short
                .trim_end_matches(|c: char| c.is_ascii_digit())
                .trim_end_matches('_');
            let group = if group.is_empty() { short } else { group };
            match groups.iter_mut().find(|(g, _)| g == group) {
                Some((_, series)) => series.push((short.to_string(), trace)),
                None => groups.push((group.to_string(), vec![(short.to_string(), trace)])),
            }
        }
        groups
            .into_iter()
            .map(|(g, series)| Panel::new(&g, "N·m", series))
            .collect()
    }
}

/// Named series over the common time axis (NaN: gap).
pub(crate) type Series<'a> = Vec<(String, &'a Vec<f64>)>;

/// One chart: a title, the y unit and its series.
pub(crate) struct Panel<'a> {
    title: String,
    unit: String,
    series: Series<'a>,
}

impl<'a> Panel<'a> {
    pub(crate) fn new(title: &str, unit: &str, series: Series<'a>) -> Self {
        Self {
            title: title.into(),
            unit: unit.into(),
            series,
        }
    }
}

/// One PNG to draw: its path, title, panels and number of panel columns.
pub(crate) struct Figure<'a> {
    pub path: PathBuf,
    pub title: String,
    pub panels: Vec<Panel<'a>>,
    pub cols: usize,
}

/// Draws the figures over the time axis `t`, each on its own thread (rasterizing and PNG
/// encoding are the slow part of writing a run's results, and the figures are independent);
/// returns their paths, in order, or the first failure.
pub(crate) fn draw_figures(t: &[f64], figures: &[Figure<'_>]) -> Result<Vec<PathBuf>> {
    register_font();
    let results: Vec<Result<()>> = std::thread::scope(|scope| {
        let jobs: Vec<_> = figures
            .iter()
            .map(|f| {
                scope.spawn(move || {
                    draw_figure(&f.path, &f.title, t, &f.panels, f.cols)
                        .with_context(|| format!("drawing {}", f.path.display()))
                })
            })
            .collect();
        jobs.into_iter()
            .map(|j| {
                j.join()
                    .unwrap_or_else(|_| Err(anyhow::anyhow!("a plotting thread panicked")))
            })
            .collect()
    });
    for r in results {
        r?;
    }
    Ok(figures.iter().map(|f| f.path.clone()).collect())
}

pub(crate) fn register_font() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        // The font is embedded and known to parse (tested); a failure would only lose text.
        let _ = plotters::style::register_font("sans-serif", FontStyle::Normal, FONT);
    });
}

const COLORS: [RGBColor; 8] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(255, 127, 14),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(23, 190, 207),
];

/// Draws `panels` in a grid of `cols` columns into `path`, through a temporary file renamed
/// at the end.
pub(crate) fn draw_figure(
    path: &Path,
    title: &str,
    t: &[f64],
    panels: &[Panel],
    cols: usize,
) -> Result<()> {
    let rows = panels.len().div_ceil(cols);
    let (w, h) = (1400u32, 80 + 300 * rows as u32);
    draw_png(path, (w, h), |root| {
        root.fill(&WHITE).map_err(plot_error)?;
        let root = root.titled(title, ("sans-serif", 26)).map_err(plot_error)?;
        let areas = root.split_evenly((rows, cols));
        for (panel, area) in panels.iter().zip(areas.iter()) {
            draw_panel(area, panel, t)?;
        }
        Ok(())
    })
}

/// Draws a `size` PNG at `path` with `draw`, through a temporary file of this process renamed
/// at the end, so a failed plot never leaves half an image over a previous one. The font is
/// registered first.
pub(crate) fn draw_png(
    path: &Path,
    size: (u32, u32),
    draw: impl FnOnce(&DrawingArea<BitMapBackend<'_>, plotters::coord::Shift>) -> Result<()>,
) -> Result<()> {
    register_font();
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    // The encoder picks the format from the extension: keep `.png` on the temporary name,
    // which is the process's own.
    let tmp = path.with_file_name(format!(".{name}.{}.partial.png", std::process::id()));
    {
        let root = BitMapBackend::new(&tmp, size).into_drawing_area();
        draw(&root)?;
        root.present().map_err(plot_error)?;
    }
    std::fs::rename(&tmp, path).with_context(|| format!("renaming {}", tmp.display()))?;
    Ok(())
}

fn draw_panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    panel: &Panel,
    t: &[f64],
) -> Result<()>
where
    DB::ErrorType: 'static,
{
    let (t0, t1) = match (t.first(), t.last()) {
        (Some(a), Some(b)) if b > a => (*a, *b),
        (Some(a), _) => (*a, a + 1e-3),
        _ => (0.0, 1.0),
    };
    let (mut lo, mut hi) = panel
        .series
        .iter()
        .flat_map(|(_, s)| s.iter().copied())
        .filter(|x| x.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), x| {
            (l.min(x), h.max(x))
        });
    if !lo.is_finite() {
        (lo, hi) = (-1.0, 1.0);
    }
    let pad = ((hi - lo) * 0.08)
        .max(1e-6 * lo.abs().max(hi.abs()))
        .max(1e-9);
    let mut chart = ChartBuilder::on(area)
        .caption(&panel.title, ("sans-serif", 18))
        .margin(8)
        .x_label_area_size(36)
        .y_label_area_size(80)
        .build_cartesian_2d(t0..t1, (lo - pad)..(hi + pad))
        .map_err(plot_error)?;
    chart
        .configure_mesh()
        .x_desc("t (s)")
        .y_desc(panel.unit.as_str())
        .label_style(("sans-serif", 14))
        .axis_desc_style(("sans-serif", 15))
        .light_line_style(RGBColor(235, 235, 235))
        .draw()
        .map_err(plot_error)?;
    for (k, (label, series)) in panel.series.iter().enumerate() {
        let color = COLORS[k % COLORS.len()];
        let style = ShapeStyle::from(&color).stroke_width(2);
        let mut labelled = false;
        // Runs of finite values, so NaN leaves a gap.
        let mut run: Vec<(f64, f64)> = vec![];
        let n = series.len().min(t.len());
        for i in 0..=n {
            let point = (i < n && series[i].is_finite()).then(|| (t[i], series[i]));
            match point {
                Some(p) => run.push(p),
                None if !run.is_empty() => {
                    let drawn = chart
                        .draw_series(LineSeries::new(std::mem::take(&mut run), style))
                        .map_err(plot_error)?;
                    if !labelled {
                        drawn.label(label.as_str()).legend(move |(x, y)| {
                            PathElement::new(vec![(x, y), (x + 20, y)], style)
                        });
                        labelled = true;
                    }
                }
                None => {}
            }
        }
    }
    if panel.series.len() > 1 {
        chart
            .configure_series_labels()
            .label_font(("sans-serif", 14))
            .background_style(WHITE.mix(0.85))
            .border_style(RGBColor(180, 180, 180))
            .position(SeriesLabelPosition::UpperRight)
            .draw()
            .map_err(plot_error)?;
    }
    Ok(())
}

fn plot_error<E: std::error::Error + Send + Sync>(e: DrawingAreaErrorKind<E>) -> anyhow::Error {
    anyhow!("{e}")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_embedded_font_parses() {
        assert!(plotters::style::register_font("test-font", FontStyle::Normal, FONT).is_ok());
    }

    #[test]
    fn center_of_pressure_follows_the_moments() {
        // 100 N at (0.02, -0.01): τx = y fz = -1, τy = -x fz = -2.
        let cop = center_of_pressure(&[0.0, 0.0, 100.0, -1.0, -2.0, 0.0]).unwrap();
        assert!((cop[0] - 0.02).abs() < 1e-12 && (cop[1] + 0.01).abs() < 1e-12);
        assert!(center_of_pressure(&[0.0, 0.0, 5.0, 0.0, 0.0, 0.0]).is_none());
    }
}
