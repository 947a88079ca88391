//! SRDF `group_state` elements → named reference configurations (Pinocchio's
//! `loadReferenceConfigurations`): start from the neutral configuration, set every listed joint.

use super::xml::{attr, children, numbers};
use crate::configuration::neutral;
use crate::error::{ModelError, Result};
use crate::joint::JointKind;
use crate::model::Model;
use std::path::Path;

/// Reads the `group_state`s of an SRDF file into `model.reference_configurations`.
/// Joints the model does not have are skipped (an SRDF often covers a fuller model), but a
/// `group_state` that names joints and none of the model's is an error: the SRDF is another
/// robot's, and its configuration would silently be the neutral one.
pub fn load_reference_configurations(model: &mut Model, path: impl AsRef<Path>) -> Result<()> {
    let path = path.as_ref();
    let text = std::fs::read_to_string(path).map_err(|e| ModelError::Io {
        path: path.display().to_string(),
        reason: e.to_string(),
    })?;
    load_reference_configurations_str(model, &text)
}

/// As [`load_reference_configurations`], from a string.
pub fn load_reference_configurations_str(model: &mut Model, xml: &str) -> Result<()> {
    let doc = roxmltree::Document::parse(xml).map_err(|e| ModelError::Xml(e.to_string()))?;
    for gs in children(&doc.root_element(), "group_state") {
        let name = attr(&gs, "name", "<group_state>")?.to_string();
        let ctx = format!("group_state '{name}'");
        let mut q = neutral(model);
        let (mut named, mut matched) = (Vec::new(), 0);
        for j in children(&gs, "joint") {
            let jname = attr(&j, "name", &ctx)?;
            named.push(jname);
            let Ok(id) = model.joint_id(jname) else {
                continue;
            };
            matched += 1;
            let values = numbers(attr(&j, "value", &ctx)?, &ctx, jname)?;
            let joint = &model.joints[id];
            let s = joint.idx_q;
            match (joint.kind, values.as_slice()) {
                (JointKind::RevoluteUnbounded { .. }, [angle]) => {
                    q[s] = angle.cos();
                    q[s + 1] = angle.sin();
                }
                (_, vals) if vals.len() == joint.nq() => {
                    q.as_mut_slice()[s..s + vals.len()].copy_from_slice(vals)
                }
                (_, vals) => {
                    return Err(ModelError::Invalid {
                        element: ctx,
                        reason: format!(
                            "joint '{jname}' takes {} value(s), got {}",
                            joint.nq(),
                            vals.len()
                        ),
                    })
                }
            }
        }
        if matched == 0 && !named.is_empty() {
            let shown: Vec<&str> = named.iter().take(3).copied().collect();
            return Err(ModelError::Invalid {
                element: ctx,
                reason: format!(
                    "names none of the model's joints ({}{}): is the SRDF this robot's?",
                    shown.join(", "),
                    if named.len() > 3 { ", …" } else { "" }
                ),
            });
        }
        crate::configuration::normalize(model, q.as_mut_slice());
        model.reference_configurations.retain(|(n, _)| *n != name);
        model.reference_configurations.push((name, q));
    }
    Ok(())
}
