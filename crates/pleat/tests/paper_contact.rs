//! Paper with a thickness: self-contact keeps a folding sheet's layers
//! apart, so flat-foldable patterns fold all the way to 180 degrees without
//! passing through themselves, where paper without contact crosses itself.

use std::path::{Path, PathBuf};

use pleat::folding::{
    hinge_states, paper_model, paper_simulation_on, paper_solver_settings_with_contact, FoldRamp,
    PAPER_THICKNESS,
};
use pleat::metrics::intersections::count_self_intersections;
use pleat::metrics::strain::max_facet_strain;
use pleat::origami::{builtin, load_pattern, CreasePattern, Sheet, SheetOptions};
use pleat::{CpuBackend, Simulation};

const FRAME_DT: f32 = 1.0 / 60.0;
/// Frames over which the progress ramps to 1, and to settle after.
const RAMP: u32 = 120;
const SETTLE: u32 = 60;

fn shared(file: &str) -> CreasePattern {
    let path: PathBuf = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../patterns/shared");
    load_pattern(path.join(file)).expect("pattern loads")
}

/// A fold of `pattern` to progress 1 with layers `thickness` apart (no
/// contact when 0), and the most self-intersections seen at every 10th
/// frame and at the end.
fn fold(pattern: &CreasePattern, thickness: f32) -> (Simulation, usize) {
    let sheet = Sheet::from_pattern(pattern, &SheetOptions::default()).expect("triangulates");
    let (model, world) = paper_model(&sheet);
    let settings = paper_solver_settings_with_contact(thickness);
    let backend = Box::new(CpuBackend::new(&model, &settings));
    let ramp = FoldRamp {
        progress: 1.0,
        frames: RAMP,
    };
    let mut sim = paper_simulation_on((model, world), settings, backend, ramp);
    let mut most = 0;
    for frame in 1..=RAMP + SETTLE {
        sim.step(FRAME_DT);
        if frame % 10 == 0 {
            let crossings = count_self_intersections(&sim.particles.x, &sim.model.triangles);
            most = most.max(crossings);
        }
    }
    (sim, most)
}

#[test]
fn flat_folds_with_a_thickness_reach_180_degrees_without_crossing() {
    let patterns = [
        ("waterbomb-base", builtin("waterbomb-base").unwrap()),
        ("miura-ori", builtin("miura-ori").unwrap()),
        ("parallel-lines", builtin("parallel-lines").unwrap()),
        ("birdBase.svg", shared("birdBase.svg")),
        ("singlesquaretwist.svg", shared("singlesquaretwist.svg")),
        ("waterbomb.cp", shared("waterbomb.cp")),
    ];
    for (name, pattern) in patterns {
        let (sim, crossings) = fold(&pattern, PAPER_THICKNESS);
        assert!(!sim.particles.has_non_finite(), "{name}: NaN");
        assert_eq!(sim.stability.verdict(), None, "{name}: unstable");
        assert_eq!(crossings, 0, "{name}: self-intersections");
        let x = &sim.particles.x;
        let strain = max_facet_strain(&sim.model.rest, x, &sim.model.triangles);
        assert!(strain <= 0.02, "{name}: strain {strain}");
        for s in hinge_states(&sim.model, x, 1.0) {
            let Some(error) = s.error() else { continue };
            assert!(
                error.to_degrees() <= 1.0,
                "{name}: hinge {:?} {:?} at {:?} degrees for {:?}",
                s.v,
                s.assignment,
                s.angle.map(f32::to_degrees),
                s.target.map(f32::to_degrees)
            );
        }
    }
}

#[test]
fn the_miura_ori_crosses_itself_without_contact_and_not_with_it() {
    let pattern = shared("miura-ori.svg");
    let (_, without) = fold(&pattern, 0.0);
    assert!(without > 0, "without contact the test cannot fail");
    let (sim, with) = fold(&pattern, PAPER_THICKNESS);
    assert_eq!(with, 0, "self-intersections with contact");
    assert!(sim.stages.self_contacts > 0, "no contact acted");
    let builds = sim.stages.self_contact_builds;
    let substeps = u64::from((RAMP + SETTLE) * 160);
    assert!(
        builds < substeps / 2,
        "paper keeps its candidates over substeps: {builds} builds in {substeps} substeps"
    );
}

