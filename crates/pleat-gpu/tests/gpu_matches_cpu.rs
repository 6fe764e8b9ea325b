//! The GPU backend against the CPU backend on whole scenes, and on one step
//! of small scenes that exercise one kernel each.

mod common;
use common::*;

/// After one frame of a small scene the GPU state is the CPU state to
/// round-off: each kernel computes what the core function it ports does.
fn one_frame_matches(text: &str, what: &str) {
    frames_match(text, what, 1);
    frames_match(text, what, 10);
}

/// [`one_frame_matches`] after `frames` frames, on both of the GPU's ways
/// of running a frame (they differ where the scene is a small sheet).
fn frames_match(text: &str, what: &str, frames: u32) {
    frames_match_on(text, what, frames, true);
    frames_match_on(text, what, frames, false);
}

fn frames_match_on(text: &str, what: &str, frames: u32, persistent: bool) {
    let scene = scene(text);
    let (mut c, mut g) = (cpu(&scene), gpu_with(&scene, persistent));
    run(&mut c, &scene, frames);
    run(&mut g, &scene, frames);
    let moved = c
        .particles
        .x
        .iter()
        .zip(&c.model.rest)
        .map(|(x, r)| x.distance(*r))
        .fold(0.0, f32::max);
    assert!(moved > 1e-4, "{what}: the scene must move ({moved})");
    let err = max_distance(&c, &g);
    // Round-off grows with the frames: 1e-5 after one, 1e-4 after more.
    let tolerance = if frames == 1 { 1e-5 } else { 1e-4 };
    assert!(
        err <= tolerance * moved.max(1.0),
        "{what}, {frames} frames (persistent {persistent}): GPU differs from CPU by {err} (moved {moved})"
    );
    assert!(!g.metrics().nan, "{what}");
}

const GRID: &str = r#"{ "grid": { "resolution": [8, 8], "size": [1.0, 1.0], "orientation": "horizontal", "center": [0.0, 1.0, 0.0] } }"#;

fn cloth(material: &str, extra: &str) -> String {
    format!(
        r#"{{ "name": "k", "frames": 1, "fps": 60, "solver": {{ "substeps": 4 }},
            "cloths": [ {{ "mesh": {GRID}, "material": {{ {material} }} {extra} }} ] "#
    )
}

#[test]
fn distance_and_dihedral_bending_kernels() {
    let text = cloth(
        r#""bending": "dihedral", "shear_compliance": 1e-5"#,
        r#", "pins": [ { "corners": ["top_left"] } ]"#,
    ) + "}";
    one_frame_matches(&text, "distance + dihedral");
}

#[test]
fn strain_limit_kernels() {
    // Edges so soft that the limits hold the hanging cloth from the first
    // frames, limited to 3 %: two sweeps a substep keep every edge within
    // 1.8 times that, so the CPU's further sweeps (while an edge is beyond)
    // do not start, and both backends run the same two.
    let hanging = |limit: &str| {
        cloth(
            &format!(r#""stretch_compliance": 0.5, "shear_compliance": 0.5 {limit}"#),
            r#", "pins": [ { "corners": ["top_left", "top_right"] } ]"#,
        ) + "}"
    };
    let text = hanging(r#", "max_strain": 0.03"#);
    one_frame_matches(&text, "distance with strain limits");
    let stretch_after_10 = |text: &str| {
        let scene = scene(text);
        let mut c = cpu(&scene);
        run(&mut c, &scene, 10);
        c.metrics().max_stretch
    };
    let (limited, free) = (stretch_after_10(&text), stretch_after_10(&hanging("")));
    assert!(
        free > 1.05 && limited < 1.035,
        "the limits hold: {limited} (without: {free})"
    );
}

#[test]
fn origami_hinge_kernels() {
    // Every crease of the waterbomb base driven to its full angle from the
    // flat sheet at once: linear creases in the first frame (the progress
    // moved), then held, stiffening springs whose errors from 178 degrees
    // down pass through every part of the law; facet diagonals stay linear.
    let text = r#"{ "name": "k", "frames": 1, "fps": 60, "gravity": [0, 0, 0],
        "solver": { "substeps": 4 },
        "cloths": [ { "mesh": { "pattern": { "builtin": "waterbomb-base", "size": 1.0 } },
                      "material": { "density": 0.08, "thickness": 0.0 } } ],
        "fold": { "progress": 1.0, "frames_to_fold": 0 } }"#;
    one_frame_matches(text, "origami hinges");
}

#[test]
fn origami_hinges_fold_in_steps() {
    // Two steps: the valleys to half their angle, then the mountains, the
    // valleys holding. The step change rewrites the hinges' start and end
    // angles in the items buffer (keeping the tracked angles the GPU
    // holds); after 6 frames both steps have run.
    let text = r#"{ "name": "k", "frames": 1, "fps": 60, "gravity": [0, 0, 0],
        "solver": { "substeps": 4 },
        "cloths": [ { "mesh": { "pattern": { "builtin": "waterbomb-base", "size": 1.0 } },
                      "material": { "density": 0.08, "thickness": 0.0 } } ],
        "fold": { "frames_to_fold": 3,
                  "steps": [ { "creases": "V", "fraction": 0.5 },
                             { "creases": "M", "fraction": 0.5 } ] } }"#;
    frames_match(text, "origami hinges folding in steps", 2);
    frames_match(text, "origami hinges folding in steps", 6);
}

