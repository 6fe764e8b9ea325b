//! `pleat fold`: fold a crease pattern (a file or a built-in) as paper with
//! the paper defaults, export its frames and write report.json with the
//! largest fold-angle errors and strain (and where they are); with
//! `--fold-out` the folded state as FOLD. Exits 1 when the run went NaN or
//! unstable.

use crate::output::{FrameSink, Output, OutputArgs};
use crate::render::{PictureArgs, Pictures};
use crate::report::Report;
use crate::run::{print_summary, rayon_threads, simulate, write_outputs};
use crate::{backend_for, check_backend, with_threads};
use pleat::fold_steps::{sheet_step_angles, FoldSteps};
use pleat::folding::{
    folded_state_fold, paper_model, paper_simulation_on, paper_solver_settings_with_contact,
    FoldRamp, LayerOrderFigures,
};
use pleat::origami::{
    builtin, check_flat_foldability, load_pattern_with_warnings, parse_pattern_steps,
    CreasePattern, FlatFoldability, FlatFolded, PatternError, Sheet, SheetOptions, BUILTIN_NAMES,
};
use pleat::Simulation;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Duration;

/// Frames the paper is left to settle at the final progress.
const SETTLE_FRAMES: u32 = 60;

/// Seconds per frame of the fold (60 frames per second).
const FRAME_DT: f32 = 1.0 / 60.0;

#[derive(clap::Args)]
pub struct FoldArgs {
    #[command(flatten)]
    pub paper: PaperArgs,
    /// Draw the fold instead of writing meshes: PNG pictures and anim.gif
    /// in --out (default out/<pattern name>).
    #[arg(long)]
    pub render: bool,
    #[command(flatten)]
    pub picture: PictureArgs,
}

/// What to fold and where the results go: `pleat fold`'s options less the
/// pictures'.
#[derive(clap::Args)]
pub struct PaperArgs {
    /// A .cp, .fold or .svg file, or a built-in pattern (miura-ori,
    /// waterbomb-base, ...).
    pub pattern: String,
    /// Fold progress C in [0, 1]: each crease folds to C times its angle.
    #[arg(long, default_value_t = 1.0)]
    pub progress: f32,
    /// Frames over which the progress rises from 0 to C (then 60 more
    /// frames to settle); for a pattern folded in steps (a multi-frame
    /// FOLD file), the frames of each step.
    #[arg(long, default_value_t = 120)]
    pub frames: u32,
    /// cpu or gpu.
    #[arg(long, default_value = "cpu")]
    pub backend: String,
    /// Write the folded state at the end as FOLD (3D vertex coordinates,
    /// each edge's fold angle in degrees) to this file.
    #[arg(long)]
    pub fold_out: Option<PathBuf>,
    /// Paper thickness in metres on the sheet scaled to 1 m: its layers are
    /// kept this far apart (self-contact; 0.0005 is real paper's 0.1 mm on
    /// a 20 cm sheet). 0, the default, folds without contact.
    #[arg(long, default_value_t = 0.0)]
    pub thickness: f32,
    #[command(flatten)]
    pub output: OutputArgs,
}

/// A crease pattern made into paper, ready to fold.
pub struct Paper {
    /// The paper on its backend, its fold ramp set.
    pub sim: Simulation,
    /// The pattern's name, for reports.
    pub name: String,
    /// `name: V vertices, T triangles, C creases`.
    pub summary: String,
    /// Kawasaki's and Maekawa's theorems at the pattern's vertices.
    pub flat_foldability: FlatFoldability,
    /// The flat-folded state and its layer order, where every crease folds
    /// flat and every vertex meets the theorems.
    pub flat_folded: Option<Result<FlatFolded, PatternError>>,
}

impl Paper {
    /// Steps the paper through `frames` frames of their length, handing
    /// each to `sink`, on `threads` threads; returns each frame's time.
    fn step_all(
        &mut self,
        frames: (u32, f32),
        sink: &mut (impl FrameSink + Send),
        threads: Option<usize>,
    ) -> Result<Vec<Duration>, String> {
        with_threads(threads, || {
            simulate(&mut self.sim, &self.name, frames, 1, Some(sink), None)
        })?
    }

