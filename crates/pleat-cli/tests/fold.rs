//! `pleat fold` end to end: a built-in folds, reports its origami figures
//! and writes its folded state as FOLD, on either backend; a malformed
//! pattern file is refused with its name and line; paper that tears (in a
//! scene, `pleat run`) exits 1 and says when and where.

use std::path::PathBuf;
use std::process::Command;

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("pleat-fold-test-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn pleat(args: &[&str]) -> (bool, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_pleat"))
        .args(args)
        .output()
        .expect("pleat runs");
    let text =
        String::from_utf8_lossy(&out.stdout).into_owned() + &String::from_utf8_lossy(&out.stderr);
    (out.status.success(), text)
}

/// A flat fold with a thickness writes its layer order: every stacked pair
/// of faces once, above (+1) or below (-1) the other.
#[test]
fn a_flat_fold_writes_its_face_orders() {
    let dir = scratch("face-orders");
    let folded = dir.join("folded.fold");
    let (ok, text) = pleat(&[
        "fold",
        "waterbomb-base",
        "--thickness",
        "0.0005",
        "--fold-out",
        folded.to_str().unwrap(),
    ]);
    assert!(ok, "{text}");
    let fold: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&folded).unwrap()).unwrap();
    let faces = fold["faces_vertices"].as_array().unwrap().len() as i64;
    let orders = fold["faceOrders"].as_array().unwrap();
    assert!(!orders.is_empty(), "{fold}");
    for order in orders {
        let [f, g, s] = [0, 1, 2].map(|k| order[k].as_i64().unwrap());
        assert!(f < g && g < faces && (s == 1 || s == -1), "{order}");
    }
    // Read back as a crease pattern, the file checks like any other.
    let (ok, text) = pleat(&["check", folded.to_str().unwrap()]);
    assert!(ok, "{text}");
}

/// The fold's report checks the folded paper's layers against the
/// pattern's flat-folded state; `pleat check` finds that state's layer
/// order, writes it, and says where a pattern has none.
#[test]
fn layer_orders_are_found_written_and_checked_against_the_fold() {
    let dir = scratch("layer-order");
    let (ok, text) = pleat(&[
        "fold",
        "waterbomb-base",
        "--thickness",
        "0.0005",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert!(ok, "{text}");
    assert!(
        text.contains("layer order: 6 facets, 11 pairs overlap when folded flat"),
        "{text}"
    );
    assert!(text.contains("in a valid order"), "{text}");
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("report.json")).unwrap()).unwrap();
    let layers = &report["layer_order"];
    assert_eq!(layers["found"], true, "{layers}");
    assert_eq!(layers["simulated"]["valid"], true, "{layers}");
    assert_eq!(layers["simulated"]["pairs"], 11, "{layers}");

    let out = dir.join("flat");
    let (ok, text) = pleat(&[
        "check",
        "waterbomb-base.fold",
        "--folded-out",
        out.to_str().unwrap(),
    ]);
    assert!(!ok, "a name that is no file: {text}");
    let pattern = patterns().join("waterbomb-base.fold");
    let twist = patterns().join("square-twist.fold");
    let (ok, text) = pleat(&[
        "check",
        pattern.to_str().unwrap(),
        twist.to_str().unwrap(),
        "--folded-out",
        out.to_str().unwrap(),
    ]);
    assert!(ok, "{text}");
    assert!(text.contains("layer order found: 6 facets"), "{text}");
    // The built-in square twist meets both theorems at every vertex, but
    // its corner flaps cannot be stacked.
    assert!(
        text.contains("not flat-foldable as a whole, no layer order"),
        "{text}"
    );
    let fold: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("waterbomb-base.fold")).unwrap())
            .unwrap();
    assert_eq!(fold["faceOrders"].as_array().unwrap().len(), 11, "{fold}");
    assert_eq!(
        fold["vertices_coords"].as_array().unwrap().len(),
        7,
        "{fold}"
    );
    assert!(!out.join("square-twist.fold").exists());
}

