//! Kinetic and potential energy.

use super::kinematics::{motion_pass, placements};
use crate::data::Data;
use crate::error::Result;
use crate::model::{check_vector, Model};

/// Kinetic energy ½ Σ v_iᵀ I_i v_i (`data.kinetic_energy`).
pub fn kinetic_energy(model: &Model, data: &mut Data, q: &[f64], v: &[f64]) -> Result<f64> {
    model.check_configuration(q)?;
    check_vector("velocity v", v, model.nv)?;
    motion_pass(model, data, q, Some(v), None, false);
    data.kinetic_energy = (0..model.njoints())
        .map(|i| model.inertias[i].kinetic_energy(&data.v[i]))
        .sum();
    Ok(data.kinetic_energy)
}

/// Potential energy −Σ m_i gᵀ c_i in the gravity field (`data.potential_energy`).
pub fn potential_energy(model: &Model, data: &mut Data, q: &[f64]) -> Result<f64> {
    model.check_configuration(q)?;
    placements(model, data, q, false);
    data.potential_energy = (0..model.njoints())
        .map(|i| {
            let inertia = &model.inertias[i];
            -inertia.mass * model.gravity.dot(&data.o_m_i[i].act_point(&inertia.lever))
        })
        .sum();
    Ok(data.potential_energy)
}
