//! The verdict of a run: `completed`, or the first failure seen — `fell` (a body other than
//! the allowed contacts carries the robot, or the CoM drops below a fraction of its initial
//! height above the support), `diverged` (a non-finite state, a contact force above a
//! multiple of the body weight, a base faster than a limit) or `controller_failed` (the safe
//! command held longer than a limit), or a task's own failure (`lost_human`: a followed
//! person out of reach). A divergence ends the run at once, and so does a lost person; the
//! others are recorded and the run goes on, so the log shows what followed.

use serde::{Deserialize, Serialize};
use std::fmt;

/// How a run ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Verdict {
    Completed,
    Fell,
    Diverged,
    ControllerFailed,
    /// The robot got too far from the point it holds by a person (co-navigation).
    LostHuman,
}

impl Verdict {
    /// The name used in scenario files and metrics (`controller_failed`).
    pub fn name(self) -> &'static str {
        match self {
            Verdict::Completed => "completed",
            Verdict::Fell => "fell",
            Verdict::Diverged => "diverged",
            Verdict::ControllerFailed => "controller_failed",
            Verdict::LostHuman => "lost_human",
        }
    }
}

impl fmt::Display for Verdict {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

pub use corps_robot::{Criteria, CriteriaError};

/// What one tick shows the observer.
#[derive(Clone, Copy, Debug)]
pub struct TickSample {
    pub t: f64,
    /// CoM height above the support (the lowest sole), m.
    pub com_height: f64,
    /// Speed of the base (m/s).
    pub base_speed: f64,
    /// Norm of the total contact force (N).
    pub total_contact_force: f64,
    /// Contact force on bodies other than the allowed contacts (N).
    pub other_contact_force: f64,
    /// Every state value finite.
    pub state_finite: bool,
    /// The controller fell back to its safe command this tick.
    pub safe_command: bool,
}

/// The verdict with when and why.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct VerdictReport {
    pub verdict: Verdict,
    /// When the failure was first seen (s); none when completed.
    pub t: Option<f64>,
    /// What was seen, with the numbers.
    pub reason: Option<String>,
}

impl Default for VerdictReport {
    /// Completed.
    fn default() -> Self {
        Self {
            verdict: Verdict::Completed,
            t: None,
            reason: None,
        }
    }
}

impl fmt::Display for VerdictReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.verdict)?;
        if let (Some(t), Some(r)) = (self.t, &self.reason) {
            write!(f, " at t = {t:.3} s: {r}")?;
        }
        Ok(())
    }
}

/// Watches a run.
#[derive(Clone, Debug)]
pub struct VerdictObserver {
    criteria: Criteria,
    weight: f64,
    initial_com_height: f64,
    first: Option<VerdictReport>,
    safe_since: Option<f64>,
}

impl VerdictObserver {
    /// For a robot of `weight` (N) whose CoM starts `initial_com_height` (m) above its support.
    pub fn new(
        criteria: Criteria,
        weight: f64,
        initial_com_height: f64,
    ) -> Result<Self, CriteriaError> {
        criteria.check()?;
        for (key, value) in [
            ("weight", weight),
            ("initial_com_height", initial_com_height),
        ] {
            if !(value > 0.0 && value.is_finite()) {
                return Err(CriteriaError::OutOfRange {
                    key,
                    what: "a finite number > 0",
                    value,
                });
            }
        }
        Ok(Self {
            criteria,
            weight,
            initial_com_height,
            first: None,
            safe_since: None,
        })
    }

    /// Looks at one tick; returns `Some(Verdict::Diverged)` when the run must stop now.
    pub fn observe(&mut self, s: &TickSample) -> Option<Verdict> {
        let c = self.criteria;
        let diverged = if !s.state_finite || !s.base_speed.is_finite() {
            Some("non-finite state".to_string())
        } else if s.total_contact_force > c.max_contact_force_weights * self.weight {
            Some(format!(
                "contact force {:.0} N, over {} body weights",
                s.total_contact_force, c.max_contact_force_weights
            ))
        } else if s.base_speed > c.max_base_speed {
            Some(format!(
                "base speed {:.1} m/s, over {} m/s",
                s.base_speed, c.max_base_speed
            ))
        } else {
            None
        };
        if let Some(reason) = diverged {
            // A divergence outranks a failure seen before it: the state is meaningless now.
            self.diverged(s.t, reason);
            return Some(Verdict::Diverged);
        }
        if self.first.is_some() {
            return None;
        }
        if s.com_height < c.min_com_height_fraction * self.initial_com_height {
            self.record(
                Verdict::Fell,
                s.t,
                format!(
                    "CoM {:.3} m above the support, below {} of its initial {:.3} m",
                    s.com_height, c.min_com_height_fraction, self.initial_com_height
                ),
            );
        } else if s.other_contact_force > c.other_contact_weight_fraction * self.weight {
            self.record(
                Verdict::Fell,
                s.t,
                format!(
                    "{:.0} N of contact on bodies other than the feet ({:.0}% of the weight)",
                    s.other_contact_force,
                    100.0 * s.other_contact_force / self.weight
                ),
            );
        }
        if s.safe_command {
            let since = *self.safe_since.get_or_insert(s.t);
            if s.t - since >= c.max_safe_command_time && self.first.is_none() {
                self.record(
                    Verdict::ControllerFailed,
                    since,
                    format!(
                        "the safe command held {:.3} s from t = {since:.3} s",
                        s.t - since
                    ),
                );
            }
        } else {
            self.safe_since = None;
        }
        None
    }

