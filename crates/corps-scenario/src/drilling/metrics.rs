//! What a drilling run measured, and its verdict against the bounds of Eq 6.2.

use serde::Serialize;

/// Energy the tank may leave unpaid over a run (J) before the verdict fails: rounding.
pub const UNPAID_TOLERANCE: f64 = 1e-6;

/// The figures of a drilling run (`metrics.json`).
#[derive(Clone, Debug, Default, Serialize)]
pub struct DrillingMetrics {
    /// "ok", or "failed: " and every bound missed.
    pub verdict: String,
    pub stations: usize,
    /// Stations finished (the contact made, the force held, the tool back at its approach
    /// point) and holes drilled among them.
    pub stations_done: usize,
    pub holes_drilled: usize,
    /// Simulated time (s) and when the cycle ended (s; NaN if it did not).
    pub duration_s: f64,
    pub cycle_time_s: f64,
    /// The true normal force on the tool while the clamping force is held (N).
    pub clamp_min_n: f64,
    pub clamp_max_n: f64,
    /// Ticks of the held phases outside [F_min, F_max], of all held ticks.
    pub clamp_out_of_bounds_ticks: usize,
    pub clamped_ticks: usize,
    pub f_min_n: f64,
    pub f_max_n: f64,
    /// Largest ratio of a tangential force component (along the tip's x or y axis, the axes
    /// of the QP's slip pyramid) to the normal force while held, and the bound μ_s.
    pub slip_ratio_max: f64,
    pub slip_ratio_bound: f64,
    /// From the touch to the release: the largest normal force (N), how far the tip slid on
    /// the plate from where it touched (mm), and how far it may slide (mm).
    pub contact_peak_n: f64,
    pub slide_max_mm: f64,
    pub slide_limit_mm: f64,
    /// Tip at the touch against the station's point, on the plate (mm).
    pub hole_position_error_max_mm: f64,
    /// The tool's orientation against the plate's normal while held (deg).
    pub normality_error_max_deg: f64,
    /// High-level updates, their interval (ms), and the ones that fell back.
    pub qp_updates: usize,
    pub qp_interval_mean_ms: f64,
    pub qp_interval_min_ms: f64,
    pub qp_interval_max_ms: f64,
    pub qp_fallbacks: usize,
    pub first_fallback: Option<String>,
    /// Updates whose storage rate exceeded the port's power, Ḣ > −q̇ᵀτ (1e-6 W slack).
    pub passivity_violations: usize,
    pub tank_min_j: f64,
    pub tank_final_j: f64,
    /// Energy the QP's torques gave the arm over the intervals between updates (from Δq),
    /// and the part of it the tank could not pay (J): what the arm received beyond the
    /// storage's loss.
    pub qp_energy_to_arm_j: f64,
    pub tank_unpaid_j: f64,
    /// Energy the local PD+ gave the arm over the run, ∫ q̇ᵀ τ_PD dt (J): the local loop's
    /// share, outside the tank's books.
    pub local_loop_energy_j: f64,
    /// Ticks where a joint was beyond its position or velocity limit.
    pub joint_limit_violations: usize,
    /// Largest |τ| / effort limit of any joint.
    pub torque_ratio_max: f64,
    /// Wall time (s) and how many times faster than real time.
    pub wall_time_s: f64,
    pub real_time_factor: f64,
}

impl DrillingMetrics {
    /// The verdict: every station done, every held tick inside the clamping bounds and the
    /// slip ratio, the force never above F_max from the touch to the release, the tool not
    /// sliding, the tank paying all the energy the QP's torques gave the arm, the tank's power row held, no joint past its limits.
    pub fn judge(&mut self) {
        let mut failed = Vec::new();
        if self.stations_done < self.stations {
            failed.push(format!(
                "{} of {} stations done",
                self.stations_done, self.stations
            ));
        }
        if self.clamp_out_of_bounds_ticks > 0 {
            failed.push(format!(
                "clamping force outside [{}, {}] N on {} ticks (min {:.1}, max {:.1} N)",
                self.f_min_n,
                self.f_max_n,
                self.clamp_out_of_bounds_ticks,
                self.clamp_min_n,
                self.clamp_max_n
            ));
        }
        if self.contact_peak_n > self.f_max_n {
            failed.push(format!(
                "the tool pressed {:.1} N, above F_max = {} N",
                self.contact_peak_n, self.f_max_n
            ));
        }
        if self.slide_max_mm > self.slide_limit_mm {
            failed.push(format!(
                "the tool slid {:.2} mm on the plate (limit {} mm)",
                self.slide_max_mm, self.slide_limit_mm
            ));
        }
        if self.slip_ratio_max > self.slip_ratio_bound {
            failed.push(format!(
                "tangential force {:.3} of the normal (bound {})",
                self.slip_ratio_max, self.slip_ratio_bound
            ));
        }
        if self.passivity_violations > 0 {
            failed.push(format!("Ḣ > −q̇ᵀτ on {} updates", self.passivity_violations));
        }
        if self.tank_unpaid_j > UNPAID_TOLERANCE {
            failed.push(format!(
                "the QP's torques gave the arm {:.4} J the tank could not pay",
                self.tank_unpaid_j
            ));
        }
        if self.joint_limit_violations > 0 {
            failed.push(format!(
                "joints past their limits on {} ticks",
                self.joint_limit_violations
            ));
        }
        if self.qp_fallbacks > 0 {
            failed.push(format!("{} QP fallbacks", self.qp_fallbacks));
        }
        self.verdict = if failed.is_empty() {
            "ok".into()
        } else {
            format!("failed: {}", failed.join("; "))
        };
    }
}
