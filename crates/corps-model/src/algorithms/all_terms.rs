//! Every term a whole-body controller needs at one state, in one call (Pinocchio's
//! `computeAllTerms`): M, h, joint Jacobians, CoM and its Jacobian, A_G and h_G, energies.

use super::centroidal::fill_from_composites;
use super::crba::composite_pass;
use super::rnea::rnea_pass;
use crate::data::{col_force, Data};
use crate::error::Result;
use crate::model::{check_vector, Model};
use crate::spatial::Force;

/// Fills `data.m`, `data.nle`, `data.j`, `data.com`, `data.jcom`, `data.ag`, `data.hg`,
/// `data.kinetic_energy` and `data.potential_energy` for (q, v).
pub fn compute_all_terms(model: &Model, data: &mut Data, q: &[f64], v: &[f64]) -> Result<()> {
    model.check_configuration(q)?;
    check_vector("velocity v", v, model.nv)?;
    rnea_pass(model, data, q, Some(v), None, true, false);
    data.nle.copy_from(&data.tau);
    let mut ke = 0.0;
    for i in 0..model.njoints() {
        ke += model.inertias[i].kinetic_energy(&data.v[i]);
    }
    data.kinetic_energy = ke;
    // The RNEA pass left the joint placements at q: the composite pass reuses them.
    composite_pass(model, data, q, true, true);
    fill_from_composites(model, data);
    let mut h = Force::zero();
    for (k, vk) in v.iter().enumerate() {
        h += col_force(&data.ag, k) * *vk;
    }
    data.hg = h;
    data.potential_energy = -model.total_mass() * model.gravity.dot(&data.com);
    Ok(())
}
