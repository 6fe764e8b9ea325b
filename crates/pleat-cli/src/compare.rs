//! `pleat compare`: one scene run with every solver. Prints a table (ms per
//! frame, max stretch, NaN, instability, energy at the end) and, with
//! `--out DIR`, writes it to `DIR/compare.md` with two plots: the max stretch
//! over time of each solver (`DIR/stretch.png`) and a stability sweep
//! (`DIR/stability.png`): for stiffnesses over several decades, mapped to
//! each solver's own parameter, which solvers stay finite.

use crate::report::FrameTimes;
use crate::run::load;
use crate::with_threads;
use pleat::metrics::stretch;
use pleat::scene::Scene;
use pleat::stability::{mechanical_energy, Instability};
use pleat::{Model, SolverKind};
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

/// The plots' font, bundled so that no system font library is needed.
const FONT: &[u8] = include_bytes!("../assets/DejaVuSans.ttf");

/// Stiffness decades of the sweep: 10^0 to 10^8 N/m.
const DECADES: std::ops::RangeInclusive<i32> = 0..=8;

/// Extra substep factors the mass-spring solver is swept at, to show that
/// only smaller steps make it stable.
const MASS_SPRING_SUBSTEP_FACTORS: [u32; 1] = [10];

#[derive(clap::Args)]
pub struct CompareArgs {
    /// Scene file (JSON).
    scene: PathBuf,
    /// Folder for compare.md, stretch.png and stability.png.
    #[arg(long)]
    out: Option<PathBuf>,
    /// Frames to simulate per solver (overrides the scene's).
    #[arg(long)]
    frames: Option<u32>,
    /// Frames per cell of the stability sweep.
    #[arg(long, default_value_t = 60, value_parser = clap::value_parser!(u32).range(1..))]
    sweep_frames: u32,
    /// Worker threads (default: all cores).
    #[arg(long)]
    threads: Option<usize>,
}

/// What one solver did on the scene.
struct SolverRun {
    label: String,
    ms_per_frame: f64,
    /// Max stretch at the end of each frame.
    stretch: Vec<f32>,
    nan: bool,
    instability: Option<(f32, Instability)>,
    /// Kinetic plus gravitational potential energy at the end (J).
    energy: f32,
}

/// One row of the stability sweep: a solver (at a substep count) over the decades.
struct SweepRow {
    label: String,
    stable: Vec<bool>,
}

pub fn compare(args: &CompareArgs) -> Result<ExitCode, String> {
    let (mut scene, file, base_dir) = load(Some(&args.scene)).map_err(|e| e.to_string())?;
    if let Some(frames) = args.frames {
        scene.frames = frames;
    }
    let (model, _) = scene.model(&base_dir, &file).map_err(|e| e.to_string())?;
    let runs = with_threads(args.threads, || {
        SolverKind::ALL
            .iter()
            .map(|&kind| run_solver(&with_kind(&scene, kind, 1), &base_dir, &file))
            .collect::<Result<Vec<_>, String>>()
    })??;
    let table = table(&runs);
    crate::print_line(format_args!("{table}"));
    if let Some(dir) = &args.out {
        let sweep = with_threads(args.threads, || {
            sweep(&scene, &model, &base_dir, &file, args.sweep_frames)
        })??;
        write_outputs(dir, &scene, &runs, &table, &sweep, args.sweep_frames)?;
    }
    Ok(ExitCode::SUCCESS)
}

/// `scene` with the solver `kind` at `substep_factor` times its substeps.
fn with_kind(scene: &Scene, kind: SolverKind, substep_factor: u32) -> Scene {
    let mut s = scene.clone();
    s.solver.kind = kind;
    s.solver.substeps *= substep_factor;
    s
}

/// Runs the scene to the end, timing each frame and measuring its stretch.
fn run_solver(scene: &Scene, base_dir: &Path, file: &str) -> Result<SolverRun, String> {
    let mut sim = scene.build(base_dir, file).map_err(|e| e.to_string())?;
    let mut times = Vec::with_capacity(scene.frames as usize);
    let mut stretches = Vec::with_capacity(scene.frames as usize);
    for _ in 0..scene.frames {
        let start = Instant::now();
        sim.step(scene.frame_dt());
        times.push(start.elapsed());
        stretches.push(stretch(&sim.model, &sim.particles).0);
    }
    Ok(SolverRun {
        label: scene.solver.kind.name().into(),
        ms_per_frame: FrameTimes::from(&times).mean,
        stretch: stretches,
        nan: sim.particles.has_non_finite(),
        instability: sim.stability.first,
        energy: mechanical_energy(&sim.model, &sim.world, &sim.particles),
    })
}

/// The results as a Markdown table.
fn table(runs: &[SolverRun]) -> String {
    let mut t = String::from(
        "| solver | ms/frame | max stretch | NaN | unstable | energy (J) |\n|---|---:|---:|---|---|---:|\n",
    );
    for r in runs {
        let unstable = match r.instability {
            None => "no".to_string(),
            Some((time, kind)) => format!("{kind:?} at {time:.3} s"),
        };
        let _ = writeln!(
            t,
            "| {} | {:.2} | {:.4} | {} | {} | {:.4} |",
            r.label,
            r.ms_per_frame,
            r.stretch.last().copied().unwrap_or(1.0),
            if r.nan { "yes" } else { "no" },
            unstable,
            r.energy
        );
    }
    t
}

