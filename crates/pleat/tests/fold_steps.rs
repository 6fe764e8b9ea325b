//! Folding in steps: a multi-frame FOLD file and a scene's `fold.steps`
//! fold step after step, creases folded in an earlier step stay folded,
//! the two forms of the same steps fold alike, and bad steps are refused
//! with the JSON path and the reason.

use pleat::folding::hinge_states;
use pleat::origami::{parse_fold, parse_fold_frames, Assignment};
use pleat::scene::{InMemory, Scene};
use pleat::Simulation;

/// A 3 x 1 strip with two valleys across it, at x = 1 (edge 8, crease A)
/// and x = 2 (edge 9, crease B); `frames` is the file's `file_frames`.
fn strip(frames: &str) -> String {
    format!(
        r#"{{ "file_spec": 1.1,
        "vertices_coords": [[0,0],[1,0],[2,0],[3,0],[3,1],[2,1],[1,1],[0,1]],
        "edges_vertices": [[0,1],[1,2],[2,3],[3,4],[4,5],[5,6],[6,7],[7,0],[1,6],[2,5]],
        "edges_assignment": ["B","B","B","B","B","B","B","B","V","V"]
        {frames} }}"#
    )
}

/// Crease A to 90 degrees in the first step, then B to 90, A held.
const TWO_STEPS: &str = r#", "file_frames": [
    { "edges_foldAngle": [0,0,0,0,0,0,0,0,90,0] },
    { "frame_inherit": true, "frame_parent": 0,
      "edges_foldAngle": [0,0,0,0,0,0,0,0,90,90] } ]"#;

fn scene(fold: &str) -> String {
    format!(
        r#"{{ "name": "strip", "frames": 1, "fps": 60, "gravity": [0, 0, 0],
        "solver": {{ "substeps": 40, "damping": 10 }},
        "cloths": [ {{ "mesh": {{ "pattern": {{ "path": "strip.fold", "size": 1.0 }} }},
                      "material": {{ "density": 0.08, "thickness": 0.0 }} }} ],
        "fold": {fold} }}"#
    )
}

fn build(scene_text: &str, fold_file: &str) -> Result<Simulation, String> {
    let scene = Scene::parse(scene_text, "steps.json").map_err(|e| e.to_string())?;
    let mut files = InMemory::default();
    files.insert("strip.fold", fold_file.as_bytes().to_vec());
    scene
        .build_with(&files, "steps.json")
        .map_err(|e| e.to_string())
}

/// The fold angles of creases A and B now (degrees).
fn creases(sim: &Simulation) -> [f32; 2] {
    let mut valleys: Vec<(f32, f32)> = hinge_states(&sim.model, &sim.particles.x, 1.0)
        .into_iter()
        .filter(|s| s.assignment == Assignment::Valley)
        .map(|s| {
            let x = sim.model.rest[s.v[0] as usize].x;
            (x, s.angle.unwrap().to_degrees())
        })
        .collect();
    valleys.sort_by(|a, b| a.0.total_cmp(&b.0));
    assert_eq!(valleys.len(), 2, "{valleys:?}");
    [valleys[0].1, valleys[1].1]
}

fn run(sim: &mut Simulation, frames: u32) {
    for _ in 0..frames {
        sim.step(1.0 / 60.0);
    }
}

