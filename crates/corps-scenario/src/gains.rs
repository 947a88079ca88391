//! Controller gains and weights, read from TOML files (`config/talos/*.toml`, embedded as the
//! defaults so the command works from any directory). Unknown keys are errors; every value is
//! checked before a run starts.

use crate::error::{bail, invalid, Context, Result};
use corps_model::Model;
use corps_robot::GainsText;
use nalgebra::DVector;
use serde::Deserialize;
use std::collections::BTreeMap;
use std::path::Path;

/// Where a controller's gains come from.
pub enum GainsSource {
    /// A gains file of the robot's description (by name), or a text already read.
    Text(GainsText),
    File(std::path::PathBuf),
}

impl GainsSource {
    /// `[controller] gains`: a name of the robot description's `[gains]` (no extension, no
    /// directory) or a path relative to the scenario's directory; None: the robot's gains for
    /// the controller `kind`.
    pub fn resolve(
        name: Option<&Path>,
        kind: &str,
        robot: &corps_robot::Robot,
        base_dir: &Path,
    ) -> Result<GainsSource> {
        let text = match name {
            None => kind.to_string(),
            Some(name) if name.extension().is_none() && name.components().count() == 1 => {
                name.to_string_lossy().into_owned()
            }
            Some(path) => return Ok(GainsSource::File(base_dir.join(path))),
        };
        let g = robot.gains(&text).map_err(|e| invalid!("{e}"))?;
        Ok(GainsSource::Text(g.clone()))
    }
}

/// A PD-controlled task in the cost: `Kp`, `Kd` (absent: 2√Kp, critical damping) and weight.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct TaskGains {
    pub kp: f64,
    pub kd: Option<f64>,
    pub weight: f64,
}

impl TaskGains {
    pub fn kd(&self) -> f64 {
        self.kd.unwrap_or(2.0 * self.kp.sqrt())
    }
}

/// The posture task: one Kp for every joint, replaced per joint group by `groups`
/// (joint-name prefix → one Kp per joint of that prefix, in model order).
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct PostureGains {
    pub kp: f64,
    #[serde(default)]
    pub groups: BTreeMap<String, Vec<f64>>,
    pub weight: f64,
}

/// The angular-momentum task (P on the momentum, reference 0).
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct MomentumGains {
    pub kp: f64,
    pub weight: f64,
}

/// Foot contacts: motion-constraint PD, friction, normal-force bounds, force regularization
/// weight and the duration of the force ramp when a contact is added or removed.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct ContactGains {
    pub kp: f64,
    pub kd: Option<f64>,
    pub mu: f64,
    pub fmin: f64,
    pub fmax: f64,
    pub force_regularization: f64,
    pub transition: f64,
    /// Contacts without friction pyramids: only the total normal force stays bounded
    /// ([`corps_control::contacts::Contact::bilateral`]). Position mode only (its contact
    /// forces are never applied); a torque-mode controller refuses it. Default false.
    #[serde(default)]
    pub bilateral: bool,
}

/// The balance stabilizer of the position-mode controllers (seed 000 Eq 2.30–2.31, gains of
/// Table 4.3): DCM PI gains, CoM admittance gain, ankle admittance gain (0: off).
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct StabilizerGains {
    pub dcm_kp: f64,
    pub dcm_ki: f64,
    pub dcm_kz: f64,
    pub com_admittance: f64,
    #[serde(default)]
    pub ankle_gain: f64,
    /// Damping of the whole-body sway through the CoM reference (s); absent: the
    /// stabilizer's default (`corps_control::stabilizer::StabilizerSettings::sway_damping`).
    pub sway_damping: Option<f64>,
    /// The stabilizer's sole half-length and half-width (m), where the document it follows
    /// uses another rectangle than the robot description's feet; absent: the description's
    /// (its largest centred rectangle).
    pub sole_half_length: Option<f64>,
    pub sole_half_width: Option<f64>,
}

impl StabilizerGains {
    pub fn check(&self) -> Result<()> {
        for (name, x) in [
            ("stabilizer.dcm_kp", self.dcm_kp),
            ("stabilizer.dcm_ki", self.dcm_ki),
            ("stabilizer.dcm_kz", self.dcm_kz),
            ("stabilizer.com_admittance", self.com_admittance),
            ("stabilizer.ankle_gain", self.ankle_gain),
            ("stabilizer.sway_damping", self.sway_damping.unwrap_or(0.0)),
            (
                "stabilizer.sole_half_length",
                self.sole_half_length.unwrap_or(0.0),
            ),
            (
                "stabilizer.sole_half_width",
                self.sole_half_width.unwrap_or(0.0),
            ),
        ] {
            check_non_negative(name, x)?;
        }
        Ok(())
    }
}

