//! Whole scenes on the GPU backend: they follow the CPU backend (before
//! chaos sets in), keep their contracts (no NaN, nothing inside a
//! collider, no spin a sheet's own constraints could not give it), repeat
//! bit for bit, and take live changes.

mod common;
use common::*;
use glam::Vec3;
use pleat::constraint::bending::dihedral_angle;
use pleat::constraint::{ComplianceKind, Compliances, FoldDrive, Grab};
use pleat::control::Control;
use pleat::folding::{
    paper_model, paper_simulation_on, paper_solver_settings, paper_solver_settings_with_contact,
    FoldRamp,
};
use pleat::origami::{load_pattern, Sheet, SheetOptions};
use pleat::stability::{mechanical_energy, tear_edges, Instability};
use pleat::{Backend, Simulation};
use pleat_gpu::GpuBackend;
use std::path::Path;

/// The shipped drape with self-collision off: the tests that use it are
/// about the sheet, its colliders and the backend's plumbing, and run at
/// the cost they had before the scene turned self-collision on.
fn drape() -> pleat::scene::Scene {
    let mut scene = scene_file("drape.json");
    scene.solver.self_collision.enabled = false;
    scene
}

/// The GPU and CPU backends agree after `frames`: mean particle distance
/// under 1% of the cloth's size, max stretch within 2%.
fn follows_cpu(name: &str, scene: &pleat::scene::Scene, frames: u32) -> (Simulation, Simulation) {
    let (mut c, mut g) = (cpu(scene), gpu(scene));
    run(&mut c, scene, frames);
    run(&mut g, scene, frames);
    let (mc, mg) = (c.metrics(), g.metrics());
    assert!(!mg.nan && !mg.unstable, "{name}: {mg:?}");
    let (lo, hi) = c
        .model
        .rest
        .iter()
        .fold((Vec3::MAX, Vec3::MIN), |(lo, hi), p| {
            (lo.min(*p), hi.max(*p))
        });
    let size = (hi - lo).max_element();
    let mean = mean_distance(&c, &g);
    assert!(
        mean < 0.01 * size,
        "{name}: mean distance {mean} vs size {size}"
    );
    let stretch = (mg.max_stretch - mc.max_stretch).abs() / mc.max_stretch;
    assert!(
        stretch < 0.02,
        "{name}: max stretch {} on the GPU, {} on the CPU",
        mg.max_stretch,
        mc.max_stretch
    );
    (c, g)
}

#[test]
fn hanging_cloth_with_tethers_follows_the_cpu_for_one_second() {
    follows_cpu("hanging", &scene_file("hanging.json"), 60);
}

#[test]
fn jacobi_pbd_hanging_cloth_follows_the_cpu_for_one_second() {
    let mut scene = scene_file("hanging.json");
    scene.solver.kind = pleat::SolverKind::JacobiPbd;
    follows_cpu("hanging, jacobi pbd", &scene, 60);
}

#[test]
fn drape_follows_the_cpu_until_it_buckles_and_never_penetrates() {
    // Bit for bit until the sheet lands (frame 15), then round-off in the
    // contacts grows tenfold every 5 frames as the symmetric sheet buckles
    // over the sphere (mean distance 2e-5 m at frame 20, 5e-4 at 25, 0.03
    // at 50): they are compared as it lands, then the GPU run goes on.
    let scene = drape();
    let (_, mut g) = follows_cpu("drape", &scene, 20);
    for _ in 0..4 {
        run(&mut g, &scene, 10);
        assert_eq!(g.metrics().collider_penetrations, 0);
    }
}

#[test]
fn flag_in_turbulent_wind_follows_the_cpu_for_a_quarter_second() {
    follows_cpu("flag", &scene_file("flag.json"), 15);
}

#[test]
fn miura_ori_folds_to_half_like_the_cpu() {
    let scene = scene(
        r#"{ "name": "miura", "frames": 60, "fps": 60, "gravity": [0, 0, 0],
             "solver": { "substeps": 40, "damping": 2.0 },
             "cloths": [ { "mesh": { "pattern": { "builtin": "miura-ori", "size": 1.0 } },
                           "material": { "density": 0.08, "stretch_compliance": 0.0, "thickness": 0.0 } } ],
             "fold": { "progress": 0.5, "frames_to_fold": 40 } }"#,
    );
    let (c, g) = follows_cpu("miura-ori", &scene, 60);
    let constraints = pleat::solver::xpbd::XpbdConstraints::new(&c.model);
    let hinges = constraints.hinges.items();
    let angle = |sim: &Simulation, v: [u32; 4]| {
        dihedral_angle(v.map(|i| sim.particles.x[i as usize]))
            .unwrap()
            .0
    };
    let mut worst = 0.0f32;
    let mut folded = 0.0f32;
    for h in hinges.iter().filter(|h| h.full_angle != 0.0) {
        worst = worst.max((angle(&c, h.v) - angle(&g, h.v)).abs());
        folded = folded.max(angle(&g, h.v).abs());
    }
    assert!(folded > 0.5, "the GPU sheet folds ({folded} rad)");
    assert!(
        worst.to_degrees() < 1.0,
        "fold angles differ by {} degrees",
        worst.to_degrees()
    );
}

/// Origami Simulator's traditional crane on the GPU backend with the paper
/// defaults and `settings`, folding to `progress` over 120 frames.
fn crane_on_gpu(settings: pleat::solver::SolverSettings, progress: f32) -> Simulation {
    let ramp = FoldRamp {
        progress,
        frames: 120,
    };
    crane_folded_on_gpu(settings, ramp)
}

