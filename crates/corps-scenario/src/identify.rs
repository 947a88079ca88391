//! The stiffness of a robot's passive joints from a one-leg static stance, as seed 000
//! App. 4 identifies TALOS' hip (L7462–L7482): the robot stands on one foot under a position
//! controller that compensates the flexibility (`[controller.flexibility] compensation =
//! "model"`) with a candidate stiffness k̂; the CoP the F/T sensors measure matches the CoM
//! of the controller's state when k̂ is the robot's, and passes it when k̂ is off (too low a
//! k̂ over-compensates: on TALOS' hips the CoP then goes outward of the stance foot). The
//! offsets scale with 1/k̂, so the search is a secant on u = 1/k̂ from u = 0 (no
//! compensation) on the sideways CoP − CoM, along the world y axis: the stance sole's
//! sideways axis for a robot that starts facing x, as the shipped scenarios do.

use crate::error::{bail, Result};
use crate::motion::MotionSection;
use crate::run::{RunOptions, ScenarioRun};
use crate::scenario::Scenario;
use std::path::Path;

/// When the search stops.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StiffnessSearch {
    /// The second probe's stiffness (the first has none), N·m/rad.
    pub first_guess: f64,
    /// |CoP − CoM| sideways below which the search has converged, m.
    pub tolerance: f64,
    /// Runs at most (the no-compensation run included).
    pub max_runs: usize,
}

impl Default for StiffnessSearch {
    /// A first guess of 1000 N·m/rad (the order of App. 4's first identification, 973),
    /// 0.05 mm, 8 runs.
    fn default() -> Self {
        Self {
            first_guess: 1000.0,
            tolerance: 5e-5,
            max_runs: 8,
        }
    }
}

/// One run of the search: the stiffness the controller assumed (None: no compensation) and
/// the hold's means (`[crate::metrics::HoldFigures]`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Probe {
    pub stiffness: Option<f64>,
    /// The stance sole's F/T moment about its x axis, N·m.
    pub moment: f64,
    /// The CoP (ZMP of the F/T sensors) minus the controller's CoM, world y, m: what the
    /// search drives to zero.
    pub cop_offset: f64,
}

/// The search's outcome.
#[derive(Clone, Debug, PartialEq)]
pub struct StiffnessEstimate {
    pub stiffness: f64,
    pub probes: Vec<Probe>,
    /// The last probe's |CoP − CoM| is within the tolerance.
    pub converged: bool,
}

/// Identifies one stiffness for the passive joints `joints` (a side's roll and pitch, say)
/// with the one-foot stance of `scenario` (relative paths from `base_dir`), which must be a
/// `one_foot` motion under `[controller.flexibility] compensation = "model"`.
pub fn identify_stiffness(
    scenario: &Scenario,
    base_dir: &Path,
    joints: &[String],
    search: &StiffnessSearch,
) -> Result<StiffnessEstimate> {
    let MotionSection::OneFoot { support, .. } = &scenario.motion else {
        bail!("identification: the scenario's motion must be a one_foot stance");
    };
    let Some(fx) = scenario
        .controller
        .as_ref()
        .and_then(|c| c.flexibility.as_ref())
    else {
        bail!("identification: the scenario needs a [controller.flexibility] section");
    };
    if fx.compensation != crate::controller::CompensationKind::Model {
        bail!("identification: [controller.flexibility] compensation must be \"model\"");
    }
    if joints.is_empty() {
        bail!("identification: name at least one passive joint");
    }
    if !(search.first_guess.is_finite() && search.first_guess > 0.0) {
        bail!(
            "identification: the first guess must be a stiffness > 0, got {}",
            search.first_guess
        );
    }
    if search.max_runs < 2 {
        bail!("identification: needs at least 2 runs");
    }
    let foot = support.index();
    if !(search.tolerance.is_finite() && search.tolerance > 0.0) {
        bail!(
            "identification: the tolerance must be > 0, got {}",
            search.tolerance
        );
    }
    let probe = |u: f64| -> Result<Probe> {
        let mut s = scenario.clone();
        let section = (s.controller.as_mut()).and_then(|c| c.flexibility.as_mut());
        let Some(section) = section else {
            bail!("identification: lost the flexibility section");
        };
        // u = 0: no compensation, which a stiffness far above any structure's gives.
        let k = if u > 0.0 { 1.0 / u } else { 1e12 };
        for j in joints {
            section.stiffness.insert(j.clone(), k);
        }
        let result =
            ScenarioRun::new(&s, "identification", base_dir, RunOptions::default())?.run(&mut [])?;
        let completed = result.metrics.verdict.verdict == corps_loop::verdict::Verdict::Completed;
        let Some(hold) = result.metrics.hold.filter(|_| completed) else {
            bail!(
                "identification: the stance did not hold with k = {} N·m/rad ({})",
                crate::numbers::number(k),
                result.metrics.verdict
            );
        };
        Ok(Probe {
            stiffness: (u > 0.0).then_some(k),
            moment: hold.ankle_torque_x_nm[foot],
            cop_offset: hold.zmp_minus_controller_com_m[1],
        })
    };
    let mut points = vec![
        (0.0, probe(0.0)?),
        (1.0 / search.first_guess, probe(1.0 / search.first_guess)?),
    ];
    while points.len() < search.max_runs {
        let (u1, p1) = points[points.len() - 1];
        if p1.cop_offset.abs() <= search.tolerance {
            break;
        }
        let (u0, p0) = points[points.len() - 2];
        let slope = (p1.cop_offset - p0.cop_offset) / (u1 - u0);
        if !(slope.is_finite() && slope != 0.0) {
            bail!("identification: the CoP does not move with the stiffness");
        }
        let u = u1 - p1.cop_offset / slope;
        if u.is_nan() || u <= 0.0 {
            bail!(
                "identification: the search left the positive stiffnesses (CoP − CoM {:.2} mm at 1/k = {u1:.3e})",
                p1.cop_offset * 1e3
            );
        }
        points.push((u, probe(u)?));
    }
    let (u, last) = points[points.len() - 1];
    Ok(StiffnessEstimate {
        stiffness: 1.0 / u,
        converged: last.cop_offset.abs() <= search.tolerance,
        probes: points.into_iter().map(|(_, p)| p).collect(),
    })
}
