//! Folds a crease pattern as `pleat fold FILE --progress C` does (paper
//! defaults, 120 frames of ramp, 60 to settle) with one setting changed at a
//! time from the environment, printing the largest fold-angle errors, the
//! strain and how many driven creases are folded against their assignment
//! as it goes, with the kinetic energy `ke` and the angular momentum `L`
//! about the centre of mass (a sheet still swinging or spinning): the probe
//! behind the figures of docs/folding.md and docs/design-notes.md.
//!
//! ```sh
//! cargo run --release -p pleat --example fold_probe -- FILE [C]
//! CC=10 SUB=160 LIST=1 cargo run --release -p pleat --example fold_probe -- hypar.svg 0.5
//! ```
//!
//! Settings: `RAMP`, `SETTLE` (frames), `CC`, `FC` (crease and facet
//! compliance per unit length), `SUB` (substeps), `ITER` (iterations a
//! substep), `DAMP` (1/s), `STRETCH` (edge compliance per unit length), `MAX_STRAIN` (the edges'
//! strain limit, 0 for none), `NOISE` (metres of
//! random initial height), `MAX_EDGE` (metres: the sheet refined to
//! triangles no larger), `THICK` (metres: the paper's thickness, its layers
//! kept apart by self-contact; 0, the default, for none), `LAYERS` (0: the
//! contacts do without the pattern's layer order). Each line counts
//! the self-intersections `x` and the self-contacts that acted so far
//! (`acts`). Output: `EVERY` (frames between lines, 20),
//! `WRONG=1` (each crease on the wrong side at each line), `LIST=1` (each
//! hinge more than 10 degrees from its target at the end).

use std::env;
use std::path::Path;

use pleat::folding::{
    hinge_states, paper_material, paper_solver_settings, FoldMetrics, FoldRamp, HingeState,
    PaperStiffness,
};
use pleat::origami::{load_pattern, Sheet, SheetOptions};
use pleat::{glam::Vec3, Model, Simulation, World};

fn setting(name: &str, default: f32) -> f32 {
    env::var(name).map_or(default, |s| {
        s.parse()
            .unwrap_or_else(|_| panic!("{name}: not a number: {s}"))
    })
}

fn flag(name: &str) -> bool {
    env::var(name).is_ok()
}

/// A driven crease folded more than `threshold` radians against its target.
fn wrong_side(s: &HingeState, threshold: f32) -> bool {
    match (s.angle, s.target) {
        (Some(a), Some(t)) => t != 0.0 && a * t < 0.0 && a.abs() > threshold,
        _ => false,
    }
}

