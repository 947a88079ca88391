//! Operational-space inertia of a frame: Λ = (J M⁻¹ Jᵀ)⁻¹ (Khatib 1987), with M⁻¹ Jᵀ from the
//! sparse factorization (six solves, no full inverse).

use super::cholesky::{factorize_mass_matrix, solve_mass_matrix};
use super::crba::crba;
use super::jacobians::{frame_jacobian, ReferenceFrame};
use crate::data::Data;
use crate::error::{ModelError, Result};
use crate::model::Model;
use nalgebra::Matrix6;

/// Λ of frame `frame_id` with its Jacobian expressed in `rf`. Fails with
/// [`ModelError::Singular`] when J M⁻¹ Jᵀ is not invertible (the frame has fewer than six
/// independent directions of motion).
pub fn frame_operational_space_inertia(
    model: &Model,
    data: &mut Data,
    q: &[f64],
    frame_id: usize,
    rf: ReferenceFrame,
) -> Result<Matrix6<f64>> {
    crba(model, data, q)?;
    factorize_mass_matrix(model, data);
    let mut jac = std::mem::take(&mut data.tmp_6xnv);
    let res = frame_jacobian(model, data, frame_id, rf, &mut jac);
    if let Err(e) = res {
        data.tmp_6xnv = jac;
        return Err(e);
    }
    let mut inv = Matrix6::zeros();
    for r in 0..6 {
        for k in 0..model.nv {
            data.tmp_nv[k] = jac[(r, k)];
        }
        solve_mass_matrix(model, &data.ltdl, data.tmp_nv.as_mut_slice());
        for s in 0..6 {
            inv[(s, r)] = (0..model.nv).map(|k| jac[(s, k)] * data.tmp_nv[k]).sum();
        }
    }
    data.tmp_6xnv = jac;
    let inv = (inv + inv.transpose()) * 0.5;
    inv.cholesky().map(|c| c.inverse()).ok_or_else(|| {
        ModelError::Singular(format!(
            "J M⁻¹ Jᵀ of frame '{}'",
            model.frames[frame_id].name
        ))
    })
}
