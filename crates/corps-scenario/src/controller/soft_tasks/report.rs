//! The stepping figures seed 001 gives for controller #2 (S2, L2960–L3136), accumulated over
//! the run as the controller sees it (its estimate against its references): strides, CoM
//! and feet errors, the distance between measured and QP-desired contact forces (of the feet
//! in contact, outside the switching windows), a released foot's early touch, and the
//! stride's duration.

use crate::metrics::ReportLine;
use nalgebra::Vector3;

#[derive(Clone, Debug, Default)]
pub struct SteppingStats {
    ticks: usize,
    com_sum: Vector3<f64>,
    com_peak: Vector3<f64>,
    /// Largest error of either foot, per axis.
    foot_peak: Vector3<f64>,
    force_sum: f64,
    force_count: usize,
    force_peak: f64,
    /// Force-error ticks above 20 N outside switching.
    force_over: usize,
    switch_force_peak: f64,
    /// Times of the feet swaps.
    swaps: Vec<f64>,
    /// The smallest distance to a joint limit (rad) and its joint.
    margin: Option<(f64, usize)>,
    /// The largest normal force measured on a foot the controller has released (N).
    released_force: f64,
}

impl SteppingStats {
    pub fn new() -> Self {
        Self {
            swaps: Vec::with_capacity(1024),
            ..Default::default()
        }
    }

    /// One tick: CoM and feet errors, and each foot's force error with whether the tick is
    /// outside the switching windows.
    pub fn push(
        &mut self,
        com_error: Vector3<f64>,
        foot_errors: [Vector3<f64>; 2],
        force_errors: [f64; 2],
        outside_switching: bool,
    ) {
        self.ticks += 1;
        self.com_sum += com_error.abs();
        self.com_peak = self.com_peak.sup(&com_error.abs());
        for e in foot_errors {
            self.foot_peak = self.foot_peak.sup(&e.abs());
        }
        for e in force_errors.into_iter().filter(|e| e.is_finite()) {
            if outside_switching {
                self.force_sum += e;
                self.force_count += 1;
                self.force_peak = self.force_peak.max(e);
                self.force_over += usize::from(e >= 20.0);
            } else {
                self.switch_force_peak = self.switch_force_peak.max(e);
            }
        }
    }

    /// The normal force measured on a released foot this tick (N).
    pub fn released_foot_force(&mut self, fz: f64) {
        if fz.is_finite() {
            self.released_force = self.released_force.max(fz);
        }
    }

    /// A tick's smallest distance to a joint limit (rad) and its joint.
    pub fn joint_margin(&mut self, margin: f64, joint: usize) {
        if self.margin.is_none_or(|(m, _)| margin < m) {
            self.margin = Some((margin, joint));
        }
    }

    /// The run's smallest distance to a joint limit (rad) and its joint.
    pub fn smallest_margin(&self) -> Option<(f64, usize)> {
        self.margin
    }

    /// A feet swap (a step completed) at `t`.
    pub fn swapped(&mut self, t: f64) {
        if self.swaps.len() < self.swaps.capacity() {
            self.swaps.push(t);
        }
    }

    /// Completed strides: two steps each.
    pub fn strides(&self) -> usize {
        self.swaps.len() / 2
    }

    /// Mean stride duration between the first and last swap (s), once three swaps happened.
    pub fn stride_duration(&self) -> Option<f64> {
        let n = self.swaps.len();
        (n >= 3).then(|| 2.0 * (self.swaps[n - 1] - self.swaps[0]) / (n - 1) as f64)
    }

    pub fn lines(&self) -> Vec<ReportLine> {
        let line = |figure: &str, value: f64, unit: &str, thesis: Option<&str>, met| ReportLine {
            figure: figure.into(),
            value,
            unit: unit.into(),
            thesis: thesis.map(str::to_string),
            met,
        };
        let n = self.ticks.max(1) as f64;
        let mut out = vec![line(
            "strides (two steps each)",
            self.strides() as f64,
            "",
            Some("≥ 50 cycles (seed 001 L3027)"),
            Some(self.strides() >= 50),
        )];
        for (k, axis) in ["x", "y", "z"].iter().enumerate() {
            out.push(line(
                &format!("CoM error {axis} (estimate − reference), mean"),
                self.com_sum[k] / n,
                "m",
                None,
                None,
            ));
            out.push(line(
                &format!("CoM error {axis} (estimate − reference), peak"),
                self.com_peak[k],
                "m",
                Some("< 0.01 m (seed 001 L3031)"),
                Some(self.com_peak[k] < 0.01),
            ));
        }
        let foot = self.foot_peak.max();
        out.push(line(
            "feet error (estimate − reference), peak of any axis",
            foot,
            "m",
            Some("≤ 0.04 m, vertical at touchdown (seed 001 L3031–L3043)"),
            Some(foot <= 0.04),
        ));
        out.push(line(
            "contact-force error outside switching, peak",
            self.force_peak,
            "N",
            Some("< 20 N except at switching (seed 001 L3013)"),
            Some(self.force_peak < 20.0),
        ));
        out.push(line(
            "contact-force error outside switching, mean",
            self.force_sum / self.force_count.max(1) as f64,
            "N",
            None,
            None,
        ));
        out.push(line(
            "contact-force error outside switching, ticks ≥ 20 N",
            self.force_over as f64,
            "",
            None,
            None,
        ));
        out.push(line(
            "largest normal force on a released foot (touching before its state)",
            self.released_force,
            "N",
            None,
            None,
        ));
        out.push(line(
            "contact-force error at switching, peak",
            self.switch_force_peak,
            "N",
            Some("< half the robot's weight (seed 001 L2888–L2900, controller #1)"),
            None,
        ));
        if let Some(d) = self.stride_duration() {
            out.push(line(
                "stride duration",
                d,
                "s",
                Some("≈ 14 s (seed 001 L3132–L3136)"),
                None,
            ));
        }
        out
    }
}