fn main() {
    let args: Vec<String> = env::args().collect();
    let Some(path) = args.get(1) else {
        eprintln!("usage: fold_probe FILE [PROGRESS]");
        std::process::exit(2);
    };
    let progress: f32 = args.get(2).map_or(1.0, |s| s.parse().expect("progress"));
    let pattern = load_pattern(Path::new(path)).unwrap_or_else(|e| panic!("{e}"));
    let max_edge = setting("MAX_EDGE", 0.0) as f64;
    let options = SheetOptions {
        max_edge: (max_edge > 0.0).then_some(max_edge),
        ..SheetOptions::default()
    };
    let sheet = Sheet::from_pattern(&pattern, &options).unwrap_or_else(|e| panic!("{e}"));
    let ramp = setting("RAMP", 120.0) as u32;
    let total = ramp + setting("SETTLE", 60.0) as u32;
    let every = (setting("EVERY", 20.0) as u32).max(1);
    let mut material = paper_material();
    material.stretch_compliance = setting("STRETCH", material.stretch_compliance);
    material.shear_compliance = material.stretch_compliance;
    let max_strain = setting("MAX_STRAIN", material.max_strain.unwrap_or(0.0));
    material.max_strain = (max_strain > 0.0).then_some(max_strain);
    let defaults = PaperStiffness::default();
    let mut model = Model::default();
    model.add_paper(
        "paper",
        &sheet,
        material,
        PaperStiffness {
            crease_compliance: setting("CC", defaults.crease_compliance),
            facet_compliance: setting("FC", defaults.facet_compliance),
        },
    );
    if setting("LAYERS", 1.0) == 0.0 {
        if let Some(paper) = model.cloths[0].paper.as_mut() {
            paper.layers = None;
        }
    }
    let world = World {
        gravity: Vec3::ZERO,
        ..World::default()
    };
    let mut settings = paper_solver_settings();
    settings.substeps = setting("SUB", settings.substeps as f32) as u32;
    settings.iterations = setting("ITER", settings.iterations as f32) as u32;
    settings.damping = setting("DAMP", settings.damping);
    let thickness = setting("THICK", 0.0);
    settings.self_collision.enabled = thickness > 0.0;
    settings.self_collision.thickness = thickness;
    let mut sim = Simulation::new(model, world, settings);
    sim.fold_ramp = Some(FoldRamp {
        progress,
        frames: ramp,
    });
    let noise = setting("NOISE", 0.0);
    if noise > 0.0 {
        let mut seed = 12345u64;
        for x in sim.particles.x.iter_mut() {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            x.z += noise * ((seed >> 33) as f32 / (1u64 << 31) as f32 - 0.5);
        }
        sim.particles.x_prev.clone_from(&sim.particles.x);
        sim.upload();
    }
    let start = std::time::Instant::now();
    for frame in 1..=total {
        sim.step(1.0 / 60.0);
        if frame % every != 0 && frame != total {
            continue;
        }
        let m = FoldMetrics::measure(&sim).expect("paper");
        let states = hinge_states(&sim.model, &sim.particles.x, sim.fold_progress());
        if flag("WRONG") {
            for s in states.iter().filter(|s| wrong_side(s, 0.0003)) {
                println!(
                    "   wrong side {:?} {:?}: {:.2} for {:.2} degrees",
                    s.v,
                    s.assignment,
                    s.angle.unwrap_or_default().to_degrees(),
                    s.target.unwrap_or_default().to_degrees()
                );
            }
        }
        let wrong = states.iter().filter(|s| wrong_side(s, 0.1)).count();
        let e = m.max_fold_angle_error_deg;
        let crossings = pleat::metrics::intersections::count_self_intersections(
            &sim.particles.x,
            &sim.model.triangles,
        );
        println!(
            "f {frame:3} c {:.3} err M {:6.1} V {:6.1} F {:6.1} strain {:.4} wrong {wrong} x {crossings} acts {} unstable {} ke {:.2e} L {:.2e}",
            m.fold_progress,
            e.mountain,
            e.valley,
            e.flat,
            m.max_strain,
            sim.stages.self_contacts,
            sim.stability.verdict().is_some(),
            sim.metrics().kinetic_energy,
            sim.particles.angular_momentum().length()
        );
    }
    println!(
        "ms/frame {:.2}",
        start.elapsed().as_secs_f64() * 1000.0 / total as f64
    );
    if flag("LISTX") {
        let x = &sim.particles.x;
        let tris = &sim.model.triangles;
        for (a, b) in pleat::metrics::intersections::intersecting_pairs(x, tris) {
            let [ta, tb] = [tris[a as usize], tris[b as usize]];
            println!(
                "crossing {ta:?} {tb:?}: {:?} / {:?}",
                ta.map(|k| x[k as usize]),
                tb.map(|k| x[k as usize])
            );
        }
    }
    if flag("LIST") {
        let states = hinge_states(&sim.model, &sim.particles.x, sim.fold_progress());
        for s in &states {
            let Some(error) = s.error() else { continue };
            if error.to_degrees() > 10.0 {
                println!(
                    "{:?} {:?} angle {:.1} target {:.1} error {:.1}",
                    s.v,
                    s.assignment,
                    s.angle.unwrap_or_default().to_degrees(),
                    s.target.unwrap_or_default().to_degrees(),
                    error.to_degrees()
                );
            }
        }
    }
}