/// The crane on the GPU backend, folding by `ramp`.
fn crane_folded_on_gpu(settings: pleat::solver::SolverSettings, ramp: FoldRamp) -> Simulation {
    pattern_folded_on_gpu("origami-simulator/traditionalCrane.svg", settings, ramp)
}

/// The pattern `file` of patterns/ on the GPU backend, folding by `ramp`.
fn pattern_folded_on_gpu(
    file: &str,
    settings: pleat::solver::SolverSettings,
    ramp: FoldRamp,
) -> Simulation {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../patterns")
        .join(file);
    let sheet =
        Sheet::from_pattern(&load_pattern(&path).unwrap(), &SheetOptions::default()).unwrap();
    let (model, world) = paper_model(&sheet);
    let (backend, _) = GpuBackend::new(context(), &model, &world, &settings).unwrap();
    paper_simulation_on((model, world), settings, Box::new(backend), ramp)
}

/// Paper's self-contacts on the GPU keep the layers of a flat fold apart:
/// the bird base (four flaps folded flat onto each other), folded with a
/// thickness as `pleat fold` folds it (120 frames of ramp, 60 at rest),
/// crosses itself at no 10th frame. Without contact its flaps pass
/// through one another as the fold closes (10 crossing pairs at frame
/// 120), so the count can fail.
#[test]
fn a_bird_base_folded_with_a_thickness_never_crosses_itself_on_the_gpu() {
    use pleat::metrics::intersections::count_self_intersections;
    let ramp = FoldRamp {
        progress: 1.0,
        frames: 120,
    };
    let crossings = |settings| {
        let mut sim = pattern_folded_on_gpu("shared/birdBase.svg", settings, ramp);
        (1..=180)
            .filter_map(|frame| {
                sim.step(1.0 / 60.0);
                (frame % 10 == 0).then(|| {
                    sim.sync();
                    count_self_intersections(&sim.particles.x, &sim.model.triangles)
                })
            })
            .collect::<Vec<_>>()
    };
    let with = crossings(paper_solver_settings_with_contact(0.0005));
    assert!(with.iter().all(|&c| c == 0), "every 10th frame: {with:?}");
    let without = crossings(paper_solver_settings());
    assert!(
        without.iter().any(|&c| c > 0),
        "every 10th frame: {without:?}"
    );
}

/// Paper's self-contacts keep the momentum on the GPU, as on the CPU: each
/// contact's corrections are scaled as one. The crane with a thickness,
/// folded in 30 frames: its flaps meet fast, jam and cross, and its
/// contacts push against its creases every substep. Averaged per particle
/// (a vertex in one contact took the whole push of a triangle in many),
/// the sheet gained 0.05 kg m/s of momentum by frame 20 and 0.56 by frame
/// 25, and 15 frames after the fold it shook with 47 J (scaled, 2.3e-4
/// kg m/s at frame 25 and 1.5e-4 J; the CPU backend 8.8e-5 and 2.1e-5).
#[test]
fn a_crane_folded_fast_with_a_thickness_keeps_its_momentum_and_comes_to_rest_on_the_gpu() {
    let ramp = FoldRamp {
        progress: 1.0,
        frames: 30,
    };
    let mut sim = crane_folded_on_gpu(paper_solver_settings_with_contact(0.0005), ramp);
    for frame in 1..=45 {
        sim.step(1.0 / 60.0);
        if frame <= ramp.frames {
            let momentum = sim.sync().momentum().length();
            assert!(momentum < 5e-3, "{momentum} kg m/s at frame {frame}");
        }
    }
    sim.sync();
    let m = sim.metrics();
    assert!(!m.nan && !m.unstable, "{m:?}");
    assert!(
        m.kinetic_energy < 2e-3,
        "{} J 15 frames after the fold",
        m.kinetic_energy
    );
}

#[test]
fn a_folding_crane_keeps_no_angular_momentum_on_the_gpu() {
    // The crane's creases fight: Gauss-Seidel sweeps of them turn the
    // sheet a little every substep unless the turn is taken back
    // (momentum.wgsl). A quarter folded, after 30 frames, the sheet held
    // 5.8e-5 kg m^2/s without it, 2.6e-5 with the turn's round-off
    // simplified away by the shader compiler, 7e-7 with both.
    let mut sim = crane_on_gpu(paper_solver_settings(), 1.0);
    for _ in 0..30 {
        sim.step(1.0 / 60.0);
    }
    sim.sync();
    let spin = sim.particles.angular_momentum().length();
    assert!(spin < 5e-6, "angular momentum {spin} kg m^2/s");
    assert!(sim.fold_progress() == 0.25 && !sim.particles.has_non_finite());
}

#[test]
fn two_gpu_runs_are_bit_identical() {
    let scene = drape();
    let (mut a, mut b) = (gpu(&scene), gpu(&scene));
    run(&mut a, &scene, 20);
    run(&mut b, &scene, 20);
    assert!(a.particles.x == b.particles.x && a.particles.v == b.particles.v);
}

#[test]
fn live_gravity_and_damping_change_without_a_rebuild() {
    let scene = scene_file("hanging.json");
    let (mut c, mut g) = (cpu(&scene), gpu(&scene));
    for sim in [&mut c, &mut g] {
        run(sim, &scene, 10);
        sim.world.gravity = Vec3::new(4.0, 0.0, 0.0);
        sim.settings.damping = 0.5;
        run(sim, &scene, 20);
        let mean_x = sim.particles.x.iter().map(|p| p.x).sum::<f32>() / sim.particles.len() as f32;
        // Pulled along its own plane, the shear-stiff cloth moves by
        // shearing alone, about 5 cm in a third of a second.
        assert!(
            mean_x > 0.03,
            "{}: the cloth swings along the new gravity ({mean_x})",
            sim.backend_name()
        );
    }
    assert!(mean_distance(&c, &g) < 0.01, "{}", mean_distance(&c, &g));
}