    /// A task failure seen by the run itself at `t` (a followed person lost, say), unless a
    /// failure came first.
    pub fn task_failed(&mut self, verdict: Verdict, t: f64, reason: String) {
        if self.first.is_none() {
            self.record(verdict, t, reason);
        }
    }

    /// A divergence seen elsewhere (the plant's own check) at `t`.
    pub fn diverged(&mut self, t: f64, reason: String) {
        if self
            .first
            .as_ref()
            .is_none_or(|f| f.verdict != Verdict::Diverged)
        {
            self.record(Verdict::Diverged, t, reason);
        }
    }

    fn record(&mut self, verdict: Verdict, t: f64, reason: String) {
        self.first = Some(VerdictReport {
            verdict,
            t: Some(t),
            reason: Some(reason),
        });
    }

    /// The first failure seen so far, if any.
    pub fn failure(&self) -> Option<&VerdictReport> {
        self.first.as_ref()
    }

    /// The verdict of a run that ended at `t_end` (s).
    pub fn finish(self, _t_end: f64) -> VerdictReport {
        self.first.unwrap_or_default()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn standing(t: f64) -> TickSample {
        TickSample {
            t,
            com_height: 0.88,
            base_speed: 0.01,
            total_contact_force: 900.0,
            other_contact_force: 0.0,
            state_finite: true,
            safe_command: false,
        }
    }

    fn observer() -> VerdictObserver {
        VerdictObserver::new(Criteria::default(), 900.0, 0.88).unwrap()
    }

    #[test]
    fn a_quiet_stand_completes() {
        let mut o = observer();
        for k in 0..1000 {
            assert!(o.observe(&standing(k as f64 * 1e-3)).is_none());
        }
        assert_eq!(o.finish(1.0).verdict, Verdict::Completed);
    }

    #[test]
    fn a_low_com_or_a_knee_on_the_ground_is_a_fall_at_its_first_tick() {
        let mut o = observer();
        o.observe(&standing(0.0));
        o.observe(&TickSample {
            com_height: 0.3,
            ..standing(0.5)
        });
        o.observe(&TickSample {
            other_contact_force: 500.0,
            ..standing(0.6)
        });
        let r = o.finish(1.0);
        assert_eq!((r.verdict, r.t), (Verdict::Fell, Some(0.5)));
        let mut o = observer();
        o.observe(&TickSample {
            other_contact_force: 200.0,
            ..standing(0.2)
        });
        let r = o.finish(1.0);
        assert_eq!(r.verdict, Verdict::Fell);
        assert!(r.reason.unwrap().contains("other than the feet"));
    }

    #[test]
    fn an_exploding_state_stops_the_run_and_outranks_a_fall() {
        let mut o = observer();
        o.observe(&TickSample {
            com_height: 0.1,
            ..standing(0.1)
        });
        let stop = o.observe(&TickSample {
            total_contact_force: 4.1e6,
            ..standing(0.2)
        });
        assert_eq!(stop, Some(Verdict::Diverged));
        let r = o.finish(0.2);
        assert_eq!((r.verdict, r.t), (Verdict::Diverged, Some(0.2)));
        for bad in [
            TickSample {
                base_speed: 12.0,
                ..standing(0.0)
            },
            TickSample {
                state_finite: false,
                ..standing(0.0)
            },
            TickSample {
                base_speed: f64::NAN,
                ..standing(0.0)
            },
        ] {
            assert_eq!(observer().observe(&bad), Some(Verdict::Diverged));
        }
    }

    #[test]
    fn the_safe_command_fails_the_controller_only_when_held() {
        let mut o = observer();
        for k in 0..50 {
            let t = k as f64 * 1e-3;
            o.observe(&TickSample {
                safe_command: k % 10 != 0,
                ..standing(t)
            });
        }
        assert_eq!(o.failure(), None, "brief fallbacks are not a failure");
        o.observe(&standing(0.5));
        for k in 0..=100 {
            o.observe(&TickSample {
                safe_command: true,
                ..standing(1.0 + k as f64 * 1e-3)
            });
        }
        let r = o.finish(2.0);
        assert_eq!((r.verdict, r.t), (Verdict::ControllerFailed, Some(1.0)));
    }

    #[test]
    fn criteria_out_of_range_name_their_key() {
        let bad = Criteria {
            max_base_speed: -1.0,
            ..Criteria::default()
        };
        let e = VerdictObserver::new(bad, 900.0, 0.88)
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("max_base_speed"), "{e}");
        let e = VerdictObserver::new(Criteria::default(), 900.0, f64::NAN)
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("initial_com_height"), "{e}");
    }
}
