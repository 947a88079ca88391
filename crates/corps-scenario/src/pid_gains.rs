//! A PID gains file for the joint position servo (`[actuation] pid_gains`): per joint p, d,
//! i, the integral torque's clamp and the command's torque clamp, as Gazebo's position
//! controllers take them (`config/talos/gazebo_pid.toml`). Every actuated joint of the model
//! needs its gains and every joint named must exist.

use crate::error::{bail, invalid, Result};
use corps_model::Model;
use corps_sim::{first_actuated, IntegralTerm, ServoGains};
use nalgebra::DVector;
use serde::Deserialize;
use std::collections::BTreeMap;
use std::path::Path;

/// One joint's gains.
#[derive(Clone, Copy, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct JointPid {
    p: f64,
    d: f64,
    i: f64,
    i_clamp: f64,
    torque_clamp: f64,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct PidFile {
    joints: BTreeMap<String, JointPid>,
}

/// The servo gains of `model` from the PID file at `path`.
pub fn load(model: &Model, path: &Path) -> Result<ServoGains> {
    let shown = path.display();
    let text = std::fs::read_to_string(path).map_err(|e| invalid!("cannot read {shown}: {e}"))?;
    parse(model, &text).map_err(|e| invalid!("{shown}: {e}"))
}

/// The servo gains of `model` from a PID file's text.
pub fn parse(model: &Model, text: &str) -> Result<ServoGains> {
    let file: PidFile = corps_robot::toml_text::parse(text).map_err(|e| invalid!("{e}"))?;
    let first = first_actuated(model);
    let na = model.nv - first;
    let mut per_dof: Vec<Option<JointPid>> = vec![None; na];
    for (name, g) in &file.joints {
        let id = model
            .joint_id(name)
            .map_err(|_| invalid!("joints.{name}: the model has no such joint"))?;
        let joint = &model.joints[id];
        if joint.idx_v < first {
            bail!("joints.{name}: not an actuated joint (the floating base has no servo)");
        }
        for (key, x) in [
            ("p", g.p),
            ("d", g.d),
            ("i", g.i),
            ("i_clamp", g.i_clamp),
            ("torque_clamp", g.torque_clamp),
        ] {
            if !(x >= 0.0 && x.is_finite()) {
                bail!("joints.{name}.{key}: must be a finite number ≥ 0, got {x}");
            }
        }
        for k in joint.idx_v..joint.idx_v + joint.nv() {
            per_dof[k - first] = Some(*g);
        }
    }
    if let Some(k) = per_dof.iter().position(Option::is_none) {
        let name = &model.joints[model.dof_joint[first + k]].name;
        bail!("joints: no gains for the model's joint {name}");
    }
    let get = |f: fn(&JointPid) -> f64| {
        DVector::from_iterator(na, per_dof.iter().map(|g| g.as_ref().map_or(0.0, f)))
    };
    Ok(ServoGains {
        kp: get(|g| g.p),
        kd: get(|g| g.d),
        integral: Some(IntegralTerm {
            ki: get(|g| g.i),
            i_clamp: get(|g| g.i_clamp),
            torque_clamp: get(|g| g.torque_clamp),
        }),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn talos() -> Model {
        let talos = corps_robot::Robot::built_in("talos").unwrap().unwrap();
        std::sync::Arc::unwrap_or_clone(talos.model)
    }

    #[test]
    fn the_talos_file_gives_every_joint_its_gazebo_gains() {
        let model = talos();
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../config/talos/gazebo_pid.toml");
        let g = load(&model, &path).unwrap();
        let knee = model.joints[model.joint_id("leg_left_4_joint").unwrap()].idx_v
            - model.first_actuated();
        assert_eq!((g.kp[knee], g.kd[knee]), (5000.0, 20.0));
        let i = g.integral.unwrap();
        assert_eq!(
            (i.ki[knee], i.i_clamp[knee], i.torque_clamp[knee]),
            (5.0, 25.0, 300.0)
        );
    }

    #[test]
    fn missing_unknown_and_negative_gains_are_refused_in_one_line() {
        let model = talos();
        let one =
            "leg_left_1_joint = { p = 1.0, d = 1.0, i = 0.0, i_clamp = 0.0, torque_clamp = 1.0 }";
        for (text, expected) in [
            (
                format!("[joints]\n{one}\n"),
                "no gains for the model's joint",
            ),
            (
                format!("[joints]\n{}\n", one.replace("leg_left_1", "leg_left_9")),
                "no such joint",
            ),
            (
                format!("[joints]\n{}\n", one.replace("p = 1.0", "p = -1.0")),
                "joints.leg_left_1_joint.p",
            ),
            (
                format!("[joints]\n{}\n", one.replace("i = 0.0", "k = 0.0")),
                "unknown field",
            ),
            (
                format!(
                    "[joints]\n{}\n",
                    one.replace("leg_left_1_joint", "root_joint")
                ),
                "not an actuated joint",
            ),
        ] {
            let e = parse(&model, &text).unwrap_err().to_string();
            assert!(e.contains(expected) && !e.contains('\n'), "{text}: {e}");
        }
    }
}
