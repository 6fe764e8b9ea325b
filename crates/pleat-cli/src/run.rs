//! `pleat run`: simulate a scene, export its frames and write report.json.

use crate::output::{Format, Output};
use crate::report::Report;
use crate::{require_cpu, with_threads};
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
    /// Folder for the meshes and report.json.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Mesh format: an OBJ or PLY file per exported frame, or one animated glb.
    #[arg(long, value_enum, default_value_t)]
    pub format: Format,
    /// Export every K-th frame.
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..))]
    pub every: u32,
    /// Worker threads (default: all cores).
    #[arg(long)]
    pub threads: Option<usize>,
    /// Print per-stage timings on stderr.
    #[arg(long)]
    pub profile: bool,
}

pub fn run(args: &RunArgs) -> Result<ExitCode, String> {
    require_cpu(if args.backend.is_empty() {
        "cpu"
    } else {
        &args.backend
    })?;
    let (mut scene, file, base_dir) = load(args.scene.as_deref()).map_err(|e| e.to_string())?;
    if let Some(frames) = args.frames {
        scene.frames = frames;
    }
    let mut sim = scene.build(&base_dir, &file).map_err(|e| e.to_string())?;
    let mut output = match &args.out {
        Some(dir) => Some(Output::create(dir, args.format, &sim, scene.frame_dt())?),
        None => None,
    };
    let every = args.every.max(1);
    let threads = args.threads;
    let frame_times = with_threads(threads, || {
        simulate(&mut sim, &scene, every, output.as_mut())
    })??;
    let report = Report::new(&sim, &scene, "cpu", &frame_times, rayon_threads(threads)?);
    if args.profile {
        eprintln!("{}", report.profile_text());
    }
    println!("{}", report.summary_line());
    if let (Some(out), Some(dir)) = (output, &args.out) {
        out.finish()?;
        let path = dir.join("report.json");
        let json = serde_json::to_string_pretty(&report).map_err(|e| e.to_string())?;
        std::fs::write(&path, json + "\n").map_err(|e| format!("{}: {e}", path.display()))?;
        println!("wrote {}", path.display());
    }
    Ok(if report.nan || report.unstable {
        ExitCode::FAILURE
    } else {
        ExitCode::SUCCESS
    })
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

/// Steps through the scene's frames, exporting every `every`-th; returns each frame's time.
fn simulate(
    sim: &mut Simulation,
    scene: &Scene,
    every: u32,
    mut output: Option<&mut Output>,
) -> Result<Vec<Duration>, String> {
    let bar = ProgressBar::new(scene.frames as u64).with_style(
        ProgressStyle::with_template("{msg} [{bar:40}] {pos}/{len} frames, {per_sec}, eta {eta}")
            .expect("valid template")
            .progress_chars("=> "),
    );
    bar.set_message(scene.name.clone());
    if let Some(out) = output.as_deref_mut() {
        out.frame(0, sim)?;
    }
    let mut times = Vec::with_capacity(scene.frames as usize);
    for frame in 1..=scene.frames {
        let start = Instant::now();
        sim.step(scene.frame_dt());
        times.push(start.elapsed());
        if let Some(out) = output.as_deref_mut() {
            if frame % every == 0 {
                out.frame(frame, sim)?;
            }
        }
        bar.inc(1);
    }
    bar.finish_and_clear();
    Ok(times)
}

/// Threads a pool of `threads` has (all cores when `None`).
fn rayon_threads(threads: Option<usize>) -> Result<usize, String> {
    with_threads(threads, rayon::current_num_threads)
}