/// The inverse-dynamics controllers (torque and position mode).
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct TsidGains {
    pub com: TaskGains,
    pub posture: PostureGains,
    pub angular_momentum: MomentumGains,
    /// Waist (base) orientation task; absent: none.
    pub waist: Option<TaskGains>,
    pub contacts: ContactGains,
    /// Swing-foot motion task.
    pub feet: TaskGains,
    /// Joint torque limits of the URDF as hard constraints.
    pub actuation_bounds: bool,
    /// Joint damping of the safe command (N·m·s/rad).
    pub safe_damping: f64,
    /// The balance stabilizer in front of a position-mode controller; absent: none.
    pub stabilizer: Option<StabilizerGains>,
    /// The global energy tank of the passive controller (`passive_torque`); absent: none.
    pub tank: Option<TankGains>,
    /// The force task of a hand's contact (a scenario's `[press]`); absent: none.
    pub force_contact: Option<ForceContactGains>,
}

/// `[force_contact]`: the PI+ force task on a hand's contact (seed 000 Table 5.2: Kp 10 on
/// every component, K_I = 0.5 K_P, no K_D; Table 5.1: weight 10), and the integral's leak
/// (seed 000 §3.9: 0.05 1/s).
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct ForceContactGains {
    pub kp: f64,
    pub ki: f64,
    #[serde(default)]
    pub kd: f64,
    pub weight: f64,
    #[serde(default = "leak")]
    pub leak: f64,
}

fn leak() -> f64 {
    0.05
}

/// `[tank]`: the passive controller's energy tank (seed 000 L6396–L6401: E_max 5 J, E_min
/// 0.1 J, P_low −0.5 W; the tank starts at 3 J in the force scenario, 5 J in the walk).
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct TankGains {
    #[serde(default = "e_max")]
    pub e_max: f64,
    #[serde(default = "e_min")]
    pub e_min: f64,
    #[serde(default = "p_low")]
    pub p_low: f64,
    /// Energy at the handover (J).
    pub initial: f64,
    /// Widths of the valves' smoothing bands (J, W); default 0.1 each.
    #[serde(default = "band")]
    pub energy_width: f64,
    #[serde(default = "band")]
    pub power_width: f64,
    /// The left inverse of the stacked task Jacobian in Λ: `weighted` by the tasks' weights in
    /// the QP (the default) or `unweighted` (seed 000 Eq 5.9).
    #[serde(default)]
    pub left_inverse: LeftInverseName,
}

/// `[tank] left_inverse`.
#[derive(Clone, Copy, Debug, Default, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum LeftInverseName {
    Unweighted,
    #[default]
    Weighted,
}

impl From<LeftInverseName> for corps_control::formulation::LeftInverse {
    fn from(n: LeftInverseName) -> Self {
        match n {
            LeftInverseName::Unweighted => Self::Unweighted,
            LeftInverseName::Weighted => Self::Weighted,
        }
    }
}

fn e_max() -> f64 {
    5.0
}
fn e_min() -> f64 {
    0.1
}
fn p_low() -> f64 {
    -0.5
}
fn band() -> f64 {
    0.1
}

impl TankGains {
    /// The tank, or a clear error (E_min ≥ E_max, P_low > 0, a negative energy...).
    pub fn tank(&self) -> Result<corps_control::passivity::EnergyTank> {
        let params = corps_control::passivity::TankParams {
            e_max: self.e_max,
            e_min: self.e_min,
            p_low: self.p_low,
            energy_width: self.energy_width,
            power_width: self.power_width,
        };
        corps_control::passivity::EnergyTank::new(params, self.initial)
            .map_err(|e| invalid!("tank: {e}"))
    }
}

/// The inverse-kinematics controller: task gains (1/s) of seed 000 Table 4.1's stack.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct IkGainsFile {
    pub contacts: f64,
    pub com_height: f64,
    pub com: f64,
    pub waist: f64,
    pub posture: f64,
    /// The balance stabilizer in front of the IK; absent: none.
    pub stabilizer: Option<StabilizerGains>,
}

