//! The app: one [`PleatApp`] drives the panels, the 3D view and the
//! simulation every frame, natively and in the browser. It never blocks on
//! the GPU: state comes back between frames ([`Session::poll`]).

use crate::demos::{shipped_files, Demo, PatternChoice};
use crate::platform::Inbox;
use crate::plot::History;
use crate::probe::Probe;
use crate::session::{BackendChoice, Session};
use crate::viewport::Viewport;
use eframe::egui;
use pleat::scene::{InMemory, Scene};
use pleat::solver::StageTimes;
use pleat_gpu::GpuContext;
use web_time::Instant;

/// Frames over which the per-stage timings are averaged.
const STAGE_WINDOW: u32 = 30;

/// How the app starts (from the command line or the page's URL).
#[derive(Clone, Debug)]
pub struct Options {
    /// The demo to open (an id of [`crate::demos::DEMOS`]).
    pub demo: String,
    /// A scene to open instead (name, bytes), with files beside it.
    pub files: Vec<(String, Vec<u8>)>,
    pub backend: BackendChoice,
    /// Parameters to set at the start (name, value).
    pub set: Vec<(String, f64)>,
}

impl Default for Options {
    fn default() -> Self {
        Options {
            demo: crate::demos::DEMOS[0].id.to_string(),
            files: Vec::new(),
            backend: BackendChoice::Gpu,
            set: Vec::new(),
        }
    }
}

/// Something to do at the start of the next frame.
#[derive(Clone, Debug)]
pub enum Command {
    Demo(String),
    Pattern(PatternChoice),
    Step,
    Reset,
    Export(&'static str),
    Set(String, f64),
    Open(Vec<(String, Vec<u8>)>),
}

pub struct PleatApp {
    pub session: Option<Session>,
    pub demo: Option<Demo>,
    pub pattern: Option<PatternChoice>,
    pub viewport: Viewport,
    pub playing: bool,
    pub commands: Vec<Command>,
    pub probe: Probe,
    pub history: History,
    pub stage_window: StageTimes,
    pub stage_frames: Option<u32>,
    /// Counts the scenes opened (the view frames each anew) and the models
    /// built, rebuilds included (the view rebuilds its renderer).
    opened: u64,
    generation: u64,
    gpu: Option<GpuContext>,
    backend: BackendChoice,
    /// Meshes and patterns shipped or dropped, for scenes that name them.
    files: InMemory,
    inbox: Inbox,
    last_frame: Option<Instant>,
    step_once: bool,
    /// The scene (its `opened` count) whose instability paused the run:
    /// it pauses once, and the person may play on.
    halted: Option<u64>,
}

impl PleatApp {
    /// The app on eframe's wgpu device (shared by the renderer and the GPU
    /// backend), opening what `options` ask for.
    pub fn new(cc: &eframe::CreationContext<'_>, options: Options) -> Self {
        let gpu = cc.wgpu_render_state.as_ref().and_then(compute_context);
        let mut app = PleatApp {
            session: None,
            demo: None,
            pattern: None,
            viewport: Viewport::new(),
            playing: true,
            commands: Vec::new(),
            probe: Probe::default(),
            history: History::default(),
            stage_window: StageTimes::default(),
            stage_frames: None,
            opened: 0,
            generation: 0,
            gpu,
            backend: options.backend,
            files: shipped_files(),
            inbox: Inbox::default(),
            last_frame: None,
            step_once: false,
            halted: None,
        };
        if options.files.is_empty() {
            app.commands.push(Command::Demo(options.demo));
        } else {
            app.commands.push(Command::Open(options.files));
        }
        app.commands
            .extend(options.set.into_iter().map(|(n, v)| Command::Set(n, v)));
        app
    }

    /// Shows `message` as the app's error (it keeps running).
    fn fail(&mut self, message: String) {
        self.probe.last_error = Some(message);
    }

    fn open(&mut self, scene: Scene, file: String) {
        let backend = self.demo.and_then(|d| d.backend).unwrap_or(self.backend);
        match Session::new(scene, file, self.files.clone(), backend, self.gpu.clone()) {
            Ok(session) => {
                // An error belongs to the action that caused it: a scene
                // that opens replaces what an earlier one left on screen.
                self.probe.last_error = None;
                // A run an instability paused plays again from the new start.
                if self.halted.take().is_some() {
                    self.playing = true;
                }
                self.session = Some(session);
                self.opened += 1;
                self.generation += 1;
                self.history.clear();
                self.stage_frames = None;
                self.probe.frame = 0;
            }
            Err(e) => self.fail(e.to_string()),
        }
    }

