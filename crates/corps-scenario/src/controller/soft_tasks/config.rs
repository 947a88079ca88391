//! The soft-tasks controller's file: weights (seed 001 Eq 2.44, Table B.3), PD gains
//! (Tables B.4–B.5), the contact-wrench limits (Table B.1), the joints a servo holds and the
//! state machine ([`super::fsm::FsmConfig`]).

use super::fsm::FsmConfig;
use super::report::ThesisFigures;
use crate::error::{bail, Result};
use crate::gains::{check_non_negative as non_negative, PostureGains};
use serde::Deserialize;

/// Task weights w = {w_CoM, w_stance, w_swing, w_neck, w_τ} of Eq 2.44 (w_s is the posture's
/// `posture.weight`).
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Weights {
    pub com: f64,
    pub stance: f64,
    pub swing: f64,
    pub neck: f64,
    pub torque: f64,
}

/// A Cartesian PD: Kp, and Kd (absent: 2√Kp, the thesis's rule in simulation).
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Pd {
    pub kp: f64,
    pub kd: Option<f64>,
}

impl Pd {
    pub fn kd(&self) -> f64 {
        self.kd.unwrap_or(2.0 * self.kp.sqrt())
    }
}

/// Feet tasks (stance and swing): linear and angular PD.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct FeetGains {
    pub linear: Pd,
    pub angular: Pd,
}

/// The orientation task of one frame under the SO(3) law: K0 = kp, K1 = kd (seed 001 §2.3).
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct OrientationGains {
    pub frame: String,
    pub kp: f64,
    pub kd: Option<f64>,
}

/// The contact wrench's limits (Eq 2.32–2.35); the centre-of-pressure box is the robot
/// description's sole.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct WrenchContactGains {
    pub fz_min: f64,
    pub fz_max: f64,
    pub mu: f64,
    pub mu_torsion: f64,
    pub vertices_per_quadrant: usize,
}

/// The posture's reference made consistent with the Cartesian tasks (seed 001 App. B.1,
/// [`corps_control::posture_consistency`]).
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct PostureConsistency {
    /// k_B of the base's reference acceleration −k_B v_B (1/s).
    pub base_gain: f64,
    /// The posture's weight in Eq B.3 against the Cartesian tasks' QP weights: small puts
    /// the posture PD in their null space, large lets it pull against them.
    pub weight: f64,
}

/// The posture's law near joint limits.
#[derive(Clone, Copy, Debug, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum Law {
    /// `s̈* = −K_p s̃ − K_d ṡ`.
    Classical,
    /// Seed 001's Eq 3.27 on `s = δ tanh ξ + s₀`.
    Reparametrised,
}

/// `[joint_limits]`: the posture's law, the clamp of ξ and limits replacing the model's.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct JointLimitsConfig {
    pub law: Law,
    /// ξ is clamped at ±xi_max (seed 001 whole-body: atanh(0.99), L4336–L4344).
    pub xi_max: f64,
    /// Joint → [lower, upper] in degrees, replacing the model's (seed 001 Table 3.1); their
    /// distance to the limits is reported.
    #[serde(default)]
    pub limits_deg: std::collections::BTreeMap<String, [f64; 2]>,
}

/// The whole file.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct SoftTasksConfig {
    /// Joint damping of the safe command used when the QP fails (N·m·s/rad).
    pub safe_damping: f64,
    /// Bound the torques by the URDF effort limits.
    #[serde(default)]
    pub actuation_bounds: bool,
    /// τ_max: a cap on every joint's torque below its effort limit (N·m; seed 001 Table A.3:
    /// 60), with `actuation_bounds`.
    pub torque_limit: Option<f64>,
    /// τ̇_max: the torque-rate bound |τ − τ₋₁| ≤ τ̇_max t_s of Eq 2.40d / 2.43c (N·m/s;
    /// Table A.3: 50). Absent: none (controller #2).
    pub torque_rate: Option<f64>,
    /// The strict-tasks controller (Eq 2.40): the Cartesian tasks (CoM, orientation, swing
    /// foot) and the feet in contact as equalities, the posture and torques in the cost.
    #[serde(default)]
    pub strict: bool,
    pub weights: Weights,
    pub com: Pd,
    pub feet: FeetGains,
    /// The orientation task (the neck in controller #2, the root in #1; `orientation` too).
    #[serde(alias = "orientation")]
    pub neck: OrientationGains,
    pub posture: PostureGains,
    /// Joint → degrees: the posture reference of these joints, replacing the handover's.
    #[serde(default)]
    pub posture_reference_deg: std::collections::BTreeMap<String, f64>,
    /// The posture's law near the joint limits (absent: classical, the model's limits).
    pub joint_limits: Option<JointLimitsConfig>,
    /// Absent: the posture task pulls towards the handover's posture with its own PD.
    pub posture_consistency: Option<PostureConsistency>,
    pub contacts: WrenchContactGains,
    /// How long after each contact change (s) the force error still counts as "at
    /// switching" (seed 001 L3013 does not say how wide).
    pub switching_window: f64,
    pub fsm: FsmConfig,
    /// The thesis's figures the run is judged by (absent: S2's).
    #[serde(default)]
    pub thesis: ThesisFigures,
}

impl SoftTasksConfig {
    /// The priority of the Cartesian tasks (CoM, orientation, swing foot): equalities in the
    /// strict-tasks controller (Eq 2.40c), costs otherwise.
    pub fn cartesian_priority(&self) -> usize {
        if self.strict {
            0
        } else {
            1
        }
    }

    /// Checks every number and the state machine.
    pub fn check(&self) -> Result<()> {
        let w = &self.weights;
        for (name, x) in [
            ("weights.com", w.com),
            ("weights.stance", w.stance),
            ("weights.swing", w.swing),
            ("weights.neck", w.neck),
            ("weights.torque", w.torque),
            ("com.kp", self.com.kp),
            ("com.kd", self.com.kd()),
            ("feet.linear.kp", self.feet.linear.kp),
            ("feet.linear.kd", self.feet.linear.kd()),
            ("feet.angular.kp", self.feet.angular.kp),
            ("feet.angular.kd", self.feet.angular.kd()),
            ("neck.kp", self.neck.kp),
            ("neck.kd", self.neck.kd.unwrap_or(0.0)),
            ("posture.kp", self.posture.kp),
            ("posture.weight", self.posture.weight),
            ("safe_damping", self.safe_damping),
            ("switching_window", self.switching_window),
            ("torque_limit", self.torque_limit.unwrap_or(0.0)),
        ] {
            non_negative(name, x)?;
        }
        if let Some(r) = self.torque_rate {
            if !(r > 0.0 && r.is_finite()) {
                bail!("torque_rate = {r}: must be positive and finite (N·m/s)");
            }
        }
        let c = &self.contacts;
        non_negative("contacts.fz_min", c.fz_min)?;
        if c.fz_max.is_nan() || c.fz_max < c.fz_min {
            bail!(
                "contacts.fz_max = {}: must be at least fz_min = {}",
                c.fz_max,
                c.fz_min
            );
        }
        if let Some(p) = &self.posture_consistency {
            non_negative("posture_consistency.base_gain", p.base_gain)?;
            if !(p.weight > 0.0 && p.weight.is_finite()) {
                bail!(
                    "posture_consistency.weight = {}: must be positive (w_s of Eq B.3)",
                    p.weight
                );
            }
        }
        self.fsm.check()
    }
}
