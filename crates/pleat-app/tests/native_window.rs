//! The native app in a real window: under Xvfb (an X server without a
//! screen) with Mesa's lavapipe as the Vulkan adapter, it runs a demo for a
//! few frames on the GPU backend and writes a screenshot that shows the
//! panels and the cloth. CI installs xvfb; without it this test fails.

use std::path::{Path, PathBuf};
use std::process::Command;

const APP: &str = env!("CARGO_BIN_EXE_pleat-app");

/// Runs the app under Xvfb with `args` and a screenshot into a folder of
/// its own named after `test`; the state it prints on exit, and the
/// screenshot's path.
fn run_in_xvfb(test: &str, args: &[&str]) -> (serde_json::Value, PathBuf) {
    let dir = std::env::temp_dir().join(format!("pleat-app-{test}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let png = dir.join("screenshot.png");
    let out = Command::new("xvfb-run")
        .args(["-a", "-s", "-screen 0 1280x800x24", APP])
        .args(args)
        .args(["--screenshot", png.to_str().unwrap()])
        .output()
        .expect("xvfb-run (Debian package xvfb) runs the app");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    let state = serde_json::from_slice(&out.stdout).expect("the state as JSON");
    (state, png)
}

#[test]
fn the_window_runs_a_demo_and_takes_a_screenshot() {
    let (state, png) = run_in_xvfb(
        "fold",
        &[
            "--demo",
            "fold",
            "--backend",
            "gpu",
            "--frames",
            "15",
            "--size",
            "960x600",
        ],
    );
    assert!(state["frame"].as_u64().unwrap() >= 15, "{state}");
    assert_eq!(state["backend"], "gpu", "{state}");
    assert!(state["last_error"].is_null(), "{state}");
    assert!(state["particles"].as_u64().unwrap() > 10, "{state}");
    let picture = image::open(&png).unwrap().to_rgba8();
    assert_eq!(picture.dimensions(), (960, 600));
    assert_shows_something(&picture, &png);
}

#[test]
fn a_lost_device_reopens_the_window_and_the_run_goes_on() {
    let (state, png) = run_in_xvfb(
        "lost",
        &[
            "--demo",
            "wind",
            "--backend",
            "gpu",
            "--lose-device-at",
            "8",
            "--frames",
            "20",
            "--size",
            "960x600",
        ],
    );
    let lost = state["device_lost"].as_str().unwrap_or_default();
    assert!(
        lost.starts_with("the GPU device was lost at frame 8 (destroyed); recovered: the simulation continues on a new GPU device from t = "),
        "{state}"
    );
    assert!(state["frame"].as_u64().unwrap() >= 20, "{state}");
    assert_eq!(state["backend"], "gpu", "{state}");
    assert!(state["last_error"].is_null(), "{state}");
    let centroid = state["centroid"].as_array().unwrap();
    assert!(
        centroid
            .iter()
            .all(|c| c.as_f64().is_some_and(f64::is_finite)),
        "{state}"
    );
    assert_shows_something(&image::open(&png).unwrap().to_rgba8(), &png);
}

#[test]
fn without_a_backend_asked_for_both_are_timed_and_the_faster_kept() {
    let (state, _) = run_in_xvfb(
        "auto",
        &["--demo", "fold", "--frames", "300", "--size", "640x400"],
    );
    let pick = state["backend_pick"]
        .as_str()
        .expect("a verdict after 300 frames");
    // "picked GPU: GPU 30.1 steps/s, CPU 29.5 steps/s"
    let rate = |name: &str| -> f64 {
        let at = pick.find(&format!("{name} ")).unwrap() + name.len() + 1;
        let (rate, _) = pick[at..].split_once(" steps/s").unwrap();
        rate.parse().unwrap()
    };
    let (cpu, gpu) = (rate("CPU"), rate("GPU"));
    assert!(cpu > 0.0 && gpu > 0.0, "{pick}");
    let kept = state["backend"].as_str().unwrap();
    assert!(
        pick.starts_with(&format!("picked {}", kept.to_uppercase())),
        "{state}"
    );
    // The one kept is not the slower by more than the trial's margin.
    let (kept_rate, other) = if kept == "gpu" {
        (gpu, cpu)
    } else {
        (cpu, gpu)
    };
    assert!(kept_rate * 1.1 >= other, "{pick}");
    assert!(state["last_error"].is_null(), "{state}");
}

/// Many colours and a spread of brightness: not a blank or one-colour window.
fn assert_shows_something(picture: &image::RgbaImage, path: &Path) {
    let mut colours = std::collections::HashSet::new();
    let (mut sum, mut sum2, mut n) = (0.0f64, 0.0f64, 0.0f64);
    for p in picture.pixels().step_by(7) {
        colours.insert([p[0], p[1], p[2]]);
        let v = p[0] as f64 + p[1] as f64 + p[2] as f64;
        sum += v;
        sum2 += v * v;
        n += 1.0;
    }
    let deviation = (sum2 / n - (sum / n).powi(2)).sqrt();
    assert!(
        colours.len() > 50 && deviation > 10.0,
        "{}: {} colours, deviation {deviation}",
        path.display(),
        colours.len()
    );
}

/// The app's stderr for `args`, which it must refuse with exit status 2.
fn refused(args: &[&str]) -> String {
    let out = Command::new(APP).args(args).output().unwrap();
    assert_eq!(out.status.code(), Some(2), "{args:?}");
    String::from_utf8_lossy(&out.stderr).into_owned()
}

#[test]
fn bad_arguments_exit_2_with_the_reason() {
    assert!(refused(&["--backend", "quantum"]).contains("--backend: expected auto, cpu or gpu"));
    assert!(refused(&["--set", "gravity"]).contains("NAME=VALUE"));
}