    fn run(&mut self, command: Command) {
        match command {
            Command::Demo(id) => match Demo::find(&id) {
                Some(demo) => match demo.scene() {
                    Ok((scene, file)) => {
                        self.demo = Some(demo);
                        self.pattern = None;
                        self.probe.demo = demo.id.to_string();
                        self.open(scene, file);
                    }
                    Err(e) => self.fail(e.to_string()),
                },
                None => self.fail(format!("no demo named '{id}'")),
            },
            Command::Pattern(choice) => {
                if let Some(Ok((mut scene, file))) = self.demo.map(|d| d.scene()) {
                    choice.apply(&mut scene);
                    self.pattern = Some(choice);
                    self.open(scene, file);
                }
            }
            Command::Step => self.step_once = true,
            Command::Reset => {
                if let Some(s) = &self.session {
                    let (scene, file) = (s.scene.clone(), s.file.clone());
                    self.open(scene, file);
                }
            }
            Command::Export(format) => {
                if let Err(e) = self.export(format) {
                    self.fail(e);
                }
            }
            Command::Set(name, value) => {
                let result = match &mut self.session {
                    Some(s) => crate::params::set(s, &name, value),
                    None => Err("no scene is open".into()),
                };
                if let Err(e) = result {
                    self.fail(e);
                }
            }
            Command::Open(files) => match crate::dropped::scene_from(files, &mut self.files) {
                Ok((scene, file)) => {
                    self.demo = None;
                    self.pattern = None;
                    self.probe.demo = file.clone();
                    self.open(scene, file);
                }
                Err(e) => self.fail(e),
            },
        }
    }

    /// Writes the current mesh as `format` (OBJ or glb): a download in a
    /// browser, a file in the working folder natively.
    fn export(&mut self, format: &str) -> Result<(), String> {
        let session = self.session.as_ref().ok_or("no scene is open")?;
        let model = &session.sim.model;
        let x = &session.sim.particles.x;
        let mut bytes = Vec::new();
        let written = if format == "obj" {
            pleat::export::write_obj(&mut bytes, x, &model.triangles, None, None)
        } else {
            let mut glb = pleat::export::GlbAnimation::new(
                &model.triangles,
                &model.rest,
                1.0 / session.scene.fps,
            );
            glb.push_frame(x).and_then(|()| glb.write(&mut bytes))
        };
        written.map_err(|e| format!("export failed: {e}"))?;
        // The scene's name may come from a dropped file: keep it a plain name.
        let stem: String = (session.scene.name.chars())
            .map(|c| {
                if c.is_alphanumeric() || "-_".contains(c) {
                    c
                } else {
                    '_'
                }
            })
            .collect();
        let name = format!("{stem}.{format}");
        crate::platform::save(&name, &bytes)
    }

    /// Takes the files read since the last frame.
    fn take_inbox(&mut self) {
        let arrived: Vec<_> = std::mem::take(&mut *self.inbox.lock().expect("inbox"));
        if arrived.is_empty() {
            return;
        }
        let mut files = Vec::new();
        for (name, bytes) in arrived {
            match bytes {
                Ok(bytes) => files.push((name, bytes)),
                Err(e) => self.fail(format!("{name}: cannot read: {e}")),
            }
        }
        if !files.is_empty() {
            self.commands.push(Command::Open(files));
        }
    }

    /// Steps the simulation one frame when playing and takes its state.
    fn advance(&mut self, now: Instant) {
        let dt = self.last_frame.map_or(0.0, |t| (now - t).as_secs_f32());
        self.last_frame = Some(now);
        self.probe.tick(dt);
        let Some(session) = &mut self.session else {
            return;
        };
        match session.poll() {
            Ok(true) => self.generation += 1,
            Ok(false) => {}
            Err(e) => self.probe.last_error = Some(e),
        }
        if (self.playing || self.step_once) && !session.is_pending() {
            session.step(1.0 / session.scene.fps);
            self.probe.frame += 1;
            self.step_once = false;
            if self.probe.frame % u64::from(STAGE_WINDOW) == 0 {
                self.stage_window = std::mem::take(&mut session.sim.stages);
                self.stage_frames = Some(STAGE_WINDOW);
            }
        }
        self.probe.observe(session);
        self.history.push(self.probe.max_stretch, self.probe.energy);
        self.halt_if_unstable();
    }

