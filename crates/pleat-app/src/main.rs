//! The native app: `pleat-app [FILES] [--demo ID] [--backend auto|cpu|gpu]`, and
//! for tests `--frames N --screenshot out.png` (a picture of the window
//! after N frames, then exit, printing the app's state as JSON) and
//! `--lose-device-at N` (the device destroyed at frame N: the window opens
//! again on a new device and the run goes on).

#[cfg(not(target_arch = "wasm32"))]
fn main() -> std::process::ExitCode {
    native::main()
}

#[cfg(target_arch = "wasm32")]
fn main() {}

#[cfg(not(target_arch = "wasm32"))]
mod native {
    use clap::Parser;
    use eframe::egui;
    use pleat_app::{recovery, BackendChoice, Options, PleatApp};
    use std::path::PathBuf;
    use std::process::ExitCode;
    use std::sync::{Arc, Mutex};

    #[derive(Parser)]
    #[command(name = "pleat-app", about = "Cloth and origami, live.")]
    struct Args {
        /// Files to open, as if dropped on the window: a scene (.json) with
        /// the meshes and patterns it names, an OBJ or a crease pattern.
        files: Vec<PathBuf>,
        /// Demo to open: rigid, fold, sdf, wind, self or drape.
        #[arg(long, default_value = "rigid")]
        demo: String,
        /// auto (time both on each scene, keep the faster), cpu or gpu.
        #[arg(long, default_value = "auto")]
        backend: String,
        /// Parameters to set, as NAME=VALUE (e.g. gravity=-3).
        #[arg(long = "set")]
        set: Vec<String>,
        /// Frames to run before the screenshot.
        #[arg(long, default_value_t = 60)]
        frames: u64,
        /// Writes a PNG of the window after --frames frames and exits.
        #[arg(long)]
        screenshot: Option<PathBuf>,
        /// Loses the GPU device on purpose at this frame (a test of the
        /// recovery).
        #[arg(long)]
        lose_device_at: Option<u64>,
        /// Window size in points.
        #[arg(long, value_parser = parse_size, default_value = "1280x800")]
        size: [f32; 2],
    }

    fn parse_size(s: &str) -> Result<[f32; 2], String> {
        let (w, h) = s.split_once('x').ok_or("give WIDTHxHEIGHT")?;
        let side = |s: &str| match s.parse::<f32>() {
            Ok(v) if v.is_finite() && v >= 1.0 => Ok(v),
            _ => Err(format!("'{s}' is not a size in points")),
        };
        Ok([side(w)?, side(h)?])
    }

    fn options(args: &Args) -> Result<Options, String> {
        let backend = match args.backend.as_str() {
            "auto" => None,
            "cpu" => Some(BackendChoice::Cpu),
            "gpu" => Some(BackendChoice::Gpu),
            other => {
                return Err(format!(
                    "--backend: expected auto, cpu or gpu, got '{other}'"
                ))
            }
        };
        let mut files = Vec::new();
        for path in &args.files {
            let bytes =
                std::fs::read(path).map_err(|e| format!("{}: cannot read: {e}", path.display()))?;
            let name = path
                .file_name()
                .map_or(String::new(), |n| n.to_string_lossy().into_owned());
            files.push((name, bytes));
        }
        let mut set = Vec::new();
        for s in &args.set {
            let (name, value) = s
                .split_once('=')
                .ok_or(format!("--set {s}: give NAME=VALUE"))?;
            let value = value
                .parse()
                .map_err(|_| format!("--set {s}: '{value}' is not a number"))?;
            set.push((name.to_string(), value));
        }
        Ok(Options {
            demo: args.demo.clone(),
            files,
            backend,
            set,
        })
    }

    /// The screenshot to take after a number of frames (and the frame to
    /// lose the device at), shared by the windows a lost device opens.
    struct Shot {
        frames: u64,
        path: PathBuf,
        lose_at: Option<u64>,
        result: Arc<Mutex<Option<Result<(), String>>>>,
        state: Arc<Mutex<String>>,
    }

    /// The app, and the screenshot it takes.
    struct Shooter {
        app: PleatApp,
        shot: Shot,
        requested: bool,
        /// App frames drawn: a run whose scene never opens gives up.
        drawn: u64,
    }