/// A flat-folded state written by `pleat check --folded-out` (no creases,
/// only the layer order) reads back into a pattern that checks and folds
/// flat again; without its `faceOrders` nothing says which way its creases
/// fold, and both commands warn that they are not driven.
#[test]
fn a_written_flat_folded_state_reads_back_and_one_without_orders_warns() {
    let dir = scratch("read-back");
    let pattern = patterns().join("waterbomb-base.fold");
    let (ok, text) = pleat(&[
        "check",
        pattern.to_str().unwrap(),
        "--folded-out",
        dir.to_str().unwrap(),
    ]);
    assert!(ok, "{text}");
    let written = dir.join("waterbomb-base.fold");
    let (ok, text) = pleat(&["check", written.to_str().unwrap()]);
    assert!(ok, "{text}");
    assert!(
        text.contains("flat-foldable (1 vertices checked); layer order found"),
        "{text}"
    );
    assert!(!text.contains("warning"), "{text}");

    let mut fold: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&written).unwrap()).unwrap();
    fold.as_object_mut().unwrap().remove("faceOrders");
    let bare = dir.join("no-orders.fold");
    std::fs::write(&bare, fold.to_string()).unwrap();
    let warning = "6 creases are folded flat with neither a mountain or valley label nor \
                   faceOrders to say which way";
    let (ok, text) = pleat(&["check", bare.to_str().unwrap()]);
    assert!(ok && text.contains(warning), "{text}");
    let out = dir.join("out");
    let (ok, text) = pleat(&[
        "fold",
        bare.to_str().unwrap(),
        "--frames",
        "5",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(
        ok && text.contains(&format!("warning: {}: {warning}", bare.display())),
        "{text}"
    );

    // A scene made of the same file says so too, under the cloth's path.
    let scene = dir.join("scene.json");
    let json = serde_json::json!({
        "name": "no-orders",
        "frames": 2,
        "gravity": [0.0, 0.0, 0.0],
        "solver": { "kind": "xpbd", "substeps": 20 },
        "cloths": [{ "name": "paper", "mesh": { "pattern": { "path": "no-orders.fold" } } }]
    });
    std::fs::write(&scene, json.to_string()).unwrap();
    let said = format!(
        "warning: {}: cloths[0].mesh.pattern: {}: {warning}",
        scene.display(),
        bare.display()
    );
    let (ok, text) = pleat(&["check", scene.to_str().unwrap()]);
    assert!(ok && text.contains(&said), "{said}\n{text}");
    let run_out = dir.join("run");
    let (ok, text) = pleat(&[
        "run",
        scene.to_str().unwrap(),
        "--out",
        run_out.to_str().unwrap(),
    ]);
    assert!(ok && text.contains(&said), "{said}\n{text}");
}

#[test]
fn builtin_folds_and_reports_fold_angle_errors() {
    let dir = scratch("miura");
    let out = dir.to_str().unwrap();
    let folded = dir.join("folded.fold");
    let (ok, text) = pleat(&[
        "fold",
        "miura-ori",
        "--fold-out",
        folded.to_str().unwrap(),
        "--progress",
        "0.5",
        "--frames",
        "30",
        "--out",
        out,
        "--format",
        "glb",
    ]);
    assert!(ok, "{text}");
    assert!(text.contains("largest fold-angle error"), "{text}");
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("report.json")).unwrap()).unwrap();
    assert_eq!(report["frames"], 90);
    assert_eq!(report["origami"]["fold_progress"], 0.5);
    assert!(report["origami"]["max_fold_angle_error_deg"]["valley"].is_number());
    assert!(report["origami"]["max_strain"].as_f64().unwrap() < 0.05);
    assert!(dir.join("anim.glb").exists());
    let worst = &report["origami"]["worst_hinge"];
    assert!(["mountain", "valley", "flat"].contains(&worst["kind"].as_str().unwrap()));
    assert!(worst["error_deg"].as_f64().unwrap() >= 0.0);
    assert_eq!(
        report["origami"]["worst_facet"]["triangle"]
            .as_array()
            .unwrap()
            .len(),
        3
    );
    let fold: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&folded).unwrap()).unwrap();
    assert_eq!(fold["frame_classes"][0], "foldedForm");
    let edges = fold["edges_vertices"].as_array().unwrap().len();
    assert_eq!(fold["edges_foldAngle"].as_array().unwrap().len(), edges);
    assert_eq!(fold["edges_assignment"].as_array().unwrap().len(), edges);
    assert_eq!(
        fold["vertices_coords"].as_array().unwrap().len(),
        report["particles"].as_u64().unwrap() as usize
    );
    // Half way, the valleys fold by about 90 degrees (valley positive).
    let valleys: Vec<f64> = fold["edges_assignment"]
        .as_array()
        .unwrap()
        .iter()
        .zip(fold["edges_foldAngle"].as_array().unwrap())
        .filter(|(a, _)| *a == "V")
        .map(|(_, angle)| angle.as_f64().unwrap())
        .collect();
    assert!(!valleys.is_empty());
    assert!(valleys.iter().all(|&a| a > 0.0 && a < 180.0), "{valleys:?}");
}

