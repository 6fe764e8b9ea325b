//! `pleat render`: simulate a scene and draw it: a PNG picture per drawn
//! frame (`frame_00000.png`, ...) and one animated GIF (`anim.gif`), with
//! report.json beside them. `pleat fold --render` draws a fold the same way.

use crate::advice::render_error;
use crate::output::FrameSink;
use crate::report::Report;
use crate::run::{load, rayon_threads, simulate};
use crate::{build_on, check_backend, with_threads};
use pleat::scene::RenderSpec;
use pleat::Simulation;
use pleat_gpu::GpuBackend;
use pleat_render::{
    headless_device, save_png, GifWriter, Headless, Positions, RenderSettings, Renderer, View,
};
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::{Duration, Instant};

/// Largest picture side `--width` and `--height` accept (the device may allow less).
const MAX_SIDE: u32 = 16384;

#[derive(clap::Args)]
pub struct RenderArgs {
    /// Scene file (JSON); the embedded drape scene if absent.
    pub scene: Option<PathBuf>,
    /// Frames to simulate (overrides the scene's).
    #[arg(long)]
    pub frames: Option<u32>,
    /// Draw frame 0 and every K-th frame.
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..))]
    pub every: u32,
    #[command(flatten)]
    pub picture: PictureArgs,
    /// cpu or gpu.
    #[arg(long, default_value = "cpu")]
    pub backend: String,
    /// Folder for the pictures, the GIF and report.json (default: out/<scene name>).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Worker threads of the simulation (default: all cores).
    #[arg(long)]
    pub threads: Option<usize>,
}

/// Size and view of the pictures (shared by `pleat render` and `pleat fold --render`).
#[derive(clap::Args)]
pub struct PictureArgs {
    /// Picture width in pixels.
    #[arg(long, default_value_t = 640, value_parser = clap::value_parser!(u32).range(1..=MAX_SIDE as i64))]
    pub width: u32,
    /// Picture height in pixels.
    #[arg(long, default_value_t = 480, value_parser = clap::value_parser!(u32).range(1..=MAX_SIDE as i64))]
    pub height: u32,
    /// shaded, wireframe, constraints or strain.
    #[arg(long, default_value = "shaded")]
    pub view: View,
}

impl PictureArgs {
    /// The scene's render settings with this size and view.
    pub fn settings(
        &self,
        spec: Option<&RenderSpec>,
        base_dir: &Path,
    ) -> Result<RenderSettings, String> {
        let settings = RenderSettings::from_scene(spec, base_dir).map_err(|e| e.to_string())?;
        Ok(RenderSettings {
            width: self.width,
            height: self.height,
            view: self.view,
            ..settings
        })
    }
}

pub fn render(args: &RenderArgs) -> Result<ExitCode, String> {
    check_backend(&args.backend)?;
    let (mut scene, file, base_dir) = load(args.scene.as_deref()).map_err(|e| e.to_string())?;
    if let Some(frames) = args.frames {
        scene.frames = frames;
    }
    let settings = args.picture.settings(scene.render.as_ref(), &base_dir)?;
    let mut sim = build_on(&scene, (&base_dir, &file), &args.backend)?;
    let dir = args
        .out
        .clone()
        .unwrap_or_else(|| Path::new("out").join(&scene.name));
    let frame_dt = scene.frame_dt();
    let mut pictures = Pictures::create(&dir, &sim, settings, frame_dt * args.every as f32)?;
    let times = with_threads(args.threads, || {
        simulate(
            &mut sim,
            &scene.name,
            (scene.frames, frame_dt),
            args.every,
            Some(&mut pictures),
            None,
        )
    })??;
    let report = Report::new(&sim, &scene, &times, rayon_threads(args.threads)?);
    finish(&report, &pictures, &dir)?;
    Ok(if report.nan || report.unstable {
        ExitCode::FAILURE
    } else {
        ExitCode::SUCCESS
    })
}

