//! `pleat bench`: whole-frame timings of the standard hanging cloth
//! (DESIGN.md section 5), as a table or one JSON object a line.

use crate::report::{dispatches_per_frame, self_contact_builds_per_frame, FrameTimes, StagesMs};
use crate::{build_on, check_backend, with_threads};
use pleat::metrics::stretch;
use pleat::scene::presets::hanging_cloth;
use serde::Serialize;
use std::path::Path;
use std::process::ExitCode;
use std::time::Instant;

#[derive(clap::Args)]
pub struct BenchArgs {
    /// cpu or gpu.
    #[arg(long, default_value = "cpu")]
    pub backend: String,
    /// Cloth sizes N (N x N particles), comma separated.
    #[arg(long, value_delimiter = ',', default_values_t = [64u32, 128, 256])]
    pub sizes: Vec<u32>,
    #[arg(long, default_value_t = 10, value_parser = clap::value_parser!(u32).range(SUBSTEPS))]
    pub substeps: u32,
    /// Solve self-collision too.
    #[arg(long)]
    pub self_collision: bool,
    /// Timed frames per size.
    #[arg(long, default_value_t = 60, value_parser = clap::value_parser!(u32).range(1..))]
    pub frames: u32,
    /// Frames simulated before timing starts.
    #[arg(long, default_value_t = 30)]
    pub warmup: u32,
    /// Long-range attachments from the pins.
    #[arg(long)]
    pub tethers: bool,
    /// Worker threads (default: all cores).
    #[arg(long)]
    pub threads: Option<usize>,
    /// One JSON object a line instead of a table.
    #[arg(long)]
    pub json: bool,
}

/// The substeps a bench may ask for.
const SUBSTEPS: std::ops::RangeInclusive<i64> = 1..=1000;

/// One line of `pleat bench --json`.
#[derive(Serialize)]
pub struct BenchLine {
    backend: &'static str,
    /// The device that ran it (a GPU adapter's name).
    device: String,
    n: u32,
    particles: usize,
    substeps: u32,
    self_collision: bool,
    ms_per_frame: f64,
    max_stretch: f32,
    p95_ms: f64,
    frames: u32,
    threads: usize,
    tethers: bool,
    /// Time per stage over the timed frames.
    stages_ms: StagesMs,
    /// Compute dispatches a frame on a GPU (mean over the timed frames);
    /// null on the CPU.
    dispatches_per_frame: Option<f64>,
    /// Builds of the self-contact candidates a frame on a GPU with
    /// self-collision (mean over the timed frames); null elsewhere.
    self_contact_builds_per_frame: Option<f64>,
}

pub fn bench(args: &BenchArgs) -> Result<ExitCode, String> {
    validate(args)?;
    if !args.json {
        crate::print_line(format_args!(
            "{:>6} {:>10} {:>9} {:>12} {:>10} {:>12}",
            "n", "particles", "substeps", "ms/frame", "p95 ms", "max stretch"
        ));
    }
    for &n in &args.sizes {
        let line = measure(args, n)?;
        if args.json {
            crate::print_line(format_args!(
                "{}",
                serde_json::to_string(&line).map_err(|e| e.to_string())?
            ));
        } else {
            crate::print_line(format_args!(
                "{:>6} {:>10} {:>9} {:>12.3} {:>10.3} {:>12.4}",
                line.n,
                line.particles,
                line.substeps,
                line.ms_per_frame,
                line.p95_ms,
                line.max_stretch
            ));
        }
    }
    Ok(ExitCode::SUCCESS)
}

/// Refuses what the command line's parser would (for callers that build
/// [`BenchArgs`] themselves): an unknown backend, sizes outside 2 to 4096,
/// substeps outside 1 to 1000, no timed frames.
pub fn validate(args: &BenchArgs) -> Result<(), String> {
    check_backend(&args.backend)?;
    if let Some(&n) = args.sizes.iter().find(|&&n| !(2..=4096).contains(&n)) {
        return Err(format!("--sizes: {n} is out of range: sizes are 2 to 4096"));
    }
    if !SUBSTEPS.contains(&i64::from(args.substeps)) {
        return Err(format!(
            "--substeps: {} is out of range: substeps are 1 to 1000",
            args.substeps
        ));
    }
    if args.frames == 0 {
        return Err("--frames: at least one frame is timed".into());
    }
    Ok(())
}

/// Times the `n` x `n` hanging cloth as `args` ask, on the pool of
/// `args.threads` threads.
pub fn measure(args: &BenchArgs, n: u32) -> Result<BenchLine, String> {
    with_threads(args.threads, || measure_here(args, n))?
}

/// [`measure`] on the current rayon pool.
fn measure_here(args: &BenchArgs, n: u32) -> Result<BenchLine, String> {
    let mut scene = hanging_cloth(n, args.substeps, args.tethers);
    scene.solver.self_collision.enabled = args.self_collision;
    let mut sim = build_on(&scene, (Path::new("."), &scene.name), &args.backend)?;
    let dt = scene.frame_dt();
    for _ in 0..args.warmup {
        sim.step(dt);
    }
    sim.finish();
    sim.stages = Default::default();
    let times: Vec<_> = (0..args.frames)
        .map(|_| {
            let start = Instant::now();
            sim.step(dt);
            sim.finish();
            start.elapsed()
        })
        .collect();
    sim.sync();
    let t = FrameTimes::from(&times);
    Ok(BenchLine {
        backend: sim.backend_name(),
        device: sim.device(),
        n,
        particles: sim.particles.len(),
        substeps: args.substeps,
        self_collision: args.self_collision,
        ms_per_frame: t.mean,
        max_stretch: stretch(&sim.model, &sim.particles).0,
        p95_ms: t.p95,
        frames: args.frames,
        threads: rayon::current_num_threads(),
        stages_ms: StagesMs::from(&sim.stages, args.frames),
        dispatches_per_frame: dispatches_per_frame(&sim, args.frames),
        self_contact_builds_per_frame: self_contact_builds_per_frame(&sim, args.frames),
        tethers: args.tethers,
    })
}