/// The stability sweep: each solver over the stiffness decades, and the
/// mass-spring solver again with more substeps.
fn sweep(
    scene: &Scene,
    model: &Model,
    base_dir: &Path,
    file: &str,
    frames: u32,
) -> Result<Vec<SweepRow>, String> {
    let mut rows: Vec<(SolverKind, u32)> = SolverKind::ALL.iter().map(|&k| (k, 1)).collect();
    rows.extend(
        MASS_SPRING_SUBSTEP_FACTORS
            .iter()
            .map(|&f| (SolverKind::MassSpring, f)),
    );
    rows.into_iter()
        .map(|(kind, factor)| {
            let base = with_kind(scene, kind, factor);
            let stable = DECADES
                .map(|d| {
                    let mut s = with_stiffness(&base, model, 10f32.powi(d));
                    s.frames = frames;
                    let mut sim = s.build(base_dir, file).map_err(|e| e.to_string())?;
                    for _ in 0..frames {
                        sim.step(s.frame_dt());
                    }
                    Ok(sim.stability.verdict().is_none())
                })
                .collect::<Result<Vec<_>, String>>()?;
            Ok(SweepRow {
                label: format!("{} ({} substeps)", kind.name(), base.solver.substeps),
                stable,
            })
        })
        .collect()
}

/// `scene` with its stretch and shear stiffness set to `k` (N/m), mapped to
/// the parameter of the scene's solver: spring constant `ks = k`, XPBD
/// compliance `1 / k`, and for PBD the factor `k / (k + m / dt^2)`: the part
/// of a constraint error that one XPBD projection with compliance `1 / k`
/// removes for particles of mass `m` at the substep `dt`.
fn with_stiffness(scene: &Scene, model: &Model, k: f32) -> Scene {
    let mut s = scene.clone();
    let dt = s.frame_dt() / s.solver.substeps as f32;
    for (spec, part) in s.cloths.iter_mut().zip(&model.cloths) {
        let m = &mut spec.material;
        match s.solver.kind {
            SolverKind::Xpbd => {
                m.stretch_compliance = 1.0 / k;
                m.shear_compliance = 1.0 / k;
            }
            SolverKind::MassSpring => {
                m.spring_stiffness.structural = k;
                m.spring_stiffness.shear = k;
            }
            SolverKind::PbdShapeMatching | SolverKind::JacobiPbd => {
                let mass: f32 = model.mass[part.particles()].iter().sum::<f32>()
                    / part.mesh.positions.len() as f32;
                m.pbd_stiffness.stretch = k / (k + mass / (dt * dt));
            }
        }
    }
    s
}

fn write_outputs(
    dir: &Path,
    scene: &Scene,
    runs: &[SolverRun],
    table: &str,
    sweep: &[SweepRow],
    sweep_frames: u32,
) -> Result<(), String> {
    std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    plotters::style::register_font("sans-serif", FontStyle::Normal, FONT)
        .map_err(|_| "the bundled font is not a valid TrueType font".to_string())?;
    let stretch_png = dir.join("stretch.png");
    plot_stretch(&stretch_png, scene, runs)
        .map_err(|e| format!("{}: {e}", stretch_png.display()))?;
    let stability_png = dir.join("stability.png");
    plot_sweep(&stability_png, sweep).map_err(|e| format!("{}: {e}", stability_png.display()))?;
    let md = dir.join("compare.md");
    std::fs::write(&md, markdown(scene, table, sweep, sweep_frames))
        .map_err(|e| format!("{}: {e}", md.display()))?;
    crate::print_line(format_args!(
        "wrote {}, {} and {}",
        md.display(),
        stretch_png.display(),
        stability_png.display()
    ));
    Ok(())
}

/// compare.md: the scene, the table, what the energy is, the sweep and the plots.
fn markdown(scene: &Scene, table: &str, sweep: &[SweepRow], sweep_frames: u32) -> String {
    let mut md = format!(
        "# Solvers compared on `{}`\n\n{} frames at {} fps, {} substeps x {} iterations; \
         mass-spring global damping {}% per step, Jacobi relaxation {}.\n\n{table}\n",
        scene.name,
        scene.frames,
        scene.fps,
        scene.solver.substeps,
        scene.solver.iterations,
        scene.solver.global_damping,
        scene.solver.relaxation,
    );
    md.push_str(
        "max stretch: largest edge length over rest length at the last frame. \
         energy: kinetic plus gravitational potential energy measured from the rest \
         shape at the last frame (elastic energy is not included, as each solver \
         models it differently); a passive cloth can only go below zero. unstable: \
         NaN/inf, or energy far above what the scene can put in.\n\n\
         ![max stretch over time](stretch.png)\n\n",
    );
    let _ = writeln!(
        md,
        "## Stability sweep\n\nStretch and shear stiffness k (N/m) per decade, {sweep_frames} frames \
         each: springs get ks = k, XPBD compliance 1/k, PBD the factor k / (k + m/dt^2). \
         `ok` stays finite, `X` goes unstable.\n"
    );
    md.push_str("| solver |");
    for d in DECADES {
        let _ = write!(md, " 1e{d} |");
    }
    md.push_str("\n|---|");
    md.push_str(&"---|".repeat(DECADES.count()));
    md.push('\n');
    for row in sweep {
        let _ = write!(md, "| {} |", row.label);
        for &ok in &row.stable {
            md.push_str(if ok { " ok |" } else { " X |" });
        }
        md.push('\n');
    }
    md.push_str("\n![stability sweep](stability.png)\n");
    md
}