/// When the fold comes to rest its strain limits tighten from the moving
/// fold's to the held ones in sweeps over the positions alone; the
/// self-contacts check those sweeps' motion in rounds, as they do a
/// substep's. Origami Simulator's whirlpool twist, folded in one go,
/// crossed itself 16 times when the sweeps ran unchecked, all of them
/// made as the limits tightened.
#[test]
fn layers_stay_apart_while_the_held_strain_limits_tighten() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../patterns/origami-simulator/whirlpool.svg");
    let pattern = load_pattern(path).expect("pattern loads");
    let (sim, crossings) = fold(&pattern, PAPER_THICKNESS);
    assert_eq!(sim.stability.verdict(), None, "unstable");
    assert_eq!(
        crossings, 0,
        "self-intersections at a 10th frame or the end"
    );
    let x = &sim.particles.x;
    let strain = max_facet_strain(&sim.model.rest, x, &sim.model.triangles);
    assert!(strain <= 0.02, "strain {strain}");
}

/// The layer order of a flat fold follows its creases: across every crease
/// folded flat (Origami Simulator's bird base leaves some at 90 degrees)
/// the two faces are stacked, each on the side the other's normal points
/// to for a valley and away from it for a mountain (FOLD's
/// faceOrders +1 and -1 for faces wound as the sheet's are). A fold whose
/// layers ended the wrong way round, or an order read the wrong way up,
/// fails here.
#[test]
fn a_flat_fold_stacks_its_layers_as_its_creases_say() {
    use pleat::metrics::layer_order::face_orders;
    use pleat::origami::Assignment;
    let patterns = [
        ("single-line", builtin("single-line").unwrap()),
        ("waterbomb-base", builtin("waterbomb-base").unwrap()),
        ("birdBase.svg", shared("birdBase.svg")),
    ];
    for (name, pattern) in patterns {
        let (sim, _) = fold(&pattern, PAPER_THICKNESS);
        let (x, triangles) = (&sim.particles.x, &sim.model.triangles);
        let orders = face_orders(x, triangles);
        let face = |corners: [u32; 3]| {
            let mut sorted = corners;
            sorted.sort_unstable();
            triangles.iter().position(|t| {
                let mut t = *t;
                t.sort_unstable();
                t == sorted
            })
        };
        let mut checked = 0;
        for s in hinge_states(&sim.model, x, 1.0) {
            let flat = s.target.is_some_and(|t| t.abs().to_degrees() > 179.0);
            let expected = match s.assignment {
                _ if !flat => continue,
                Assignment::Valley => 1,
                Assignment::Mountain => -1,
                _ => continue,
            };
            let [a, b, c, d] = s.v;
            let (Some(f), Some(g)) = (face([a, b, c]), face([a, b, d])) else {
                panic!("{name}: hinge {:?} has no faces", s.v);
            };
            let (f, g) = (f.min(g) as u32, f.max(g) as u32);
            let order = orders.iter().find(|o| o.f == f && o.g == g);
            assert_eq!(
                order.map(|o| o.s),
                Some(expected),
                "{name}: the faces across {:?} crease {:?}",
                s.assignment,
                s.v
            );
            checked += 1;
        }
        assert!(checked > 0, "{name}: no crease checked");
    }
}

/// Folded with a thickness, flat-foldable patterns end with their layers in
/// an order their flat-folded state allows: every crease's facets stacked
/// as its assignment says, no fold with a facet wrongly inside it, no
/// three layers in a cycle ([`FlatFolded::check`]). The same layers read
/// the other way up break it, so the check can fail.
#[test]
fn folded_paper_stacks_its_layers_in_an_order_the_flat_fold_allows() {
    use pleat::folding::LayerOrderFigures;
    use pleat::metrics::layer_order::face_orders;
    use pleat::origami::FlatFolded;
    let patterns = [
        ("waterbomb-base", builtin("waterbomb-base").unwrap()),
        ("singlesquaretwist.svg", shared("singlesquaretwist.svg")),
        ("lines.cp", shared("lines.cp")),
    ];
    for (name, pattern) in patterns {
        let sheet = Sheet::from_pattern(&pattern, &SheetOptions::default()).unwrap();
        let solved = FlatFolded::solve(&sheet);
        let (sim, most) = fold(&pattern, PAPER_THICKNESS);
        assert_eq!(most, 0, "{name}: crossed itself");
        let figures = LayerOrderFigures::of(&solved, &sim.model.cloths[0], &sim.particles.x);
        let check = figures.simulated.expect("an order");
        assert!(check.valid, "{name}: {check:?}");
        assert_eq!(
            check.pairs, figures.overlapping_pairs,
            "{name}: every pair stacked"
        );
        let orders = face_orders(&sim.particles.x, &sim.model.triangles);
        let reversed = solved
            .as_ref()
            .unwrap()
            .check(orders.iter().map(|o| (o.f, o.g, -o.s)));
        assert!(
            !reversed.valid && reversed.creases_broken > 0,
            "{name}: {reversed:?}"
        );
    }
}
