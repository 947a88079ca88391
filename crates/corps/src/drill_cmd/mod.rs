//! `corps drill`: a fixed-base arm drills a plate under the passive QP (seed 000 §3.19, the
//! cycle of Table 6.2; `corps_scenario::drilling`). Writes `log.csv` (streamed),
//! `metrics.json` and `drilling.png` (the clamping force against its bounds with the thrust,
//! the tank's energy, its valves β and γ) into the output directory and prints the metrics;
//! exits non-zero when the verdict is not "ok".

mod plots;

use crate::output::{self, CsvLog};
use crate::progress::Progress;
use anyhow::{anyhow, bail, Context, Result};
use clap::Args;
use corps_scenario::drilling::{DrillingMetrics, DrillingRun, DrillingScenario};
use corps_scenario::run::RowSink;
use corps_scenario::ScenarioError;
use std::path::{Path, PathBuf};

#[derive(Args)]
pub struct DrillArgs {
    /// The drilling scenario (TOML).
    #[arg(default_value = "scenarios/drilling/ur5_drilling.toml")]
    pub scenario: PathBuf,
    /// Output directory (default out/<scenario name>).
    #[arg(short, long)]
    pub output: Option<PathBuf>,
    /// Holes drilled between R1 and R2 (replaces `[cycle] holes`).
    #[arg(long)]
    pub holes: Option<usize>,
    /// Simulated time (s; replaces `duration`).
    #[arg(long)]
    pub duration: Option<f64>,
    /// The high-level QP's rate (Hz; replaces `[loops] qp_rate_hz`).
    #[arg(long)]
    pub qp_rate_hz: Option<f64>,
    /// The QP updates' jitter (s; replaces `[loops] jitter`).
    #[arg(long)]
    pub jitter: Option<f64>,
    /// The local PD+ loop's rate (Hz; replaces `[loops] local_rate_hz`).
    #[arg(long)]
    pub local_rate_hz: Option<f64>,
    /// The drill's thrust (N; replaces `[cycle] thrust`).
    #[arg(long)]
    pub thrust: Option<f64>,
    /// Log every N-th local tick.
    #[arg(long, default_value_t = 5)]
    pub log_every: usize,
    /// No progress bar.
    #[arg(long)]
    pub quiet: bool,
}

/// The log's rows to the CSV (every `every`-th), the plot's series and the progress bar.
struct Sink {
    log: CsvLog,
    every: usize,
    progress: Progress,
    series: plots::Series,
}

impl RowSink for Sink {
    fn row(&mut self, index: usize, row: &[f64]) -> Result<(), ScenarioError> {
        if index.is_multiple_of(self.every) {
            self.log
                .row(row)
                .map_err(|e| ScenarioError::Output(format!("{e:#}")))?;
            self.series.push(row);
        }
        self.progress.tick(index);
        Ok(())
    }
}

pub fn run(args: DrillArgs) -> Result<()> {
    let report = drill(&args)?;
    crate::stdout::print(&report.text)?;
    if report.metrics.verdict != "ok" {
        bail!("{}: {}", args.scenario.display(), report.metrics.verdict);
    }
    Ok(())
}

/// What a drilling run wrote and measured.
pub struct DrillReport {
    pub metrics: DrillingMetrics,
    pub dir: PathBuf,
    pub text: String,
}