    impl eframe::App for Shooter {
        fn ui(&mut self, ui: &mut egui::Ui, frame: &mut eframe::Frame) {
            let shot = &self.shot;
            let lose = shot.lose_at.is_some_and(|at| self.app.probe.frame >= at);
            if lose && self.app.probe.device_lost.is_none() {
                self.app.lose_device();
            }
            self.app.ui(ui, frame);
            if recovery::is_pending() {
                return; // The window closes; the next one resumes the run.
            }
            *shot.state.lock().expect("state") = self.app.probe.to_json();
            let ctx = ui.ctx().clone();
            self.drawn += 1;
            if self.drawn > shot.frames * 20 + 600 && !self.requested {
                let why = self.app.probe.last_error.clone().unwrap_or_default();
                *shot.result.lock().expect("result") = Some(Err(format!(
                    "no frames after {} app frames: {why}",
                    self.drawn
                )));
            }
            if shot.result.lock().expect("result").is_some() {
                ctx.send_viewport_cmd(egui::ViewportCommand::Close);
            } else if !self.requested && self.app.probe.frame >= shot.frames {
                self.requested = true;
                let (path, result) = (shot.path.clone(), shot.result.clone());
                let repaint = ctx.clone();
                ctx.request_screenshot(move |image| {
                    *result.lock().expect("result") = Some(save(&path, &image));
                    repaint.request_repaint();
                });
            }
        }
    }

    fn save(path: &PathBuf, image: &egui::ColorImage) -> Result<(), String> {
        let [w, h] = image.size;
        let bytes: Vec<u8> = image.pixels.iter().flat_map(|c| c.to_array()).collect();
        image::RgbaImage::from_raw(w as u32, h as u32, bytes)
            .ok_or("bad screenshot size")?
            .save(path)
            .map_err(|e| format!("cannot write {}: {e}", path.display()))
    }

    /// Runs the app in a window until it closes: a new app, or the run a
    /// lost device handed over; with a screenshot to take when `shot`.
    fn open_window(args: &Args, options: Options, shot: Option<Shot>) -> Result<(), eframe::Error> {
        let native = eframe::NativeOptions {
            viewport: egui::ViewportBuilder::default()
                .with_inner_size(args.size)
                .with_title("pleat"),
            wgpu_options: pleat_app::wgpu_options(),
            ..Default::default()
        };
        eframe::run_native(
            "pleat",
            native,
            Box::new(move |cc| {
                let app = match recovery::take() {
                    Some(run) => PleatApp::resume(cc, run),
                    None => PleatApp::new(cc, options),
                };
                Ok(match shot {
                    Some(shot) => Box::new(Shooter {
                        app,
                        shot,
                        requested: false,
                        drawn: 0,
                    }),
                    None => Box::new(app),
                })
            }),
        )
    }

    pub fn main() -> ExitCode {
        let args = Args::parse();
        let options = match options(&args) {
            Ok(o) => o,
            Err(e) => {
                eprintln!("error: {e}");
                return ExitCode::from(2);
            }
        };
        let result = Arc::new(Mutex::new(None));
        let state = Arc::new(Mutex::new(String::new()));
        // A lost device closes the window; a new one resumes the run.
        loop {
            let shot = args.screenshot.clone().map(|path| Shot {
                frames: args.frames,
                path,
                lose_at: args.lose_device_at,
                result: result.clone(),
                state: state.clone(),
            });
            if let Err(e) = open_window(&args, options.clone(), shot) {
                eprintln!("error: the window could not open: {e}");
                return ExitCode::from(2);
            }
            if !recovery::is_pending() {
                break;
            }
        }
        if args.screenshot.is_some() {
            println!("{}", state.lock().expect("state"));
            return match result.lock().expect("result").take() {
                Some(Ok(())) => ExitCode::SUCCESS,
                Some(Err(e)) => {
                    eprintln!("error: {e}");
                    ExitCode::FAILURE
                }
                None => {
                    eprintln!("error: the window closed before the screenshot");
                    ExitCode::FAILURE
                }
            };
        }
        ExitCode::SUCCESS
    }
}