#[test]
fn steps_fold_in_order_and_earlier_creases_stay_folded() {
    let mut sim = build(&scene(r#"{ "frames_to_fold": 60 }"#), &strip(TWO_STEPS)).unwrap();
    assert_eq!(sim.fold_steps.as_ref().unwrap().frames, [60, 60]);
    run(&mut sim, 60);
    assert_eq!(sim.fold_step().unwrap().0, 0);
    let [a, b] = creases(&sim);
    assert!((a - 90.0).abs() < 5.0, "after step 1, A at {a}");
    assert!(b.abs() < 5.0, "after step 1, B at {b} (should be flat)");
    run(&mut sim, 90);
    assert_eq!(sim.fold_step().unwrap().0, 1);
    let [a, b] = creases(&sim);
    assert!((a - 90.0).abs() < 5.0, "after step 2, A at {a} (unfolded?)");
    assert!((b - 90.0).abs() < 5.0, "after step 2, B at {b}");
    assert!(!sim.metrics().nan);
    let m = pleat::folding::FoldMetrics::measure(&sim).unwrap();
    assert!(m.max_fold_angle_error_deg.valley < 5.0, "{m:?}");
}

#[test]
fn the_scene_form_and_the_fold_form_fold_alike() {
    let mut from_file = build(&scene(r#"{ "frames_to_fold": 30 }"#), &strip(TWO_STEPS)).unwrap();
    let steps = r#"{ "frames_to_fold": 30, "steps": [
        { "creases": [8], "fraction": 0.5 },
        { "creases": [9], "fraction": 0.5 } ] }"#;
    let mut from_scene = build(&scene(steps), &strip("")).unwrap();
    assert_eq!(from_file.fold_steps, from_scene.fold_steps);
    run(&mut from_file, 80);
    run(&mut from_scene, 80);
    let err = from_file
        .particles
        .x
        .iter()
        .zip(&from_scene.particles.x)
        .map(|(a, b)| a.distance(*b))
        .fold(0.0, f32::max);
    assert!(err < 1e-6, "the two forms differ by {err}");
    let [a, b] = creases(&from_scene);
    assert!(a > 45.0 && b > 45.0, "{a} {b}");
}

#[test]
fn a_step_by_kind_moves_the_creases_of_that_kind() {
    let steps = r#"{ "frames_to_fold": 30, "steps": [
        { "creases": "V", "fraction": 0.25 },
        { "creases": "all", "fraction": 0.5, "frames": 40 } ] }"#;
    let mut sim = build(&scene(steps), &strip("")).unwrap();
    assert_eq!(sim.fold_steps.as_ref().unwrap().frames, [30, 40]);
    run(&mut sim, 30);
    let [a, b] = creases(&sim);
    assert!((a - 45.0).abs() < 5.0 && (b - 45.0).abs() < 5.0, "{a} {b}");
    run(&mut sim, 60);
    let [a, b] = creases(&sim);
    assert!((a - 90.0).abs() < 5.0 && (b - 90.0).abs() < 5.0, "{a} {b}");
}

#[test]
fn frames_inherit_their_parents_angles() {
    let text = strip(
        r#", "edges_foldAngle": [0,0,0,0,0,0,0,0,30,40],
        "file_frames": [
        { "frame_inherit": true },
        { "frame_inherit": true, "frame_parent": 1 },
        { "edges_foldAngle": [0,0,0,0,0,0,0,0,-90,null] } ]"#,
    );
    let pattern = parse_fold(&text).unwrap();
    let steps = parse_fold_frames(&text, &pattern).unwrap();
    assert_eq!(steps.len(), 3);
    assert_eq!(steps[0][8..], [Some(30.0), Some(40.0)]);
    assert_eq!(steps[1], steps[0]);
    // Valleys keep their sign; null is the full fold.
    assert_eq!(steps[2][8..], [Some(90.0), None]);
    assert!(parse_fold_frames(&strip(""), &pattern).unwrap().is_empty());
}

/// Frames with no fold angle anywhere (Rabbit Ear writes the folded form
/// and its layer order as a frame) are not steps: the key frame's crease
/// pattern folds in one go.
#[test]
fn frames_without_fold_angles_are_not_steps() {
    let text = strip(
        r#", "file_frames": [ { "frame_parent": 0, "frame_inherit": true,
            "frame_classes": ["foldedForm"], "faceOrders": [[0, 1, 1]] } ]"#,
    );
    let pattern = parse_fold(&text).unwrap();
    assert!(parse_fold_frames(&text, &pattern).unwrap().is_empty());
}

fn refused(scene_text: &str, fold_file: &str) -> String {
    match build(scene_text, fold_file) {
        Ok(_) => panic!("accepted: {scene_text}"),
        Err(e) => e,
    }
}