const SERIES_COLORS: [RGBColor; 5] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(255, 127, 14),
    RGBColor(148, 103, 189),
];

/// Max stretch over time, one line per solver, on a log scale; a line ends
/// where its solver's state stops being finite.
fn plot_stretch(
    path: &Path,
    scene: &Scene,
    runs: &[SolverRun],
) -> Result<(), Box<dyn std::error::Error>> {
    let root = BitMapBackend::new(path, (900, 560)).into_drawing_area();
    root.fill(&WHITE)?;
    let dt = scene.frame_dt();
    let t_end = scene.frames as f32 * dt;
    let top = runs
        .iter()
        .flat_map(|r| r.stretch.iter().copied().filter(|s| s.is_finite()))
        .fold(2.0f32, f32::max)
        .min(1e6)
        * 1.5;
    let mut chart = ChartBuilder::on(&root)
        .caption(
            format!("max stretch over time: {}", scene.name),
            ("sans-serif", 24),
        )
        .margin(15)
        .x_label_area_size(45)
        .y_label_area_size(70)
        .build_cartesian_2d(0f32..t_end, (0.95f32..top).log_scale())?;
    chart
        .configure_mesh()
        .x_desc("time (s)")
        .y_desc("max edge length / rest length")
        .label_style(("sans-serif", 15))
        .draw()?;
    for (run, &color) in runs.iter().zip(SERIES_COLORS.iter().cycle()) {
        let points = run
            .stretch
            .iter()
            .enumerate()
            .take_while(|(_, s)| s.is_finite())
            .map(|(f, &s)| ((f + 1) as f32 * dt, s.clamp(0.95, top)));
        chart
            .draw_series(LineSeries::new(points, color.stroke_width(2)))?
            .label(run.label.clone())
            .legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 24, y)], color.stroke_width(3))
            });
    }
    chart
        .configure_series_labels()
        .label_font(("sans-serif", 16))
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .position(SeriesLabelPosition::UpperRight)
        .draw()?;
    root.present()?;
    Ok(())
}

/// The sweep as a grid: a row per solver, a column per decade, green when
/// the solver stayed finite and red when it went unstable.
fn plot_sweep(path: &Path, rows: &[SweepRow]) -> Result<(), Box<dyn std::error::Error>> {
    let (label_w, cell_w, cell_h, top, bottom) = (330, 70, 48, 60, 60);
    let columns = DECADES.count() as i32;
    let width = (label_w + columns * cell_w + 20) as u32;
    let height = (top + rows.len() as i32 * cell_h + bottom) as u32;
    let root = BitMapBackend::new(path, (width, height)).into_drawing_area();
    root.fill(&WHITE)?;
    let centred = |size| {
        ("sans-serif", size)
            .into_font()
            .color(&BLACK)
            .pos(Pos::new(HPos::Center, VPos::Center))
    };
    root.draw(&Text::new(
        "stays finite? stretch stiffness k (N/m) per solver",
        (width as i32 / 2, top / 2),
        centred(20),
    ))?;
    for (r, row) in rows.iter().enumerate() {
        let y = top + r as i32 * cell_h;
        root.draw(&Text::new(
            row.label.clone(),
            (10, y + cell_h / 2),
            ("sans-serif", 16)
                .into_font()
                .color(&BLACK)
                .pos(Pos::new(HPos::Left, VPos::Center)),
        ))?;
        for (c, &ok) in row.stable.iter().enumerate() {
            let x = label_w + c as i32 * cell_w;
            let fill = if ok {
                RGBColor(120, 200, 120)
            } else {
                RGBColor(225, 90, 80)
            };
            root.draw(&Rectangle::new(
                [(x, y), (x + cell_w, y + cell_h)],
                fill.filled(),
            ))?;
            root.draw(&Rectangle::new(
                [(x, y), (x + cell_w, y + cell_h)],
                WHITE.stroke_width(2),
            ))?;
            let mark = if ok { "ok" } else { "X" };
            root.draw(&Text::new(
                mark,
                (x + cell_w / 2, y + cell_h / 2),
                centred(16),
            ))?;
        }
    }
    for (c, d) in DECADES.enumerate() {
        let x = label_w + c as i32 * cell_w + cell_w / 2;
        let y = top + rows.len() as i32 * cell_h + 20;
        root.draw(&Text::new(format!("1e{d}"), (x, y), centred(16)))?;
    }
    root.present()?;
    Ok(())
}