#[test]
fn a_grabbed_particle_follows_its_target_on_both_backends() {
    let scene = scene_file("hanging.json");
    for mut sim in [cpu(&scene), gpu(&scene)] {
        let corner = sim.model.rest.len() as u32 - 1;
        let target = sim.model.rest[corner as usize] + Vec3::new(0.0, 0.2, 0.3);
        sim.grab(Some(Grab {
            particle: corner,
            target,
            compliance: 0.0,
        }));
        run(&mut sim, &scene, 30);
        let d = sim.particles.x[corner as usize].distance(target);
        assert!(
            d < 0.02,
            "{}: grabbed particle {d} m from its target",
            sim.backend_name()
        );
        sim.grab(None);
        run(&mut sim, &scene, 30);
        let d = sim.particles.x[corner as usize].distance(target);
        assert!(
            d > 0.05,
            "{}: released particle falls away ({d})",
            sim.backend_name()
        );
    }
}

#[test]
fn a_moving_grab_drags_the_cloth_alike_on_both_backends() {
    // Both backends move the grab's target on over each frame's substeps
    // (`Control::at_substep`), from where the last frame left it: they end
    // 0.4 mm apart on lavapipe, 29 mm when the GPU's target jumped at each
    // frame's first substep.
    let scene = scene_file("hanging.json");
    let mut sims = [cpu(&scene), gpu(&scene)];
    let corner = sims[0].model.rest.len() as u32 - 1;
    let start = sims[0].model.rest[corner as usize];
    for frame in 1..=30 {
        let target = start + Vec3::new(0.0, 0.2, 0.3) * (frame as f32 / 30.0);
        for sim in &mut sims {
            sim.grab(Some(Grab {
                particle: corner,
                target,
                compliance: 0.0,
            }));
            steps(sim, &scene, 1);
        }
    }
    for sim in &mut sims {
        sim.sync();
    }
    let apart = max_distance(&sims[0], &sims[1]);
    assert!(apart < 2e-3, "the backends end {apart} m apart");
}

#[test]
fn a_strain_limit_holds_against_friction_on_both_backends() {
    // The spinning-sphere demo's cloth (without self-collision) with a 3 %
    // strain limit, its corner dragged up off the sphere for a second: the
    // sphere's and the ground's friction hold parts of it back after the
    // constraints. Both backends sweep the limits again after the contacts
    // and keep every edge within the limit and its slack (1.054); with the
    // sweeps before the contacts alone the CPU reached 1.10.
    let mut scene = scene_file("rotating_sphere.json");
    scene.solver.self_collision.enabled = false;
    scene.cloths[0].material.max_strain = Some(0.03);
    let bound = 1.0 + pleat::solver::xpbd::STRAIN_LIMIT_SLACK * 0.03;
    for mut sim in [cpu(&scene), gpu(&scene)] {
        run(&mut sim, &scene, 60);
        let start = sim.particles.x[0];
        let mut worst: f32 = 0.0;
        for frame in 1..=60 {
            sim.grab(Some(Grab {
                particle: 0,
                target: start + Vec3::new(-0.5, 1.0, 0.0) * (frame as f32 / 60.0),
                compliance: 1e-5,
            }));
            run(&mut sim, &scene, 1);
            worst = worst.max(sim.metrics().max_stretch);
        }
        let name = sim.backend_name();
        assert!(
            worst <= bound + 2e-3,
            "{name}: max stretch {worst} while dragged"
        );
    }
}

#[test]
fn unsupported_features_are_refused_naming_the_field() {
    let mut scene = scene_file("hanging.json");
    scene.solver.kind = pleat::SolverKind::MassSpring;
    let (model, world) = scene.model(scenes_dir(), "t").unwrap();
    let e = pleat_gpu::GpuBackend::new(context(), &model, &world, &scene.solver)
        .err()
        .unwrap();
    assert!(e.to_string().contains("solver.kind"), "{e}");
    let mut scene = scene_file("fold_onto_itself.json");
    scene.solver.kind = pleat::SolverKind::JacobiPbd;
    let (model, world) = scene.model(scenes_dir(), "t").unwrap();
    let e = pleat_gpu::GpuBackend::new(context(), &model, &world, &scene.solver)
        .err()
        .unwrap();
    assert!(e.to_string().contains("solver.self_collision"), "{e}");
    let scene = scene_file("tablecloth_pull.json");
    let (model, world) = scene.model(scenes_dir(), "t").unwrap();
    let e = pleat_gpu::GpuBackend::new(context(), &model, &world, &scene.solver)
        .err()
        .unwrap();
    assert!(e.to_string().contains("colliders[2].body"), "{e}");
}

/// A small fold-onto-itself: a hanging cloth falls onto a flat one on the
/// ground and folds onto itself.
const SMALL_FOLD: &str = r#"{ "name": "small_fold", "frames": 120, "fps": 60,
    "solver": { "substeps": 10, "damping": 0.1,
                "self_collision": { "enabled": true, "thickness": 0.012 } },
    "cloths": [
      { "mesh": { "grid": { "resolution": [16, 16], "size": [0.8, 0.8], "orientation": "horizontal", "center": [0, 0.006, 0] } },
        "material": { "density": 0.2, "stretch_compliance": 0.0, "shear_compliance": 1e-6, "bend_compliance": 1.0, "thickness": 0.005 } },
      { "mesh": { "grid": { "resolution": [16, 16], "size": [0.6, 0.6], "orientation": "vertical", "center": [0, 0.4, 0] } },
        "material": { "density": 0.2, "stretch_compliance": 0.0, "shear_compliance": 1e-6, "bend_compliance": 1.0, "thickness": 0.005 } } ],
    "colliders": [ { "shape": { "plane": {} } } ] }"#;

