//! Whole-simulation physics checks of the XPBD solver: conservation, rest,
//! iteration-independent stiffness, robustness and contacts.

use pleat::glam::Vec3;
use pleat::scene::presets::hanging_cloth;
use pleat::scene::Scene;
use pleat::Simulation;
use std::path::Path;

fn scenes_dir() -> &'static Path {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../../scenes"))
}

fn build(scene: &Scene) -> Simulation {
    scene.build(scenes_dir(), &scene.name).expect("valid scene")
}

fn load(name: &str) -> Scene {
    Scene::load(&scenes_dir().join(name)).expect("shipped scene is valid")
}

fn run(sim: &mut Simulation, frames: u32, dt: f32) {
    for _ in 0..frames {
        sim.step(dt);
    }
}

/// The largest distance between the same particle in `a` and `b`.
fn farthest_apart(a: &[Vec3], b: &[Vec3]) -> f32 {
    a.iter()
        .zip(b)
        .map(|(p, q)| p.distance(*q))
        .fold(0.0, f32::max)
}

/// A free 12 x 12 cloth at the origin with no gravity, no damping and no pins.
fn free_cloth(stretch_compliance: f32) -> Scene {
    let mut scene = hanging_cloth(12, 10, false);
    scene.gravity = Vec3::ZERO;
    if let pleat::scene::MeshSpec::Grid(grid) = &mut scene.cloths[0].mesh {
        grid.center = Vec3::ZERO;
    }
    scene.solver.damping = 0.0;
    scene.cloths[0].pins.clear();
    scene.cloths[0].material.stretch_compliance = stretch_compliance;
    scene
}

#[test]
fn compliance_zero_cloth_at_rest_stays_at_rest() {
    let mut sim = build(&free_cloth(0.0));
    let rest = sim.particles.x.clone();
    run(&mut sim, 120, 1.0 / 60.0);
    let drift = farthest_apart(&sim.particles.x, &rest);
    assert!(drift < 1e-6, "a cloth at rest moved by {drift} m");
}

#[test]
fn linear_momentum_is_kept_without_external_forces() {
    let mut sim = build(&free_cloth(1e-5));
    // Stir it: a velocity field with net momentum and plenty of shear and bending.
    for (i, v) in sim.particles.v.iter_mut().enumerate() {
        let f = i as f32;
        *v = Vec3::new(
            (f * 0.37).sin() + 0.3,
            (f * 0.11).cos() - 0.2,
            (f * 0.73).sin() * 2.0 + 0.1,
        );
    }
    let before = sim.particles.momentum();
    let energy = sim.particles.kinetic_energy();
    run(&mut sim, 60, 1.0 / 60.0);
    let after = sim.particles.momentum();
    assert!(
        sim.particles.kinetic_energy() < 0.9 * energy,
        "the constraints worked: energy went into deformation and was dissipated"
    );
    assert!(
        after.distance(before) < 1e-3 * before.length(),
        "momentum {before} became {after}"
    );
}

#[test]
fn pinned_cloth_comes_to_rest() {
    let mut scene = hanging_cloth(24, 10, false);
    scene.solver.damping = 1.0;
    let mut sim = build(&scene);
    let pins: Vec<Vec3> = sim
        .model
        .pins
        .iter()
        .map(|p| sim.particles.x[p.particle as usize])
        .collect();
    run(&mut sim, 600, 1.0 / 60.0);
    let before = sim.particles.x.clone();
    run(&mut sim, 60, 1.0 / 60.0);
    let drift = farthest_apart(&sim.particles.x, &before);
    assert!(drift < 1e-3, "still moving {drift} m per second after 10 s");
    assert!(
        sim.particles.kinetic_energy() < 1e-6,
        "kinetic energy {}",
        sim.particles.kinetic_energy()
    );
    for (p, x0) in sim.model.pins.iter().zip(pins) {
        assert_eq!(sim.particles.x[p.particle as usize], x0, "a pin moved");
    }
    // Hung by its corners, which are as far apart as at rest, the
    // inextensible top edge stays straight: its middle cannot sag from
    // 2 m without stretching it (a solve that has not converged lets it).
    let top_middle = sim.particles.x[12].y;
    assert!(
        (top_middle - 2.0).abs() < 1e-3,
        "the top edge sags: its middle is at {top_middle} m"
    );
}

