//! The `pleat` command's work, as a library: each subcommand's module
//! (`run`, `check`, `bench`, `render`, `fold`, `compare`), the report it
//! writes (`report`), and how a scene becomes a simulation on the backend a
//! user names ([`build_on`], [`backend_for`]). The `pleat` binary parses the
//! command line and calls in; the Python bindings (crates/pleat-py) call the
//! same code, so both give the same reports, validation and messages
//! (DESIGN.md section 5 for the contracts).

pub mod advice;
pub mod bench;
pub mod check;
pub mod compare;
pub mod fold;
pub mod output;
pub mod render;
pub mod report;
pub mod run;

use pleat::scene::Scene;
use pleat::{Backend, CpuBackend, Model, Simulation, SolverSettings, World};
use std::path::Path;

/// Prints a line on stdout. A closed pipe (`pleat check ... | head -1`) ends
/// the program quietly with success, as the SIGPIPE of other tools would;
/// any other write error ends it with a message.
pub fn print_line(line: impl std::fmt::Display) {
    use std::io::Write;
    if let Err(e) = writeln!(std::io::stdout(), "{line}") {
        if e.kind() == std::io::ErrorKind::BrokenPipe {
            std::process::exit(0);
        }
        eprintln!("error: cannot write to stdout: {e}");
        std::process::exit(2);
    }
}

/// Runs `f` on a rayon pool of `threads` threads (all cores when `None`).
pub fn with_threads<R: Send>(
    threads: Option<usize>,
    f: impl FnOnce() -> R + Send,
) -> Result<R, String> {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads.unwrap_or(0))
        .build()
        .map_err(|e| format!("cannot start {threads:?} threads: {e}"))?;
    Ok(pool.install(f))
}

/// Refuses a backend name other than `cpu` and `gpu`.
pub fn check_backend(backend: &str) -> Result<(), String> {
    match backend {
        "cpu" | "gpu" => Ok(()),
        other => Err(format!("unknown backend '{other}': use cpu or gpu")),
    }
}

/// The simulation `scene` describes (paths relative to `base_dir`, `file`
/// naming it in errors) on the backend named `backend`, each built once;
/// the warnings of its crease patterns' importers go to stderr.
pub fn build_on(
    scene: &Scene,
    (base_dir, file): (&Path, &str),
    backend: &str,
) -> Result<Simulation, String> {
    check_backend(backend)?;
    let (model, world, warnings) = scene
        .model_and_warnings(base_dir, file)
        .map_err(|e| e.to_string())?;
    for w in warnings {
        eprintln!("warning: {w}");
    }
    let backend = backend_for(&model, &world, &scene.solver, backend)?;
    Ok(scene.simulation(model, world, backend))
}

/// The backend named `backend` (`cpu` or `gpu`) built for `model` in
/// `world`. The GPU backend's notes (mesh colliders baked into distance
/// fields) go to stderr; no adapter, or a scene feature the GPU lacks, is
/// an error.
pub fn backend_for(
    model: &Model,
    world: &World,
    settings: &SolverSettings,
    backend: &str,
) -> Result<Box<dyn Backend>, String> {
    if backend != "gpu" {
        return Ok(Box::new(CpuBackend::new(model, settings)));
    }
    let context = pleat_gpu::GpuContext::new().map_err(advice::gpu_error)?;
    let (gpu, notes) =
        pleat_gpu::GpuBackend::new(&context, model, world, settings).map_err(advice::gpu_error)?;
    for note in notes {
        eprintln!("note: {note}");
    }
    Ok(Box::new(gpu))
}