#[test]
fn cloth_folding_onto_itself_ends_without_self_intersections_on_the_gpu() {
    let scene = scene(SMALL_FOLD);
    let mut g = gpu(&scene);
    for k in 1..=scene.frames / 10 {
        run(&mut g, &scene, 10);
        assert_eq!(g.metrics().self_intersections, 0, "at frame {}", 10 * k);
    }
    let m = g.metrics();
    assert!(!m.nan && !m.unstable, "{m:?}");
    assert_eq!(m.collider_penetrations, 0);
    // The falling cloth lies on the floor cloth: contacts held it up.
    let top = g.model.cloths[1].particles();
    let lowest = g.particles.x[top]
        .iter()
        .map(|p| p.y)
        .fold(f32::MAX, f32::min);
    assert!(
        lowest > 0.006 + 0.01,
        "the top cloth sank into the floor cloth ({lowest})"
    );
}

/// The self-intersections of `scene` on the GPU every 10 frames of its
/// first `frames`.
fn crossings_every_10_frames(scene: &pleat::scene::Scene, frames: u32) -> Vec<usize> {
    let mut g = gpu(scene);
    (0..frames / 10)
        .map(|_| {
            run(&mut g, scene, 10);
            let m = g.metrics();
            assert!(!m.nan && !m.unstable, "{m:?}");
            m.self_intersections
        })
        .collect()
}

/// The shipped napkin folded in half on the floor, grazed at 10 m/s by a
/// sphere (the napkin hardly moves).
fn fast_sphere() -> pleat::scene::Scene {
    scene_file("napkin_fast_sphere.json")
}

#[test]
fn a_sphere_at_10_m_s_grazing_a_folded_cloth_leaves_no_crossings_on_the_gpu() {
    let mut scene = fast_sphere();
    let on = crossings_every_10_frames(&scene, scene.frames);
    assert!(on.iter().all(|&n| n == 0), "{on:?}");
    scene.solver.self_collision.enabled = false;
    let off = crossings_every_10_frames(&scene, 10);
    assert!(off.iter().any(|&n| n > 0), "{off:?}");
}

/// The shipped towel hanging folded over a rail, lifted off and carried by
/// a sphere at 10 m/s that presses its layers together: no crossings at
/// any 10th frame; without self-collision its layers pass through each
/// other by frame 30 (134 crossings there).
#[test]
fn a_towel_dragged_by_a_sphere_at_10_m_s_leaves_no_crossings_on_the_gpu() {
    let mut scene = scene_file("towel_rail_sphere.json");
    let on = crossings_every_10_frames(&scene, scene.frames);
    assert!(on.iter().all(|&n| n == 0), "{on:?}");
    scene.solver.self_collision.enabled = false;
    let off = crossings_every_10_frames(&scene, 30);
    assert!(off.iter().any(|&n| n > 0), "{off:?}");
}

/// A strip of paper 1 x 0.1 as a FOLD file: one rectangle, no crease.
const PAPER_STRIP: &str = r#"{ "file_spec": 1.1,
    "vertices_coords": [[0, 0], [1, 0], [1, 0.1], [0, 0.1]],
    "edges_vertices": [[0, 1], [1, 2], [2, 3], [3, 0]],
    "edges_assignment": ["B", "B", "B", "B"],
    "faces_vertices": [[0, 1, 2, 3]] }"#;

/// Two such strips of paper crossed like an X, 2 cm thick, on a floor
/// under the sheets' x-y plane (gravity along -z): the lower lies on the
/// floor, the upper (turned a quarter, 5 cm up) drops on it.
/// Each strip's corners lie beyond the other strip, so no vertex meets a
/// triangle: only their long edges meet, where the strips cross.
fn crossed_paper_strips(dir: &Path) -> pleat::scene::Scene {
    std::fs::create_dir_all(dir).unwrap();
    std::fs::write(dir.join("strip.fold"), PAPER_STRIP).unwrap();
    let turned = PAPER_STRIP.replace(
        "[[0, 0], [1, 0], [1, 0.1], [0, 0.1]]",
        "[[0, 0], [0.1, 0], [0.1, 1], [0, 1]]",
    );
    std::fs::write(dir.join("turned.fold"), turned).unwrap();
    let pattern = |name: &str| dir.join(name).display().to_string();
    scene(&format!(
        r#"{{ "frames": 40, "fps": 60, "gravity": [0, 0, -9.81],
        "solver": {{ "substeps": 10, "self_collision": {{ "enabled": true, "thickness": 0.02 }} }},
        "cloths": [
          {{ "mesh": {{ "pattern": {{ "path": "{}", "size": 1.0, "center": [0, 0, 0.002] }} }} }},
          {{ "mesh": {{ "pattern": {{ "path": "{}", "size": 1.0, "center": [0, 0, 0.05] }} }} }} ],
        "colliders": [ {{ "shape": {{ "plane": {{ "normal": [0, 0, 1] }} }} }} ] }}"#,
        pattern("strip.fold"),
        pattern("turned.fold")
    ))
}

/// The lowest height (z) of the upper strip of [`crossed_paper_strips`]
/// after its frames: the lower one lies at 5 mm, the floor's distance.
fn upper_strip_lowest(mut sim: Simulation, scene: &pleat::scene::Scene) -> f32 {
    run(&mut sim, scene, scene.frames);
    let m = sim.metrics();
    assert!(!m.nan && !m.unstable, "{m:?}");
    let upper = sim.model.cloths[1].particles();
    sim.particles.x[upper]
        .iter()
        .map(|p| p.z)
        .fold(f32::MAX, f32::min)
}