    /// report.json's contents for the run that took `frame_times`.
    fn report(&self, frame_times: &[Duration], threads: usize) -> Report {
        Report {
            flat_foldability: Some(self.flat_foldability.clone()),
            layer_order: self.flat_folded.as_ref().map(|solved| {
                LayerOrderFigures::of(solved, &self.sim.model.cloths[0], &self.sim.particles.x)
            }),
            ..Report::named(&self.sim, &self.name, FRAME_DT, frame_times, threads)
        }
    }
}

/// What a fold without pictures measured and wrote.
pub struct Folded {
    /// The folded paper.
    pub paper: Paper,
    /// report.json's contents.
    pub report: Report,
    /// The files written: report.json (with `--out`) and the FOLD file
    /// (with `--fold-out`).
    pub written: Vec<PathBuf>,
}

/// Checks `args` and builds the paper of its pattern on its backend.
pub fn paper(args: &PaperArgs) -> Result<Paper, String> {
    if !(0.0..=1.0).contains(&args.progress) {
        return Err(format!(
            "--progress must be between 0 and 1, got {}",
            args.progress
        ));
    }
    check_backend(&args.backend)?;
    if !(args.thickness >= 0.0 && args.thickness < 0.1) {
        return Err(format!(
            "--thickness must be at least 0 and below 0.1 m (a tenth of the sheet), got {}",
            args.thickness
        ));
    }
    let (pattern, name, steps) = load(&args.pattern)?;
    let sheet = Sheet::from_pattern(&pattern, &SheetOptions::default())
        .map_err(|e| e.with_file(args.pattern.clone()).to_string())?;
    if !steps.is_empty() && args.progress != 1.0 {
        return Err(format!(
            "{}: --progress does not apply to a pattern folded in steps ({} steps, each of --frames frames)",
            args.pattern,
            steps.len()
        ));
    }
    let steps = sheet_step_angles(&pattern, &SheetOptions::default(), &sheet, &steps)
        .map_err(|e| e.with_file(args.pattern.clone()).to_string())?;
    let flat_foldability = check_flat_foldability(&pattern)
        .map_err(|e| e.with_file(args.pattern.clone()).to_string())?;
    let flat_folded = (flat_foldability.is_flat_foldable()
        && flat_foldability.vertices_skipped == 0)
        .then(|| FlatFolded::solve(&sheet));
    let ramp = FoldRamp {
        progress: args.progress,
        frames: args.frames,
    };
    let (mut model, world) = paper_model(&sheet);
    let step_count = steps.len();
    if let Some(paper) = model.cloths[0].paper.as_mut() {
        paper.steps = steps;
    }
    let settings = paper_solver_settings_with_contact(args.thickness);
    let backend = backend_for(&model, &world, &settings, &args.backend)?;
    let mut summary = format!(
        "{}: {} vertices, {} triangles, {} creases",
        name,
        sheet.positions.len(),
        sheet.triangles.len(),
        sheet.crease_count()
    );
    if step_count > 0 {
        summary += &format!(", folded in {step_count} steps of {} frames", args.frames);
    }
    if args.thickness > 0.0 {
        summary += &format!(", layers {} m apart", args.thickness);
    }
    let mut sim = paper_simulation_on((model, world), settings, backend, ramp);
    sim.fold_steps = FoldSteps::of_model(&sim.model, &[args.frames]);
    Ok(Paper {
        sim,
        name,
        summary,
        flat_foldability,
        flat_folded,
    })
}

/// Folds as `args` ask, without pictures and without printing: the
/// meshes and report.json go to `args.output.out`, the folded state to
/// `args.fold_out`, where given (with each step's end as a frame, for a
/// fold in steps).
pub fn fold_meshes(args: &PaperArgs) -> Result<Folded, String> {
    let mut paper = paper(args)?;
    let threads = rayon_threads(args.output.threads)?;
    let frames = frames(&paper.sim, args);
    let mut output = match &args.output.out {
        Some(dir) => Some(Output::create(
            dir,
            args.output.format,
            &paper.sim,
            FRAME_DT,
        )?),
        None => None,
    };
    let mut sink = StepStates::new(&paper.sim, output.as_mut(), args.output.every.max(1));
    let frame_times = paper.step_all(frames, &mut sink, args.output.threads)?;
    let steps = sink.states;
    let report = paper.report(&frame_times, threads);
    let mut written: Vec<PathBuf> = write_outputs(&report, output, &args.output)?
        .into_iter()
        .collect();
    if let Some(path) = &args.fold_out {
        write_folded_state(&paper.sim, &steps, path)?;
        written.push(path.clone());
    }
    Ok(Folded {
        paper,
        report,
        written,
    })
}

