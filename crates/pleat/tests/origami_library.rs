//! Every pattern of `patterns/origami-simulator` and `patterns/shared`
//! folded as `pleat fold FILE --progress C` folds it (the paper defaults,
//! 120 frames of ramp and 60 to settle) at C = 0.25, 0.5 and 1: no NaN, no
//! instability, facet strain within 2 %, and at C = 1 every driven crease
//! within 5 degrees of its target on the patterns Origami Simulator folds
//! to within 1 degree, and no further from the targets than Origami
//! Simulator on the patterns it leaves far from them (issue 12).

use std::path::{Path, PathBuf};

use pleat::folding::{paper_simulation, FoldMetrics, FoldRamp};
use pleat::origami::{load_pattern, Sheet, SheetOptions};

const FRAME_DT: f32 = 1.0 / 60.0;
const RAMP: u32 = 120;
const SETTLE: u32 = 60;
const PROGRESSES: [f32; 3] = [0.25, 0.5, 1.0];

/// Largest facet strain issue 12 allows.
const STRAIN_LIMIT: f32 = 0.02;

/// Patterns Origami Simulator folds to within 1 degree at full progress,
/// and the map fold, Moosers' train (0.8 degrees there) and the flat
/// crane, which jammed on the way with paper held within 1 % while the
/// fold moved, the mazes helloworld (0.57 there) and cross, which
/// jammed with paper that gave 2 %, and the twists FTpoly7, whirlpool and
/// langHyperbolicLimit (0.06, 0.04 and 0.003 there), which jammed while
/// the import merged their finest features, and Origami_Sphere_16Flaps
/// (53.6 there), which jammed while the convex hull made its outline's
/// creases hinges of sliver triangles: all must end within 5 degrees here.
const WITHIN_FIVE_DEGREES: [&str; 15] = [
    "Origami_Sphere_16Flaps.svg",
    "FTpoly7.svg",
    "whirlpool.svg",
    "langHyperbolicLimit.svg",
    "helloworld.svg",
    "cross.svg",
    "mapfold.svg",
    "MoosersTrainRigid-Gardner.svg",
    "flat_crane.svg",
    "waterbombBase.svg",
    "birdBase.svg",
    "flappingBird.svg",
    "hypar.svg",
    "miura-ori.svg",
    "reschTriTessellation.svg",
];

/// Origami Simulator's largest fold-angle error at full progress on the
/// patterns it leaves far from their targets (its own page run headless,
/// its defaults, settled: docs/folding.md; huffmanTower after 300 s, not
/// settled; waterbombTwist, removed upstream, as issue 12 gives it: 82
/// rounded, so at least 81.5): pleat's must be no larger.
const ORIGAMI_SIMULATOR_AT_ONE: [(&str, f32); 4] = [
    ("huffmanWaterbomb.svg", 81.91),
    ("waterbombTwist.svg", 81.5),
    ("traditionalCrane.svg", 87.05),
    ("huffmanTower.svg", 20.85),
];

fn files() -> Vec<PathBuf> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../patterns");
    let mut files: Vec<PathBuf> = ["origami-simulator", "shared"]
        .iter()
        .flat_map(|dir| std::fs::read_dir(root.join(dir)).expect("pattern folder"))
        .map(|entry| entry.expect("readable entry").path())
        .filter(|p| {
            matches!(
                p.extension().and_then(|e| e.to_str()),
                Some("cp" | "fold" | "svg")
            )
        })
        .collect();
    files.sort();
    files
}

/// The figures of `path` folded to `progress`, and whether the run stayed stable.
fn fold(path: &Path, progress: f32) -> (FoldMetrics, bool) {
    let pattern = load_pattern(path).unwrap_or_else(|e| panic!("{e}"));
    let sheet = Sheet::from_pattern(&pattern, &SheetOptions::default())
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut sim = paper_simulation(
        &sheet,
        FoldRamp {
            progress,
            frames: RAMP,
        },
    );
    for _ in 0..RAMP + SETTLE {
        sim.step(FRAME_DT);
    }
    let stable = sim.stability.verdict().is_none() && !sim.particles.has_non_finite();
    (FoldMetrics::measure(&sim).expect("paper"), stable)
}

#[test]
fn every_library_pattern_folds_stably_with_little_strain() {
    let files = files();
    assert_eq!(files.len(), 30, "{files:?}");
    let results: Vec<(String, f32, FoldMetrics, bool)> = std::thread::scope(|scope| {
        let handles: Vec<_> = files
            .iter()
            .flat_map(|path| PROGRESSES.map(|c| (path, c)))
            .map(|(path, c)| {
                scope.spawn(move || {
                    let name = path.file_name().unwrap().to_string_lossy().into_owned();
                    let (metrics, stable) = fold(path, c);
                    (name, c, metrics, stable)
                })
            })
            .collect();
        handles.into_iter().map(|h| h.join().unwrap()).collect()
    });
    for (name, c, m, stable) in &results {
        assert!(stable, "{name} at {c}: unstable ({m:?})");
        assert!(
            m.max_strain <= STRAIN_LIMIT,
            "{name} at {c}: strain {} over {STRAIN_LIMIT}",
            m.max_strain
        );
        if *c < 1.0 {
            continue;
        }
        let e = m.max_fold_angle_error_deg;
        let worst = e.mountain.max(e.valley);
        if WITHIN_FIVE_DEGREES.contains(&name.as_str()) {
            assert!(worst < 5.0, "{name}: fold-angle error {worst} degrees");
        }
        if let Some((_, theirs)) = ORIGAMI_SIMULATOR_AT_ONE.iter().find(|(n, _)| n == name) {
            assert!(
                worst <= *theirs,
                "{name}: fold-angle error {worst} degrees, Origami Simulator's {theirs}"
            );
        }
    }
}
