//! Project tasks that need more than cargo:
//!
//! - `cargo xtask web [--debug] [--no-serve] [--out DIR] [--port N]`: builds
//!   the app for the browser (WebAssembly + WebGPU; the release build, the
//!   one BENCHMARKS.md measures, unless `--debug`) with wasm-bindgen-cli
//!   pinned to the wasm-bindgen crate's exact version (installed with `cargo
//!   install`, into the target folder), writes a folder of static files, and
//!   serves it on localhost (not with `--no-serve`, which only writes the
//!   folder to deploy), saying each step as it starts.
//! - `cargo xtask test`: the Rust tests (doctests included), the library's
//!   example, the Python package's tests (the wheel built by maturin,
//!   installed into a fresh virtual environment, pytest; see
//!   [`python_tests`]), then the web build and the browser test (tests/web,
//!   headless Chromium with WebGPU through playwright-core).

use std::path::{Path, PathBuf};
use std::process::{Command, ExitCode};

mod serve;

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let result = match args.first().map(String::as_str) {
        Some("web") => web(&args[1..]),
        Some("test") => test(),
        _ => Err(USAGE.to_string()),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}

const USAGE: &str =
    "usage: cargo xtask web [--debug] [--no-serve] [--out DIR] [--port N] | cargo xtask test";

/// Options of `cargo xtask web`.
struct WebOptions {
    /// The optimised build (the default) or the debug one (`--debug`).
    release: bool,
    /// Whether to serve the folder once it is written.
    serve: bool,
    out: Option<PathBuf>,
    port: u16,
}

fn parse_web(args: &[String]) -> Result<WebOptions, String> {
    let mut options = WebOptions {
        release: true,
        serve: true,
        out: None,
        port: 8080,
    };
    let mut args = args.iter();
    while let Some(arg) = args.next() {
        match arg.as_str() {
            "--debug" => options.release = false,
            // The folder to deploy: the release build, not served.
            "--no-serve" | "--release" => options.serve = false,
            "--out" => options.out = Some(args.next().ok_or("--out needs a folder")?.into()),
            "--port" => {
                let port = args.next().ok_or("--port needs a number")?;
                options.port = port
                    .parse()
                    .map_err(|_| format!("--port: '{port}' is not a port"))?;
            }
            other => return Err(format!("unknown argument '{other}'\n{USAGE}")),
        }
    }
    Ok(options)
}

fn web(args: &[String]) -> Result<(), String> {
    let options = parse_web(args)?;
    let dist = build_web(options.release, options.out)?;
    if options.serve {
        serve::serve(&dist, options.port)
    } else {
        println!(
            "the app is in {}: serve that folder over http(s)",
            dist.display()
        );
        Ok(())
    }
}

/// Builds the wasm app and writes the page into `out` (default:
/// target/web); returns the folder.
fn build_web(release: bool, out: Option<PathBuf>) -> Result<PathBuf, String> {
    let root = workspace_root()?;
    let target = target_dir(&root)?;
    step(1, "adding the wasm32-unknown-unknown target (rustup)");
    run(Command::new("rustup").args(["target", "add", "wasm32-unknown-unknown"]))?;
    step(2, "wasm-bindgen-cli at the wasm-bindgen crate's version");
    let bindgen = wasm_bindgen_cli(&root, &target)?;
    let profile = if release { "release" } else { "debug" };
    step(
        3,
        &format!(
            "building the app for the browser ({profile}; a first build takes 15 minutes or \
             more on two cores, later ones seconds)"
        ),
    );
    let mut build = cargo();
    build.args([
        "build",
        "--locked",
        "-p",
        "pleat-app",
        "--lib",
        "--target",
        "wasm32-unknown-unknown",
    ]);
    if release {
        build.arg("--release");
    }
    run(build.current_dir(&root))?;
    let wasm = target
        .join("wasm32-unknown-unknown")
        .join(profile)
        .join("pleat_app.wasm");
    let dist = out.unwrap_or_else(|| target.join("web"));
    step(4, &format!("writing the page into {}", dist.display()));
    std::fs::create_dir_all(&dist).map_err(|e| format!("{}: {e}", dist.display()))?;
    run(Command::new(&bindgen)
        .args([
            "--target",
            "web",
            "--no-typescript",
            "--out-name",
            "pleat_app",
            "--out-dir",
        ])
        .arg(&dist)
        .arg(&wasm))?;
    let page = root.join("crates/pleat-app/web/index.html");
    std::fs::copy(&page, dist.join("index.html"))
        .map_err(|e| format!("{}: {e}", page.display()))?;
    Ok(dist)
}