/// A soft hanging strip (2 x 12 particles, pinned at its top corners) of
/// stretch compliance `compliance`, settled for 10 s.
fn settled_strip(iterations: u32, compliance: f32, max_strain: Option<f32>) -> Simulation {
    let mut scene = hanging_cloth(2, 20, false);
    if let pleat::scene::MeshSpec::Grid(grid) = &mut scene.cloths[0].mesh {
        grid.resolution = [2, 12];
        grid.size = [0.1, 1.0];
    }
    scene.solver.iterations = iterations;
    scene.solver.damping = 5.0;
    let material = &mut scene.cloths[0].material;
    material.stretch_compliance = compliance;
    material.shear_compliance = compliance;
    material.max_strain = max_strain;
    let mut sim = build(&scene);
    run(&mut sim, 600, 1.0 / 60.0);
    sim
}

/// Relative elongation of the soft strip once it has settled.
fn settled_elongation(iterations: u32) -> f32 {
    let sim = settled_strip(iterations, 2e-2, None);
    let length = sim.particles.x[0].distance(sim.particles.x[22]);
    length - 1.0
}

#[test]
fn a_strain_limit_holds_a_soft_strip_at_its_limit() {
    let free = settled_strip(1, 0.2, None).metrics();
    assert!(free.max_stretch > 1.05, "unlimited: {}", free.max_stretch);
    let limited = settled_strip(1, 0.2, Some(0.01)).metrics();
    assert!(!limited.nan);
    // Every edge stops at 1 %: the soft strip hangs on its limits.
    assert!(
        (1.009..=1.0105).contains(&limited.max_stretch),
        "limited to 1 %: {}",
        limited.max_stretch
    );
}

#[test]
fn the_strain_limit_converges_on_a_long_heavy_strip() {
    // A strip of 120 rows hung from its top, so soft that gravity alone
    // would stretch it by half: two Gauss-Seidel sweeps of the limits a
    // substep leave its top edges near 5 %, since each correction
    // stretches the neighbours; the sweeps go on until every edge is
    // within 1.8 times its 1 % limit.
    let mut scene = hanging_cloth(2, 20, false);
    if let pleat::scene::MeshSpec::Grid(grid) = &mut scene.cloths[0].mesh {
        grid.resolution = [2, 120];
        grid.size = [0.05, 3.0];
    }
    let material = &mut scene.cloths[0].material;
    material.stretch_compliance = 1.0;
    material.shear_compliance = 1.0;
    material.max_strain = Some(0.01);
    let mut sim = build(&scene);
    run(&mut sim, 120, 1.0 / 60.0);
    let m = sim.metrics();
    assert!(!m.nan);
    assert!(
        m.max_stretch <= 1.018 + 1e-4,
        "every edge within 1.8 % at the end of each substep: {}",
        m.max_stretch
    );
}

#[test]
fn xpbd_stiffness_does_not_depend_on_iterations() {
    let one = settled_elongation(1);
    let ten = settled_elongation(10);
    assert!(one > 0.005, "the soft strip stretches visibly: {one}");
    // Plain PBD would be far stiffer with ten iterations than with one; with
    // XPBD the compliance alone sets the stiffness.
    assert!(
        (one - ten).abs() < 0.05 * ten,
        "elongation with 1 iteration {one}, with 10 {ten}"
    );
}

#[test]
fn extreme_inputs_give_no_nan() {
    let mut scene = hanging_cloth(16, 1, false);
    scene.fps = 30.0;
    scene.cloths[0].material.stretch_compliance = 0.0;
    scene.wind = Some(pleat::force::Wind {
        velocity: Vec3::new(2500.0, 0.0, 2500.0),
        turbulence: 1.0,
        ..Default::default()
    });
    let (mut model, world) = scene.model(scenes_dir(), "extreme").unwrap();
    // One particle of a microgram, the rest as usual.
    model.mass[100] = 1e-6;
    let mut sim = Simulation::new(model, world, scene.solver);
    run(&mut sim, 120, 1.0 / 30.0);
    assert!(!sim.metrics().nan, "NaN or infinity in the state");
}

