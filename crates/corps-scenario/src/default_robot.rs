//! The default model of `corps model`: TALOS (`talos_reduced.urdf` and `talos.srdf` from
//! example-robot-data, LGPL-3.0; see robots/README.md), embedded so the command works from any
//! directory. Runs take their robot from a description (`corps_robot`).

use crate::error::{Context, Result};
use corps_model::{build_model_from_urdf_file, build_model_from_urdf_str, Model, RootJoint};
use std::path::Path;

const TALOS_URDF: &str = include_str!("../../../robots/talos_data/robots/talos_reduced.urdf");
const TALOS_SRDF: &str = include_str!("../../../robots/talos_data/srdf/talos.srdf");

/// Loads `urdf` (or TALOS when None) with an optional SRDF for reference configurations.
pub fn load_model(urdf: Option<&Path>, srdf: Option<&Path>, fixed_base: bool) -> Result<Model> {
    let root = if fixed_base {
        RootJoint::Fixed
    } else {
        RootJoint::FreeFlyer
    };
    let mut model = match urdf {
        Some(p) => build_model_from_urdf_file(p, root)
            .with_context(|| format!("loading {}", p.display()))?,
        None => {
            let mut m = build_model_from_urdf_str(TALOS_URDF, root)
                .context("loading the embedded TALOS model")?;
            if srdf.is_none() {
                corps_model::parse::load_reference_configurations_str(&mut m, TALOS_SRDF)
                    .context("loading the embedded TALOS SRDF")?;
            }
            m
        }
    };
    if let Some(s) = srdf {
        corps_model::load_reference_configurations(&mut model, s)
            .with_context(|| format!("loading {}", s.display()))?;
    }
    Ok(model)
}
