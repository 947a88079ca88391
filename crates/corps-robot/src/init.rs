//! A first description for a new robot, written from its model: the feet are guessed from
//! the lowest collision bodies at the reference posture (left = the one further along +y),
//! and every guess carries a `# CHECK:` comment saying what a person must verify.

use corps_model::{forward_kinematics_placements, Data, FrameKind, Model, Shape};
use nalgebra::Vector3;

/// A foot guessed from the model.
struct GuessedFoot {
    /// The body (link) frame it hangs from.
    link: String,
    /// Sole frame origin in the link frame, and the sole half sizes.
    origin: Vector3<f64>,
    half: (f64, f64),
    /// Whether the URDF has a primitive there (else the sole is a placeholder box).
    from_box: bool,
    world_y: f64,
}

/// The text of a starting description for `model` (loaded from `urdf`, with `srdf`; paths
/// as they should appear in the file, relative to where it will be written).
pub fn draft(model: &Model, urdf: &str, srdf: Option<&str>) -> String {
    let posture = model.reference_configurations.first();
    let q = posture
        .map(|(_, q)| q.clone())
        .unwrap_or_else(|| corps_model::neutral(model));
    let mut data = Data::new(model);
    let feet = match forward_kinematics_placements(model, &mut data, q.as_slice()) {
        Ok(()) => guess_feet(model, &data),
        Err(_) => vec![],
    };
    let base = (model.frames.iter())
        .find(|f| f.kind == FrameKind::Body && f.parent_joint == Some(0))
        .map(|f| f.name.as_str())
        .or_else(|| model.joints.first().map(|j| j.name.as_str()))
        .unwrap_or("CHECK");
    let mut out = String::new();
    let name = if model.name.is_empty() {
        "robot"
    } else {
        &model.name
    };
    out.push_str(&format!(
        "# Robot description for corps, drafted by `corps robot init` from {urdf}.\n\
         # Lines marked CHECK are guesses: verify each before trusting a run.\n\n\
         name = \"{name}\"\nurdf = \"{urdf}\"\n"
    ));
    match srdf {
        Some(s) => out.push_str(&format!("srdf = \"{s}\"\n")),
        None => out.push_str(
            "# CHECK: no SRDF given; the posture below must be one of its group_states.\n",
        ),
    }
    match posture {
        Some((n, _)) => out.push_str(&format!(
            "# CHECK: the standing posture controllers hold (an SRDF group_state).\nposture = \"{n}\"\n"
        )),
        None => out.push_str(
            "# CHECK: no reference configuration found; add a group_state to the SRDF.\nposture = \"half_sitting\"\n",
        ),
    }
    out.push_str(&format!(
        "# CHECK: the waist frame (orientation task, pushes).\nbase = \"{base}\"\n"
    ));
    let mut frames = String::new();
    let mut feet_text = String::new();
    for (k, f) in feet.iter().enumerate() {
        let label = match (feet.len(), k) {
            (2, 0) => "left".to_string(),
            (2, 1) => "right".to_string(),
            _ => format!("foot{k}"),
        };
        let frame = format!("{label}_sole");
        frames.push_str(&format!(
            "\n# CHECK: the sole frame: origin on the sole surface, z up, x forward.\n\
             [[frames]]\nname = \"{frame}\"\nparent = \"{}\"\ntranslation = [{:.4}, {:.4}, {:.4}]\n",
            f.link, f.origin.x, f.origin.y, f.origin.z
        ));
        feet_text.push_str(&format!(
            "\n[[feet]]\nlabel = \"{label}\"\nframe = \"{frame}\"\n"
        ));
        if f.from_box {
            feet_text.push_str(&format!(
                "# CHECK: from the URDF's collision box of '{}'.\n\
                 sole = {{ front = {:.4}, back = {:.4}, left = {:.4}, right = {:.4} }}\n",
                f.link, f.half.0, f.half.0, f.half.1, f.half.1
            ));
        } else {
            feet_text.push_str(&format!(
                "# CHECK: '{}' has only mesh collision: this sole is a placeholder, measure it.\n\
                 sole = {{ front = {:.4}, back = {:.4}, left = {:.4}, right = {:.4} }}\n\
                 contact = \"sole_box\"\n",
                f.link, f.half.0, f.half.0, f.half.1, f.half.1
            ));
        }
    }
    if feet.is_empty() {
        feet_text.push_str(
            "\n# CHECK: no foot found (no collision geometry); name each sole frame and its rectangle.\n\
             [[feet]]\nlabel = \"left\"\nframe = \"CHECK\"\n\
             sole = { front = 0.1, back = 0.1, left = 0.05, right = 0.05 }\ncontact = \"sole_box\"\n",
        );
    }
    out.push_str(&frames);
    out.push_str(&feet_text);
    out.push_str(
        "\n# Force/torque sensors and the IMU: name each, then give a foot its sensor with\n\
         # `force_torque = \"<name>\"` (without one, controllers that need a measured ZMP fail).\n\
         [sensors]\n# imu = \"<frame>\"\n# [[sensors.force_torque]]\n# name = \"left_ankle\"\n# frame = \"left_sole\"\n\
         \n# Gains files by controller kind, e.g. tsid_torque = \"tsid_torque.toml\".\n[gains]\n",
    );
    out
}

