//! The app: one [`PleatApp`] drives the panels, the 3D view and the
//! simulation every frame, natively and in the browser. It never blocks on
//! the GPU: state comes back between frames ([`Session::poll`]). A lost
//! device hands the run over to a new start on a new device
//! ([`crate::recovery`]).

use crate::backend_trial::{BackendTrial, Running};
use crate::demos::{shipped_files, Demo, PatternChoice};
use crate::device::DeviceWatch;
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

/// Below this width (points) the controls are a sheet under the view (a
/// phone held upright), not a panel beside it.
const NARROW: f32 = 700.0;

/// How the app starts (from the command line or the page's URL).
#[derive(Clone, Debug)]
pub struct Options {
    /// The demo to open (an id of [`crate::demos::DEMOS`]).
    pub demo: String,
    /// A scene to open instead (name, bytes), with files beside it.
    pub files: Vec<(String, Vec<u8>)>,
    /// The backend asked for; `None` tries both on each scene and keeps
    /// the faster ([`crate::backend_trial`]).
    pub backend: Option<BackendChoice>,
    /// Parameters to set at the start (name, value).
    pub set: Vec<(String, f64)>,
}

impl Default for Options {
    fn default() -> Self {
        Options {
            demo: crate::demos::DEMOS[0].id.to_string(),
            files: Vec::new(),
            backend: None,
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
    /// The backend asked for, or `None` to pick the faster per scene.
    backend: Option<BackendChoice>,
    /// The trial of both backends on the open scene, while the backend is
    /// picked by measurement (not asked for, nor chosen on the panel).
    pub trial: Option<BackendTrial>,
    /// Meshes and patterns shipped or dropped, for scenes that name them.
    files: InMemory,
    inbox: Inbox,
    last_frame: Option<Instant>,
    /// When the app started: the trial's clock.
    started: Instant,
    step_once: bool,
    /// The scene (its `opened` count) whose instability paused the run:
    /// it pauses once, and the person may play on.
    halted: Option<u64>,
    /// Loss and errors of the device eframe draws on (and the GPU
    /// backend runs on).
    watch: Option<DeviceWatch>,
    /// Whether this app lost its device and handed its run over.
    handed_over: bool,
    /// Whether the controls are shown (a button hides them).
    controls_open: bool,
}

impl PleatApp {
    /// The app on eframe's wgpu device (shared by the renderer and the GPU
    /// backend), opening what `options` ask for.
    pub fn new(cc: &eframe::CreationContext<'_>, options: Options) -> Self {
        let mut app = PleatApp::bare(options.backend);
        app.attach(cc);
        if options.files.is_empty() {
            app.commands.push(Command::Demo(options.demo));
        } else {
            app.commands.push(Command::Open(options.files));
        }
        app.commands
            .extend(options.set.into_iter().map(|(n, v)| Command::Set(n, v)));
        app
    }

    /// The run `old` handed over when its device was lost, on the new
    /// device eframe made: the simulation built again from the state last
    /// read back, the view drawn anew, the panels and counters as they were.
    pub fn resume(cc: &eframe::CreationContext<'_>, mut old: PleatApp) -> Self {
        old.attach(cc);
        old.viewport = old.viewport.on_new_device();
        old.generation += 1;
        let lost = old.probe.device_lost.take().unwrap_or_default();
        let resumed = match &mut old.session {
            Some(session) => session.recover(old.gpu.clone()).map_err(|e| e.to_string()),
            None => Ok("no scene was open".into()),
        };
        old.probe.device_lost = Some(match resumed {
            Ok(how) => {
                old.forget_halt_by_lost_device();
                format!("{lost}; recovered: {how}")
            }
            Err(e) => {
                old.session = None;
                format!("{lost}; the scene could not be built again: {e}")
            }
        });
        old
    }

    /// An app with nothing open and no device yet.
    fn bare(backend: Option<BackendChoice>) -> Self {
        PleatApp {
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
            gpu: None,
            backend,
            trial: None,
            files: shipped_files(),
            inbox: Inbox::default(),
            last_frame: None,
            started: Instant::now(),
            step_once: false,
            halted: None,
            watch: None,
            handed_over: false,
            controls_open: true,
        }
    }

    /// Takes eframe's wgpu device (shared by the renderer and the GPU
    /// backend) and watches it.
    fn attach(&mut self, cc: &eframe::CreationContext<'_>) {
        let state = cc.wgpu_render_state.as_ref();
        self.gpu = state.and_then(compute_context);
        self.watch = state.map(|s| DeviceWatch::attach(&s.device));
    }

    /// Loses the device on purpose (for tests), as a driver reset would.
    pub fn lose_device(&self) {
        if let Some(watch) = &self.watch {
            watch.destroy();
        }
    }

    /// Whether the device has been lost.
    fn device_gone(&self) -> bool {
        self.handed_over || self.watch.as_ref().is_some_and(|w| w.lost().is_some())
    }

    /// Reads the device's watch: shows its uncaptured errors, and once it
    /// is lost hands the run over to a new start of eframe on a new
    /// device. Says whether the device is gone.
    fn watch_device(&mut self, ctx: &egui::Context) -> bool {
        if crate::platform::take_lose_request() {
            self.lose_device();
        }
        if self.handed_over {
            return true;
        }
        let Some(watch) = &self.watch else {
            return false;
        };
        if let Some(reason) = watch.lost() {
            let frame = self.probe.frame;
            let mut run = std::mem::replace(self, PleatApp::bare(self.backend));
            run.probe.device_lost = Some(format!(
                "the GPU device was lost at frame {frame} ({reason})"
            ));
            crate::recovery::hand_over(run);
            self.handed_over = true;
            crate::platform::restart(ctx);
            return true;
        }
        for error in watch.take_errors() {
            self.fail(format!("GPU error: {error}"));
        }
        false
    }

    /// Shows `message` as the app's error (it keeps running).
    fn fail(&mut self, message: String) {
        self.probe.last_error = Some(message);
    }

    fn open(&mut self, scene: Scene, file: String) {
        let backend = self
            .backend
            .or(self.demo.and_then(|d| d.backend))
            .unwrap_or(BackendChoice::Gpu);
        match Session::new(scene, file, self.files.clone(), backend, self.gpu.clone()) {
            Ok(session) => {
                // Both backends are tried where both can run and none was asked for.
                self.trial = (self.backend.is_none() && self.gpu.is_some())
                    .then(|| BackendTrial::new(session.backend));
                self.probe.backend_pick = None;
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
        if self.device_gone() {
            // A read that failed as the device went is not the state.
            return;
        }
        let Some(session) = &mut self.session else {
            return;
        };
        if let Some(trial) = &mut self.trial {
            let running = Running {
                now: (now - self.started).as_secs_f64(),
                backend: session.backend,
                moving: session.is_pending(),
                frame: self.probe.frame,
                playing: self.playing,
            };
            if let Some(to) = trial.observe(running) {
                session.request(crate::session::Pending::Backend(to));
            }
            if self.probe.backend_pick.is_none() {
                self.probe.backend_pick = trial.verdict();
            }
        }
        if (self.playing || self.step_once) && !session.is_pending() {
            session.step(1.0 / session.scene.fps);
            self.probe.count_step();
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
    /// runaway energy, torn paper or cloth), instead of stepping on over NaN; the
    /// banner says when and where.
    fn halt_if_unstable(&mut self) {
        if self.probe.instability.is_some() && self.halted != Some(self.opened) {
            self.halted = Some(self.opened);
            self.playing = false;
        }
        self.probe.paused = !self.playing;
    }

    /// Plays again a run that the instability check paused before its
    /// device was lost: the read that failed as the device went leaves
    /// NaN, which can be judged before the loss is known. The run goes on
    /// from the last finite state read back, and is paused anew if that
    /// goes unstable.
    fn forget_halt_by_lost_device(&mut self) {
        if self.halted.take().is_some() {
            self.playing = true;
            self.probe.instability = None;
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
        device_type: info.device_type,
    })
}

impl eframe::App for PleatApp {
    fn ui(&mut self, ui: &mut egui::Ui, frame: &mut eframe::Frame) {
        let ctx = ui.ctx().clone();
        if let Some(reason) = crate::platform::take_crash_request() {
            panic!("{reason}");
        }
        // Nothing is drawn on a lost device: egui's painter would fail
        // (natively it panics when its buffers cannot be written).
        if self.watch_device(&ctx) {
            return;
        }
        crate::platform::receive_drops(&ctx, &self.inbox);
        self.take_inbox();
        for (name, value) in crate::platform::take_commands() {
            self.commands.push(Command::Set(name, value));
        }
        for command in std::mem::take(&mut self.commands) {
            self.run(command);
        }
        self.advance(Instant::now());
        if self.watch_device(&ctx) {
            return; // Lost while the state was read.
        }
        self.controls(ui);
        egui::CentralPanel::default().show(ui, |ui| {
            let label = if self.controls_open {
                "hide controls"
            } else {
                "show controls"
            };
            if ui.small_button(label).clicked() {
                self.controls_open = !self.controls_open;
            }
            self.error_bar(ui);
            self.device_lost_banner(ui);
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
    /// The controls, when open: a panel on the left of a wide window, a
    /// sheet under the view of a narrow one; either scrolls.
    fn controls(&mut self, ui: &mut egui::Ui) {
        let area = ui.available_rect_before_wrap();
        self.probe.screen = [area.width(), area.height()];
        self.probe.controls = None;
        if !self.controls_open {
            return;
        }
        let shown = if area.width() < NARROW {
            let height = area.height();
            egui::Panel::bottom("controls sheet")
                .resizable(true)
                .default_size(height * 0.42)
                .size_range(100.0..=height * 0.75)
                .show(ui, |ui| self.side_panel(ui))
        } else {
            egui::Panel::left("controls")
                .resizable(true)
                .default_size(300.0)
                .size_range(220.0..=area.width() * 0.45)
                .show(ui, |ui| self.side_panel(ui))
        };
        let r = shown.response.rect;
        self.probe.controls = Some([r.min.x, r.min.y, r.max.x, r.max.y]);
    }

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
                ui.horizontal_wrapped(|ui| {
                    ui.colored_label(egui::Color32::WHITE, format!("{what}{paused}"));
                    reset = ui.button("reset").clicked();
                });
            });
        if reset {
            self.commands.push(Command::Reset);
        }
    }

    /// The banner of a device lost and recovered: when, and where the run
    /// went on.
    fn device_lost_banner(&mut self, ui: &mut egui::Ui) {
        let Some(what) = self.probe.device_lost.clone() else {
            return;
        };
        let mut dismissed = false;
        egui::Frame::new()
            .fill(egui::Color32::from_rgb(40, 70, 130))
            .inner_margin(6.0)
            .show(ui, |ui| {
                ui.horizontal_wrapped(|ui| {
                    ui.colored_label(egui::Color32::WHITE, what);
                    dismissed = ui.button("dismiss").clicked();
                });
            });
        if dismissed {
            self.probe.device_lost = None;
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
                ui.horizontal_wrapped(|ui| {
                    ui.colored_label(egui::Color32::WHITE, &error);
                    dismissed = ui.button("dismiss").clicked();
                });
            });
        if dismissed {
            self.probe.last_error = None;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_halt_seen_as_the_device_went_is_forgotten_but_a_pause_by_hand_is_kept() {
        let mut app = PleatApp::bare(None);
        app.probe.instability = Some("the simulation went unstable (NaN) at 0.12 s".into());
        app.halt_if_unstable();
        assert!(app.probe.paused);
        app.forget_halt_by_lost_device();
        assert!(app.playing && !app.probe.paused);
        assert_eq!(app.probe.instability, None);

        let mut app = PleatApp::bare(None);
        app.playing = false;
        app.forget_halt_by_lost_device();
        assert!(!app.playing && app.probe.paused, "the user's pause stays");
    }
}