/// Runs the scenario of `args` and writes its outputs.
pub fn drill(args: &DrillArgs) -> Result<DrillReport> {
    if args.log_every == 0 {
        bail!("--log-every: must be at least 1");
    }
    let path = &args.scenario;
    let text =
        std::fs::read_to_string(path).with_context(|| format!("reading {}", path.display()))?;
    let mut scenario =
        DrillingScenario::parse(&text).map_err(|e| anyhow!("{}: {e}", path.display()))?;
    if let Some(h) = args.holes {
        scenario.cycle.holes = h;
    }
    if let Some(d) = args.duration {
        scenario.duration = Some(d);
    }
    let l = &mut scenario.loops;
    l.qp_rate_hz = args.qp_rate_hz.unwrap_or(l.qp_rate_hz);
    l.jitter = args.jitter.unwrap_or(l.jitter);
    l.local_rate_hz = args.local_rate_hz.unwrap_or(l.local_rate_hz);
    scenario.cycle.thrust = args.thrust.unwrap_or(scenario.cycle.thrust);
    let base = path.parent().unwrap_or(Path::new("."));
    let run = DrillingRun::new(&scenario, base).map_err(|e| anyhow!("{}: {e}", path.display()))?;
    let name = path
        .file_stem()
        .map_or("drilling".into(), |s| s.to_string_lossy().into_owned());
    let dir = args
        .output
        .clone()
        .unwrap_or_else(|| Path::new("out").join(&name));
    let header = run.columns().to_vec();
    let cap = 2u64 << 30;
    output::check_size(run.ticks().div_ceil(args.log_every), header.len(), cap)?;
    std::fs::create_dir_all(&dir).with_context(|| format!("creating {}", dir.display()))?;
    let _lock = output::DirLock::acquire(&dir)?;
    let mut sink = Sink {
        log: CsvLog::create(&dir, &header, cap)?,
        every: args.log_every,
        progress: Progress::new(run.ticks(), run.dt(), !args.quiet),
        series: plots::Series::new(&header)?,
    };
    let metrics = run
        .run(&mut [&mut sink], Some(&crate::interrupt::FLAG))
        .map_err(|e| crate::run::command_error(e, &dir))
        .with_context(|| path.display().to_string())?;
    sink.progress.finish();
    let log = sink.log.finish()?;
    let json = serde_json::to_string_pretty(&metrics)?;
    let metrics_path = output::write_atomic(&dir, "metrics.json", json.as_bytes())?;
    let plot = dir.join("drilling.png");
    plots::draw(&plot, &name, &sink.series, &scenario)?;
    let text = summary(&metrics, &name, &[log, metrics_path, plot]);
    Ok(DrillReport { metrics, dir, text })
}

fn summary(m: &DrillingMetrics, name: &str, files: &[PathBuf]) -> String {
    let files: Vec<String> = files.iter().map(|f| f.display().to_string()).collect();
    format!(
        "{name}: {verdict}\n  stations {done}/{n} ({holes} holes drilled), cycle {cycle:.1} s of {dur:.1} s simulated, {rtf:.1}× real time\n  clamping force while held: {cmin:.1}–{cmax:.1} N (bounds {fmin}–{fmax} N, {oob} of {held} ticks outside)\n  tangential/normal ≤ {ratio:.3} (bound {rb}), normality ≤ {norm:.3}°, hole position ≤ {hole:.2} mm\n  from touch to release: force ≤ {peak:.1} N, slide ≤ {slide:.3} mm (limit {sl} mm)\n  QP updates {upd} every {imean:.2} ms ({imin:.1}–{imax:.1} ms), fallbacks {fb}, Ḣ > −q̇ᵀτ on {pv}\n  tank {tmin:.2} J at least, {tfin:.2} J at the end; the QP's torques gave the arm {qpe:.3} J ({unpaid:.2e} J unpaid), the local loop {local:.3} J\n  joints past their limits on {lim} ticks; largest |τ|/τ_max {tr:.2}\nwrote {files}\n",
        verdict = m.verdict,
        done = m.stations_done,
        n = m.stations,
        holes = m.holes_drilled,
        cycle = m.cycle_time_s,
        dur = m.duration_s,
        rtf = m.real_time_factor,
        cmin = m.clamp_min_n,
        cmax = m.clamp_max_n,
        fmin = m.f_min_n,
        fmax = m.f_max_n,
        oob = m.clamp_out_of_bounds_ticks,
        held = m.clamped_ticks,
        ratio = m.slip_ratio_max,
        rb = m.slip_ratio_bound,
        norm = m.normality_error_max_deg,
        hole = m.hole_position_error_max_mm,
        peak = m.contact_peak_n,
        slide = m.slide_max_mm,
        sl = m.slide_limit_mm,
        qpe = m.qp_energy_to_arm_j,
        unpaid = m.tank_unpaid_j,
        upd = m.qp_updates,
        imean = m.qp_interval_mean_ms,
        imin = m.qp_interval_min_ms,
        imax = m.qp_interval_max_ms,
        fb = m.qp_fallbacks,
        pv = m.passivity_violations,
        tmin = m.tank_min_j,
        tfin = m.tank_final_j,
        local = m.local_loop_energy_j,
        lim = m.joint_limit_violations,
        tr = m.torque_ratio_max,
        files = files.join(", "),
    )
}