#[test]
fn tiny_density_cloth_in_gale_gives_no_nan() {
    let mut scene = hanging_cloth(16, 1, true);
    scene.fps = 30.0;
    scene.cloths[0].material.density = 1e-3; // particles of about 4e-6 kg
    scene.wind = Some(pleat::force::Wind {
        velocity: Vec3::new(0.0, 0.0, 2500.0),
        ..Default::default()
    });
    let mut sim = build(&scene);
    run(&mut sim, 120, 1.0 / 30.0);
    assert!(!sim.metrics().nan);
}

/// Runs a shipped scene to its end and checks that no particle is inside a collider.
fn assert_no_particle_inside(name: &str) {
    let scene = load(name);
    let mut sim = build(&scene);
    run(&mut sim, scene.frames, scene.frame_dt());
    let m = sim.metrics();
    assert!(!m.nan);
    assert_eq!(m.collider_penetrations, 0);
    let t = sim.world.time;
    let deepest = sim
        .particles
        .x
        .iter()
        .flat_map(|x| {
            sim.world
                .colliders
                .iter()
                .map(move |c| c.signed_distance_at(*x, t))
        })
        .fold(f32::MAX, f32::min);
    assert!(
        deepest >= 0.0,
        "{name}: a particle is {deepest} m inside a collider"
    );
}

#[test]
fn drape_ends_with_no_particle_inside_a_collider() {
    assert_no_particle_inside("drape.json");
}

#[test]
fn rotating_sphere_ends_with_no_particle_inside_a_collider() {
    assert_no_particle_inside("rotating_sphere.json");
}

#[test]
fn rotating_sphere_drags_the_cloth_round() {
    let scene = load("rotating_sphere.json");
    let mut sim = build(&scene);
    run(&mut sim, 180, scene.frame_dt());
    // Angular momentum about the sphere's (vertical) axis, from the cloth resting on top.
    let top: Vec<usize> = (0..sim.particles.len())
        .filter(|&i| sim.particles.x[i].y > 0.85)
        .collect();
    assert!(!top.is_empty());
    let spin: f32 = top
        .iter()
        .map(|&i| sim.particles.x[i].cross(sim.particles.v[i]).y)
        .sum::<f32>()
        / top.len() as f32;
    assert!(
        spin > 0.0,
        "friction turns the cloth with the sphere (mean r x v . y = {spin})"
    );
}

#[test]
fn tethers_limit_stretch_of_large_hanging_cloth() {
    let mut sim = build(&hanging_cloth(128, 10, true));
    run(&mut sim, 300, 1.0 / 60.0);
    let m = sim.metrics();
    assert!(!m.nan);
    assert!(
        m.max_stretch <= 1.02,
        "max stretch with tethers after 5 s: {}",
        m.max_stretch
    );
}

/// How far the hanging cloth reaches below its pins after the bench's 90
/// frames (1.5 s) with `iterations` sweeps a substep, and its largest
/// stretch.
fn hanging_reach(n: u32, iterations: u32) -> (f32, f32) {
    let mut scene = hanging_cloth(n, 10, false);
    scene.solver.iterations = iterations;
    let mut sim = build(&scene);
    run(&mut sim, 90, 1.0 / 60.0);
    let m = sim.metrics();
    assert!(!m.unstable, "{n} x {n}: unstable");
    let x = &sim.particles.x;
    let top = x.iter().map(|p| p.y).fold(f32::MIN, f32::max);
    let bottom = x.iter().map(|p| p.y).fold(f32::MAX, f32::min);
    (top - bottom, m.max_stretch)
}

#[test]
fn fine_hanging_cloth_holds_its_length_and_hangs_alike_at_every_resolution() {
    // One sweep a substep moves a correction one edge: without the
    // hierarchy's coarse levels the cloth reaches 3.2 (128) and 232 (256)
    // times an edge's length at the pins, and falls 4.6 m at 256.
    let (reference, _) = hanging_reach(64, 1);
    for (n, iterations) in [(128, 1), (256, 1), (64, 4), (128, 4)] {
        let (reach, stretch) = hanging_reach(n, iterations);
        assert!(stretch <= 1.05, "{n} x {n}: max stretch {stretch}");
        assert!(
            (reach - reference).abs() <= 0.05 * reference,
            "{n} x {n}, {iterations} iterations: reaches {reach} m below its top, 64 x 64: {reference} m"
        );
    }
}

