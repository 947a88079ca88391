//! The stepping figures seed 001 gives for its controllers (S1 for #1, L2763–L2900; S2 for #2,
//! L2960–L3136), accumulated over the run as the controller sees it (its estimate against
//! its references): strides, CoM and feet errors, the distance between measured and
//! QP-desired contact forces (of the feet in contact, outside the switching windows), a
//! released foot's early touch, and the stride's duration. The thesis's figures to set
//! beside them come from the controller's file (`[thesis]`, [`ThesisFigures`]).

use crate::metrics::ReportLine;
use nalgebra::Vector3;
use serde::Deserialize;

/// One figure of the thesis and where it is.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Figure {
    pub value: f64,
    pub source: String,
}

fn figure(value: f64, source: &str) -> Figure {
    Figure {
        value,
        source: source.into(),
    }
}

/// `[thesis]`: the bounds a stepping run is judged by; default S2's (controller #2, FSM #2).
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct ThesisFigures {
    /// Strides (two steps each) without a fall, at least.
    pub strides: Figure,
    /// CoM error per axis, below (m).
    pub com_error: Figure,
    /// Feet error, at most (m).
    pub foot_error: Figure,
    /// Contact-force error outside switching, below (N).
    pub force_error: Figure,
    /// Stride duration, about (s).
    pub stride: Figure,
}

impl Default for ThesisFigures {
    fn default() -> Self {
        Self {
            strides: figure(50.0, "seed 001 L3027"),
            com_error: figure(0.01, "seed 001 L3031"),
            foot_error: figure(0.04, "seed 001 L3031–L3043, vertical at touchdown"),
            force_error: figure(20.0, "seed 001 L3013"),
            stride: figure(14.0, "seed 001 L3132–L3136"),
        }
    }
}

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
    /// Force-error ticks at or above the thesis's bound outside switching.
    force_over: usize,
    switch_force_peak: f64,
    /// Times of the feet swaps.
    swaps: Vec<f64>,
    /// The smallest distance to a joint limit (rad) and its joint.
    margin: Option<(f64, usize)>,
    /// The largest normal force measured on a foot the controller has released (N).
    released_force: f64,
    thesis: ThesisFigures,
}

impl SteppingStats {
    pub fn new(thesis: ThesisFigures) -> Self {
        Self {
            swaps: Vec::with_capacity(1024),
            thesis,
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
                self.force_over += usize::from(e >= self.thesis.force_error.value);
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
        let th = &self.thesis;
        let strides = self.strides() as f64;
        let mut out = vec![line(
            "strides (two steps each)",
            strides,
            "",
            Some(format!("≥ {} cycles ({})", th.strides.value, th.strides.source).as_str()),
            Some(strides >= th.strides.value),
        )];
        let com = &th.com_error;
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
                Some(format!("< {} m ({})", com.value, com.source).as_str()),
                Some(self.com_peak[k] < com.value),
            ));
        }
        let foot = self.foot_peak.max();
        out.push(line(
            "feet error (estimate − reference), peak of any axis",
            foot,
            "m",
            Some(format!("≤ {} m ({})", th.foot_error.value, th.foot_error.source).as_str()),
            Some(foot <= th.foot_error.value),
        ));
        let force = &th.force_error;
        out.push(line(
            "contact-force error outside switching, peak",
            self.force_peak,
            "N",
            Some(format!("< {} N except at switching ({})", force.value, force.source).as_str()),
            Some(self.force_peak < force.value),
        ));
        out.push(line(
            "contact-force error outside switching, mean",
            self.force_sum / self.force_count.max(1) as f64,
            "N",
            None,
            None,
        ));
        out.push(line(
            &format!(
                "contact-force error outside switching, ticks ≥ {} N",
                force.value
            ),
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
                Some(format!("≈ {} s ({})", th.stride.value, th.stride.source).as_str()),
                None,
            ));
        }
        out
    }
}