/// Reads gains of type `T` from `source`, with the values of `overrides` (a scenario's
/// `[controller.set]` table, e.g. `posture.weight = 1e-3`) replacing the file's.
pub fn load<T: serde::de::DeserializeOwned>(
    source: &GainsSource,
    overrides: &toml::Table,
) -> Result<T> {
    let (mut text, mut name) = match source {
        GainsSource::File(p) => (
            std::fs::read_to_string(p).with_context(|| format!("reading {}", p.display()))?,
            p.display().to_string(),
        ),
        GainsSource::Text(g) => (g.text.clone(), g.shown.clone()),
    };
    if !overrides.is_empty() {
        let mut table: toml::Table = text
            .parse()
            .map_err(|e: toml::de::Error| invalid!("{name}: {}", e.message()))?;
        corps_robot::toml_text::merge(&mut table, overrides);
        text = toml::to_string(&table).context("merging controller.set")?;
        name = format!("{name} with controller.set");
    }
    corps_robot::toml_text::parse(&text).map_err(|e| invalid!("{name}: {e}"))
}

pub(crate) fn check_non_negative(what: &str, x: f64) -> Result<()> {
    if !(x >= 0.0 && x.is_finite()) {
        bail!("{what} = {x}: must be finite and not negative");
    }
    Ok(())
}

impl TsidGains {
    /// Checks every value (finite, not negative, fmin ≤ fmax, μ > 0).
    pub fn check(&self) -> Result<()> {
        for (name, g) in [("com", &self.com), ("feet", &self.feet)]
            .into_iter()
            .chain(self.waist.as_ref().map(|w| ("waist", w)))
        {
            check_non_negative(&format!("{name}.kp"), g.kp)?;
            check_non_negative(&format!("{name}.kd"), g.kd())?;
            check_non_negative(&format!("{name}.weight"), g.weight)?;
        }
        check_non_negative("posture.kp", self.posture.kp)?;
        check_non_negative("posture.weight", self.posture.weight)?;
        for (group, values) in &self.posture.groups {
            for x in values {
                check_non_negative(&format!("posture.groups.{group}"), *x)?;
            }
        }
        check_non_negative("angular_momentum.kp", self.angular_momentum.kp)?;
        check_non_negative("angular_momentum.weight", self.angular_momentum.weight)?;
        let c = &self.contacts;
        check_non_negative("contacts.kp", c.kp)?;
        check_non_negative("contacts.kd", c.kd.unwrap_or(0.0))?;
        check_non_negative("contacts.fmin", c.fmin)?;
        check_non_negative("contacts.force_regularization", c.force_regularization)?;
        check_non_negative("contacts.transition", c.transition)?;
        check_non_negative("safe_damping", self.safe_damping)?;
        if let Some(s) = &self.stabilizer {
            s.check()?;
        }
        if let Some(t) = &self.tank {
            t.tank()?;
        }
        if let Some(f) = &self.force_contact {
            for (name, x) in [
                ("kp", f.kp),
                ("ki", f.ki),
                ("kd", f.kd),
                ("weight", f.weight),
            ] {
                check_non_negative(&format!("force_contact.{name}"), x)?;
            }
            check_non_negative("force_contact.leak", f.leak)?;
        }
        if !(c.mu > 0.0 && c.mu.is_finite()) {
            bail!("contacts.mu = {}: must be positive", c.mu);
        }
        if c.fmax.is_nan() || c.fmax < c.fmin {
            bail!("contacts: fmax {} is below fmin {}", c.fmax, c.fmin);
        }
        Ok(())
    }

    /// Posture Kp per actuated joint (na entries) for `model`.
    pub fn posture_kp(&self, model: &Model) -> Result<DVector<f64>> {
        self.posture.kp_per_joint(model)
    }
}

impl PostureGains {
    /// Kp per actuated joint (na entries) for `model`: `kp`, replaced by `groups`.
    pub fn kp_per_joint(&self, model: &Model) -> Result<DVector<f64>> {
        let first = if model.has_free_flyer() { 6 } else { 0 };
        // (velocity index − first, name) of every joint but the free-flyer, in velocity order.
        let actuated: Vec<(usize, &str)> = model
            .joints
            .iter()
            .filter(|j| !matches!(j.kind, corps_model::JointKind::FreeFlyer))
            .map(|j| (j.idx_v - first, j.name.as_str()))
            .collect();
        let mut kp = DVector::repeat(model.nv - first, self.kp);
        for (prefix, values) in &self.groups {
            let idx: Vec<usize> = actuated
                .iter()
                .filter(|(_, n)| n.starts_with(prefix.as_str()))
                .map(|(i, _)| *i)
                .collect();
            if idx.len() != values.len() {
                bail!(
                    "posture.groups.{prefix}: {} values for the {} joints named '{prefix}…'",
                    values.len(),
                    idx.len()
                );
            }
            for (i, x) in idx.into_iter().zip(values) {
                kp[i] = *x;
            }
        }
        Ok(kp)
    }
}