#[test]
fn a_fine_cloth_hanging_in_its_plane_is_not_squeezed_by_its_coarse_levels() {
    // Held by its two top corners, the sheet in its vertical plane rests
    // partly on compression: the strip under its taut top edge is held up
    // by the cloth below it. Coarse limits that only pulled lifted the
    // rows below and squeezed that strip; at 512 x 512 the one fine sweep
    // a substep could not undo it, rows passed through one another and
    // edges reached 1.12 times their length by frame 30 (1.45 at 1024).
    let mut sim = build(&hanging_cloth(512, 10, false));
    run(&mut sim, 30, 1.0 / 60.0);
    let m = sim.metrics();
    assert!(!m.unstable, "unstable");
    assert!(m.max_stretch <= 1.05, "max stretch {}", m.max_stretch);
}

/// The largest stretch at a frame's end while `particle` of the rigid
/// demo's cloth, draped on its spinning sphere, is dragged at `velocity`
/// (m/s) for 1 s.
fn stretch_while_dragged(sim: &mut Simulation, particle: u32, velocity: Vec3) -> f32 {
    run(sim, 60, 1.0 / 60.0);
    let start = sim.sync().x[particle as usize];
    let mut worst: f32 = 0.0;
    for frame in 1..=60 {
        let t = frame as f32 / 60.0;
        sim.grab(Some(pleat::constraint::Grab {
            particle,
            target: start + velocity * t,
            compliance: 1e-5,
        }));
        sim.step(1.0 / 60.0);
        sim.sync();
        worst = worst.max(sim.metrics().max_stretch);
    }
    worst
}

#[test]
fn dragging_the_rigid_demo_stretches_no_edge_past_a_tenth() {
    // The app's spinning-sphere demo as shipped, draped, then dragged for
    // a second as a user tried it: by a corner up and away (a spike of 9.2
    // times an edge's length before the grab reached over the cloth, 1.13
    // after) and by the middle of an edge up across the sphere, whose
    // friction and the ground's hold parts of the cloth back (1.25). The
    // demo's 5 % strain limit, swept again after the contacts, holds every
    // edge within the limit and its slack, 1.09; swept before the contacts
    // alone, the edge drag reached 3.73.
    let scene = load("rotating_sphere.json");
    let limit = scene.cloths[0].material.max_strain.expect("a strain limit");
    let bound = 1.0 + pleat::solver::xpbd::STRAIN_LIMIT_SLACK * limit;
    assert!(bound <= 1.1, "the demo's limit allows {bound}");
    for (particle, velocity) in [
        (0, Vec3::new(-0.5, 1.0, 0.0)),
        (32, Vec3::new(0.0, 0.6, -1.0)),
    ] {
        let mut sim = build(&scene);
        let stretch = stretch_while_dragged(&mut sim, particle, velocity);
        assert!(
            stretch <= bound + 1e-3,
            "particle {particle}: max stretch {stretch} while dragged"
        );
    }
}

/// Where a 16 x 16 hanging cloth ends after its lower left corner is
/// dragged 0.2 m in, 0.3 m up and 0.2 m out over half a second, in frames
/// of `1 / fps` with `substeps` each, the grab's target set at each
/// frame's end as a hand would be read.
fn dragged_corner(fps: f32, substeps: u32) -> Vec<Vec3> {
    let mut scene = hanging_cloth(16, substeps, false);
    scene.fps = fps;
    let mut sim = build(&scene);
    let x = &sim.particles.x;
    let corner = (0..x.len())
        .min_by(|&a, &b| (x[a].y + x[a].x).total_cmp(&(x[b].y + x[b].x)))
        .unwrap();
    let start = x[corner];
    let frames = (0.5 * fps).round() as u32;
    for frame in 1..=frames {
        let t = frame as f32 / frames as f32;
        sim.grab(Some(pleat::constraint::Grab {
            particle: corner as u32,
            target: start + Vec3::new(0.2, 0.3, 0.2) * t,
            compliance: 0.0,
        }));
        sim.step(1.0 / fps);
    }
    sim.sync().x.clone()
}

