//! The exceptions: a bad scene is a `SceneError` (a `ValueError` naming
//! the file, the JSON path and the reason, as `pleat check` prints it), a
//! GPU that is missing or lacks a scene's feature a `BackendError`.

use pleat::scene::SceneErrors;
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;

pyo3::create_exception!(
    pleat,
    SceneError,
    PyValueError,
    "A scene that cannot be simulated: the message names the file, the JSON \
     path and the reason, one error a line, as the `pleat` command prints \
     them. `file`, `path` and `reason` are the first error's; `errors` \
     lists every error as a dict with those keys."
);

pyo3::create_exception!(
    pleat,
    BackendError,
    PyRuntimeError,
    "The GPU backend cannot run: no usable adapter, or a scene feature the \
     GPU backend lacks (the message names the scene field)."
);

/// The Python exception for `errors`, with their parts as attributes.
pub fn scene_error(py: Python<'_>, errors: &SceneErrors) -> PyErr {
    let err = SceneError::new_err(errors.to_string());
    if let Err(e) = annotate(py, &err, errors) {
        return e;
    }
    err
}

/// Sets `file`, `path`, `reason` and `errors` on the exception `err`.
fn annotate(py: Python<'_>, err: &PyErr, errors: &SceneErrors) -> PyResult<()> {
    let value = err.value(py);
    let list = errors
        .0
        .iter()
        .map(|e| {
            let d = PyDict::new(py);
            d.set_item("file", &e.file)?;
            d.set_item("path", &e.path)?;
            d.set_item("reason", &e.reason)?;
            Ok(d)
        })
        .collect::<PyResult<Vec<_>>>()?;
    let first = errors.0.first();
    value.setattr("file", first.map(|e| e.file.as_str()))?;
    value.setattr("path", first.map(|e| e.path.as_str()))?;
    value.setattr("reason", first.map(|e| e.reason.as_str()))?;
    value.setattr("errors", list)
}

/// A `ValueError` with `message`: bad arguments, as the command line
/// refuses them (the command exits with 2).
pub fn value_error(message: impl Into<String>) -> PyErr {
    PyValueError::new_err(message.into())
}

/// Parses a backend name (`"cpu"` or `"gpu"`) as the command does.
pub fn check_backend(backend: &str) -> PyResult<()> {
    pleat_cli::check_backend(backend).map_err(value_error)
}
