//! The summary printed after a run: simulated and wall time, real-time factor, final base
//! position, lowest base height, largest foot slip, and the verdict.

use corps_loop::verdict::VerdictReport;
use std::fmt;
use std::path::PathBuf;
use std::time::Duration;

/// What the run did.
pub struct Summary {
    pub name: String,
    pub simulated: f64,
    pub ticks: usize,
    pub control_dt: f64,
    pub wall: Duration,
    pub final_base: [f64; 3],
    pub min_base_z: f64,
    /// How the run ended.
    pub verdict: VerdictReport,
    /// Simulated time reached when Ctrl-C stopped the run (s); the log ends there.
    pub interrupted_at: Option<f64>,
    /// Largest horizontal displacement of each foot from its start (label, m).
    pub slip: Vec<(String, f64)>,
    pub log: PathBuf,
    pub rows: usize,
    pub columns: usize,
    pub plots: Vec<PathBuf>,
}

impl Summary {
    /// Simulated seconds per wall-clock second.
    pub fn real_time_factor(&self) -> f64 {
        self.simulated / self.wall.as_secs_f64().max(1e-9)
    }
}

impl fmt::Display for Summary {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(f, "scenario {}", self.name)?;
        writeln!(
            f,
            "  simulated        {:.3} s ({} ticks of {} ms)",
            self.simulated,
            self.ticks,
            self.control_dt * 1e3
        )?;
        writeln!(
            f,
            "  wall time        {:.2} s (real-time factor {:.2})",
            self.wall.as_secs_f64(),
            self.real_time_factor()
        )?;
        let [x, y, z] = self.final_base;
        writeln!(
            f,
            "  final base       x = {x:.4} m, y = {y:.4} m, z = {z:.4} m"
        )?;
        writeln!(f, "  min base height  {:.4} m", self.min_base_z)?;
        if self.slip.is_empty() {
            writeln!(f, "  max foot slip    n/a (no feet in [sensors])")?;
        } else {
            let slips: Vec<String> = self
                .slip
                .iter()
                .map(|(label, s)| format!("{label} {:.2} mm", s * 1e3))
                .collect();
            writeln!(f, "  max foot slip    {}", slips.join(", "))?;
        }
        writeln!(f, "  verdict          {}", self.verdict)?;
        if let Some(t) = self.interrupted_at {
            writeln!(f, "  interrupted      at t = {t:.3} s: the log ends there")?;
        }
        writeln!(
            f,
            "  log              {} ({} rows, {} columns)",
            self.log.display(),
            self.rows,
            self.columns
        )?;
        if !self.plots.is_empty() {
            let names: Vec<String> = self
                .plots
                .iter()
                .filter_map(|p| p.file_name().map(|n| n.to_string_lossy().into_owned()))
                .collect();
            writeln!(f, "  plots            {}", names.join(", "))?;
        }
        Ok(())
    }
}
