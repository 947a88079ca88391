//! Early touch-down: a swinging foot that meets the ground before its planned touch-down is
//! put in contact then, instead of being held on its swing trajectory until the plan says so.
//!
//! At the end of a swing the foot descends at a few mm/s with millimetre tracking errors; on
//! a near-rigid floor it can touch a few tens of milliseconds early. Still tracking the
//! swing reference (a little above it), the foot task then lifts it off again and the contact
//! added at the planned time lands it a second time, hard: on the tilted platforms a 1.3 kN
//! spike of a 90 kg robot (seed 000's walks switch contacts by the plan alone). Here the
//! sole's measured normal force switches the contact as soon as it exceeds a threshold in
//! the last part of the swing.

use super::motion::{MotionPlan, Targets};

/// Puts a landing foot in contact once its sole carries `force` newtons within the last
/// `window` seconds before the plan's touch-down.
pub struct TouchdownDetector {
    force: f64,
    window: f64,
    ahead: Targets,
    latched: [bool; 2],
}

impl TouchdownDetector {
    pub fn new(force: f64, window: f64, plan: &MotionPlan) -> Self {
        Self {
            force,
            window,
            ahead: plan.initial_targets(),
            latched: [false; 2],
        }
    }

    /// Overrides `targets` (the plan's at `t`) with the feet that have landed early, from
    /// the soles' measured normal forces.
    pub fn apply(&mut self, plan: &MotionPlan, t: f64, foot_fz: [f64; 2], targets: &mut Targets) {
        plan.sample(t + self.window, &mut self.ahead);
        for (k, foot) in targets.feet.iter_mut().enumerate() {
            if foot.in_contact || !self.ahead.feet[k].in_contact {
                self.latched[k] = false;
                continue;
            }
            self.latched[k] |= foot_fz[k] >= self.force;
            foot.in_contact |= self.latched[k];
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::run::motion::MotionSection;
    use corps_model::spatial::Se3;
    use nalgebra::{Matrix3, Vector3};

    fn plan() -> MotionPlan {
        let feet0 = [
            Se3::new(Matrix3::identity(), Vector3::new(0.0, 0.085, 0.0)),
            Se3::new(Matrix3::identity(), Vector3::new(0.0, -0.085, 0.0)),
        ];
        let section: MotionSection =
            toml::from_str("kind = \"walk\"\nsteps = 2\nstep_length = 0.2").unwrap();
        MotionPlan::new(
            section,
            Vector3::new(0.0, 0.0, 0.87),
            feet0,
            1e-3,
            8.0,
            std::path::Path::new("."),
            &corps_sim::Terrain::default(),
        )
        .unwrap()
    }

    /// The first foot to swing, the times it leaves and lands (plan's contact flags).
    fn first_swing(plan: &MotionPlan) -> (usize, f64, f64) {
        let mut targets = plan.initial_targets();
        let (mut foot, mut lift) = (None, 0.0);
        for k in 0..8000 {
            let t = k as f64 * 1e-3;
            plan.sample(t, &mut targets);
            match foot {
                None => {
                    if let Some(f) = targets.feet.iter().position(|f| !f.in_contact) {
                        (foot, lift) = (Some(f), t);
                    }
                }
                Some(f) if targets.feet[f].in_contact => return (f, lift, t),
                _ => {}
            }
        }
        panic!("no swing in the plan");
    }

    #[test]
    fn a_loaded_sole_lands_early_only_near_the_planned_touch_down() {
        let plan = plan();
        let (foot, lift, land) = first_swing(&plan);
        let mut d = TouchdownDetector::new(50.0, 0.1, &plan);
        let mut targets = plan.initial_targets();
        let mut fz = [0.0; 2];
        fz[foot] = 200.0;
        // Mid-swing, a loaded sole is not a landing (e.g. a foot still pushing off).
        let mid = 0.5 * (lift + land);
        plan.sample(mid, &mut targets);
        d.apply(&plan, mid, fz, &mut targets);
        assert!(!targets.feet[foot].in_contact);
        // 50 ms before the touch-down: a light touch is not enough, 200 N is.
        let early = land - 0.05;
        plan.sample(early, &mut targets);
        d.apply(&plan, early, [10.0; 2], &mut targets);
        assert!(!targets.feet[foot].in_contact);
        plan.sample(early, &mut targets);
        d.apply(&plan, early, fz, &mut targets);
        assert!(targets.feet[foot].in_contact);
        // Latched: a bounce (force gone) does not lift the foot off again.
        let later = land - 0.02;
        plan.sample(later, &mut targets);
        d.apply(&plan, later, [0.0; 2], &mut targets);
        assert!(targets.feet[foot].in_contact);
        // The plan catches up and the latch lets go.
        plan.sample(land, &mut targets);
        d.apply(&plan, land, [0.0; 2], &mut targets);
        assert!(targets.feet[foot].in_contact && !d.latched[foot]);
    }
}