#[test]
fn bad_steps_are_refused_with_where_and_why() {
    let cases = [
        (
            scene(r#"{ "steps": [ { "creases": [99] } ] }"#),
            strip(""),
            "fold.steps[0].creases[0]",
            "edge 99 does not exist: the pattern has 10 edges",
        ),
        (
            scene(r#"{ "steps": [ { "creases": [8] }, { "creases": [2] } ] }"#),
            strip(""),
            "fold.steps[1].creases[0]",
            "edge 2 is not a crease",
        ),
        (
            scene(r#"{ "steps": [ { "creases": "X", "fraction": 2 } ] }"#),
            strip(""),
            "fold.steps[0].fraction",
            "must be between 0 and 1, got 2",
        ),
        (
            scene(r#"{ "steps": [ { "creases": "X" } ] }"#),
            strip(""),
            "fold.steps[0].creases",
            r#"expected "all", "M", "V" or a list of edge indices, got "X""#,
        ),
        (
            scene(r#"{ "frames_to_fold": 0, "steps": [ { "creases": "all" } ] }"#),
            strip(""),
            "fold.steps[0].frames",
            "a step needs at least 1 frame",
        ),
        (
            scene(r#"{ "steps": [ { "creases": "all" } ] }"#),
            strip(TWO_STEPS),
            "fold.steps",
            "has steps of its own",
        ),
        (
            scene("{}"),
            strip(r#", "file_frames": [ { "edges_foldAngle": [0, 90] } ]"#),
            "file_frames[0].edges_foldAngle",
            "has 2 entries, but edges_vertices has 10",
        ),
        (
            scene("{}"),
            strip(
                r#", "file_frames": [ { "edges_foldAngle": [0,0,0,0,0,0,0,0,90,0] },
                                      { "frame_title": "no angles" } ]"#,
            ),
            "file_frames[1]",
            "a step needs edges_foldAngle",
        ),
        (
            scene("{}"),
            strip(
                r#", "file_frames": [ { "edges_foldAngle": [0,0,0,0,0,0,0,0,90,0] },
                                      { "frame_inherit": true } ]"#,
            ),
            "file_frames[1]",
            "inherits no edges_foldAngle: the key frame has none",
        ),
        (
            scene("{}"),
            strip(
                r#", "file_frames": [ { "frame_inherit": true, "frame_parent": 2 },
                                      { "frame_inherit": true, "frame_parent": 1 },
                                      { "edges_foldAngle": [0,0,0,0,0,0,0,0,90,0] } ]"#,
            ),
            "file_frames[0].frame_parent",
            "cycle",
        ),
        (
            scene("{}"),
            strip(
                r#", "file_frames": [ { "frame_inherit": true, "frame_parent": 7 },
                                      { "edges_foldAngle": [0,0,0,0,0,0,0,0,90,0] } ]"#,
            ),
            "file_frames[0].frame_parent",
            "expected a frame index from 0 (the key frame) to 2, found 7",
        ),
        (
            scene("{}"),
            strip(r#", "file_frames": [ { "edges_foldAngle": [0,0,0,0,0,0,0,0,270,0] } ]"#),
            "file_frames[0].edges_foldAngle[8]",
            "must be between -180 and 180 degrees",
        ),
        (
            scene("{}"),
            strip(r#", "file_frames": 3"#),
            "file_frames",
            "expected an array, found a number",
        ),
    ];
    for (scene_text, fold_file, path, reason) in cases {
        let message = refused(&scene_text, &fold_file);
        assert!(
            message.contains(path) && message.contains(reason),
            "expected {path}: {reason}, got: {message}"
        );
    }
}

#[test]
fn the_shipped_scene_folds_in_its_three_steps() {
    let repo = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let scene = Scene::load(&repo.join("scenes/fold_waterbomb_in_steps.json")).unwrap();
    let sim = scene
        .build(&repo.join("scenes"), "fold_waterbomb_in_steps.json")
        .unwrap();
    assert_eq!(sim.fold_steps.as_ref().unwrap().frames, [80, 80, 120]);
}

/// A step may fold a crease the other way from the key frame, when its
/// frame gives its own `edges_assignment`, and may fold a line the key
/// frame leaves flat: the strip's crease B, a valley in the key frame, goes
/// to a mountain in the first step; a flat line there would fold too.
#[test]
fn a_step_with_its_own_assignments_turns_a_crease_over() {
    let file = strip(
        r#", "file_frames": [
        { "edges_foldAngle": [0,0,0,0,0,0,0,0,90,-90],
          "edges_assignment": ["B","B","B","B","B","B","B","B","V","M"] } ]"#,
    );
    let pattern = parse_fold(&file).unwrap();
    let steps = parse_fold_frames(&file, &pattern).unwrap();
    assert_eq!(steps[0][9], Some(-90.0));
    // Without its own assignments the frame's sign gives way to the key
    // frame's, as before.
    let file = strip(r#", "file_frames": [ { "edges_foldAngle": [0,0,0,0,0,0,0,0,90,-90] } ]"#);
    let steps = parse_fold_frames(&file, &pattern).unwrap();
    assert_eq!(steps[0][9], Some(90.0));
    let bad = strip(
        r#", "file_frames": [ { "edges_foldAngle": [0,0,0,0,0,0,0,0,90,-90],
          "edges_assignment": ["B","V"] } ]"#,
    );
    let e = parse_fold_frames(&bad, &pattern).unwrap_err().to_string();
    assert!(e.contains("file_frames[0].edges_assignment"), "{e}");
}

/// The shipped crane in six steps: every step but the last (whose wings
/// stand at 90 degrees) is a state that folds flat, with a layer order; and
/// its first two, the preliminary base and the bird base, fold with a
/// thickness without crossing and within a degree and a half of their
/// targets.
#[test]
fn the_crane_in_steps_is_a_sequence_of_flat_folds_and_its_bases_fold_clean() {
    use pleat::fold_steps::{sheet_step_angles, step_pattern, FoldSteps};
    use pleat::folding::{
        paper_model, paper_simulation_on, paper_solver_settings_with_contact, FoldMetrics,
        FoldRamp, PAPER_THICKNESS,
    };
    use pleat::metrics::intersections::count_self_intersections;
    use pleat::origami::{FlatFolded, Sheet, SheetOptions};
    use pleat::CpuBackend;
    let path =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../patterns/crane-in-steps.fold");
    let text = std::fs::read_to_string(path).unwrap();
    let pattern = parse_fold(&text).unwrap();
    let steps = parse_fold_frames(&text, &pattern).unwrap();
    assert_eq!(steps.len(), 6);
    for (k, angles) in steps.iter().enumerate() {
        let state = step_pattern(&pattern, angles);
        let sheet = Sheet::from_pattern(&state, &SheetOptions::default()).unwrap();
        let solved = FlatFolded::solve(&sheet);
        assert_eq!(solved.is_ok(), k < 5, "step {}: {:?}", k + 1, solved.err());
    }
    // The first two steps, folded as `pleat fold` does.
    let options = SheetOptions::default();
    let sheet = Sheet::from_pattern(&pattern, &options).unwrap();
    let (mut model, world) = paper_model(&sheet);
    model.cloths[0].paper.as_mut().unwrap().steps =
        sheet_step_angles(&pattern, &options, &sheet, &steps[..2]).unwrap();
    let settings = paper_solver_settings_with_contact(PAPER_THICKNESS);
    let backend = Box::new(CpuBackend::new(&model, &settings));
    let ramp = FoldRamp {
        progress: 1.0,
        frames: 120,
    };
    let mut sim = paper_simulation_on((model, world), settings, backend, ramp);
    sim.fold_steps = FoldSteps::of_model(&sim.model, &[120]);
    for frame in 1..=300 {
        sim.step(1.0 / 60.0);
        if frame % 10 == 0 {
            let crossings = count_self_intersections(&sim.particles.x, &sim.model.triangles);
            assert_eq!(crossings, 0, "frame {frame}");
        }
    }
    let m = FoldMetrics::measure(&sim).unwrap();
    let e = m.max_fold_angle_error_deg;
    assert!(e.mountain.max(e.valley) < 1.5, "{e:?}");
    assert!(m.max_strain < 0.01, "{}", m.max_strain);
}