impl IkGainsFile {
    pub fn check(&self) -> Result<()> {
        for (name, x) in [
            ("contacts", self.contacts),
            ("com_height", self.com_height),
            ("com", self.com),
            ("waist", self.waist),
            ("posture", self.posture),
        ] {
            check_non_negative(name, x)?;
        }
        if let Some(s) = &self.stabilizer {
            s.check()?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// TALOS' gains file `name` from its description.
    fn talos(name: &str) -> GainsSource {
        let robot = corps_robot::Robot::built_in("talos").unwrap().unwrap();
        GainsSource::resolve(None, name, &robot, Path::new(".")).unwrap()
    }

    fn text(name: &str) -> String {
        match talos(name) {
            GainsSource::Text(g) => g.text,
            GainsSource::File(_) => unreachable!("built-in"),
        }
    }

    #[test]
    fn the_built_in_gains_parse_and_check() {
        let t: TsidGains = load(&talos("tsid_torque"), &toml::Table::new()).unwrap();
        t.check().unwrap();
        assert_eq!(t.com.kp, 50.0);
        let p: TsidGains = load(&talos("tsid_position"), &toml::Table::new()).unwrap();
        p.check().unwrap();
        assert_eq!(
            p.posture.groups["leg_left_"],
            vec![10.0, 5.0, 5.0, 1.0, 10.0, 10.0]
        );
        let w: TsidGains = load(&talos("tsid_torque_walk"), &toml::Table::new()).unwrap();
        w.check().unwrap();
        assert_eq!((w.com.kp, w.feet.kp), (20.0, 1200.0));
        let ik: IkGainsFile = load(&talos("ik_position"), &toml::Table::new()).unwrap();
        ik.check().unwrap();
        assert_eq!(ik.waist, 300.0);
    }

    #[test]
    fn unknown_keys_and_bad_values_are_errors() {
        let bad = text("tsid_torque").replace("[com]\n", "[com]\nkpp = 1.0\n");
        let source = GainsSource::Text(GainsText {
            text: bad,
            shown: "test".into(),
        });
        let e = load::<TsidGains>(&source, &toml::Table::new())
            .unwrap_err()
            .to_string();
        assert!(e.contains("com") && e.contains("kpp"), "{e}");
        let mut t: TsidGains = load(&talos("tsid_torque"), &toml::Table::new()).unwrap();
        t.contacts.fmax = 0.5;
        assert!(t.check().unwrap_err().to_string().contains("fmax"));
        t.contacts.fmax = 1000.0;
        t.com.kp = f64::NAN;
        assert!(t.check().unwrap_err().to_string().contains("com.kp"));
    }

    #[test]
    fn the_passive_gains_parse_and_a_bad_tank_is_refused() {
        for name in ["passive_torque", "passive_torque_walk"] {
            let t: TsidGains = load(&talos(name), &toml::Table::new()).unwrap();
            t.check().unwrap();
            assert!(t.tank.is_some());
        }
        for (set, says) in [
            ("tank.e_min = 6.0", "E_min"),
            ("tank.p_low = 0.5", "P_low"),
            ("tank.initial = -1.0", "initial energy"),
        ] {
            let set: toml::Table = set.parse().unwrap();
            let t: TsidGains = load(&talos("passive_torque"), &set).unwrap();
            let e = t.check().unwrap_err().to_string();
            assert!(e.contains(says), "{e}");
        }
    }

    #[test]
    fn overrides_replace_single_values_and_are_checked_like_the_file() {
        let set: toml::Table = "posture.weight = 1e-3\ncom.kp = 20.0".parse().unwrap();
        let t: TsidGains = load(&talos("tsid_torque"), &set).unwrap();
        assert_eq!(
            (t.posture.weight, t.com.kp, t.com.kd),
            (1e-3, 20.0, Some(5.0))
        );
        let set: toml::Table = "posture.wieght = 1.0".parse().unwrap();
        let e = load::<TsidGains>(&talos("tsid_torque"), &set).unwrap_err();
        assert!(e.to_string().contains("wieght"), "{e}");
    }
}