/// Paper with creases ten thousand times stiffer than the defaults and no
/// strain limit (`max_strain`), folded in 5 frames at 4 substeps: the paper
/// defaults no longer tear any pattern of Origami Simulator's library, this
/// does.
const TEARING_SCENE: &str = r#"{
  "name": "tear", "frames": 60, "fps": 60, "gravity": [0.0, 0.0, 0.0],
  "solver": { "kind": "xpbd", "substeps": 4, "iterations": 1, "damping": 1.0 },
  "cloths": [ { "name": "paper",
    "mesh": { "pattern": { "path": "PATTERN", "size": 1.0,
      "stiffness": { "crease_compliance": 1e-6, "facet_compliance": 1e-6 } } },
    "material": { "density": 0.08, "stretch_compliance": 1e-2, "thickness": 0.0 } } ],
  "fold": { "progress": 1.0, "frames_to_fold": 5 }
}"#;

#[test]
fn paper_that_tears_exits_1_and_says_when_and_where() {
    let dir = scratch("torn");
    let pattern = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/data/Carved_Cylinder.svg"
    );
    let scene = dir.join("tear.json");
    std::fs::write(&scene, TEARING_SCENE.replace("PATTERN", pattern)).unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_pleat"))
        .args([
            "run",
            scene.to_str().unwrap(),
            "--out",
            dir.to_str().unwrap(),
            "--every",
            "1000",
        ])
        .output()
        .expect("pleat runs");
    let text = String::from_utf8_lossy(&out.stdout);
    assert_eq!(out.status.code(), Some(1), "{text}");
    assert!(text.contains("unstable (torn) from"), "{text}");
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("report.json")).unwrap()).unwrap();
    assert_eq!(report["unstable"], true);
    assert_eq!(report["unstable_kind"], "torn");
    assert!(report["unstable_at"].as_f64().unwrap() > 0.0);
    assert!(
        report["origami"]["worst_hinge"]["error_deg"]
            .as_f64()
            .unwrap()
            > 10.0
    );
}

#[test]
fn malformed_pattern_and_unknown_names_are_refused() {
    let dir = scratch("bad");
    let bad = dir.join("bad.cp");
    std::fs::write(&bad, "1 0 0 1 0\n2 0 0 one 1\n").unwrap();
    let (ok, text) = pleat(&["fold", bad.to_str().unwrap()]);
    assert!(!ok);
    assert!(text.contains("bad.cp") && text.contains("line 2"), "{text}");
    let (ok, text) = pleat(&["fold", "crane"]);
    assert!(!ok);
    assert!(text.contains("miura-ori"), "{text}");
    let (ok, text) = pleat(&["fold", "miura-ori", "--progress", "2"]);
    assert!(!ok);
    assert!(text.contains("--progress"), "{text}");
    let (ok, text) = pleat(&["fold", "miura-ori", "--backend", "tpu"]);
    assert!(!ok);
    assert!(text.contains("unknown backend"), "{text}");
}

#[test]
fn a_builtin_folds_on_the_gpu_backend() {
    let dir = scratch("gpu");
    let (ok, text) = pleat(&[
        "fold",
        "miura-ori",
        "--backend",
        "gpu",
        "--progress",
        "0.5",
        "--frames",
        "10",
        "--out",
        dir.to_str().unwrap(),
        "--every",
        "1000",
    ]);
    assert!(ok, "{text}");
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("report.json")).unwrap()).unwrap();
    assert_eq!(report["backend"], "gpu");
    assert_eq!(report["frames"], 70);
    assert_eq!(report["origami"]["fold_progress"], 0.5);
    assert!(report["origami"]["max_strain"].as_f64().unwrap() < 0.05);
}

/// The path of a pattern the project ships, `patterns/<path>`.
fn shipped_pattern(path: &str) -> String {
    format!("{}/../../patterns/{path}", env!("CARGO_MANIFEST_DIR"))
}

