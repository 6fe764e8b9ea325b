//! `pleat render` and `pleat fold --render` as users call them: PNG frames,
//! an animated GIF with one frame per drawn frame, report.json, and clear
//! refusals (exit 2) of bad arguments. Needs a GPU adapter (lavapipe in CI).

use image::AnimationDecoder;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn pleat(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_pleat"))
        .args(args)
        .current_dir(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
        .output()
        .expect("pleat runs")
}

fn out_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("pleat-render-cli-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

fn gif_frames(path: &Path) -> usize {
    let file = std::io::BufReader::new(std::fs::File::open(path).unwrap());
    image::codecs::gif::GifDecoder::new(file)
        .unwrap()
        .into_frames()
        .collect_frames()
        .unwrap()
        .len()
}

fn assert_ok(out: &Output) {
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

#[test]
fn render_writes_png_frames_and_a_gif() {
    let dir = out_dir("hanging");
    let out = pleat(&[
        "render",
        "scenes/hanging.json",
        "--frames",
        "4",
        "--every",
        "2",
        "--width",
        "96",
        "--height",
        "64",
        "--view",
        "strain",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert_ok(&out);
    for frame in [0, 2, 4] {
        let png = image::open(dir.join(format!("frame_{frame:05}.png"))).unwrap();
        assert_eq!((png.width(), png.height()), (96, 64));
    }
    assert!(!dir.join("frame_00001.png").exists());
    assert_eq!(gif_frames(&dir.join("anim.gif")), 3);
    assert!(dir.join("report.json").exists());
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(stdout.contains("rendered 3 pictures"), "{stdout}");
}

#[test]
fn fold_render_draws_the_fold() {
    let dir = out_dir("miura");
    let out = pleat(&[
        "fold",
        "miura-ori",
        "--frames",
        "4",
        "--every",
        "32",
        "--render",
        "--width",
        "64",
        "--height",
        "48",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert_ok(&out);
    // 4 folding frames and 60 settling: frames 0, 32 and 64 are drawn.
    assert_eq!(gif_frames(&dir.join("anim.gif")), 3);
    assert!(dir.join("frame_00064.png").exists());
}

#[test]
fn no_adapter_is_a_clear_error_with_exit_2() {
    let dir = out_dir("no-adapter");
    // A Vulkan loader that finds no driver: no adapter at all.
    let out = Command::new(env!("CARGO_BIN_EXE_pleat"))
        .args(["render", "--frames", "1", "--out", dir.to_str().unwrap()])
        .current_dir(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
        .env("WGPU_BACKEND", "vulkan")
        .env("VK_DRIVER_FILES", "/nonexistent/icd.json")
        .env("VK_ICD_FILENAMES", "/nonexistent/icd.json")
        .output()
        .expect("pleat runs");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains("no usable GPU adapter"), "{stderr}");
    assert!(stderr.contains("mesa-vulkan-drivers"), "{stderr}");
    assert!(!dir.exists(), "nothing is written without an adapter");
}

#[test]
fn render_draws_the_gpu_backend_too() {
    let dir = out_dir("hanging_gpu");
    let out = pleat(&[
        "render",
        "scenes/hanging.json",
        "--frames",
        "2",
        "--width",
        "64",
        "--height",
        "48",
        "--backend",
        "gpu",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert_ok(&out);
    assert_eq!(gif_frames(&dir.join("anim.gif")), 3);
    let report = std::fs::read_to_string(dir.join("report.json")).unwrap();
    assert!(report.contains(r#""backend": "gpu""#), "{report}");
}

#[test]
fn render_refuses_bad_arguments_with_exit_2() {
    for (args, expected) in [
        (&["render", "--width", "0"][..], "width"),
        (&["render", "--view", "sketch"][..], "sketch"),
        (&["render", "--backend", "tpu"][..], "unknown backend"),
        (&["render", "no/such/scene.json"][..], "no/such/scene.json"),
    ] {
        let out = pleat(args);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {stderr}");
        assert!(stderr.contains(expected), "{args:?}: {stderr}");
        assert!(!stderr.contains("panicked"), "{args:?}: {stderr}");
    }
}
