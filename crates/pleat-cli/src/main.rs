//! The `pleat` command: headless runs, pictures, checks and benchmarks of
//! cloth and origami scenes (see DESIGN.md section 5 for the contracts).

mod advice;
mod bench;
mod check;
mod compare;
mod fold;
mod output;
mod render;
mod report;
mod run;

use clap::{Parser, Subcommand};
use pleat::scene::Scene;
use pleat::{Backend, CpuBackend, Model, Simulation, SolverSettings, World};
use std::path::Path;
use std::process::ExitCode;

#[derive(Parser)]
#[command(name = "pleat", version, about = "Cloth and origami simulation", long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
}

#[derive(Subcommand)]
enum Command {
    /// Simulate a scene (the embedded drape scene if none is given).
    Run(run::RunArgs),
    /// Validate scene, mesh and crease-pattern files without simulating.
    Check(check::CheckArgs),
    /// Time the standard hanging cloth at several sizes.
    Bench(bench::BenchArgs),
    /// Simulate a scene and draw it: PNG pictures and an animated GIF.
    Render(render::RenderArgs),
    /// Fold a crease pattern (a .cp, .fold or .svg file, or a built-in) as paper.
    Fold(fold::FoldArgs),
    /// Run one scene with every solver: table, stretch plot and stability sweep.
    Compare(compare::CompareArgs),
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        None => run::run(&run::RunArgs::default()),
        Some(Command::Run(args)) => run::run(&args),
        Some(Command::Check(args)) => check::check(&args),
        Some(Command::Bench(args)) => bench::bench(&args),
        Some(Command::Render(args)) => render::render(&args),
        Some(Command::Fold(args)) => fold::fold(&args),
        Some(Command::Compare(args)) => compare::compare(&args),
    };
    match result {
        Ok(code) => code,
        Err(message) => {
            eprintln!("error: {message}");
            ExitCode::from(2)
        }
    }
}

/// Prints a line on stdout. A closed pipe (`pleat check ... | head -1`) ends
/// the program quietly with success, as the SIGPIPE of other tools would;
/// any other write error ends it with a message.
fn print_line(line: impl std::fmt::Display) {
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
fn with_threads<R: Send>(
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
fn check_backend(backend: &str) -> Result<(), String> {
    match backend {
        "cpu" | "gpu" => Ok(()),
        other => Err(format!("unknown backend '{other}': use cpu or gpu")),
    }
}

/// The simulation `scene` describes (paths relative to `base_dir`, `file`
/// naming it in errors) on the backend named `backend`, each built once.
fn build_on(
    scene: &Scene,
    (base_dir, file): (&Path, &str),
    backend: &str,
) -> Result<Simulation, String> {
    check_backend(backend)?;
    let (model, world) = scene.model(base_dir, file).map_err(|e| e.to_string())?;
    let backend = backend_for(&model, &world, &scene.solver, backend)?;
    Ok(scene.simulation(model, world, backend))
}

/// The backend named `backend` (`cpu` or `gpu`) built for `model` in
/// `world`. The GPU backend's notes (mesh colliders baked into distance
/// fields) go to stderr; no adapter, or a scene feature the GPU lacks, is
/// an error.
fn backend_for(
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