/// The frames of a fold (the ramp, or every step, then the settling) and
/// their length.
fn frames(sim: &Simulation, args: &PaperArgs) -> (u32, f32) {
    let folding = sim
        .fold_steps
        .as_ref()
        .map_or(args.frames, |s| s.total_frames());
    (folding + SETTLE_FRAMES, FRAME_DT)
}

pub fn fold(args: &FoldArgs) -> Result<ExitCode, String> {
    let report = if args.render {
        let mut paper = paper(&args.paper)?;
        let threads = rayon_threads(args.paper.output.threads)?;
        let dir = args
            .paper
            .output
            .out
            .clone()
            .unwrap_or_else(|| Path::new("out").join(&paper.name));
        let settings = args.picture.settings(None, Path::new("."))?;
        let every = args.paper.output.every;
        let mut pictures = Pictures::create(&dir, &paper.sim, settings, FRAME_DT * every as f32)?;
        let frames = frames(&paper.sim, &args.paper);
        let mut sink = StepStates::new(&paper.sim, Some(&mut pictures), every.max(1));
        let frame_times = paper.step_all(frames, &mut sink, args.paper.output.threads)?;
        let steps = sink.states;
        let report = paper.report(&frame_times, threads);
        crate::print_line(&paper.summary);
        print_flat_foldability(&report);
        crate::render::finish(&report, &pictures, &dir)?;
        if let Some(path) = &args.paper.fold_out {
            write_folded_state(&paper.sim, &steps, path)?;
            crate::print_line(format_args!("wrote {}", path.display()));
        }
        report
    } else {
        let folded = fold_meshes(&args.paper)?;
        crate::print_line(&folded.paper.summary);
        print_flat_foldability(&folded.report);
        print_summary(&folded.report);
        for path in &folded.written {
            crate::print_line(format_args!("wrote {}", path.display()));
        }
        folded.report
    };
    Ok(if report.nan || report.unstable {
        ExitCode::FAILURE
    } else {
        ExitCode::SUCCESS
    })
}

/// Prints whether the pattern folds flat: a line when it does, a warning
/// on stderr where it does not (a partial fold of it is still folded).
fn print_flat_foldability(report: &Report) {
    let Some(check) = &report.flat_foldability else {
        return;
    };
    if check.is_flat_foldable() {
        crate::print_line(check.summary());
    } else {
        eprintln!("warning: {}", check.summary());
    }
    if let Some(layers) = &report.layer_order {
        print_layer_order(layers);
    }
}

/// Prints the pattern's layer order and how the folded paper's layers
/// agree with it: a line when they do, a warning where they do not.
fn print_layer_order(layers: &LayerOrderFigures) {
    let Some(sim) = &layers.simulated else {
        eprintln!(
            "warning: {}",
            layers.reason.as_deref().unwrap_or("no layer order")
        );
        return;
    };
    let order = format!(
        "layer order: {} facets, {} pairs overlap when folded flat ({} forced), {} conditions",
        layers.facets, layers.overlapping_pairs, layers.forced_pairs, layers.conditions
    );
    if sim.valid {
        crate::print_line(format_args!(
            "{order}; the folded paper stacks {} pairs, in a valid order ({} as solved)",
            sim.pairs, sim.as_solved
        ));
    } else {
        eprintln!(
            "warning: {order}; the folded paper's {} stacked pairs break it: {} creases stacked the wrong way round, {} of {} conditions broken, {} pairs stacked both ways",
            sim.pairs, sim.creases_broken, sim.conditions_broken, sim.conditions_checked, sim.both_ways
        );
    }
}

/// Hands every `every`-th frame to `inner` (the meshes or the pictures)
/// and keeps the folded state at the end of each step of a fold in steps.
struct StepStates<'a, S: FrameSink + ?Sized> {
    inner: Option<&'a mut S>,
    every: u32,
    /// The last frame of each step.
    ends: Vec<u32>,
    /// The folded state (FOLD) at the end of each step so far.
    states: Vec<serde_json::Value>,
}

