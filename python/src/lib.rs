//! `tabula._tabula`: the native half of the `tabula` Python package. Arrays come in as
//! float64 numpy arrays (the Python half converts and checks shapes), long work runs with
//! the GIL released, and every error is a Python exception with the CLI's message.

mod cloud;
mod plan;
mod robot;
mod scene;
mod stable;

use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;

/// A bad input: `ValueError` with the library's message.
pub(crate) fn value_error(e: impl std::fmt::Display) -> PyErr {
    PyValueError::new_err(e.to_string())
}

/// A failure while working: `RuntimeError` with the library's message.
pub(crate) fn runtime_error(e: impl std::fmt::Display) -> PyErr {
    PyRuntimeError::new_err(e.to_string())
}

/// `values` when every one is finite, else a `ValueError` naming `what`.
pub(crate) fn finite<'a>(values: &'a [f64], what: &str) -> PyResult<&'a [f64]> {
    match values.iter().position(|v| !v.is_finite()) {
        None => Ok(values),
        Some(i) => Err(value_error(format!(
            "{what}: value {i} is {} (every value must be finite)",
            values[i]
        ))),
    }
}

#[pymodule]
fn _tabula(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add_class::<robot::Robot>()?;
    m.add_class::<scene::Scene>()?;
    m.add_function(wrap_pyfunction!(stable::stable_poses, m)?)?;
    m.add_function(wrap_pyfunction!(cloud::read_cloud, m)?)?;
    m.add_function(wrap_pyfunction!(cloud::perceive, m)?)?;
    m.add_function(wrap_pyfunction!(plan::plan_pddl, m)?)?;
    Ok(())
}
