//! The `corps` Python package's native module (`corps._corps`): models and the rigid-body
//! algorithms with Pinocchio's names and conventions, and scenario runs returning numpy
//! arrays. The pure-Python part lives in `python/corps/`.

mod algorithms;
mod arrays;
mod errors;
mod learn;
mod model;
mod plant;
mod run;
mod tree;

use pyo3::prelude::*;

#[pymodule]
fn _corps(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    errors::register(m)?;
    m.add_class::<model::PyModel>()?;
    m.add_class::<model::PyData>()?;
    m.add_class::<model::PySe3>()?;
    m.add_class::<model::PyReferenceFrame>()?;
    m.add("LOCAL", model::PyReferenceFrame::LOCAL)?;
    m.add("WORLD", model::PyReferenceFrame::WORLD)?;
    m.add(
        "LOCAL_WORLD_ALIGNED",
        model::PyReferenceFrame::LOCAL_WORLD_ALIGNED,
    )?;
    m.add_class::<run::PyRunResult>()?;
    m.add_class::<plant::PyCommand>()?;
    m.add_function(wrap_pyfunction!(algorithms::rnea, m)?)?;
    m.add_function(wrap_pyfunction!(algorithms::nonlinear_effects, m)?)?;
    m.add_function(wrap_pyfunction!(
        algorithms::compute_generalized_gravity,
        m
    )?)?;
    m.add_function(wrap_pyfunction!(algorithms::crba, m)?)?;
    m.add_function(wrap_pyfunction!(algorithms::compute_minverse, m)?)?;
    m.add_function(wrap_pyfunction!(algorithms::aba, m)?)?;
    m.add_function(wrap_pyfunction!(algorithms::forward_kinematics, m)?)?;
    m.add_function(wrap_pyfunction!(algorithms::frame_placement, m)?)?;
    m.add_function(wrap_pyfunction!(algorithms::compute_joint_jacobians, m)?)?;
    m.add_function(wrap_pyfunction!(algorithms::compute_frame_jacobian, m)?)?;
    m.add_function(wrap_pyfunction!(algorithms::get_frame_jacobian, m)?)?;
    m.add_function(wrap_pyfunction!(algorithms::center_of_mass, m)?)?;
    m.add_function(wrap_pyfunction!(algorithms::jacobian_center_of_mass, m)?)?;
    m.add_function(wrap_pyfunction!(algorithms::centroidal_map, m)?)?;
    m.add_function(wrap_pyfunction!(
        algorithms::compute_centroidal_momentum,
        m
    )?)?;
    m.add_function(wrap_pyfunction!(algorithms::compute_kinetic_energy, m)?)?;
    m.add_function(wrap_pyfunction!(algorithms::compute_potential_energy, m)?)?;
    m.add_function(wrap_pyfunction!(algorithms::neutral, m)?)?;
    m.add_function(wrap_pyfunction!(algorithms::integrate, m)?)?;
    m.add_function(wrap_pyfunction!(algorithms::difference, m)?)?;
    m.add_function(wrap_pyfunction!(algorithms::random_configuration, m)?)?;
    m.add_function(wrap_pyfunction!(run::run, m)?)?;
    m.add_function(wrap_pyfunction!(learn::learn, m)?)?;
    m.add_function(wrap_pyfunction!(learn::learning_rollout, m)?)?;
    m.add_function(wrap_pyfunction!(run::_panic_for_test, m)?)?;
    Ok(())
}