/// A Miura-ori of paper-like cloth limited to 1 % strain, with `substeps`,
/// the edges' `stretch_compliance` and its fold `(progress, frames_to_fold)`.
fn limited_miura_paper(substeps: u32, stretch_compliance: f32, fold: (f32, u32)) -> String {
    format!(
        r#"{{ "name": "k", "frames": 2, "fps": 60, "gravity": [0, 0, 0],
            "solver": {{ "substeps": {substeps} }},
            "cloths": [ {{ "mesh": {{ "pattern": {{ "builtin": "miura-ori", "size": 1.0 }} }},
                          "material": {{ "density": 0.08, "thickness": 0.0,
                                         "stretch_compliance": {stretch_compliance:e},
                                         "max_strain": 0.01 }} }} ],
            "fold": {{ "progress": {progress:?}, "frames_to_fold": {frames} }} }}"#,
        progress = fold.0,
        frames = fold.1
    )
}

#[test]
fn strain_limit_kernel_while_the_fold_moves() {
    // Soft paper driven hard: its edges stretch past their 1 % limit, which
    // gives 20 times as much while the progress moves (the first ten frames;
    // the backend writes the moving limits into its items).
    // After one frame and after ten: the edges the first two sweeps left
    // beyond 1.8 times the limit take further sweeps on both backends.
    let text = limited_miura_paper(4, 1e-3, (1.0, 10));
    frames_match(&text, "strain limit while the fold moves", 1);
    frames_match(&text, "strain limit while the fold moves", 10);
}

#[test]
fn strain_limit_kernel_when_the_fold_comes_to_rest() {
    // Paper stretched beyond its 1 % limit while the progress moves (the
    // first frame, limits 20 %), then held: the limits are swept over the
    // positions before the second frame's first prediction, until no edge
    // is beyond its limit (up to 500 sweeps on both backends). Without that
    // pass the GPU differs by 8.7e-3 m; without the further sweeps in the
    // substeps (while an edge is beyond 1.8 times the limit) by 3.6e-4;
    // with both by round-off (6e-7).
    let scene = scene(&limited_miura_paper(16, 1e-1, (0.2, 1)));
    let mut c = cpu(&scene);
    run(&mut c, &scene, 2);
    for persistent in [true, false] {
        let mut g = gpu_with(&scene, persistent);
        run(&mut g, &scene, 2);
        let err = max_distance(&c, &g);
        assert!(
            err < 1e-5,
            "GPU (persistent {persistent}) differs from CPU by {err} m"
        );
        assert!(!g.metrics().nan);
    }
}

