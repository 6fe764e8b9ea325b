//! `pleat fold`: fold a crease pattern (a file or a built-in) as paper with
//! the paper defaults, export its frames and write report.json with the
//! largest fold-angle errors and strain (and where they are); with
//! `--fold-out` the folded state as FOLD. Exits 1 when the run went NaN or
//! unstable.

use crate::output::OutputArgs;
use crate::render::{PictureArgs, Pictures};
use crate::report::Report;
use crate::run::{finish, rayon_threads, run_frames, simulate};
use crate::{backend_for, check_backend, with_threads};
use pleat::folding::{
    folded_state_fold, paper_model, paper_simulation_on, paper_solver_settings, FoldRamp,
};
use pleat::origami::{builtin, load_pattern, CreasePattern, Sheet, SheetOptions, BUILTIN_NAMES};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// Frames the paper is left to settle at the final progress.
const SETTLE_FRAMES: u32 = 60;

/// Frames per second of the fold.
const FPS: f32 = 60.0;

#[derive(clap::Args)]
pub struct FoldArgs {
    /// A .cp, .fold or .svg file, or a built-in pattern (miura-ori,
    /// waterbomb-base, ...).
    pub pattern: String,
    /// Fold progress C in [0, 1]: each crease folds to C times its angle.
    #[arg(long, default_value_t = 1.0)]
    pub progress: f32,
    /// Frames over which the progress rises from 0 to C (then 60 more
    /// frames to settle).
    #[arg(long, default_value_t = 120)]
    pub frames: u32,
    /// cpu or gpu.
    #[arg(long, default_value = "cpu")]
    pub backend: String,
    /// Write the folded state at the end as FOLD (3D vertex coordinates,
    /// each edge's fold angle in degrees) to this file.
    #[arg(long)]
    pub fold_out: Option<PathBuf>,
    #[command(flatten)]
    pub output: OutputArgs,
    /// Draw the fold instead of writing meshes: PNG pictures and anim.gif
    /// in --out (default out/<pattern name>).
    #[arg(long)]
    pub render: bool,
    #[command(flatten)]
    pub picture: PictureArgs,
}

pub fn fold(args: &FoldArgs) -> Result<ExitCode, String> {
    if !(0.0..=1.0).contains(&args.progress) {
        return Err(format!(
            "--progress must be between 0 and 1, got {}",
            args.progress
        ));
    }
    check_backend(&args.backend)?;
    let (pattern, name) = load(&args.pattern)?;
    let sheet = Sheet::from_pattern(&pattern, &SheetOptions::default())
        .map_err(|e| e.with_file(args.pattern.clone()).to_string())?;
    let ramp = FoldRamp {
        progress: args.progress,
        frames: args.frames,
    };
    let (model, world) = paper_model(&sheet);
    let backend = backend_for(&model, &world, &paper_solver_settings(), &args.backend)?;
    let mut sim = paper_simulation_on((model, world), backend, ramp);
    let frame_dt = 1.0 / FPS;
    let frames = (args.frames + SETTLE_FRAMES, frame_dt);
    let threads = rayon_threads(args.output.threads)?;
    let sheet_line = format!(
        "{}: {} vertices, {} triangles, {} creases",
        name,
        sheet.positions.len(),
        sheet.triangles.len(),
        sheet.crease_count()
    );
    let report = if args.render {
        let dir = args
            .output
            .out
            .clone()
            .unwrap_or_else(|| Path::new("out").join(&name));
        let settings = args.picture.settings(None, Path::new("."))?;
        let every = args.output.every;
        let mut pictures = Pictures::create(&dir, &sim, settings, frame_dt * every as f32)?;
        let frame_times = with_threads(args.output.threads, || {
            simulate(&mut sim, &name, frames, every, Some(&mut pictures))
        })??;
        let report = Report::named(&sim, &name, frame_dt, &frame_times, threads);
        crate::print_line(sheet_line);
        crate::render::finish(&report, &pictures, &dir)?;
        report
    } else {
        let (frame_times, output) = run_frames(&mut sim, &name, frames, &args.output)?;
        let report = Report::named(&sim, &name, frame_dt, &frame_times, threads);
        crate::print_line(sheet_line);
        finish(&report, output, &args.output)?;
        report
    };
    if let Some(path) = &args.fold_out {
        write_folded_state(&sim, path)?;
        crate::print_line(format_args!("wrote {}", path.display()));
    }
    Ok(if report.nan || report.unstable {
        ExitCode::FAILURE
    } else {
        ExitCode::SUCCESS
    })
}

/// Writes the folded paper of `sim` as a FOLD file.
fn write_folded_state(sim: &pleat::Simulation, path: &Path) -> Result<(), String> {
    let fold = sim
        .model
        .cloths
        .iter()
        .find_map(|cloth| folded_state_fold(cloth, &sim.particles.x))
        .ok_or("the simulation has no paper to export")?;
    let text = serde_json::to_string_pretty(&fold).map_err(|e| e.to_string())?;
    std::fs::write(path, text + "\n").map_err(|e| format!("{}: {e}", path.display()))
}

/// The pattern `arg` names, read from a file (anything with an extension,
/// or that exists) or built in, and a name for reports.
fn load(arg: &str) -> Result<(CreasePattern, String), String> {
    let path = Path::new(arg);
    if path.extension().is_some() || path.exists() {
        let name = path
            .file_stem()
            .map_or_else(|| arg.to_string(), |s| s.to_string_lossy().into_owned());
        return Ok((load_pattern(path).map_err(|e| e.to_string())?, name));
    }
    let pattern = builtin(arg).ok_or_else(|| {
        format!(
            "'{arg}' is neither a crease-pattern file nor a built-in pattern ({})",
            BUILTIN_NAMES.join(", ")
        )
    })?;
    Ok((pattern, arg.to_string()))
}