/// `pleat fold PATTERN ARGS --out DIR` (a scratch folder named `name`),
/// which must succeed: its report.
fn fold_report(name: &str, pattern: &str, args: &[&str]) -> serde_json::Value {
    let dir = scratch(name);
    let out = ["--out", dir.to_str().unwrap(), "--every", "1000"];
    let (ok, text) = pleat(&[&["fold", pattern][..], args, &out].concat());
    assert!(ok, "{text}");
    let report = std::fs::read_to_string(dir.join("report.json")).unwrap();
    serde_json::from_str(&report).unwrap()
}

/// Paper with a thickness folds in the GPU backend's persistent kernel,
/// self-contacts and all (one dispatch a frame besides the health check
/// and the margin's choice, and once, as the fold comes to rest, the held
/// limits' rounds, each checked by the hash grid's contacts: 65.1
/// dispatches a frame over the fold's 180, where a dispatch per colour
/// and substep made thousands): the simple vertex ends with its layers
/// apart, where without a thickness two of its triangle pairs cross.
#[test]
fn thick_paper_folds_in_one_dispatch_a_frame_on_the_gpu_without_crossing() {
    let pattern = &shipped_pattern("shared/simpleVertex.svg");
    let fold = |thickness: &str| {
        let args = [
            "--backend",
            "gpu",
            "--progress",
            "1",
            "--thickness",
            thickness,
        ];
        fold_report(&format!("thick-gpu-{thickness}"), pattern, &args)
    };
    let thick = fold("0.0005");
    assert_eq!(thick["self_intersections"], 0, "{thick}");
    let per_frame = |key: &str| thick[key].as_f64().unwrap();
    assert!(per_frame("self_contacts_per_frame") > 0.0, "{thick}");
    let hold = HOLD_DISPATCHES / per_frame("frames");
    assert!(per_frame("dispatches_per_frame") < 5.0 + hold, "{thick}");
    let thin = fold("0");
    assert!(thin["self_intersections"].as_u64().unwrap() > 0, "{thin}");
}

/// Most dispatches of the held limits' rounds with contacts, once a fold.
const HOLD_DISPATCHES: f64 = 12000.0;

/// A large pattern folds on the GPU backend as on the CPU wherever the GPU
/// runs: a software adapter (lavapipe, in CI) ends every loop of a shader
/// after 65,535 iterations, which cut each frame of the persistent kernel
/// short on Origami_Sphere_16Flaps.svg (825 vertices), 12 to 25 degrees
/// off where the CPU ends within 1; the frame is now split into
/// dispatches that fit.
#[test]
fn a_large_pattern_folds_on_the_gpu_as_on_the_cpu() {
    let pattern = &shipped_pattern("origami-simulator/Origami_Sphere_16Flaps.svg");
    let worst = |backend: &str| {
        let args = ["--backend", backend, "--progress", "1"];
        let report = fold_report(&format!("large-{backend}"), pattern, &args);
        let errors = &report["origami"]["max_fold_angle_error_deg"];
        ["mountain", "valley"].map(|k| errors[k].as_f64().unwrap())
    };
    let (cpu, gpu) = (worst("cpu"), worst("gpu"));
    for (c, g) in cpu.iter().zip(&gpu) {
        assert!((c - g).abs() < 1.0, "CPU {cpu:?}, GPU {gpu:?}");
    }
}

#[test]
fn flat_foldability_is_reported_and_a_broken_vertex_is_a_warning() {
    // The built-in waterbomb base folds flat: report.json says so.
    let dir = scratch("flat-foldable");
    let out = dir.to_str().unwrap();
    let (ok, text) = pleat(&["fold", "waterbomb-base", "--frames", "10", "--out", out]);
    assert!(ok, "{text}");
    assert!(
        text.contains("flat-foldable at every interior vertex"),
        "{text}"
    );
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("report.json")).unwrap()).unwrap();
    let check = &report["flat_foldability"];
    assert_eq!(check["vertices_checked"], 1, "{check}");
    assert_eq!(check["violations"].as_array().unwrap().len(), 0, "{check}");
    // Four creases through a point moved off the centre: Kawasaki fails
    // there; the fold still runs (exit 0) with a warning naming the vertex.
    let dir = scratch("not-flat-foldable");
    let pattern = dir.join("moved.fold");
    std::fs::write(
        &pattern,
        r#"{ "vertices_coords": [[0,0],[2,0],[2,2],[0,2],[1.3,1.2],[1,0],[2,1],[1,2],[0,1]],
             "edges_vertices": [[0,5],[5,1],[1,6],[6,2],[2,7],[7,3],[3,8],[8,0],[4,5],[4,6],[4,7],[4,8]],
             "edges_assignment": ["B","B","B","B","B","B","B","B","M","M","M","V"] }"#,
    )
    .unwrap();
    let out = dir.to_str().unwrap();
    let (ok, text) = pleat(&[
        "fold",
        pattern.to_str().unwrap(),
        "--frames",
        "10",
        "--out",
        out,
    ]);
    assert!(ok, "{text}");
    assert!(
        text.contains("warning: not flat-foldable as drawn"),
        "{text}"
    );
    assert!(text.contains("vertex 4 at (1.3000, 1.2000)"), "{text}");
    assert!(text.contains("Kawasaki"), "{text}");
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("report.json")).unwrap()).unwrap();
    let v = &report["flat_foldability"]["violations"][0];
    assert_eq!(v["pattern_vertex"], 4, "{v}");
    assert_eq!(v["theorem"], "kawasaki", "{v}");
    assert!(v["by"].as_f64().unwrap().abs() > 1.0, "{v}");
}