#[test]
fn a_drag_does_not_depend_on_how_its_frames_are_cut_into_substeps() {
    // The grab's target moves on over a frame's substeps, as the hand
    // did: ten substeps a frame move the cloth as ten frames of one
    // substep do (0.5 mm apart at the end, from the first frame, where
    // the target starts). When the target jumped at each frame's first
    // substep, yanking the corner ten substeps' worth at once, they ended
    // 12 mm apart.
    let coarse = dragged_corner(60.0, 10);
    let fine = dragged_corner(600.0, 1);
    let apart = farthest_apart(&coarse, &fine);
    assert!(apart < 2e-3, "the two runs end {apart} m apart");
}

/// An 8 x 8 cloth, 1 m wide, whose top corners scripted pins pull apart
/// at 2 m/s each: 3 m apart after half a second.
fn pulled_apart(stretch_compliance: f32) -> Scene {
    let json = format!(
        r#"{{ "name": "pulled", "fps": 60, "solver": {{ "substeps": 10 }},
        "cloths": [ {{ "mesh": {{ "grid": {{ "resolution": [8, 8], "size": [1.0, 1.0], "orientation": "vertical", "center": [0.0, 1.0, 0.0] }} }},
            "material": {{ "stretch_compliance": {stretch_compliance} }},
            "pins": [ {{ "corners": ["top_left"], "motion": {{ "linear_velocity": [-2.0, 0.0, 0.0] }} }},
                      {{ "corners": ["top_right"], "motion": {{ "linear_velocity": [2.0, 0.0, 0.0] }} }} ] }} ] }}"#
    );
    Scene::parse(&json, "pulled.json").unwrap()
}

#[test]
fn a_cloth_pulled_to_three_times_its_width_is_torn_unless_it_may_stretch() {
    // Inextensible: more than 1 % of its edges pass three times their
    // length (the width is 3 m at 0.5 s, 4 m at 0.75 s), counted once
    // that has lasted 0.25 s.
    let mut sim = build(&pulled_apart(0.0));
    run(&mut sim, 60, 1.0 / 60.0);
    let (at, kind) = sim.stability.first.expect("torn");
    assert_eq!(kind, pleat::stability::Instability::Torn);
    assert!(at > 0.0 && at < 0.75, "torn since {at} s");
    // A compliant cloth stretches as it may.
    let mut sim = build(&pulled_apart(1e-2));
    run(&mut sim, 60, 1.0 / 60.0);
    assert!(sim.metrics().max_stretch > 2.0, "stretched");
    assert_eq!(sim.stability.first, None);
}

#[test]
fn results_do_not_depend_on_thread_count() {
    let scene = load("flag.json");
    let positions = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            let mut sim = build(&scene);
            run(&mut sim, 30, scene.frame_dt());
            sim.particles.x
        })
    };
    let (one, two) = (positions(1), positions(2));
    assert!(one
        .iter()
        .zip(&two)
        .all(|(a, b)| a.to_array().map(f32::to_bits) == b.to_array().map(f32::to_bits)));
}

#[test]
fn cloth_rests_on_box_and_capsule_without_penetrating() {
    let json = r#"{
      "frames": 150,
      "cloths": [ { "mesh": { "grid": { "resolution": [24, 24], "size": [1.2, 1.2], "center": [0, 1, 0] } } } ],
      "colliders": [
        { "shape": { "box": { "center": [0, 0.4, 0], "half_extents": [0.2, 0.4, 0.2], "rotation_degrees": [0, 30, 0] } } },
        { "shape": { "capsule": { "a": [0.45, 0.2, -0.3], "b": [0.45, 0.2, 0.3], "radius": 0.12 } } },
        { "shape": { "plane": {} } }
      ]
    }"#;
    let scene = Scene::parse(json, "box_capsule.json").unwrap();
    let mut sim = build(&scene);
    run(&mut sim, scene.frames, scene.frame_dt());
    let m = sim.metrics();
    assert!(!m.nan && m.collider_penetrations == 0);
    // Something rests on top of the box (its top face is at 0.8 m).
    let on_box = sim
        .particles
        .x
        .iter()
        .filter(|x| x.y > 0.79 && x.y < 0.83)
        .count();
    assert!(on_box > 0, "the cloth lies on the box");
}

