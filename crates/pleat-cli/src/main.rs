//! The `pleat` command: headless runs, pictures, checks and benchmarks of
//! cloth and origami scenes (see DESIGN.md section 5 for the contracts).
//! The work is done by the `pleat_cli` library; this parses the command line.

use clap::{Parser, Subcommand};
use pleat_cli::{bench, check, compare, fold, render, run};
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