/// Says which of the web build's four steps starts.
fn step(n: u32, what: &str) {
    eprintln!("[{n}/4] {what}");
}

/// wasm-bindgen-cli at the exact version of the wasm-bindgen crate in
/// Cargo.lock (the two must match), installed under the target folder.
fn wasm_bindgen_cli(root: &Path, target: &Path) -> Result<PathBuf, String> {
    let version = locked_version(root, "wasm-bindgen")?;
    let tools = target.join("tools");
    let binary = tools.join("bin").join("wasm-bindgen");
    let installed = Command::new(&binary)
        .arg("--version")
        .output()
        .is_ok_and(|o| String::from_utf8_lossy(&o.stdout).contains(&version));
    if !installed {
        eprintln!("installing wasm-bindgen-cli {version} (once)");
        run(cargo()
            .args(["install", "wasm-bindgen-cli", "--version"])
            .arg(format!("={version}"))
            .arg("--root")
            .arg(&tools))?;
    }
    Ok(binary)
}

/// The version Cargo.lock pins for the package `name`.
fn locked_version(root: &Path, name: &str) -> Result<String, String> {
    let lock =
        std::fs::read_to_string(root.join("Cargo.lock")).map_err(|e| format!("Cargo.lock: {e}"))?;
    let mut lines = lock.lines();
    while let Some(line) = lines.next() {
        if line.trim() == format!("name = \"{name}\"") {
            let version = lines.next().unwrap_or_default();
            return version
                .trim()
                .strip_prefix("version = \"")
                .and_then(|v| v.strip_suffix('"'))
                .map(str::to_string)
                .ok_or_else(|| format!("Cargo.lock: no version after {name}"));
        }
    }
    Err(format!("Cargo.lock has no package {name}"))
}

fn test() -> Result<(), String> {
    let root = workspace_root()?;
    run(cargo()
        .args(["test", "--workspace", "--locked"])
        .current_dir(&root))?;
    // The library's runnable example: a scene built in code, stepped on the
    // CPU and the GPU, written as glb. Built for the whole workspace, with
    // the features `cargo test` resolved, so nothing is compiled again (`-p
    // pleat-gpu` alone resolves other features and rebuilds the
    // dependencies: 3 minutes on a cold two-core machine).
    run(cargo()
        .args(["build", "--workspace", "--examples", "--locked"])
        .current_dir(&root))?;
    let target = target_dir(&root)?;
    let glb = target.join("examples-out/drape_in_code.glb");
    let example = format!(
        "debug/examples/drape_in_code{}",
        std::env::consts::EXE_SUFFIX
    );
    run(Command::new(target.join(example))
        .arg(&glb)
        .current_dir(&root))?;
    python_tests(&root, &target)?;
    let dist = build_web(true, None)?;
    let tests = root.join("tests/web");
    if !tests.join("node_modules").exists() {
        run(Command::new("npm")
            .args(["ci", "--no-audit", "--no-fund"])
            .current_dir(&tests))?;
    }
    run(Command::new("node")
        .arg("app.test.mjs")
        .arg(&dist)
        .current_dir(&tests))
}