impl<'a, S: FrameSink + ?Sized> StepStates<'a, S> {
    fn new(sim: &Simulation, inner: Option<&'a mut S>, every: u32) -> Self {
        let ends = sim.fold_steps.as_ref().map_or_else(Vec::new, |s| {
            s.frames
                .iter()
                .scan(0, |end, &n| {
                    *end += n;
                    Some(*end)
                })
                .collect()
        });
        StepStates {
            inner,
            every,
            ends,
            states: Vec::new(),
        }
    }
}

impl<S: FrameSink + ?Sized> FrameSink for StepStates<'_, S> {
    fn frame(&mut self, index: u32, sim: &Simulation) -> Result<(), String> {
        if self.ends.contains(&index) {
            if let Some(state) = paper_state(sim) {
                self.states.push(state);
            }
        }
        match &mut self.inner {
            Some(inner) if index % self.every == 0 => inner.frame(index, sim),
            _ => Ok(()),
        }
    }

    fn reads_particles(&self) -> bool {
        !self.ends.is_empty() || self.inner.as_ref().is_none_or(|i| i.reads_particles())
    }

    fn wants(&self, index: u32) -> bool {
        self.ends.contains(&index)
    }
}

/// The folded state of `sim`'s paper as FOLD, if it has paper.
fn paper_state(sim: &Simulation) -> Option<serde_json::Value> {
    sim.model
        .cloths
        .iter()
        .find_map(|cloth| folded_state_fold(cloth, &sim.particles.x))
}

/// Writes the folded paper of `sim` as a FOLD file; a fold in steps adds
/// the folded state at the end of each step (`steps`) as a frame of
/// `file_frames` (its vertices and fold angles; the rest inherited from
/// the key frame, the state at the end).
pub fn write_folded_state(
    sim: &Simulation,
    steps: &[serde_json::Value],
    path: &Path,
) -> Result<(), String> {
    let mut fold = paper_state(sim).ok_or("the simulation has no paper to export")?;
    if !steps.is_empty() {
        let frames: Vec<serde_json::Value> = steps
            .iter()
            .enumerate()
            .map(|(k, state)| {
                serde_json::json!({
                    "frame_title": format!("end of step {} of {}", k + 1, steps.len()),
                    "frame_parent": 0,
                    "frame_inherit": true,
                    "vertices_coords": state["vertices_coords"],
                    "edges_foldAngle": state["edges_foldAngle"],
                })
            })
            .collect();
        fold["file_frames"] = serde_json::Value::Array(frames);
    }
    let text = serde_json::to_string_pretty(&fold).map_err(|e| e.to_string())?;
    std::fs::write(path, text + "\n").map_err(|e| format!("{}: {e}", path.display()))
}

/// Each pattern edge's fold angle at the end of each step (degrees).
type EdgeAngles = Vec<Vec<Option<f64>>>;

/// The pattern `arg` names, read from a file (anything with an extension,
/// or that exists) or built in, a name for reports, and the file's steps
/// (each edge's angle at each step's end; none but for a multi-frame FOLD
/// file).
fn load(arg: &str) -> Result<(CreasePattern, String, EdgeAngles), String> {
    let path = Path::new(arg);
    if path.extension().is_some() || path.exists() {
        let name = path
            .file_stem()
            .map_or_else(|| arg.to_string(), |s| s.to_string_lossy().into_owned());
        let (pattern, warnings) = load_pattern_with_warnings(path).map_err(|e| e.to_string())?;
        for w in warnings {
            eprintln!("warning: {arg}: {w}");
        }
        let bytes = std::fs::read(path).map_err(|e| format!("{arg}: {e}"))?;
        let steps = parse_pattern_steps(arg, &bytes, &pattern).map_err(|e| e.to_string())?;
        return Ok((pattern, name, steps));
    }
    let pattern = builtin(arg).ok_or_else(|| {
        format!(
            "'{arg}' is neither a crease-pattern file nor a built-in pattern ({})",
            BUILTIN_NAMES.join(", ")
        )
    })?;
    Ok((pattern, arg.to_string(), Vec::new()))
}
