//! The simulator's variant of a robot with passive elastic joints (seed 000 App. 4, Eq 6.4):
//! the URDF with each [`PassiveJointSpec`] inserted into its tree, loaded through the same
//! description as the rigid model, so both models share every frame, sensor and limit.

use crate::description::PassiveJointSpec;
use corps_model::Model;
use std::sync::Arc;

/// The plant's model of a robot with passive joints and those joints' spring-dampers.
#[derive(Clone, Debug)]
pub struct PlantVariant {
    /// The rigid model plus the passive joints (the simulator's model).
    pub model: Arc<Model>,
    pub passive: Vec<PassiveJoint>,
}

/// A passive joint, resolved.
#[derive(Clone, Debug, PartialEq)]
pub struct PassiveJoint {
    pub name: String,
    /// Its index among the plant model's joints.
    pub joint: usize,
    /// `k` (N·m/rad) and `d` (N·m·s/rad) of `τ = −k θ − d θ̇`.
    pub stiffness: f64,
    pub damping: f64,
    /// The rigid model's actuated joint about the same axis (its index in the rigid model).
    pub compensated_by: Option<usize>,
}

type Checked<T> = Result<T, String>;

/// Checks the spec's numbers and names (`key` prefixes the messages).
pub(crate) fn check_spec(spec: &PassiveJointSpec, key: &str) -> Checked<()> {
    if !(spec.stiffness.is_finite() && spec.stiffness > 0.0) {
        return Err(format!(
            "{key}.stiffness: must be a finite number > 0 (N·m/rad), got {}",
            spec.stiffness
        ));
    }
    if !(spec.damping.is_finite() && spec.damping >= 0.0) {
        return Err(format!(
            "{key}.damping: must be a finite number ≥ 0 (N·m·s/rad), got {}",
            spec.damping
        ));
    }
    let norm = spec.axis.iter().map(|a| a * a).sum::<f64>().sqrt();
    if !(norm.is_finite() && norm > 1e-9) {
        return Err(format!("{key}.axis: must be a finite non-zero vector"));
    }
    Ok(())
}

/// The URDF text with `spec` inserted: a revolute joint named `spec.name` from the parent link
/// of `spec.before`, at its origin, to a new massless link `<name>_link`, from which
/// `spec.before` then hangs at the identity.
pub(crate) fn insert(urdf: &str, spec: &PassiveJointSpec, key: &str) -> Checked<String> {
    let doc = roxmltree::Document::parse(urdf).map_err(|e| format!("urdf: {e}"))?;
    let robot = doc.root_element();
    let named = |tag: &str, name: &str| {
        robot
            .children()
            .filter(|n| n.has_tag_name(tag))
            .find(|n| n.attribute("name") == Some(name))
    };
    let link = format!("{}_link", spec.name);
    if named("joint", &spec.name).is_some() || named("link", &link).is_some() {
        return Err(format!(
            "{key}.name: the URDF already has a joint '{}' or a link '{link}'",
            spec.name
        ));
    }
    let joint = named("joint", &spec.before)
        .ok_or_else(|| format!("{key}.before: the URDF has no joint '{}'", spec.before))?;
    if joint.attribute("type") == Some("fixed") {
        return Err(format!("{key}.before: '{}' is a fixed joint", spec.before));
    }
    let element = |tag: &str| joint.children().find(|n| n.has_tag_name(tag));
    let parent = element("parent")
        .ok_or_else(|| format!("{key}.before: joint '{}' has no <parent>", spec.before))?;
    let parent_link = parent.attribute("link").unwrap_or_default();
    let origin = element("origin");
    let origin_text = origin.map_or("", |o| &urdf[o.range()]);
    let [ax, ay, az] = spec.axis;
    let added = format!(
        "  <link name=\"{link}\"/>\n  <joint name=\"{}\" type=\"revolute\">\n    \
         <parent link=\"{parent_link}\"/>\n    <child link=\"{link}\"/>\n    {origin_text}\n    \
         <axis xyz=\"{ax} {ay} {az}\"/>\n    \
         <limit effort=\"1e6\" lower=\"-1\" upper=\"1\" velocity=\"1e3\"/>\n  </joint>\n",
        spec.name
    );
    // Edits from the end of the text back, so that earlier ranges stay valid.
    let end = robot.range().end;
    let close = urdf[..end]
        .rfind("</")
        .ok_or_else(|| "urdf: <robot> has no closing tag".to_string())?;
    let mut edits: Vec<(std::ops::Range<usize>, String)> = vec![
        (close..close, added),
        (parent.range(), format!("<parent link=\"{link}\"/>")),
    ];
    if let Some(o) = origin {
        edits.push((o.range(), "<origin xyz=\"0 0 0\" rpy=\"0 0 0\"/>".into()));
    }
    edits.sort_by_key(|(r, _)| std::cmp::Reverse(r.start));
    let mut text = urdf.to_string();
    for (range, with) in edits {
        text.replace_range(range, &with);
    }
    Ok(text)
}
