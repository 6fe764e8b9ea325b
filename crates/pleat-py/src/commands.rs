//! `pleat.fold` and `pleat.bench`: the commands `pleat fold` and `pleat
//! bench` as functions, run by the command's own code with the GIL
//! released, returning what the command writes (report.json, or one bench
//! line a size) as dicts.

use crate::errors::value_error;
use crate::json;
use pleat_cli::bench::{measure, validate, BenchArgs};
use pleat_cli::fold::{fold_meshes, PaperArgs};
use pleat_cli::output::{Format, OutputArgs};
use pyo3::prelude::*;
use pyo3::types::PyList;
use std::path::PathBuf;

/// The mesh format named `format`.
fn format(format: &str) -> PyResult<Format> {
    match format {
        "obj" => Ok(Format::Obj),
        "ply" => Ok(Format::Ply),
        "glb" => Ok(Format::Glb),
        other => Err(value_error(format!(
            "unknown format '{other}': use obj, ply or glb"
        ))),
    }
}

/// Folds a crease pattern (a .cp, .fold or .svg file, or a built-in name
/// such as "miura-ori") as paper, as `pleat fold` does: the progress rises
/// from 0 to `progress` over `frames` frames, then 60 frames settle. With
/// `out`, writes the meshes and report.json there; with `fold_out`, the
/// folded state as FOLD; with `thickness` (m, on the sheet scaled to 1 m),
/// its layers are kept that far apart. Returns report.json's fields as a
/// dict.
#[pyfunction]
#[pyo3(signature = (
    pattern, progress = 1.0, frames = 120, backend = "cpu".to_owned(), threads = None,
    out = None, format = "obj", every = 1, fold_out = None, thickness = 0.0
))]
#[allow(clippy::too_many_arguments)] // Python's keyword arguments, as the command's options.
pub fn fold<'py>(
    py: Python<'py>,
    pattern: String,
    progress: f32,
    frames: u32,
    backend: String,
    threads: Option<usize>,
    out: Option<PathBuf>,
    format: &str,
    every: u32,
    fold_out: Option<PathBuf>,
    thickness: f32,
) -> PyResult<Bound<'py, PyAny>> {
    if every == 0 {
        return Err(value_error("every must be at least 1"));
    }
    let args = PaperArgs {
        pattern,
        progress,
        frames,
        backend,
        fold_out,
        thickness,
        output: OutputArgs {
            out,
            format: self::format(format)?,
            every,
            threads,
        },
    };
    let report = py
        .detach(|| fold_meshes(&args).map(|folded| serde_json::to_string(&folded.report)))
        .map_err(value_error)?
        .map_err(|e| value_error(e.to_string()))?;
    json::loads(py, &report)
}

/// Times the standard hanging cloth (N x N, 1 m, pinned at its two top
/// corners) at each size, as `pleat bench --json` does; returns its lines
/// as dicts, one a size.
#[pyfunction]
#[pyo3(signature = (
    sizes = vec![64, 128, 256], backend = "cpu".to_owned(), substeps = 10, self_collision = false,
    frames = 60, warmup = 30, tethers = false, threads = None
))]
#[allow(clippy::too_many_arguments)] // Python's keyword arguments, as the command's options.
pub fn bench<'py>(
    py: Python<'py>,
    sizes: Vec<u32>,
    backend: String,
    substeps: u32,
    self_collision: bool,
    frames: u32,
    warmup: u32,
    tethers: bool,
    threads: Option<usize>,
) -> PyResult<Bound<'py, PyList>> {
    let args = BenchArgs {
        backend,
        sizes,
        substeps,
        self_collision,
        frames,
        warmup,
        tethers,
        threads,
        json: true,
    };
    validate(&args).map_err(value_error)?;
    let lines = PyList::empty(py);
    for &n in &args.sizes {
        let line = py.detach(|| measure(&args, n)).map_err(value_error)?;
        lines.append(json::to_py(py, &line)?)?;
    }
    Ok(lines)
}