#[test]
fn a_small_sheet_folds_in_one_dispatch_a_frame_as_in_many() {
    // The waterbomb base folding, free (its turn kept every substep) and
    // held: one workgroup running every substep of a frame follows the
    // dispatches per colour, kind and substep, in a handful of dispatches
    // a frame (the frame, the health check's two, the held limits' one
    // when the fold comes to rest) instead of hundreds (19 a substep, the
    // strain limits' sweeps among them in one dispatch). The two differ by
    // round-off after a frame; the free sheet's drift from round-off then
    // grows by about 6e-6 m a frame, as much as either's from the CPU.
    let text = r#"{ "name": "k", "frames": 40, "fps": 60, "gravity": [0, 0, 0],
        "solver": { "substeps": 40 },
        "cloths": [ { "mesh": { "pattern": { "builtin": "waterbomb-base", "size": 1.0 } },
                      "material": { "density": 0.08, "thickness": 0.0, "max_strain": 0.01 } } ],
        "fold": { "progress": 0.9, "frames_to_fold": 20 } }"#;
    let scene = scene(text);
    let (mut one, mut many) = (gpu_with(&scene, true), gpu_with(&scene, false));
    let mut most = [0, 0];
    for frame in 1..=scene.frames {
        for (k, sim) in [&mut one, &mut many].into_iter().enumerate() {
            sim.step(scene.frame_dt());
            most[k] = most[k].max(sim.backend().dispatches_per_frame().unwrap());
        }
        if frame == 1 || frame == scene.frames {
            one.sync();
            many.sync();
            let err = max_distance(&one, &many);
            let tolerance = if frame == 1 { 1e-6 } else { 1e-3 };
            assert!(err < tolerance, "frame {frame}: the two differ by {err} m");
        }
    }
    let spin = one.particles.angular_momentum().length();
    assert!(spin < 1e-6, "angular momentum {spin} kg m^2/s");
    assert!(!one.metrics().nan && one.fold_progress() == 0.9);
    assert!(
        most[0] <= 4,
        "{} dispatches a frame in one workgroup",
        most[0]
    );
    assert!(
        most[1] > 500,
        "{} dispatches a frame, colour by colour",
        most[1]
    );
}

#[test]
fn the_strain_limit_converges_on_a_long_heavy_strip_on_both_backends() {
    // pleat's physics test of the same name, on the GPU too: a strip of
    // 120 rows hung from its top, so soft that gravity alone would stretch
    // it by half. Two sweeps of the limits a substep leave its top edges
    // near 5 %; the further sweeps, while an edge is beyond 1.8 times its
    // 1 % limit, hold every edge within 1.8 %.
    let mut scene = pleat::scene::presets::hanging_cloth(2, 20, false);
    if let pleat::scene::MeshSpec::Grid(grid) = &mut scene.cloths[0].mesh {
        grid.resolution = [2, 120];
        grid.size = [0.05, 3.0];
    }
    let material = &mut scene.cloths[0].material;
    material.stretch_compliance = 1.0;
    material.shear_compliance = 1.0;
    material.max_strain = Some(0.01);
    let (mut c, mut g) = (cpu(&scene), gpu(&scene));
    run(&mut c, &scene, 120);
    run(&mut g, &scene, 120);
    for (backend, sim) in [("cpu", &c), ("gpu", &g)] {
        let m = sim.metrics();
        assert!(!m.nan, "{backend}");
        assert!(
            m.max_stretch <= 1.018 + 1e-4,
            "{backend}: every edge within 1.8 % at the end of each substep: {}",
            m.max_stretch
        );
    }
    // The 3 m strip swings for two seconds. The coarse levels' floors (a
    // pair pushed back to its distance when the pass began) carry the
    // backends' different round-off further than pulls alone: 6e-6 m
    // apart after 5 frames, 2.6e-3 m after 120 (8e-5 m without floors).
    let err = max_distance(&c, &g);
    assert!(err < 5e-3, "GPU differs from CPU by {err} m");
}

#[test]
fn hierarchy_kernels() {
    // Pinned at two corners, the 8 x 8 cloth gets coarse levels; a drop
    // far beyond their limits makes every level's edges and
    // prolongation move it.
    let text = cloth(
        "",
        r#", "pins": [ { "corners": ["top_left", "top_right"] } ]"#,
    ) + "}";
    one_frame_matches(&text, "hierarchy");
}