/// Paper's edges keep its layers apart on the GPU as on the CPU: crossed
/// strips of paper rest on each other a thickness apart, and without
/// self-contact the upper falls through the lower to the floor.
#[test]
fn crossed_paper_strips_rest_on_each_other_on_both_backends() {
    let dir = std::env::temp_dir().join(format!("pleat-crossed-strips-{}", std::process::id()));
    let mut scene = crossed_paper_strips(&dir);
    for (backend, sim) in [("cpu", cpu(&scene)), ("gpu", gpu(&scene))] {
        let lowest = upper_strip_lowest(sim, &scene);
        assert!(lowest > 0.02, "{backend}: the upper strip sank to {lowest}");
    }
    scene.solver.self_collision.enabled = false;
    for (backend, sim) in [("cpu", cpu(&scene)), ("gpu", gpu(&scene))] {
        let lowest = upper_strip_lowest(sim, &scene);
        assert!(
            lowest < 0.01,
            "{backend}: without contacts the upper strip stayed at {lowest}"
        );
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The shipped fold_onto_itself (64 x 64): the hanging cloth falls onto the
/// floor cloth and folds onto itself, with no crossing at any 10th frame of
/// its fall, landing and settling (the first two seconds); without
/// self-collision it passes through itself by frame 20.
#[test]
fn cloth_folding_onto_itself_never_crosses_on_the_gpu() {
    let mut scene = scene_file("fold_onto_itself.json");
    let on = crossings_every_10_frames(&scene, 120);
    assert!(on.iter().all(|&n| n == 0), "{on:?}");
    scene.solver.self_collision.enabled = false;
    let off = crossings_every_10_frames(&scene, 20);
    assert!(off.iter().any(|&n| n > 0), "{off:?}");
}

/// fold_onto_itself_128.json at half its size (64 x 64 cloths, the same
/// edges): the thickness is one edge of the falling cloth, which crumples
/// as tightly as that as it lands, bringing triangles two edges apart at
/// rest face to face. With the pairs closer at rest than twice the
/// thickness left out, as they were, it crossed itself 53 times at frame 22.
const TIGHT_CRUMPLE: &str = r#"{ "frames": 30, "fps": 60,
    "solver": { "substeps": 10, "damping": 0.1,
                "self_collision": { "enabled": true, "thickness": 0.008, "friction": { "static": 0.3, "kinetic": 0.2 } } },
    "cloths": [
      { "mesh": { "grid": { "resolution": [64, 64], "size": [0.7, 0.7], "orientation": "horizontal", "center": [0, 0.006, 0] } },
        "material": { "density": 0.2, "stretch_compliance": 0.0, "shear_compliance": 1e-6, "bend_compliance": 1.0, "thickness": 0.005 } },
      { "mesh": { "grid": { "resolution": [64, 64], "size": [0.5, 0.5], "orientation": "vertical", "center": [0, 0.325, 0] } },
        "material": { "density": 0.2, "stretch_compliance": 0.0, "shear_compliance": 1e-6, "bend_compliance": 1.0, "thickness": 0.005 } } ],
    "colliders": [ { "shape": { "plane": {} }, "friction": { "static": 0.6, "kinetic": 0.5 } } ],
    "wind": { "velocity": [0, 0, 1.5] } }"#;

#[test]
fn cloth_crumpled_as_tightly_as_its_thickness_never_crosses_on_the_gpu() {
    let scene = scene(TIGHT_CRUMPLE);
    let mut g = gpu(&scene);
    for frame in (2..=scene.frames).step_by(2) {
        run(&mut g, &scene, 2);
        let m = g.metrics();
        assert!(!m.nan && !m.unstable, "{m:?}");
        assert_eq!(m.self_intersections, 0, "at frame {frame}");
    }
}

#[test]
fn self_contacts_are_bit_identical_between_runs() {
    for scene in [scene(SMALL_FOLD), fast_sphere()] {
        let (mut a, mut b) = (gpu(&scene), gpu(&scene));
        run(&mut a, &scene, 30);
        run(&mut b, &scene, 30);
        assert!(a.particles.x == b.particles.x);
    }
}

/// The self-contacts decide their margin on the GPU, so that a run does
/// not depend on when its counts reach the host: a cloth landing on
/// another (SMALL_FOLD) and a stack whose candidates outgrow their first
/// buffer (THICK_STACK), each run alone and read back every frame, and
/// run twice at once on the same device and read back at the end (each
/// run's polls then collect the other's results), end bit-identical.
#[test]
fn self_contacts_do_not_depend_on_when_results_are_read() {
    for scene in [scene(SMALL_FOLD), scene(THICK_STACK)] {
        let frames = 40.min(scene.frames);
        let mut alone = gpu(&scene);
        for _ in 0..frames {
            run(&mut alone, &scene, 1);
        }
        assert!(alone.stages.self_contact_builds > 0);
        std::thread::scope(|s| {
            let together = [0, 1].map(|_| {
                s.spawn(|| {
                    let mut sim = gpu(&scene);
                    run(&mut sim, &scene, frames);
                    sim.particles.x
                })
            });
            for run in together {
                assert!(run.join().unwrap() == alone.particles.x);
            }
        });
    }
}

/// Two weightless 16 x 16 sheets 3.5 cm apart with a thickness of 3 cm,
/// three edge lengths: each particle finds about a hundred pairs in the
/// other sheet, several times the 16 a particle the GPU's candidates hold
/// at first.
const THICK_STACK: &str = r#"{ "frames": 20, "gravity": [0, 0, 0],
    "solver": { "substeps": 4, "self_collision": { "enabled": true, "thickness": 0.03 } },
    "cloths": [
      { "mesh": { "grid": { "resolution": [16, 16], "size": [0.15, 0.15], "orientation": "horizontal", "center": [0, 0, 0] } } },
      { "mesh": { "grid": { "resolution": [16, 16], "size": [0.15, 0.15], "orientation": "horizontal", "center": [0, 0.035, 0] } } } ] }"#;