    /// Pauses the run the first time its scene goes unstable (NaN,
    /// runaway energy, torn paper), instead of stepping on over NaN; the
    /// banner says when and where.
    fn halt_if_unstable(&mut self) {
        if self.probe.instability.is_some() && self.halted != Some(self.opened) {
            self.halted = Some(self.opened);
            self.playing = false;
        }
        self.probe.paused = !self.playing;
    }
}

/// A context for the GPU backend on eframe's device, if it has compute
/// shaders (WebGPU, Vulkan, Metal, DX12; not WebGL).
fn compute_context(state: &eframe::egui_wgpu::RenderState) -> Option<GpuContext> {
    let compute = state
        .adapter
        .get_downlevel_capabilities()
        .flags
        .contains(wgpu::DownlevelFlags::COMPUTE_SHADERS);
    let info = state.adapter.get_info();
    // Browsers keep the adapter's name to themselves.
    let name = if info.name.is_empty() {
        "WebGPU adapter"
    } else {
        &info.name
    };
    compute.then(|| GpuContext {
        device: state.device.clone(),
        queue: state.queue.clone(),
        adapter: format!("{name} ({:?})", info.backend),
    })
}

impl eframe::App for PleatApp {
    fn ui(&mut self, ui: &mut egui::Ui, frame: &mut eframe::Frame) {
        let ctx = ui.ctx().clone();
        crate::platform::receive_drops(&ctx, &self.inbox);
        self.take_inbox();
        for (name, value) in crate::platform::take_commands() {
            self.commands.push(Command::Set(name, value));
        }
        for command in std::mem::take(&mut self.commands) {
            self.run(command);
        }
        self.advance(Instant::now());
        egui::Panel::left("controls")
            .resizable(true)
            .default_size(300.0)
            .show(ui, |ui| self.side_panel(ui));
        egui::CentralPanel::default().show(ui, |ui| {
            self.error_bar(ui);
            self.instability_banner(ui);
            let (Some(state), Some(session)) = (frame.wgpu_render_state(), &mut self.session)
            else {
                ui.label("no scene is open");
                return;
            };
            let compute = self.gpu.is_some();
            let built = [self.opened, self.generation];
            if let Err(e) =
                self.viewport
                    .show(ui, state, session, built, compute, self.probe.max_stretch)
            {
                self.probe.last_error = Some(e);
            }
        });
        self.probe.grabbing = self.viewport.is_grabbing();
        self.probe.cloth_point = self.viewport.cloth_point;
        crate::platform::publish(&self.probe);
        ctx.request_repaint();
    }
}

impl PleatApp {
    /// The banner of an unstable run: what happened, when and where, with
    /// reset at hand.
    fn instability_banner(&mut self, ui: &mut egui::Ui) {
        let Some(what) = self.probe.instability.clone() else {
            return;
        };
        let paused = if self.playing { "" } else { "; paused" };
        let mut reset = false;
        egui::Frame::new()
            .fill(egui::Color32::from_rgb(140, 90, 10))
            .inner_margin(6.0)
            .show(ui, |ui| {
                ui.horizontal(|ui| {
                    ui.colored_label(egui::Color32::WHITE, format!("{what}{paused}"));
                    reset = ui.button("reset").clicked();
                });
            });
        if reset {
            self.commands.push(Command::Reset);
        }
    }

    fn error_bar(&mut self, ui: &mut egui::Ui) {
        let Some(error) = self.probe.last_error.clone() else {
            return;
        };
        let mut dismissed = false;
        egui::Frame::new()
            .fill(egui::Color32::from_rgb(120, 30, 30))
            .inner_margin(6.0)
            .show(ui, |ui| {
                ui.horizontal(|ui| {
                    ui.colored_label(egui::Color32::WHITE, &error);
                    dismissed = ui.button("dismiss").clicked();
                });
            });
        if dismissed {
            self.probe.last_error = None;
        }
    }
}