#[test]
fn fine_hanging_cloth_holds_its_length_on_both_backends() {
    // Without the hierarchy: 3.2 times an edge's length at the pins.
    let scene = pleat::scene::presets::hanging_cloth(128, 10, false);
    let (mut c, mut g) = (cpu(&scene), gpu(&scene));
    run(&mut c, &scene, 90);
    run(&mut g, &scene, 90);
    for (backend, sim) in [("cpu", &c), ("gpu", &g)] {
        let m = sim.metrics();
        assert!(!m.unstable, "{backend}");
        assert!(
            m.max_stretch <= 1.05,
            "{backend}: max stretch {}",
            m.max_stretch
        );
    }
}

#[test]
fn grab_reach_kernel() {
    // A corner of a falling cloth dragged 1 m up over 10 frames: the rest
    // of the cloth comes along, on both backends alike.
    let text = cloth("", "") + "}";
    let scene = scene(&text);
    let (mut c, mut g) = (cpu(&scene), gpu(&scene));
    for frame in 1..=10 {
        let grab = pleat::constraint::Grab {
            particle: 0,
            target: pleat::glam::Vec3::new(-0.5, 1.0 + 0.1 * frame as f32, -0.5),
            compliance: 1e-5,
        };
        for sim in [&mut c, &mut g] {
            sim.grab(Some(grab));
            sim.step(scene.frame_dt());
            sim.sync();
        }
    }
    let err = max_distance(&c, &g);
    assert!(err <= 1e-4, "GPU differs from CPU by {err}");
    for (backend, sim) in [("cpu", &c), ("gpu", &g)] {
        let stretch = sim.metrics().max_stretch;
        assert!(
            stretch <= 1.1,
            "{backend}: max stretch while dragged {stretch}"
        );
    }
}

#[test]
fn isometric_bending_tether_and_soft_pin_kernels() {
    let text = cloth(
        r#""bending": "isometric""#,
        r#", "pins": [ { "corners": ["top_left"] }, { "corners": ["top_right"], "compliance": 1e-4 } ], "tethers": true"#,
    ) + "}";
    one_frame_matches(&text, "isometric + tethers + soft pin");
}

#[test]
fn jacobi_pbd_kernels() {
    let text = format!(
        r#"{{ "name": "k", "frames": 1, "fps": 60, "solver": {{ "kind": "jacobi_pbd", "substeps": 4, "iterations": 3 }},
            "cloths": [ {{ "mesh": {GRID}, "material": {{ "bending": "skip_one" }},
                          "pins": [ {{ "corners": ["top_left"] }}, {{ "corners": ["top_right"], "compliance": 1e-4 }} ] }} ] }}"#
    );
    // Jacobi corrections are small in the first frame of a fall: 20 frames.
    frames_match(&text, "jacobi pbd + soft pin", 20);
}

#[test]
fn wind_kernel() {
    let text = cloth(
        "",
        r#", "pins": [ { "corners": ["top_left", "top_right"] } ]"#,
    ) + r#", "wind": { "velocity": [3.0, 1.0, 2.0], "turbulence": 0.5 } }"#;
    one_frame_matches(&text, "wind with turbulence");
}

#[test]
fn collider_kernels() {
    for (name, shape) in [
        (
            "plane",
            r#"{ "plane": { "point": [0, 0.99, 0], "normal": [0, 1, 0] } }"#,
        ),
        (
            "sphere",
            r#"{ "sphere": { "center": [0.1, 0.6, 0], "radius": 0.4 } }"#,
        ),
        (
            "box",
            r#"{ "box": { "center": [0, 0.7, 0], "half_extents": [0.3, 0.3, 0.3], "rotation_degrees": [20, 10, 5] } }"#,
        ),
        (
            "capsule",
            r#"{ "capsule": { "a": [-0.3, 0.7, 0], "b": [0.3, 0.7, 0.1], "radius": 0.3 } }"#,
        ),
    ] {
        let text = cloth("", "") + &format!(r#", "colliders": [ {{ "shape": {shape} }} ] }}"#);
        one_frame_matches(&text, name);
    }
}
