//! Python exceptions for corps' typed errors. Every message is the one line the `corps`
//! command prints after `corps: error:`.

use pyo3::create_exception;
use pyo3::exceptions::PyException;
use pyo3::prelude::*;

create_exception!(
    corps,
    CorpsError,
    PyException,
    "Base class of every error corps raises."
);
create_exception!(
    corps,
    ModelError,
    CorpsError,
    "A model could not be loaded, or an algorithm got bad input (sizes, names, frame ids)."
);
create_exception!(
    corps,
    ScenarioError,
    CorpsError,
    "A scenario could not be read, built or run."
);
create_exception!(
    corps,
    PlantError,
    CorpsError,
    "A Python plant broke its protocol (a missing method, a reading of the wrong size)."
);

/// `ModelError` with the error's one-line message.
pub fn model_error(e: impl std::fmt::Display) -> PyErr {
    ModelError::new_err(e.to_string())
}

/// `ScenarioError` with the error's one-line message.
pub fn scenario_error(e: impl std::fmt::Display) -> PyErr {
    ScenarioError::new_err(e.to_string())
}

/// Registers the exception classes on the module.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("CorpsError", py.get_type::<CorpsError>())?;
    m.add("ModelError", py.get_type::<ModelError>())?;
    m.add("ScenarioError", py.get_type::<ScenarioError>())?;
    m.add("PlantError", py.get_type::<PlantError>())?;
    Ok(())
}