#[test]
fn scripted_pin_follows_its_motion() {
    let json = r#"{
      "cloths": [ { "mesh": { "grid": { "resolution": [8, 8], "orientation": "vertical", "center": [0, 1, 0] } },
                    "pins": [ { "corners": ["top_left"], "motion": { "linear_velocity": [0.5, 0, 0] } },
                              { "corners": ["top_right"], "compliance": 1e-4 } ] } ]
    }"#;
    let scene = Scene::parse(json, "moving_pin.json").unwrap();
    let mut sim = build(&scene);
    let start = sim.particles.x[0];
    run(&mut sim, 60, 1.0 / 60.0);
    let moved = sim.particles.x[0] - start;
    assert!(
        moved.distance(Vec3::new(0.5, 0.0, 0.0)) < 1e-4,
        "hard pin moved by {moved}"
    );
    // The soft pin holds its corner near its anchor, but not exactly.
    let soft = sim.particles.x[7].distance(Vec3::new(0.5, 1.5, 0.0));
    assert!(
        soft > 0.0 && soft < 0.05,
        "soft pin is {soft} m from its anchor"
    );
}

#[test]
fn wind_blows_the_flag_downwind() {
    let scene = load("flag.json");
    let mut sim = build(&scene);
    run(&mut sim, 120, scene.frame_dt());
    let mean_z = sim.particles.x.iter().map(|x| x.z).sum::<f32>() / sim.particles.len() as f32;
    let free_edge_x = sim.particles.x[59].x;
    assert!(
        mean_z > 0.02,
        "the wind's z component pushes the flag: mean z {mean_z}"
    );
    assert!(
        free_edge_x > 1.0,
        "the free edge streams out downwind: x = {free_edge_x}"
    );
}

#[test]
fn bunny_drape_on_the_mesh_collider_ends_with_no_particle_inside() {
    assert_no_particle_inside("bunny_drape.json");
}

#[test]
fn bunny_drape_on_the_sdf_collider_ends_with_no_particle_inside() {
    assert_no_particle_inside("bunny_sdf.json");
}

#[test]
fn a_grab_whose_target_jumps_follows_at_a_hands_speed_without_crossings() {
    // The drape demo's inextensible tablecloth, settled on its sphere and
    // grabbed at the top, the grab's target set 0.5 m up at once, as a
    // cursor does when a slow frame lets it run ahead: reached within one
    // frame's first substep, it flung the cloth through itself (13,000
    // crossing triangle pairs, and 10 GB of contact candidates that the
    // browser's WebAssembly could not allocate). Followed at a hand's
    // speed, it rises without a crossing and ends at the target.
    let dt = 1.0 / 60.0;
    let mut sim = build(&load("drape.json"));
    run(&mut sim, 43, dt);
    let x = sim.sync().x.clone();
    let particle = (0..x.len())
        .max_by(|&a, &b| x[a].y.total_cmp(&x[b].y))
        .unwrap();
    let start = x[particle];
    let target = start + Vec3::Y * 0.5;
    sim.grab(Some(pleat::constraint::Grab {
        particle: particle as u32,
        target,
        compliance: 1e-5,
    }));
    for frame in 1..=60 {
        sim.step(dt);
        let risen = sim.sync().x[particle].y - start.y;
        // Half the demo's contact thickness (8 mm) a substep, 10 a frame.
        let hand = 0.5 * 0.008 * 10.0 * frame as f32;
        assert!(
            risen <= hand + 0.01,
            "frame {frame}: risen {risen} m, a hand {hand} m"
        );
        let crossings = sim.metrics().self_intersections;
        assert_eq!(crossings, 0, "frame {frame}: crossing triangle pairs");
    }
    let off = sim.particles.x[particle].distance(target);
    assert!(
        off < 0.05,
        "the grabbed particle ends {off} m from its target"
    );
}