/// The Python package's tests: a fresh virtual environment under the
/// target folder with the pinned requirements of
/// crates/pleat-py/requirements-test.txt (maturin, numpy, pytest, Ray),
/// the wheel built there by maturin in the dev profile and the workspace's
/// target folder (so it reuses the crates `cargo test` compiled) and
/// installed, then pytest on crates/pleat-py/tests against the `pleat`
/// command of the same build. Nothing is cached outside the target folder.
/// On the 2-core development machine after `cargo test --workspace`: 80 s
/// (pip 20 s, maturin 30 s compiling pyo3 and the module only, pytest 8 s).
fn python_tests(root: &Path, target: &Path) -> Result<(), String> {
    let dir = target.join("python-test");
    if dir.exists() {
        std::fs::remove_dir_all(&dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    }
    let venv = dir.join("venv");
    let wheels = dir.join("wheels");
    eprintln!("python: a fresh virtual environment in {}", venv.display());
    run(Command::new("python3").args(["-m", "venv"]).arg(&venv))?;
    let bin = venv.join("bin");
    let pip = |args: &[&str]| {
        let mut pip = Command::new(bin.join("pip"));
        pip.args([
            "install",
            "--quiet",
            "--no-cache-dir",
            "--disable-pip-version-check",
        ])
        .args(args);
        pip
    };
    let requirements = root.join("crates/pleat-py/requirements-test.txt");
    run(pip(&["-r"]).arg(&requirements))?;
    run(Command::new(bin.join("maturin"))
        .args([
            "build",
            "--locked",
            "--profile",
            "dev",
            "--strip",
            "--manifest-path",
        ])
        .arg(root.join("crates/pleat-py/Cargo.toml"))
        .arg("--out")
        .arg(&wheels)
        .env("CARGO_TARGET_DIR", target))?;
    let wheel = std::fs::read_dir(&wheels)
        .map_err(|e| format!("{}: {e}", wheels.display()))?
        .filter_map(|entry| entry.ok().map(|e| e.path()))
        .find(|path| path.extension().is_some_and(|ext| ext == "whl"))
        .ok_or_else(|| format!("maturin wrote no wheel in {}", wheels.display()))?;
    run(pip(&[]).arg(&wheel))?;
    // The command the tests compare reports with: the build `cargo test
    // --workspace` made for pleat-cli's own tests (building it again with
    // `-p pleat-cli` would resolve other features and compile it again).
    let pleat = target.join("debug").join("pleat");
    if !pleat.exists() {
        return Err(format!(
            "{} is missing: run cargo test --workspace first",
            pleat.display()
        ));
    }
    run(Command::new(bin.join("python"))
        .args(["-m", "pytest", "-q", "-p", "no:cacheprovider"])
        .arg(root.join("crates/pleat-py/tests"))
        .env("PLEAT_BIN", &pleat)
        .current_dir(root))
}

fn cargo() -> Command {
    Command::new(std::env::var("CARGO").unwrap_or_else(|_| "cargo".into()))
}

/// The workspace the command runs in (not the one xtask was built in: a
/// shared target folder may hold an xtask built from another checkout).
fn workspace_root() -> Result<PathBuf, String> {
    let output = cargo()
        .args(["locate-project", "--workspace", "--message-format", "plain"])
        .output()
        .map_err(|e| format!("cargo locate-project: {e}"))?;
    let manifest = PathBuf::from(String::from_utf8_lossy(&output.stdout).trim());
    manifest
        .parent()
        .filter(|_| output.status.success())
        .map(Path::to_path_buf)
        .ok_or_else(|| "cannot find the workspace (run inside the project)".to_string())
}

/// The target folder cargo uses (CARGO_TARGET_DIR or the workspace's).
fn target_dir(root: &Path) -> Result<PathBuf, String> {
    let output = cargo()
        .args(["metadata", "--format-version", "1", "--no-deps"])
        .current_dir(root)
        .output()
        .map_err(|e| format!("cargo metadata: {e}"))?;
    let metadata: serde_json::Value =
        serde_json::from_slice(&output.stdout).map_err(|e| format!("cargo metadata: {e}"))?;
    metadata["target_directory"]
        .as_str()
        .map(PathBuf::from)
        .ok_or_else(|| "cargo metadata: no target_directory".into())
}

fn run(command: &mut Command) -> Result<(), String> {
    let status = command.status().map_err(|e| format!("{command:?}: {e}"))?;
    if status.success() {
        Ok(())
    } else {
        Err(format!("{command:?} failed ({status})"))
    }
}