#[test]
fn candidates_beyond_the_first_buffer_grow_it_and_are_all_solved() {
    let scene = scene(THICK_STACK);
    let mut g = gpu(&scene);
    let particles = g.model.particle_count() as u64;
    let substeps = u64::from(scene.solver.substeps);
    let mut per_substep = Vec::new();
    for _ in 0..scene.frames {
        g.stages = Default::default();
        run(&mut g, &scene, 1);
        per_substep.push(g.stages.self_contact_candidates / substeps);
    }
    // The counts come back a frame or two late, several frames' at once:
    // the mean of the last frames', after the buffer grew.
    let last = per_substep[per_substep.len() - 4..].iter().sum::<u64>() / 4;
    assert!(
        last > 16 * particles,
        "{last} candidates solved a substep, {particles} particles: {per_substep:?}"
    );
    let m = g.metrics();
    assert!(!m.nan && !m.unstable, "{m:?}");
    assert_eq!(m.self_intersections, 0);
}

#[test]
fn state_read_without_blocking_matches_the_blocking_read() {
    let scene = drape();
    let (mut a, mut b) = (gpu(&scene), gpu(&scene));
    for sim in [&mut a, &mut b] {
        steps(sim, &scene, 10);
    }
    a.sync();
    b.request_sync();
    let mut polls = 0;
    while !b.try_sync() {
        polls += 1;
        assert!(polls < 100_000, "the state never arrived");
        std::thread::yield_now();
    }
    assert!(a.particles.x == b.particles.x && a.particles.v == b.particles.v);
}

/// A free 8 x 8 sheet falling under gravity.
const FALLING: &str = r#"{ "name": "falling", "frames": 10, "fps": 60, "solver": { "substeps": 4 },
    "cloths": [ { "mesh": { "grid": { "resolution": [8, 8], "size": [1.0, 1.0], "orientation": "horizontal", "center": [0.0, 1.0, 0.0] } } } ] }"#;

/// Steps `frames` frames and waits for them, never reading the state back.
fn step_unread(sim: &mut Simulation, scene: &pleat::scene::Scene, frames: u32) {
    for _ in 0..frames {
        sim.step(scene.frame_dt());
        sim.finish();
    }
}

#[test]
fn instability_is_flagged_on_the_gpu_without_reading_the_state_back() {
    let scene = scene(FALLING);
    let mut calm = gpu(&scene);
    step_unread(&mut calm, &scene, 10);
    assert_eq!(calm.stability.first, None, "free fall is calm");
    // Thrown up at 100 m/s: 5000 J/kg against a scale of about 1000.
    let mut thrown = gpu(&scene);
    thrown.particles.v.fill(Vec3::new(0.0, 100.0, 0.0));
    thrown.upload();
    step_unread(&mut thrown, &scene, 3);
    assert_eq!(
        thrown.stability.first,
        Some((scene.frame_dt(), Instability::Runaway)),
        "flagged at the first frame's end"
    );
    let mut broken = gpu(&scene);
    broken.particles.v[0].x = f32::NAN;
    broken.upload();
    step_unread(&mut broken, &scene, 3);
    assert_eq!(
        broken.stability.first.map(|(_, kind)| kind),
        Some(Instability::NonFinite)
    );
    assert_eq!(
        broken.stability.particle,
        Some(0),
        "the first non-finite particle"
    );
}

/// An 8 x 8 cloth, 1 m wide, whose top corners scripted pins pull apart
/// at 2 m/s each: 3 m apart after half a second.
fn pulled_apart(stretch_compliance: f32) -> pleat::scene::Scene {
    scene(&format!(
        r#"{{ "name": "pulled", "fps": 60, "solver": {{ "substeps": 10 }},
        "cloths": [ {{ "mesh": {{ "grid": {{ "resolution": [8, 8], "size": [1.0, 1.0], "orientation": "vertical", "center": [0.0, 1.0, 0.0] }} }},
            "material": {{ "stretch_compliance": {stretch_compliance} }},
            "pins": [ {{ "corners": ["top_left"], "motion": {{ "linear_velocity": [-2.0, 0.0, 0.0] }} }},
                      {{ "corners": ["top_right"], "motion": {{ "linear_velocity": [2.0, 0.0, 0.0] }} }} ] }} ] }}"#
    ))
}

/// Steps `frames` frames, reading the state back after each.
fn step_read(sim: &mut Simulation, scene: &pleat::scene::Scene, frames: u32) {
    for _ in 0..frames {
        sim.step(scene.frame_dt());
        sim.sync();
    }
}

#[test]
fn a_torn_cloth_is_flagged_on_the_gpu_when_read_back() {
    let torn = pulled_apart(0.0);
    let mut sim = gpu(&torn);
    step_read(&mut sim, &torn, 60);
    let (at, kind) = sim.stability.first.expect("torn");
    assert_eq!(kind, Instability::Torn);
    assert!(at > 0.0 && at < 0.75, "torn since {at} s");
    // Softened live, the same cloth may stretch.
    let mut sim = gpu(&torn);
    let stretch = sim.compliances.get_mut(0, ComplianceKind::Stretch).unwrap();
    *stretch = 1e-2;
    step_read(&mut sim, &torn, 60);
    assert!(sim.metrics().max_stretch > 2.0, "stretched");
    assert_eq!(sim.stability.first, None);
}

