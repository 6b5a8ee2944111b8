//! `tabula._tabula`: the native half of the `tabula` Python package. Arrays come in as
//! float64 numpy arrays (the Python half converts and checks shapes), long work runs with
//! the GIL released, and every error is a Python exception with the CLI's message.

mod cloud;
mod motion;
mod params;
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

/// A pose as the rows of its (4, 4) homogeneous matrix.
pub(crate) fn rows(p: &tabula_geom::Pose) -> Vec<Vec<f64>> {
    let m = tabula_geom::Mat4::from_rotation_translation(p.rotation, p.translation);
    (0..4)
        .map(|r| (0..4).map(|c| m.col(c)[r]).collect())
        .collect()
}

/// A pose from a (4, 4) matrix given as rows.
pub(crate) fn pose_of_rows(rows: &[Vec<f64>]) -> PyResult<tabula_geom::Pose> {
    if rows.len() != 4 || rows.iter().any(|r| r.len() != 4) {
        return Err(value_error("a pose must be a (4, 4) matrix"));
    }
    let flat: Vec<f64> = rows.iter().flatten().copied().collect();
    pose_of_matrix(&flat)
}

/// A pose from a (4, 4) homogeneous matrix, row after row (numpy's C order).
pub(crate) fn pose_of_matrix(m: &[f64]) -> PyResult<tabula_geom::Pose> {
    if m.len() != 16 {
        return Err(value_error("a pose must be a (4, 4) matrix"));
    }
    finite(m, "the pose")?;
    let cols: Vec<f64> = (0..16).map(|k| m[(k % 4) * 4 + k / 4]).collect();
    let (scale, rotation, translation) =
        tabula_geom::Mat4::from_cols_slice(&cols).to_scale_rotation_translation();
    if (scale - tabula_geom::Vec3::ONE).abs().max_element() > 1e-6
        || m[12..] != [0.0, 0.0, 0.0, 1.0]
    {
        return Err(value_error(
            "a pose's rotation must be a rotation and its last row 0 0 0 1",
        ));
    }
    Ok(tabula_geom::Pose::from_parts(translation, rotation))
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
    m.add_function(wrap_pyfunction!(motion::plan_motion, m)?)?;
    Ok(())
}
