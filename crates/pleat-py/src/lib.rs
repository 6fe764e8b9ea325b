//! `pleat._pleat`: the native half of the `pleat` Python package.
//!
//! Scenes ([`scene`]), simulations with their state as numpy arrays
//! ([`simulation`]), their live settings ([`settings`]), mesh export
//! ([`export`]), `pleat fold` and `pleat bench` as functions ([`commands`])
//! and the exceptions they raise ([`errors`]). Everything a scene file or a
//! command does goes through the same code as the `pleat` command (the
//! `pleat_cli` library and the core), so Python gets the same validation,
//! messages and reports. The plain Python half (python/pleat) adds the
//! sweeps on Ray.

#![warn(missing_docs)]

mod commands;
mod errors;
mod export;
mod json;
mod scene;
mod settings;
mod simulation;

use pyo3::prelude::*;

/// The native module; `pleat/__init__.py` re-exports what users need.
#[pymodule]
fn _pleat(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add("SceneError", py.get_type::<errors::SceneError>())?;
    m.add("BackendError", py.get_type::<errors::BackendError>())?;
    m.add_class::<scene::PyScene>()?;
    m.add_class::<simulation::PySimulation>()?;
    m.add_class::<settings::PySettings>()?;
    m.add_function(wrap_pyfunction!(commands::fold, m)?)?;
    m.add_function(wrap_pyfunction!(commands::bench, m)?)?;
    Ok(())
}
