//! The posture's reference acceleration per joint, by the classical PD
//! `s̈* = −K_p (s − s_d) − K_d ṡ` or by seed 001's re-parametrised law (Eq 3.27)
//! `s̈* = −J⁻¹K_p ξ̃ − J⁻¹K_d J⁻¹ ṡ` that keeps each joint inside its limits
//! ([`corps_control::joint_limits`]) on the joints whose limits the file gives (seed 001
//! applies it to all 23 with its Table 3.1 limits), and the run's smallest distance to a
//! limit. The reference moves between set-points by minimum-jerk quintics ([`Smoothed`]),
//! whose velocity and acceleration feed both laws.

use super::config::{JointLimitsConfig, Law};
use super::smoothing::Smoothed;
use crate::error::{bail, Result};
use corps_control::joint_limits::{postural_acceleration, TanhJointMap};
use corps_control::RobotState;
use corps_model::{JointKind, Model};
use nalgebra::DVector;

pub struct PostureLaw {
    /// (configuration index, velocity index − first) of each actuated one-dof joint.
    joints: Vec<(usize, usize)>,
    names: Vec<String>,
    lower: Vec<f64>,
    upper: Vec<f64>,
    map: TanhJointMap,
    law: Law,
    kp: DVector<f64>,
    kd: DVector<f64>,
    /// The initial set-point (the handover's posture with the file's overrides), per joint
    /// of `joints`.
    initial: Vec<f64>,
    /// The reference per joint, and its position, velocity and acceleration at the last
    /// [`PostureLaw::sample`].
    reference: Vec<Smoothed<f64>>,
    sampled: Vec<[f64; 3]>,
    /// Per joint, whether the file gives its limits: the re-parametrised law acts on those
    /// (the others keep the classical PD) and their margin is watched (else every joint's).
    given: Vec<bool>,
}

impl PostureLaw {
    /// The law for the actuated joints of `model` (all one-dof), gains per actuated dof,
    /// the reference posture `q_ref` with `overrides_deg` (joint → degrees) and the limits of
    /// the model with `limits`' replacements. The re-parametrised law refuses a reference on
    /// or outside a joint's limits (seed 001 §2.9, Assumption 2).
    pub fn new(
        model: &Model,
        kp: DVector<f64>,
        kd: DVector<f64>,
        q_ref: &DVector<f64>,
        overrides_deg: &std::collections::BTreeMap<String, f64>,
        limits: Option<&JointLimitsConfig>,
    ) -> Result<Self> {
        let first = model.first_actuated();
        let (mut joints, mut names, mut lower, mut upper, mut reference, mut given) =
            (vec![], vec![], vec![], vec![], vec![], vec![]);
        for j in model
            .joints
            .iter()
            .filter(|j| j.kind != JointKind::FreeFlyer)
        {
            if j.nq() != 1 || j.nv() != 1 {
                bail!("posture: joint '{}' has more than one dof", j.name);
            }
            joints.push((j.idx_q, j.idx_v - first));
            names.push(j.name.clone());
            let (mut lo, mut hi) = (
                model.lower_position_limit[j.idx_q],
                model.upper_position_limit[j.idx_q],
            );
            let listed = limits.and_then(|l| l.limits_deg.get(&j.name));
            given.push(listed.is_some());
            if let Some([a, b]) = listed {
                if !(a.is_finite() && b.is_finite() && b > a) {
                    bail!(
                        "joint_limits.limits_deg.{}: [{a}, {b}] is not an interval",
                        j.name
                    );
                }
                (lo, hi) = (a.to_radians(), b.to_radians());
            }
            lower.push(lo);
            upper.push(hi);
            reference.push(q_ref[j.idx_q]);
        }
        for name in limits.iter().flat_map(|l| l.limits_deg.keys()) {
            if !names.contains(name) {
                bail!("posture: no actuated joint named '{name}'");
            }
        }
        let law = limits.map_or(Law::Classical, |l| l.law);
        let xi_max = limits.map_or(1.0, |l| l.xi_max);
        // A joint without finite limits cannot be re-parametrised: it keeps a wide box.
        let (lo, hi): (Vec<f64>, Vec<f64>) = (lower.iter().zip(&upper))
            .map(|(l, u)| {
                if l.is_finite() && u.is_finite() && u > l {
                    (*l, *u)
                } else {
                    (-1e3, 1e3)
                }
            })
            .unzip();
        let map = TanhJointMap::new(&lo, &hi, xi_max)?;
        let mut out = Self {
            given,
            joints,
            names,
            lower: lo,
            upper: hi,
            map,
            law,
            kp,
            kd,
            reference: Vec::new(),
            sampled: Vec::new(),
            initial: reference,
        };
        // The handover's posture with the overrides, checked, is the initial set-point.
        out.initial = out.set_point(overrides_deg)?;
        out.reference = out.initial.iter().map(|r| Smoothed::at(*r)).collect();
        out.sampled = out.initial.iter().map(|r| [*r, 0.0, 0.0]).collect();
        Ok(out)
    }

