//! `[[push]]` of a scenario: a force (and torque) at a frame for a while, once or repeated
//! every `every` seconds until the run ends, its sign flipped at each repetition with
//! `alternate = true` (a soak test's "a push every 30 s, alternating directions").

use corps_sim::Push;
use serde::Deserialize;

/// Largest component of a push's force (N) or torque (N·m).
pub const MAX_PUSH: f64 = 1e9;

/// Pushes one scenario may expand to at most.
pub const MAX_PUSHES: usize = 100_000;

/// One `[[push]]` table.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct PushSpec {
    /// The force acts at this frame's origin, along world axes.
    pub frame: String,
    /// First start (s).
    pub start: f64,
    pub duration: f64,
    /// N.
    pub force: [f64; 3],
    /// N·m.
    #[serde(default)]
    pub torque: [f64; 3],
    /// Period of the repetition (s); absent: once.
    pub every: Option<f64>,
    /// Flip the force and torque at each repetition.
    #[serde(default)]
    pub alternate: bool,
    /// The force and torque are for a robot of this many kg: another robot gets them scaled
    /// by its mass over this one (the same change of momentum per kg). Absent: as written,
    /// whatever the robot.
    pub for_mass: Option<f64>,
}

impl PushSpec {
    /// Checks the values; the error names the key under `push[k]`.
    pub fn check(&self, k: usize) -> Result<(), String> {
        if !(self.start >= 0.0 && self.start.is_finite()) {
            return Err(format!(
                "push[{k}].start: must be a finite time ≥ 0 s, got {}",
                self.start
            ));
        }
        if !(self.duration >= 0.0 && self.duration.is_finite()) {
            return Err(format!(
                "push[{k}].duration: must be a finite time ≥ 0 s, got {}",
                self.duration
            ));
        }
        for (key, v) in [("force", self.force), ("torque", self.torque)] {
            if v.iter().any(|x| !x.is_finite()) {
                return Err(format!("push[{k}].{key}: must be finite"));
            }
            if v.iter().any(|x| x.abs() > MAX_PUSH) {
                return Err(format!(
                    "push[{k}].{key}: a component is over the limit of {MAX_PUSH:.0e} in magnitude"
                ));
            }
        }
        if let Some(every) = self.every {
            if !(every.is_finite() && every > self.duration) {
                return Err(format!(
                    "push[{k}].every: must be a finite period longer than the push's duration ({} s), got {every}",
                    self.duration
                ));
            }
        }
        if let Some(m) = self.for_mass {
            if !(m > 0.0 && m.is_finite()) {
                return Err(format!(
                    "push[{k}].for_mass: must be a finite mass > 0 kg, got {m}"
                ));
            }
        }
        if self.alternate && self.every.is_none() {
            return Err(format!("push[{k}].alternate: needs push[{k}].every"));
        }
        Ok(())
    }

    /// The pushes that start before `until` (s), the first at `start` + `offset`, for a robot
    /// of `mass` kg.
    fn expand(
        &self,
        offset: f64,
        until: f64,
        mass: Option<f64>,
        out: &mut Vec<Push>,
    ) -> Result<(), String> {
        let mut start = self.start;
        let scale = match (self.for_mass, mass) {
            (Some(written), Some(robot)) => robot / written,
            _ => 1.0,
        };
        let mut sign = scale;
        loop {
            if out.len() >= MAX_PUSHES {
                return Err(format!(
                    "push: more than {MAX_PUSHES} pushes in the run (a longer push.every?)"
                ));
            }
            out.push(Push {
                frame: self.frame.clone(),
                start: start + offset,
                duration: self.duration,
                force: self.force.map(|f| sign * f),
                torque: self.torque.map(|t| sign * t),
            });
            match self.every {
                Some(every) if start + every < until => start += every,
                _ => return Ok(()),
            }
            if self.alternate {
                sign = -sign;
            }
        }
    }
}

/// Every push of `specs` that starts within a run of `duration` seconds, the times shifted by
/// `offset` (a controller run counts them from the handover), for a robot of `mass` kg (None:
/// every force as written).
pub fn schedule(
    specs: &[PushSpec],
    offset: f64,
    duration: f64,
    mass: Option<f64>,
) -> Result<Vec<Push>, String> {
    let mut out = vec![];
    for spec in specs {
        spec.expand(offset, duration, mass, &mut out)?;
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spec(every: Option<f64>, alternate: bool) -> PushSpec {
        PushSpec {
            frame: "base_link".into(),
            start: 5.0,
            duration: 0.1,
            force: [100.0, 0.0, 0.0],
            torque: [0.0; 3],
            every,
            alternate,
            for_mass: None,
        }
    }

    #[test]
    fn a_repeated_push_alternates_until_the_run_ends() {
        let pushes = schedule(&[spec(Some(30.0), true)], 0.5, 3600.0, None).unwrap();
        assert_eq!(pushes.len(), 120);
        assert_eq!(pushes[1].start, 35.5);
        assert_eq!(pushes[1].force[0], -100.0);
        assert_eq!(pushes[2].force[0], 100.0);
        assert_eq!(pushes[119].start, 5.5 + 119.0 * 30.0);
        assert_eq!(
            schedule(&[spec(None, false)], 0.0, 10.0, None)
                .unwrap()
                .len(),
            1
        );
        let mut light = spec(None, false);
        light.for_mass = Some(90.0);
        let pushes = schedule(&[light], 0.0, 10.0, Some(30.0)).unwrap();
        assert!((pushes[0].force[0] - 100.0 / 3.0).abs() < 1e-12);
    }

    #[test]
    fn periods_that_would_flood_the_run_are_refused() {
        assert!(spec(Some(0.05), false)
            .check(0)
            .unwrap_err()
            .contains("every"));
        assert!(spec(None, true).check(0).unwrap_err().contains("alternate"));
        let mut fast = spec(Some(0.2), false);
        fast.start = 0.0;
        let e = schedule(&[fast], 0.0, 1e6, None).unwrap_err();
        assert!(e.contains("more than"), "{e}");
    }
}
