//! The `pleat` command as users and other tools call it: report.json,
//! exports, thread-count independence, check and bench output.

use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn pleat(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_pleat"))
        .args(args)
        .current_dir(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
        .output()
        .expect("pleat runs")
}

/// Runs `pleat` and fails the test, showing its stderr, unless it succeeds.
fn pleat_ok(args: &[&str]) -> Output {
    let out = pleat(args);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    out
}

fn out_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("pleat-cli-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

fn report(dir: &Path) -> Value {
    serde_json::from_str(&std::fs::read_to_string(dir.join("report.json")).unwrap()).unwrap()
}

/// The report without the fields that measure the machine rather than the physics.
fn physics_fields(mut report: Value) -> Value {
    let map = report.as_object_mut().unwrap();
    for timing in ["ms_per_frame", "stages_ms", "threads"] {
        map.remove(timing);
    }
    report
}

#[test]
fn default_run_writes_the_report_contract() {
    let dir = out_dir("default");
    pleat_ok(&["run", "--frames", "5", "--out", dir.to_str().unwrap()]);
    let r = report(&dir);
    for key in [
        "scene",
        "backend",
        "solver",
        "frames",
        "frame_dt",
        "substeps",
        "particles",
        "triangles",
        "constraints",
        "ms_per_frame",
        "stages_ms",
        "max_stretch",
        "mean_stretch",
        "nan",
        "self_intersections",
        "collider_penetrations",
    ] {
        assert!(r.get(key).is_some(), "report.json lacks {key}");
    }
    assert_eq!(r["scene"], "drape");
    assert_eq!(r["backend"], "cpu");
    assert_eq!(r["frames"], 5);
    assert_eq!(r["nan"], false);
    for stage in [
        "predict",
        "constraints",
        "collisions",
        "self_collision",
        "self_broad_phase",
        "self_narrow_phase",
        "self_solve",
    ] {
        assert!(r["stages_ms"][stage].is_number(), "stages_ms.{stage}");
    }
    // drape has self-collision on: its broad phase ran.
    assert!(r["stages_ms"]["self_broad_phase"].as_f64().unwrap() > 0.0);
    for k in ["mean", "p50", "p95"] {
        assert!(r["ms_per_frame"][k].as_f64().unwrap() > 0.0);
    }
    assert!(dir.join("frame_00000.obj").exists() && dir.join("frame_00005.obj").exists());
}

#[test]
fn one_and_two_threads_give_identical_results() {
    for scene in [
        "scenes/flag.json",
        "scenes/rotating_sphere.json",
        "scenes/tablecloth_pull.json",
    ] {
        let runs: Vec<PathBuf> = [1, 2]
            .iter()
            .map(|t| {
                let dir = out_dir(&format!("threads{t}-{}", scene.replace('/', "_")));
                pleat_ok(&[
                    "run",
                    scene,
                    "--frames",
                    "20",
                    "--every",
                    "10",
                    "--threads",
                    &t.to_string(),
                    "--out",
                    dir.to_str().unwrap(),
                ]);
                dir
            })
            .collect();
        assert_eq!(
            physics_fields(report(&runs[0])),
            physics_fields(report(&runs[1])),
            "{scene}"
        );
        for frame in ["frame_00000.obj", "frame_00010.obj", "frame_00020.obj"] {
            let a = std::fs::read(runs[0].join(frame)).unwrap();
            let b = std::fs::read(runs[1].join(frame)).unwrap();
            assert!(a == b, "{scene} {frame} differs between 1 and 2 threads");
        }
    }
}

#[test]
fn check_every_counts_self_intersections_along_the_run() {
    // Two cloths placed through each other, weightless, self-collision
    // off: they cross at every frame.
    let scene = r#"{ "frames": 12, "gravity": [0, 0, 0],
        "cloths": [
          { "mesh": { "grid": { "resolution": [8, 8], "size": [0.4, 0.4], "orientation": "vertical", "center": [0, 0, 0] } } },
          { "mesh": { "grid": { "resolution": [8, 8], "size": [0.4, 0.4], "center": [0, 0, 0] } } } ] }"#;
    let dir = out_dir("check_every");
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("through.json");
    std::fs::write(&file, scene).unwrap();
    pleat_ok(&[
        "run",
        file.to_str().unwrap(),
        "--check-every",
        "3",
        "--out",
        dir.to_str().unwrap(),
    ]);
    let r = report(&dir);
    let checked = &r["self_intersections_every"];
    assert_eq!(checked["every"], 3);
    let counts: Vec<u64> = checked["counts"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| c.as_u64().unwrap())
        .collect();
    assert_eq!(counts.len(), 4, "frames 3, 6, 9 and 12: {counts:?}");
    assert_eq!(counts[3], r["self_intersections"].as_u64().unwrap());
    assert!(counts.iter().any(|&c| c > 0), "{counts:?}");
    // Without the flag the field is left out.
    pleat_ok(&[
        "run",
        file.to_str().unwrap(),
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert!(report(&dir).get("self_intersections_every").is_none());
}

#[test]
fn glb_export_is_one_animated_file() {
    let dir = out_dir("glb");
    pleat_ok(&[
        "run",
        "scenes/hanging.json",
        "--frames",
        "6",
        "--every",
        "2",
        "--format",
        "glb",
        "--out",
        dir.to_str().unwrap(),
    ]);
    let glb = gltf::Gltf::open(dir.join("anim.glb")).expect("valid glb");
    let mesh = glb.meshes().next().unwrap();
    let targets = mesh.primitives().next().unwrap().morph_targets().count();
    assert_eq!(
        targets, 3,
        "frames 2, 4 and 6 as morph targets over frame 0"
    );
    assert_eq!(glb.animations().count(), 1);
}

#[test]
fn ply_export() {
    let dir = out_dir("ply");
    let out = pleat(&[
        "run",
        "scenes/hanging.json",
        "--frames",
        "2",
        "--format",
        "ply",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert!(out.status.success());
    let ply = std::fs::read(dir.join("frame_00002.ply")).unwrap();
    assert!(ply.starts_with(b"ply\nformat binary_little_endian 1.0\n"));
}

#[test]
fn check_reports_every_file_and_fails_on_a_bad_one() {
    let bad = out_dir("check").with_extension("json");
    std::fs::write(
        &bad,
        r#"{ "cloths": [ { "mesh": { "grid": { "resolution": [1, 4] } } } ] }"#,
    )
    .unwrap();
    let out = pleat(&[
        "check",
        "scenes/drape.json",
        "patterns/shared/miura_ori.cp",
        bad.to_str().unwrap(),
    ]);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert_eq!(out.status.code(), Some(1), "{stdout}");
    assert!(
        stdout.contains("ok   scenes/drape.json: scene 'drape'"),
        "{stdout}"
    );
    assert!(
        stdout.contains("ok   patterns/shared/miura_ori.cp: crease pattern"),
        "{stdout}"
    );
    assert!(
        stdout.contains("cloths[0].mesh.grid.resolution[0]: must be between 2 and 4096"),
        "{stdout}"
    );
    let good = pleat(&["check", "scenes/flag.json"]);
    assert!(good.status.success());
}

#[test]
fn bench_json_lines() {
    let out = pleat_ok(&[
        "bench", "--sizes", "8,12", "--frames", "2", "--warmup", "1", "--json",
    ]);
    let lines: Vec<Value> = String::from_utf8_lossy(&out.stdout)
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    assert_eq!(lines.len(), 2);
    for (line, n) in lines.iter().zip([8, 12]) {
        for key in [
            "backend",
            "n",
            "particles",
            "substeps",
            "self_collision",
            "ms_per_frame",
            "max_stretch",
        ] {
            assert!(line.get(key).is_some(), "bench line lacks {key}: {line}");
        }
        assert_eq!(line["n"], n);
        assert_eq!(line["particles"], n * n);
        assert_eq!(line["substeps"], 10);
        assert!(line["dispatches_per_frame"].is_null(), "none on the CPU");
    }
}

#[test]
fn gpu_backend_runs_and_names_its_adapter() {
    let dir = out_dir("gpu");
    pleat_ok(&[
        "run",
        "--backend",
        "gpu",
        "--frames",
        "3",
        "--out",
        dir.to_str().unwrap(),
    ]);
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("report.json")).unwrap()).unwrap();
    assert_eq!(report["backend"], "gpu");
    assert!(!report["device"].as_str().unwrap().is_empty(), "{report}");
    assert!(
        report["dispatches_per_frame"].as_f64().unwrap_or(0.0) > 30.0,
        "{report}"
    );
    assert_eq!(report["nan"], false);
    let out = pleat_ok(&[
        "bench",
        "--backend",
        "gpu",
        "--sizes",
        "8",
        "--frames",
        "2",
        "--warmup",
        "0",
        "--json",
    ]);
    let line: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(
        (line["backend"].as_str(), line["particles"].as_u64()),
        (Some("gpu"), Some(64))
    );
    assert!(
        line["device"].as_str().is_some_and(|d| !d.is_empty()),
        "{line}"
    );
    // At least prediction, projection and velocity update in each of 10 substeps.
    let dispatches = line["dispatches_per_frame"].as_f64().unwrap_or(0.0);
    assert!(dispatches >= 30.0, "dispatches per frame: {line}");
}

#[test]
fn gpu_backend_refuses_what_it_lacks_and_a_missing_adapter() {
    let out = pleat(&[
        "run",
        "scenes/tablecloth_pull.json",
        "--backend",
        "gpu",
        "--frames",
        "1",
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("colliders[2].body"));
    // Vulkan is the only backend built for Linux: without a driver there is no adapter.
    let out = Command::new(env!("CARGO_BIN_EXE_pleat"))
        .args(["run", "--backend", "gpu", "--frames", "1"])
        .current_dir(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
        .env("WGPU_BACKEND", "vulkan")
        .env("VK_DRIVER_FILES", "/nonexistent/icd.json")
        .env("VK_ICD_FILENAMES", "/nonexistent/icd.json")
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains("no GPU adapter"), "{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    let out = pleat(&["run", "--backend", "tpu", "--frames", "1"]);
    assert_eq!(out.status.code(), Some(2));
}

#[test]
fn closed_stdout_ends_quietly_without_a_panic() {
    let mut child = Command::new(env!("CARGO_BIN_EXE_pleat"))
        .args([
            "bench",
            "--sizes",
            "2,3,4,5,6,7,8",
            "--frames",
            "1",
            "--warmup",
            "0",
        ])
        .current_dir(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("pleat runs");
    // Close the reading end at once, as `pleat bench | head -0` would.
    drop(child.stdout.take());
    let out = child.wait_with_output().expect("pleat ends");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert!(out.status.success(), "{:?}: {stderr}", out.status);
}