    /// The re-parametrised law needs every reference strictly inside the limits it acts on.
    pub fn check_inside(&self, set_point: &[f64]) -> Result<()> {
        if self.law != Law::Reparametrised {
            return Ok(());
        }
        for (i, r) in set_point.iter().enumerate() {
            if self.given[i] && self.map.xi_of_reference(i, *r).is_err() {
                bail!(
                    "posture: the reference of '{}' ({:.2}°) is not inside its limits [{:.2}°, {:.2}°], which the re-parametrised law needs",
                    self.names[i],
                    r.to_degrees(),
                    self.lower[i].to_degrees(),
                    self.upper[i].to_degrees()
                );
            }
        }
        Ok(())
    }

    /// The initial set-point with `overrides_deg` (joint → degrees), per joint, checked (at
    /// construction, the handover's posture with them).
    pub fn set_point(
        &self,
        overrides_deg: &std::collections::BTreeMap<String, f64>,
    ) -> Result<Vec<f64>> {
        let mut out = self.initial.clone();
        for (name, deg) in overrides_deg {
            let Some(i) = self.index_of(name) else {
                bail!("posture: no actuated joint named '{name}'");
            };
            out[i] = deg.to_radians();
        }
        self.check_inside(&out)?;
        Ok(out)
    }

    /// Joint `i`'s index in the configuration.
    pub fn q_index(&self, i: usize) -> usize {
        self.joints[i].0
    }

    /// The law's index of the joint named `name`.
    pub fn index_of(&self, name: &str) -> Option<usize> {
        self.names.iter().position(|n| n == name)
    }

    /// Joint `i`'s distance to `set_point` at configuration `q` (rad).
    pub fn error(&self, q: &[f64], i: usize, set_point: f64) -> f64 {
        (q[self.joints[i].0] - set_point).abs()
    }

    /// Every joint's reference heads to `set_point` from `t` over `duration`.
    pub fn go_to(&mut self, t: f64, set_point: &[f64], duration: f64) {
        for (r, x) in self.reference.iter_mut().zip(set_point) {
            r.go_to(t, *x, duration);
        }
    }

    /// Samples the references at `t` (their position, velocity and acceleration).
    pub fn sample(&mut self, t: f64) {
        for (out, r) in self.sampled.iter_mut().zip(&self.reference) {
            *out = r.sample(t);
        }
    }

    /// Kp per actuated dof and Kd = 2√Kp.
    pub fn set_gains(&mut self, kp: &DVector<f64>) {
        self.kp.copy_from(kp);
        for (d, p) in self.kd.iter_mut().zip(kp.iter()) {
            *d = 2.0 * p.sqrt();
        }
    }

    /// The reference accelerations of the actuated dofs into `out` (na).
    pub fn accelerations(&self, s: &RobotState, out: &mut DVector<f64>) -> Result<()> {
        for (i, &(iq, ia)) in self.joints.iter().enumerate() {
            let (q, v) = (s.q[iq], s.v[ia + (s.v.len() - out.len())]);
            let (kp, kd, [r, r_dot, r_ddot]) = (self.kp[ia], self.kd[ia], self.sampled[i]);
            out[ia] = match self.law {
                Law::Reparametrised if self.given[i] => {
                    postural_acceleration(&self.map, i, q, v, (r, r_dot, r_ddot), kp, kd)?
                }
                _ => r_ddot - kp * (q - r) - kd * (v - r_dot),
            };
        }
        Ok(())
    }