/// The lowest bodies: primitives within 2 cm of the lowest point, else (mesh-only) the two
/// lowest body frames.
fn guess_feet(model: &Model, data: &Data) -> Vec<GuessedFoot> {
    let body_name = |joint: usize| {
        model
            .frames
            .iter()
            .find(|f| f.kind == FrameKind::Body && f.parent_joint == Some(joint))
            .map(|f| (f.name.clone(), f.placement))
    };
    let mut boxes: Vec<(f64, GuessedFoot)> = vec![];
    for c in &model.collisions {
        let (Some(j), Shape::Box { size }) = (c.parent_joint, &c.shape) else {
            continue;
        };
        let Some((link, link_placement)) = body_name(j) else {
            continue;
        };
        let world = data.o_m_i[j] * c.placement;
        let bottom_local = Vector3::new(0.0, 0.0, -size.z / 2.0);
        let bottom = world.act_point(&bottom_local);
        let in_link = link_placement.act_inv_point(&c.placement.act_point(&bottom_local));
        boxes.push((
            bottom.z,
            GuessedFoot {
                link,
                origin: in_link,
                half: (size.x / 2.0, size.y / 2.0),
                from_box: true,
                world_y: bottom.y,
            },
        ));
    }
    let mut picked = lowest_two(boxes);
    if picked.is_empty() {
        let mut bodies: Vec<(f64, GuessedFoot)> = (1..model.njoints())
            .filter(|j| !model.joints.iter().any(|o| o.parent == Some(*j)))
            .filter_map(|j| {
                let (link, placement) = body_name(j)?;
                let p = data.o_m_i[j].act_point(&placement.translation);
                Some((
                    p.z,
                    GuessedFoot {
                        link,
                        origin: Vector3::zeros(),
                        half: (0.1, 0.05),
                        from_box: false,
                        world_y: p.y,
                    },
                ))
            })
            .collect();
        bodies.sort_by(|a, b| a.0.total_cmp(&b.0));
        picked = lowest_two(bodies);
    }
    picked.sort_by(|a, b| b.world_y.total_cmp(&a.world_y));
    picked
}

/// The candidates within 2 cm of the lowest, at most two, on distinct links.
fn lowest_two(mut candidates: Vec<(f64, GuessedFoot)>) -> Vec<GuessedFoot> {
    candidates.sort_by(|a, b| a.0.total_cmp(&b.0));
    let Some(low) = candidates.first().map(|c| c.0) else {
        return vec![];
    };
    let mut out: Vec<GuessedFoot> = vec![];
    for (z, f) in candidates {
        if z > low + 0.02 || out.len() == 2 {
            break;
        }
        if !out.iter().any(|o| o.link == f.link) {
            out.push(f);
        }
    }
    out
}