#[test]
fn the_health_reduction_measures_what_the_core_does() {
    let scene = scene(
        r#"{ "name": "miura", "fps": 60, "solver": { "substeps": 10 },
             "cloths": [ { "mesh": { "pattern": { "builtin": "miura-ori", "size": 1.0 } },
                           "material": { "density": 0.08, "stretch_compliance": 1e-4, "thickness": 0.0 } } ] }"#,
    );
    let (model, mut world) = scene.model(scenes_dir(), "t").unwrap();
    let (mut backend, _) = GpuBackend::new(context(), &model, &world, &scene.solver).unwrap();
    let mut particles = pleat::Particles::new(model.rest.clone(), &model.mass);
    for (i, v) in particles.v.iter_mut().enumerate() {
        *v = Vec3::new(0.0, 0.0, (i % 7) as f32 * 0.1);
    }
    backend.upload(&particles);
    let control = Control {
        fold: FoldDrive {
            progress: 0.8,
            held: false,
            flat: false,
        },
        ..Control::frame(scene.frame_dt())
    };
    let mut stages = pleat::solver::StageTimes::default();
    let mut health = None;
    let compliances = Compliances::of(&model);
    for _ in 0..10 {
        backend.step(
            &mut particles,
            &mut world,
            &scene.solver,
            &compliances,
            &control,
            &mut stages,
        );
        world.time += scene.frame_dt();
        backend.finish(&mut stages);
        health = backend.health();
        assert!(
            health.is_some(),
            "each frame's health arrives once it has run"
        );
    }
    let health = health.unwrap();
    backend.download(&mut particles);
    let energy = mechanical_energy(&model, &world, &particles);
    let kinetic = particles.kinetic_energy();
    assert!(kinetic > 1e-4, "the sheet moves ({kinetic} J)");
    assert!(
        (health.mechanical_energy - energy).abs() <= 1e-4 * (kinetic + energy.abs()),
        "{} J on the GPU, {energy} J on the CPU",
        health.mechanical_energy
    );
    let tear = tear_edges(&model)
        .map(|e| e.tear(&particles.x))
        .fold(f32::MIN, f32::max);
    let strained = tear * (1.0 + pleat::stability::PAPER_TEAR_STRAIN) - 1.0;
    assert!(strained > 1e-4, "the folding sheet strains ({strained})");
    assert!(
        (health.tear - tear).abs() < 1e-5,
        "{} vs {tear}",
        health.tear
    );
    assert!(!health.non_finite);
    assert_eq!(health.time, world.time);
    let fastest = (0..particles.len()).max_by(|&a, &b| {
        particles.v[a]
            .length_squared()
            .total_cmp(&particles.v[b].length_squared())
    });
    assert_eq!(
        health
            .culprit
            .map(|i| particles.v[i as usize].length_squared()),
        fastest.map(|i| particles.v[i].length_squared())
    );
}

/// A 16 x 16 sheet, flat at first, hanging from two corners (no tethers).
const SWINGING: &str = r#"{ "name": "swinging", "fps": 60, "solver": { "substeps": 10 },
    "cloths": [ { "mesh": { "grid": { "resolution": [16, 16], "size": [1.0, 1.0], "orientation": "horizontal", "center": [0.0, 1.5, 0.0] } },
                  "material": { "stretch_compliance": 0.0, "shear_compliance": 1e-6 },
                  "pins": [ { "corners": ["top_left", "top_right"] } ] } ] }"#;

/// Largest distance between two sets of positions.
fn largest_move(a: &[Vec3], b: &[Vec3]) -> f32 {
    a.iter()
        .zip(b)
        .map(|(p, q)| p.distance(*q))
        .fold(0.0, f32::max)
}

#[test]
fn a_live_stretch_compliance_changes_both_backends_alike_and_keeps_the_state() {
    let scene = scene(SWINGING);
    let mut stiff = cpu(&scene);
    run(&mut stiff, &scene, 60);
    let stiff_stretch = stiff.metrics().max_stretch;
    let (mut c, mut g) = (cpu(&scene), gpu(&scene));
    for sim in [&mut c, &mut g] {
        run(sim, &scene, 30);
        let before = sim.particles.x.clone();
        let swung = largest_move(&before, &sim.model.rest);
        *sim.compliances.get_mut(0, ComplianceKind::Stretch).unwrap() = 1e-2;
        run(sim, &scene, 1);
        let jump = largest_move(&before, &sim.particles.x);
        assert!(
            swung > 0.3 && jump < 0.2 * swung,
            "{}: the state goes on ({jump} m in a frame, {swung} m from rest)",
            sim.backend_name()
        );
        run(sim, &scene, 29);
        let soft_stretch = sim.metrics().max_stretch;
        assert!(
            soft_stretch > stiff_stretch + 0.05,
            "{}: softer edges stretch more ({soft_stretch} vs {stiff_stretch})",
            sim.backend_name()
        );
    }
    let mean = mean_distance(&c, &g);
    assert!(mean < 0.01, "GPU differs from CPU by {mean} m on average");
    let (mc, mg) = (c.metrics().max_stretch, g.metrics().max_stretch);
    assert!(
        (mg - mc).abs() < 0.02 * mc,
        "max stretch {mg} on the GPU, {mc} on the CPU"
    );
}

#[test]
fn a_blocking_read_after_an_untaken_request_reads_the_current_state() {
    let scene = drape();
    let (mut a, mut b) = (gpu(&scene), gpu(&scene));
    for sim in [&mut a, &mut b] {
        steps(sim, &scene, 5);
    }
    b.request_sync();
    for round in 0..3 {
        for sim in [&mut a, &mut b] {
            run(sim, &scene, 5);
        }
        assert!(
            a.particles.x == b.particles.x && a.particles.v == b.particles.v,
            "read {round}"
        );
    }
}

