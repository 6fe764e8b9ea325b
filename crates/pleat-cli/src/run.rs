//! `pleat run`: simulate a scene, export its frames and write report.json.

use crate::output::{FrameSink, Output, OutputArgs};
use crate::report::{CheckedCrossings, Report};
use crate::{build_on, check_backend, with_threads};
use indicatif::{ProgressBar, ProgressStyle};
use pleat::scene::Scene;
use pleat::Simulation;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::{Duration, Instant};

/// The scene `pleat` runs when given none: a cloth draped over a sphere onto the ground.
pub const DEFAULT_SCENE: &str = include_str!("../../../scenes/drape.json");

#[derive(clap::Args, Default)]
pub struct RunArgs {
    /// Scene file (JSON); the embedded drape scene if absent.
    pub scene: Option<PathBuf>,
    /// Frames to simulate (overrides the scene's).
    #[arg(long)]
    pub frames: Option<u32>,
    /// cpu or gpu.
    #[arg(long, default_value = "cpu")]
    pub backend: String,
    #[command(flatten)]
    pub output: OutputArgs,
    /// Print per-stage timings on stderr.
    #[arg(long)]
    pub profile: bool,
    /// Count self-intersections at every N-th frame too, not only at the
    /// last (report.json's `self_intersections_every`).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..))]
    pub check_every: Option<u32>,
}

pub fn run(args: &RunArgs) -> Result<ExitCode, String> {
    let backend = if args.backend.is_empty() {
        "cpu"
    } else {
        &args.backend
    };
    check_backend(backend)?;
    let (mut scene, file, base_dir) = load(args.scene.as_deref()).map_err(|e| e.to_string())?;
    if let Some(frames) = args.frames {
        scene.frames = frames;
    }
    let mut sim = build_on(&scene, (&base_dir, &file), backend)?;
    let mut checked = args.check_every.map(CheckedCrossings::new);
    let (frame_times, output) = run_frames(
        &mut sim,
        &scene.name,
        (scene.frames, scene.frame_dt()),
        &args.output,
        checked.as_mut(),
    )?;
    let mut report = Report::new(
        &sim,
        &scene,
        &frame_times,
        rayon_threads(args.output.threads)?,
    );
    report.self_intersections_every = checked;
    if args.profile {
        eprintln!("{}", report.profile_text());
    }
    finish(&report, output, &args.output)?;
    Ok(if report.nan || report.unstable {
        ExitCode::FAILURE
    } else {
        ExitCode::SUCCESS
    })
}

/// Steps `sim` through `frames` frames of `frame_dt` on the threads of
/// `args`, exporting as it asks and counting self-intersections where
/// `checked` asks; returns each frame's time and the output still to be
/// finished.
pub fn run_frames(
    sim: &mut Simulation,
    name: &str,
    frames: (u32, f32),
    args: &OutputArgs,
    checked: Option<&mut CheckedCrossings>,
) -> Result<(Vec<Duration>, Option<Output>), String> {
    let mut output = match &args.out {
        Some(dir) => Some(Output::create(dir, args.format, sim, frames.1)?),
        None => None,
    };
    let every = args.every.max(1);
    let times = with_threads(args.threads, || {
        simulate(
            sim,
            name,
            frames,
            every,
            output.as_mut().map(|o| o as &mut dyn FrameSink),
            checked,
        )
    })??;
    Ok((times, output))
}

/// Prints the report's summary and writes the exports and report.json.
pub fn finish(report: &Report, output: Option<Output>, args: &OutputArgs) -> Result<(), String> {
    print_summary(report);
    if let Some(path) = write_outputs(report, output, args)? {
        crate::print_line(format_args!("wrote {}", path.display()));
    }
    Ok(())
}

/// Prints the report's summary line, and its fold line where there is paper.
pub fn print_summary(report: &Report) {
    crate::print_line(format_args!("{}", report.summary_line()));
    if let Some(checked) = &report.self_intersections_every {
        crate::print_line(format_args!("{}", checked.line()));
    }
    if let Some(line) = report.fold_line() {
        crate::print_line(format_args!("{line}"));
    }
}

/// Writes what is left of the exports and report.json, with `--out`;
/// returns report.json's path.
pub fn write_outputs(
    report: &Report,
    output: Option<Output>,
    args: &OutputArgs,
) -> Result<Option<PathBuf>, String> {
    match (output, &args.out) {
        (Some(out), Some(dir)) => {
            out.finish()?;
            report.write(dir).map(Some)
        }
        _ => Ok(None),
    }
}

/// The scene, its name for messages and the folder its relative paths start from.
pub fn load(path: Option<&Path>) -> Result<(Scene, String, PathBuf), pleat::scene::SceneErrors> {
    match path {
        Some(p) => {
            let base = p
                .parent()
                .map_or_else(|| PathBuf::from("."), Path::to_path_buf);
            Ok((Scene::load(p)?, p.display().to_string(), base))
        }
        None => {
            let file = "<embedded drape.json>".to_string();
            Ok((
                Scene::parse(DEFAULT_SCENE, &file)?,
                file,
                PathBuf::from("."),
            ))
        }
    }
}

/// Steps through `frames` frames of `frame_dt` seconds, handing frame 0 and
/// every `every`-th to `output` and each frame to `checked` (not timed);
/// returns each frame's time.
pub fn simulate(
    sim: &mut Simulation,
    name: &str,
    (frames, frame_dt): (u32, f32),
    every: u32,
    mut output: Option<&mut dyn FrameSink>,
    mut checked: Option<&mut CheckedCrossings>,
) -> Result<Vec<Duration>, String> {
    let bar = ProgressBar::new(frames as u64).with_style(
        ProgressStyle::with_template("{msg} [{bar:40}] {pos}/{len} frames, {per_sec}, eta {eta}")
            .expect("valid template")
            .progress_chars("=> "),
    );
    bar.set_message(name.to_string());
    if let Some(out) = output.as_deref_mut() {
        out.frame(0, sim)?;
    }
    let mut times = Vec::with_capacity(frames as usize);
    for frame in 1..=frames {
        let start = Instant::now();
        sim.step(frame_dt);
        sim.finish();
        times.push(start.elapsed());
        let export = output
            .as_deref()
            .is_some_and(|o| frame % every == 0 || o.wants(frame));
        let reads = output.as_deref().is_some_and(|o| o.reads_particles());
        // Instability is watched at every frame without a read of the
        // state: a GPU backend reduces it on the device.
        if export && reads {
            sim.sync();
        }
        if let (Some(out), true) = (output.as_deref_mut(), export) {
            out.frame(frame, sim)?;
        }
        if let Some(checked) = checked.as_deref_mut() {
            checked.frame(frame, sim);
        }
        bar.inc(1);
    }
    sim.sync();
    bar.finish_and_clear();
    Ok(times)
}

/// Threads a pool of `threads` has (all cores when `None`).
pub fn rayon_threads(threads: Option<usize>) -> Result<usize, String> {
    with_threads(threads, rayon::current_num_threads)
}