    /// The smallest distance of a watched joint (those whose limits the file gives, else
    /// every one) to one of its limits at `q` (rad; negative past it) and that joint's index.
    pub fn margin(&self, q: &DVector<f64>) -> (f64, usize) {
        let mut best = (f64::INFINITY, 0);
        let all = !self.given.contains(&true);
        for i in (0..self.joints.len()).filter(|&i| all || self.given[i]) {
            let iq = self.joints[i].0;
            let m = (q[iq] - self.lower[i]).min(self.upper[i] - q[iq]);
            if m < best.0 {
                best = (m, i);
            }
        }
        best
    }

    pub fn name(&self, i: usize) -> &str {
        &self.names[i]
    }

    pub fn law(&self) -> Law {
        self.law
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::BTreeMap;

    /// iCub at half-sitting with the right elbow at `elbow` (rad) moving at `rate`.
    fn state(model: &Model, q0: &DVector<f64>, elbow: f64, rate: f64) -> RobotState {
        let j = &model.joints[model.joint_id("r_elbow").unwrap()];
        let mut q = q0.clone();
        q[j.idx_q] = elbow;
        let mut v = DVector::zeros(model.nv);
        v[j.idx_v] = rate;
        let mut s = RobotState::new(model);
        s.update(model, q.as_slice(), v.as_slice()).unwrap();
        s
    }

    fn law(model: &Model, q0: &DVector<f64>, which: Law) -> Result<PostureLaw> {
        let na = model.na();
        let limits = JointLimitsConfig {
            law: which,
            xi_max: 0.99_f64.atanh(),
            limits_deg: BTreeMap::from([("r_elbow".to_string(), [15.0, 106.0])]),
        };
        let reference = BTreeMap::from([("r_elbow".to_string(), 22.5)]);
        let (kp, kd) = (
            DVector::repeat(na, 8.0),
            DVector::repeat(na, 2.0 * 8f64.sqrt()),
        );
        PostureLaw::new(model, kp, kd, q0, &reference, Some(&limits))
    }

    /// Near its limit and moving towards it, the elbow is pulled back far harder by Eq 3.27
    /// than by the classical PD; just off its reference both pull back towards it; a
    /// reference outside the limits is refused by the re-parametrised law.
    #[test]
    fn near_a_limit_the_reparametrised_law_pulls_back_harder() {
        let robot = corps_robot::Robot::built_in("icub").unwrap().unwrap();
        let (model, q0) = (&robot.model, &robot.posture);
        let elbow = model.joints[model.joint_id("r_elbow").unwrap()].idx_v - 6;
        let classical = law(model, q0, Law::Classical).unwrap();
        let reparametrised = law(model, q0, Law::Reparametrised).unwrap();
        let mut a = DVector::zeros(model.na());
        let mut b = DVector::zeros(model.na());
        let near = state(model, q0, 16f64.to_radians(), -0.5);
        classical.accelerations(&near, &mut a).unwrap();
        reparametrised.accelerations(&near, &mut b).unwrap();
        println!(
            "at 16° moving at −0.5 rad/s: classical {:.2}, re-parametrised {:.2} rad/s²",
            a[elbow], b[elbow]
        );
        assert!(a[elbow] > 0.0 && b[elbow] > 5.0 * a[elbow] && b[elbow].is_finite());
        let (m, j) = reparametrised.margin(&near.q);
        assert_eq!(reparametrised.name(j), "r_elbow");
        assert!((m - 1f64.to_radians()).abs() < 1e-12);
        // Just off the reference, at rest: both pull back towards it.
        let close = state(model, q0, 22.5f64.to_radians() + 1e-5, 0.0);
        classical.accelerations(&close, &mut a).unwrap();
        reparametrised.accelerations(&close, &mut b).unwrap();
        assert!(a[elbow] < 0.0 && b[elbow] < 0.0);
        // The reference outside the limits.
        let mut bad = BTreeMap::new();
        bad.insert("r_elbow".to_string(), 10.0);
        let limits = JointLimitsConfig {
            law: Law::Reparametrised,
            xi_max: 2.6,
            limits_deg: BTreeMap::from([("r_elbow".to_string(), [15.0, 106.0])]),
        };
        let na = model.na();
        let err = PostureLaw::new(
            model,
            DVector::zeros(na),
            DVector::zeros(na),
            q0,
            &bad,
            Some(&limits),
        );
        assert!(err
            .err()
            .unwrap()
            .to_string()
            .contains("not inside its limits"));
    }
}