/// An 8 x 8 sheet lying on a frictionless floor, gravity tilted as on a
/// slope of 0.3: it slides until friction holds it.
const SLIDING: &str = r#"{ "name": "sliding", "fps": 60, "gravity": [3.0, -9.81, 0.0], "solver": { "substeps": 10 },
    "cloths": [ { "mesh": { "grid": { "resolution": [8, 8], "size": [0.5, 0.5], "orientation": "horizontal", "center": [0.0, 0.005, 0.0] } } } ],
    "colliders": [ { "shape": { "plane": {} }, "friction": { "static": 0.0, "kinetic": 0.0 } } ] }"#;

/// Mean velocity along the slope.
fn mean_slide(sim: &Simulation) -> f32 {
    sim.particles.v.iter().map(|v| v.x).sum::<f32>() / sim.particles.len() as f32
}

#[test]
fn a_live_collider_friction_change_stops_the_sliding_sheet_on_both_backends() {
    let scene = scene(SLIDING);
    let (mut c, mut g) = (cpu(&scene), gpu(&scene));
    for sim in [&mut c, &mut g] {
        run(sim, &scene, 10);
        let slide = mean_slide(sim);
        assert!(
            slide > 0.3,
            "{}: the sheet slides on the frictionless floor ({slide} m/s)",
            sim.backend_name()
        );
        sim.world.colliders[0].friction = pleat::collide::Friction {
            static_coefficient: 1.0,
            kinetic_coefficient: 0.9,
        };
        run(sim, &scene, 20);
        let slide = mean_slide(sim);
        assert!(
            slide.abs() < 0.01,
            "{}: friction holds the sheet ({slide} m/s)",
            sim.backend_name()
        );
    }
    let mean = mean_distance(&c, &g);
    assert!(mean < 1e-3, "GPU differs from CPU by {mean} m on average");
}

#[test]
fn stage_times_keep_coming_after_the_substeps_are_raised() {
    assert!(
        context()
            .device
            .features()
            .contains(wgpu::Features::TIMESTAMP_QUERY),
        "the adapter stamps passes (lavapipe does)"
    );
    let scene = scene(FALLING);
    let mut g = gpu(&scene);
    step_unread(&mut g, &scene, 2);
    assert!(g.stages.constraints > std::time::Duration::ZERO);
    g.settings.substeps = 3 * scene.solver.substeps;
    g.stages = Default::default();
    step_unread(&mut g, &scene, 2);
    let s = g.stages;
    assert!(
        s.predict > std::time::Duration::ZERO && s.constraints > std::time::Duration::ZERO,
        "{s:?}"
    );
}

/// When a fold comes to rest its strain limits tighten to the held ones in
/// sweeps over the positions alone, checked by the self-contacts in
/// rounds, as on the CPU. Origami Simulator's whirlpool twist with a
/// thickness, folded on the CPU to two frames before it comes to rest,
/// then on the GPU: with the sweeps unchecked it crossed itself 17 times
/// in the frame they tightened, and twice with rounds of ten sweeps.
#[test]
fn layers_stay_apart_while_the_held_strain_limits_tighten_on_the_gpu() {
    use pleat::metrics::intersections::count_self_intersections;
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../patterns/origami-simulator/whirlpool.svg");
    let sheet =
        Sheet::from_pattern(&load_pattern(&path).unwrap(), &SheetOptions::default()).unwrap();
    let (model, world) = paper_model(&sheet);
    let settings = paper_solver_settings_with_contact(0.0005);
    let cpu = Box::new(pleat::CpuBackend::new(&model, &settings));
    let ramp = FoldRamp {
        progress: 1.0,
        frames: 120,
    };
    let mut sim = paper_simulation_on((model, world), settings, cpu, ramp);
    for _ in 0..HELD_AT - 2 {
        sim.step(1.0 / 60.0);
    }
    let (gpu, _) = GpuBackend::new(context(), &sim.model, &sim.world, &sim.settings).unwrap();
    sim.replace_backend(Box::new(gpu));
    for frame in HELD_AT - 1..=HELD_AT + 2 {
        sim.step(1.0 / 60.0);
        sim.sync();
        let crossings = count_self_intersections(&sim.particles.x, &sim.model.triangles);
        assert_eq!(crossings, 0, "at frame {frame}");
    }
    assert!(sim.metrics().max_stretch < 1.05);
}

/// The frame in which a fold ramped over 120 frames comes to rest.
const HELD_AT: u32 = 121;

/// The persistent kernel keeps a sheet's contact pairs over its dispatches
/// and frames: Origami Simulator's crane with a thickness, lying flat and
/// still, builds them once in ten frames (a CPU adapter cuts each frame
/// into dozens of dispatches, which each built them anew before). The
/// fold is held from the start, so the first frame also checks the held
/// limits' sweeps with the candidates of the hash grid: one build more.
#[test]
fn a_still_sheet_keeps_its_contact_pairs_over_dispatches_and_frames() {
    let mut sim = crane_on_gpu(paper_solver_settings_with_contact(0.0005), 0.0);
    for _ in 0..10 {
        sim.step(1.0 / 60.0);
    }
    sim.sync();
    // The persistent kernel: fewer dispatches a frame than substeps.
    let dispatches = sim.backend().dispatches_per_frame().unwrap();
    assert!(
        dispatches < sim.settings.substeps,
        "{dispatches} dispatches"
    );
    assert_eq!(sim.stages.self_contact_builds, 2);
}
