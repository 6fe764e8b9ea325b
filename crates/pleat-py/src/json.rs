//! Values crossing to Python as JSON: reports and scenes become the dicts
//! and lists `json.loads` makes of the files the command writes, so a
//! dict from Python and report.json from the command are the same by
//! construction.

use pyo3::exceptions::PyRuntimeError;
use pyo3::prelude::*;

/// A Python object from JSON text.
pub fn loads<'py>(py: Python<'py>, text: &str) -> PyResult<Bound<'py, PyAny>> {
    py.import("json")?.call_method1("loads", (text,))
}

/// JSON text of a Python object (dicts, lists, numbers, strings).
pub fn dumps(value: &Bound<'_, PyAny>) -> PyResult<String> {
    value
        .py()
        .import("json")?
        .call_method1("dumps", (value,))?
        .extract()
}

/// The Python object of anything serde writes as JSON.
pub fn to_py<'py>(py: Python<'py>, value: &impl serde::Serialize) -> PyResult<Bound<'py, PyAny>> {
    let text = serde_json::to_string(value).map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
    loads(py, &text)
}