/// Prints the summary and what was drawn, and writes report.json.
pub fn finish(report: &Report, pictures: &Pictures, dir: &Path) -> Result<(), String> {
    crate::print_line(report.summary_line());
    if let Some(line) = report.fold_line() {
        crate::print_line(line);
    }
    crate::print_line(pictures.summary());
    crate::print_line(format_args!("wrote {}", report.write(dir)?.display()));
    Ok(())
}

/// Draws frames into `dir`: a PNG each and one animated GIF.
pub struct Pictures {
    renderer: Renderer,
    gif: GifWriter,
    dir: PathBuf,
    adapter: String,
    count: u32,
    draw_time: Duration,
    write_time: Duration,
    /// Positions come straight from the GPU backend's buffer (no readback).
    from_gpu: bool,
}

/// The GPU backend stepping `sim`, if it is one.
fn gpu_backend(sim: &Simulation) -> Option<&GpuBackend> {
    sim.backend().as_any().downcast_ref::<GpuBackend>()
}

impl Pictures {
    /// A renderer for `sim` on a headless device, and `dir` for its
    /// pictures; the GIF shows each picture for `frame_seconds`.
    pub fn create(
        dir: &Path,
        sim: &Simulation,
        settings: RenderSettings,
        frame_seconds: f32,
    ) -> Result<Self, String> {
        // Drawn on the GPU backend's own device, from its buffers; else headless.
        let (device, queue, adapter) = match gpu_backend(sim) {
            Some(gpu) => {
                let c = gpu.context();
                (c.device.clone(), c.queue.clone(), c.adapter.clone())
            }
            None => {
                let headless = headless_device().map_err(render_error)?;
                let adapter = headless.describe();
                let Headless { device, queue, .. } = headless;
                (device, queue, adapter)
            }
        };
        std::fs::create_dir_all(dir)
            .map_err(|e| format!("{}: cannot create the folder: {e}", dir.display()))?;
        let renderer =
            Renderer::new(device, queue, &sim.model, &sim.world, settings).map_err(render_error)?;
        let gif =
            GifWriter::create(&dir.join("anim.gif"), frame_seconds).map_err(|e| e.to_string())?;
        Ok(Pictures {
            renderer,
            gif,
            dir: dir.to_path_buf(),
            adapter,
            count: 0,
            draw_time: Duration::ZERO,
            write_time: Duration::ZERO,
            from_gpu: gpu_backend(sim).is_some(),
        })
    }

    /// What was drawn, where, on what, and how long it took.
    pub fn summary(&self) -> String {
        let s = self.renderer.settings();
        let per = |t: Duration| t.as_secs_f64() * 1e3 / self.count.max(1) as f64;
        format!(
            "rendered {} pictures ({} view, {} x {}) on {}: {:.1} ms per picture to draw and read back, {:.1} ms to write PNG and GIF; wrote {}",
            self.count,
            s.view,
            s.width,
            s.height,
            self.adapter,
            per(self.draw_time),
            per(self.write_time),
            self.dir.join("anim.gif").display()
        )
    }
}

impl FrameSink for Pictures {
    fn reads_particles(&self) -> bool {
        // Paper is framed as it is: its positions come back to frame it.
        !self.from_gpu || self.renderer.follows_paper()
    }

    fn frame(&mut self, index: u32, sim: &Simulation) -> Result<(), String> {
        let start = Instant::now();
        let positions = match gpu_backend(sim) {
            Some(gpu) => {
                self.renderer.frame_paper(&sim.particles.x);
                Positions::Gpu(gpu.positions())
            }
            None => Positions::Cpu(&sim.particles.x),
        };
        let picture = self
            .renderer
            .render(positions, &sim.world)
            .map_err(|e| e.to_string())?;
        let drawn = Instant::now();
        save_png(&picture, &self.dir.join(format!("frame_{index:05}.png")))
            .map_err(|e| e.to_string())?;
        self.gif.push(&picture).map_err(|e| e.to_string())?;
        self.draw_time += drawn - start;
        self.write_time += drawn.elapsed();
        self.count += 1;
        Ok(())
    }
}