/// The repository's `patterns/` folder.
fn patterns() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../patterns")
}

#[test]
fn a_multi_frame_fold_file_folds_step_after_step() {
    // The crane's six steps (preliminary base, bird base, legs narrowed,
    // neck and tail reversed, head reversed, crane), 20 frames each, then
    // 60 to settle.
    let dir = scratch("crane-steps");
    let crane = patterns().join("crane-in-steps.fold");
    let (ok, text) = pleat(&[
        "fold",
        crane.to_str().unwrap(),
        "--frames",
        "20",
        "--out",
        dir.to_str().unwrap(),
        "--every",
        "7",
        "--fold-out",
        dir.join("folded.fold").to_str().unwrap(),
    ]);
    assert!(ok, "{text}");
    assert!(text.contains("folded in 6 steps of 20 frames"), "{text}");
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("report.json")).unwrap()).unwrap();
    assert_eq!(report["frames"], 180);
    assert_eq!(report["nan"], false);
    assert_eq!(report["origami"]["fold_step"]["step"], 6);
    assert_eq!(report["origami"]["fold_step"]["of"], 6);
    // Meshes every 7th frame only, the step ends (20, 40, ...) not among them.
    assert!(dir.join("frame_00007.obj").exists() && !dir.join("frame_00020.obj").exists());
    // The folded state at the end, and each step's end as a frame.
    let fold: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("folded.fold")).unwrap()).unwrap();
    let frames = fold["file_frames"].as_array().unwrap();
    assert_eq!(frames.len(), 6);
    assert_eq!(frames[0]["frame_title"], "end of step 1 of 6");
    let edges = fold["edges_vertices"].as_array().unwrap().len();
    for frame in frames {
        assert_eq!(frame["frame_parent"], 0);
        assert_eq!(frame["edges_foldAngle"].as_array().unwrap().len(), edges);
        assert_eq!(frame["vertices_coords"].as_array().unwrap().len(), 68);
    }
    assert_ne!(frames[0]["vertices_coords"], frames[2]["vertices_coords"]);
    let (ok, text) = pleat(&["check", crane.to_str().unwrap()]);
    assert!(ok && text.contains("folded in 6 steps"), "{text}");
    // Every step but the crane's (wings at 90 degrees) folds flat.
    assert!(
        text.contains("(steps 1-5 fold flat with a layer order)"),
        "{text}"
    );
    // --progress is a single fold's: refused for a fold in steps.
    let (ok, text) = pleat(&["fold", crane.to_str().unwrap(), "--progress", "0.5"]);
    assert!(!ok && text.contains("--progress does not apply"), "{text}");
}

#[test]
fn a_bad_frame_is_refused_with_its_path() {
    let dir = scratch("bad-frame");
    let path = dir.join("bad.fold");
    std::fs::write(
        &path,
        r#"{ "vertices_coords": [[0,0],[1,0],[1,1],[0,1]],
            "edges_vertices": [[0,1],[1,2],[2,3],[3,0],[0,2]],
            "edges_assignment": ["B","B","B","B","V"],
            "file_frames": [ { "edges_foldAngle": [0, 0, 0, 0, "ninety"] } ] }"#,
    )
    .unwrap();
    for command in ["fold", "check"] {
        let (ok, text) = pleat(&[command, path.to_str().unwrap()]);
        assert!(!ok, "{command}: {text}");
        assert!(
            text.contains("bad.fold") && text.contains("file_frames[0].edges_foldAngle[4]"),
            "{command}: {text}"
        );
    }
}
