//! `pleat check`: validate files without simulating; `ok` and a summary per
//! good file, every error of a bad one, non-zero exit if any is bad.

use pleat::fold_steps::{sheet_step_angles, step_pattern};
use pleat::mesh::obj::load_obj;
use pleat::origami::{
    check_flat_foldability, load_pattern_with_warnings, parse_pattern_steps, CreasePattern,
    FlatFolded, Sheet, SheetOptions,
};
use pleat::scene::Scene;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

#[derive(clap::Args)]
pub struct CheckArgs {
    /// Scene (.json), mesh (.obj) and crease-pattern (.cp, .fold, .svg) files.
    #[arg(required = true)]
    files: Vec<PathBuf>,
    /// Write the flat-folded state of each crease pattern that has one to
    /// DIR/NAME.fold: its vertices where they land (2D), its triangles and
    /// their layer order (`faceOrders`).
    #[arg(long, value_name = "DIR")]
    folded_out: Option<PathBuf>,
}

pub fn check(args: &CheckArgs) -> Result<ExitCode, String> {
    let mut bad = 0;
    if let Some(dir) = &args.folded_out {
        std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    }
    for path in &args.files {
        match summary(path, args.folded_out.as_deref()) {
            Ok(line) => crate::print_line(format_args!("ok   {}: {line}", path.display())),
            Err(errors) => {
                bad += 1;
                crate::print_line(format_args!("FAIL {}", path.display()));
                for e in errors.lines() {
                    crate::print_line(format_args!("     {e}"));
                }
            }
        }
    }
    Ok(if bad == 0 {
        ExitCode::SUCCESS
    } else {
        ExitCode::FAILURE
    })
}

/// One-line description of a valid file, or its errors; a pattern's
/// flat-folded state goes to `folded_out`, where given.
fn summary(path: &Path, folded_out: Option<&Path>) -> Result<String, String> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .unwrap_or("")
        .to_ascii_lowercase();
    match ext.as_str() {
        "json" => scene_summary(path),
        "obj" => {
            let mesh = load_obj(path).map_err(|e| e.to_string())?;
            Ok(format!(
                "mesh, {} vertices, {} triangles",
                mesh.positions.len(),
                mesh.triangles.len()
            ))
        }
        "cp" | "fold" | "svg" => pattern_summary(path, folded_out),
        _ => Err(format!(
            "{}: unknown file type '.{ext}': expected .json, .obj, .cp, .fold or .svg",
            path.display()
        )),
    }
}

fn scene_summary(path: &Path) -> Result<String, String> {
    let scene = Scene::load(path).map_err(|e| e.to_string())?;
    let base = path.parent().unwrap_or(Path::new("."));
    let (model, world, warnings) = scene
        .model_and_warnings(base, &path.display().to_string())
        .map_err(|e| e.to_string())?;
    let mut line = format!(
        "scene '{}', {} cloths, {} particles, {} triangles, {} colliders, {} frames",
        scene.name,
        model.cloths.len(),
        model.particle_count(),
        model.triangles.len(),
        world.colliders.len(),
        scene.frames
    );
    for w in warnings {
        line.push_str(&format!("; warning: {w}"));
    }
    Ok(line)
}

fn pattern_summary(path: &Path, folded_out: Option<&Path>) -> Result<String, String> {
    let (pattern, warnings) = load_pattern_with_warnings(path).map_err(|e| e.to_string())?;
    let sheet = Sheet::from_pattern(&pattern, &SheetOptions::default())
        .map_err(|e| e.with_file(path.display().to_string()).to_string())?;
    let name = path.display().to_string();
    let bytes = std::fs::read(path).map_err(|e| format!("{name}: {e}"))?;
    let steps = parse_pattern_steps(&name, &bytes, &pattern).map_err(|e| e.to_string())?;
    sheet_step_angles(&pattern, &SheetOptions::default(), &sheet, &steps)
        .map_err(|e| e.with_file(name).to_string())?;
    let mut line = format!(
        "crease pattern, {} vertices, {} triangles, {} creases",
        sheet.positions.len(),
        sheet.triangles.len(),
        sheet.crease_count()
    );
    if !steps.is_empty() {
        line.push_str(&format!(", folded in {} steps", steps.len()));
        line.push_str(&steps_with_an_order(&pattern, &steps));
    }
    let flat = check_flat_foldability(&pattern)
        .map_err(|e| e.with_file(path.display().to_string()).to_string())?;
    line.push_str(&if flat.vertices_checked == 0 && flat.vertices_skipped > 0 {
        format!(
            "; no interior vertex folds flat ({} with partial or unassigned creases)",
            flat.vertices_skipped
        )
    } else if flat.is_flat_foldable() {
        format!("; flat-foldable ({} vertices checked)", flat.vertices_checked)
    } else {
        format!(
            "; not flat-foldable as drawn ({} of {} vertices checked break Kawasaki's or Maekawa's theorem, Kawasaki by up to {:.2} deg)",
            flat.vertices_with_violations(),
            flat.vertices_checked,
            flat.max_kawasaki_defect_deg
        )
    });
    if flat.is_flat_foldable() && flat.vertices_skipped == 0 {
        line.push_str(&match FlatFolded::solve(&sheet) {
            Ok(folded) => {
                let mut found = format!(
                    "; layer order found: {} facets, {} pairs overlap when folded flat ({} forced), {} conditions",
                    folded.facet_count(),
                    folded.overlapping_pairs(),
                    folded.forced_pairs(),
                    folded.condition_count()
                );
                if let Some(dir) = folded_out {
                    let stem = path.file_stem().and_then(|s| s.to_str()).unwrap_or("pattern");
                    let out = dir.join(format!("{stem}.fold"));
                    let json = folded.to_fold_json(&sheet, stem);
                    let text = serde_json::to_string(&json).map_err(|e| e.to_string())?;
                    std::fs::write(&out, text + "\n").map_err(|e| format!("{}: {e}", out.display()))?;
                    found.push_str(&format!(" (written to {})", out.display()));
                }
                found
            }
            Err(e) => format!("; not flat-foldable as a whole, {e}"),
        });
    }
    for w in warnings {
        line.push_str(&format!("; warning: {w}"));
    }
    Ok(line)
}

/// Which steps of a fold in steps end in a state that folds flat with a
/// layer order: ` (steps 1-5 fold flat with a layer order)`, or nothing
/// when none does.
fn steps_with_an_order(pattern: &CreasePattern, steps: &[Vec<Option<f64>>]) -> String {
    let ordered: Vec<usize> = steps
        .iter()
        .enumerate()
        .filter(|(_, angles)| {
            Sheet::from_pattern(&step_pattern(pattern, angles), &SheetOptions::default())
                .is_ok_and(|sheet| FlatFolded::solve(&sheet).is_ok())
        })
        .map(|(k, _)| k + 1)
        .collect();
    if ordered.is_empty() {
        return String::new();
    }
    let mut runs: Vec<String> = Vec::new();
    let mut k = 0;
    while k < ordered.len() {
        let start = ordered[k];
        while k + 1 < ordered.len() && ordered[k + 1] == ordered[k] + 1 {
            k += 1;
        }
        runs.push(if ordered[k] == start {
            start.to_string()
        } else {
            format!("{start}-{}", ordered[k])
        });
        k += 1;
    }
    let word = if ordered.len() == 1 { "step" } else { "steps" };
    format!(" ({word} {} fold flat with a layer order)", runs.join(", "))
}
