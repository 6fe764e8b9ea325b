//! The running simulation behind the app: a scene, the files it reads, the
//! simulation on the CPU or the GPU backend, the fold's progress, and the
//! changes that wait until the GPU's state has come back (in a browser the
//! state can only be read between frames, so nothing here ever blocks).
//! The state last read back from the GPU is kept: when the device is lost,
//! the simulation is built again on a new one and goes on from there
//! ([`Session::recover`]).

use glam::Vec3;
use pleat::collide::RigidBody;
use pleat::constraint::Grab;
use pleat::scene::{InMemory, Scene, SceneErrors};
use pleat::{Backend, CpuBackend, Model, Simulation, SolverSettings, World};
use pleat_gpu::{GpuBackend, GpuContext};

/// Which backend steps the simulation.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BackendChoice {
    /// The CPU backend (rayon).
    Cpu,
    /// The GPU backend (wgpu compute, on the app's own device).
    Gpu,
}

impl BackendChoice {
    /// Both, in the panel's order.
    pub const ALL: [BackendChoice; 2] = [BackendChoice::Cpu, BackendChoice::Gpu];

    /// Its name on the panel.
    pub fn name(self) -> &'static str {
        match self {
            BackendChoice::Cpu => "CPU",
            BackendChoice::Gpu => "GPU",
        }
    }

    /// The other backend.
    pub fn other(self) -> BackendChoice {
        match self {
            BackendChoice::Cpu => BackendChoice::Gpu,
            BackendChoice::Gpu => BackendChoice::Cpu,
        }
    }
}

/// A change that needs the state on the CPU first.
#[derive(Clone, Debug)]
pub enum Pending {
    /// Rebuild from the (edited) scene, keeping positions and velocities.
    Rebuild,
    /// Move to the other backend.
    Backend(BackendChoice),
}

/// The simulation and what it was built from.
pub struct Session {
    /// The scene as edited on the panels.
    pub scene: Scene,
    /// Its file name, for errors.
    pub file: String,
    /// Files the scene may name (shipped and dropped).
    pub files: InMemory,
    pub sim: Simulation,
    /// The backend asked for; the simulation may still be on the CPU
    /// (see [`Session::notice`]).
    pub backend: BackendChoice,
    /// Why the GPU backend is not in use, or notes from building it.
    pub notice: Option<String>,
    /// Where the fold's progress goes, and how fast (progress per second).
    pub fold_target: f32,
    pub fold_speed: f32,
    /// Changes waiting for the state: a rebuild, a move, or both (neither
    /// replaces the other).
    rebuild: bool,
    moving_to: Option<BackendChoice>,
    gpu: Option<GpuContext>,
    /// The last finite state read back from the GPU backend.
    last_read: Option<State>,
}

/// What a rebuilt simulation goes on from: the particles, the clock, the
/// grab, the dynamic colliders and the fold's progress.
#[derive(Clone, Debug)]
struct State {
    x: Vec<Vec3>,
    x_prev: Vec<Vec3>,
    v: Vec<Vec3>,
    time: f32,
    grab: Option<Grab>,
    bodies: Vec<Option<RigidBody>>,
    fold_progress: f32,
}

impl State {
    /// The state `sim` holds on the CPU (as last synced).
    fn of(sim: &Simulation) -> Self {
        let p = &sim.particles;
        State {
            x: p.x.clone(),
            x_prev: p.x_prev.clone(),
            v: p.v.clone(),
            time: sim.world.time,
            grab: sim.grabbed(),
            bodies: sim.world.colliders.iter().map(|c| c.body.clone()).collect(),
            fold_progress: sim.fold_progress(),
        }
    }

    /// Puts the state into `sim` (built from the same scene, or one
    /// edited on the panels) and hands it to its backend; a model with
    /// other particles starts anew.
    fn restore(&self, sim: &mut Simulation) {
        sim.fold_ramp = None;
        if sim.particles.len() != self.x.len() {
            return;
        }
        let p = &mut sim.particles;
        p.x.clone_from(&self.x);
        p.x_prev.clone_from(&self.x_prev);
        p.v.clone_from(&self.v);
        sim.world.time = self.time;
        sim.grab(self.grab);
        for (collider, body) in sim.world.colliders.iter_mut().zip(&self.bodies) {
            collider.body.clone_from(body);
        }
        sim.set_fold_progress(self.fold_progress);
        sim.upload();
    }

    fn is_finite(&self) -> bool {
        [&self.x, &self.x_prev, &self.v]
            .iter()
            .all(|v| v.iter().all(|p| p.is_finite()))
    }
}

impl Session {
    /// Builds `scene` (files from `files`) on the CPU, then moves it to the
    /// GPU when asked for and possible.
    pub fn new(
        scene: Scene,
        file: String,
        files: InMemory,
        backend: BackendChoice,
        gpu: Option<GpuContext>,
    ) -> Result<Self, SceneErrors> {
        let (mut sim, used, notice) = build(&scene, &files, &file, backend, gpu.as_ref())?;
        let (fold_target, fold_speed) = match sim.fold_ramp.take() {
            Some(ramp) => (
                ramp.progress,
                ramp.progress / ramp.frames.max(1) as f32 * scene.fps,
            ),
            None => (0.0, 0.0),
        };
        Ok(Session {
            scene,
            file,
            files,
            sim,
            backend: used,
            notice,
            fold_target,
            fold_speed,
            rebuild: false,
            moving_to: None,
            gpu,
            last_read: None,
        })
    }

    /// Whether the model is paper (a crease pattern) that folds.
    pub fn is_paper(&self) -> bool {
        self.sim.model.cloths.iter().any(|c| c.paper.is_some())
    }

    /// Asks for `change` once the state is on the CPU.
    pub fn request(&mut self, change: Pending) {
        match change {
            Pending::Rebuild => self.rebuild = true,
            Pending::Backend(choice) => self.moving_to = Some(choice),
        }
    }

    /// Whether a change waits for the state.
    pub fn is_pending(&self) -> bool {
        self.rebuild || self.moving_to.is_some()
    }

    /// Advances one frame of `dt` seconds (the fold's progress with it).
    pub fn step(&mut self, dt: f32) {
        if self.is_paper() {
            let c = self.sim.fold_progress();
            let reach = self.fold_speed * dt;
            let next = if self.fold_speed <= 0.0 {
                self.fold_target
            } else {
                c + (self.fold_target - c).clamp(-reach, reach)
            };
            if next != c {
                self.sim.set_fold_progress(next);
            }
        }
        self.sim.step(dt);
    }

    /// Asks for the state without waiting, takes it if it has come back,
    /// and then makes the changes that waited for it: the rebuild, then
    /// the move. Says whether the model was rebuilt, or why it failed.
    pub fn poll(&mut self) -> Result<bool, String> {
        self.sim.request_sync();
        if !self.sim.try_sync() {
            return Ok(false);
        }
        self.keep_state();
        let rebuilt = std::mem::take(&mut self.rebuild);
        if rebuilt {
            self.rebuild().map_err(|e| e.to_string())?;
        }
        if let Some(choice) = self.moving_to.take() {
            self.move_to(choice);
        }
        Ok(rebuilt)
    }

    /// Keeps the state just read back from the GPU (if finite: a read
    /// that failed as the device went leaves NaN).
    fn keep_state(&mut self) {
        if self.sim.backend_name() == "gpu" {
            let state = State::of(&self.sim);
            if state.is_finite() {
                self.last_read = Some(state);
            }
        }
    }

    /// Rebuilds from the edited scene, keeping the state (same particles).
    fn rebuild(&mut self) -> Result<(), SceneErrors> {
        let state = State::of(&self.sim);
        self.rebuild_from(&state)
    }

    /// Builds the simulation again (from the edited scene) and puts `state` in it.
    fn rebuild_from(&mut self, state: &State) -> Result<(), SceneErrors> {
        let (mut sim, used, notice) = build(
            &self.scene,
            &self.files,
            &self.file,
            self.backend,
            self.gpu.as_ref(),
        )?;
        state.restore(&mut sim);
        self.sim = sim;
        self.backend = used;
        self.notice = notice;
        Ok(())
    }

    /// After the device was lost: builds the simulation again on `gpu` (a
    /// new device; the CPU where there is none or it has no compute
    /// shaders) from the last state read back, never reading the lost
    /// device. A change that waited for the state is dropped. Says
    /// where the run goes on.
    pub fn recover(&mut self, gpu: Option<GpuContext>) -> Result<String, SceneErrors> {
        self.gpu = gpu;
        (self.rebuild, self.moving_to) = (false, None);
        // On the CPU the state never left it; nothing read back yet: the
        // scene's start.
        let state = match (self.backend, self.last_read.take()) {
            (BackendChoice::Gpu, Some(state)) => state,
            _ => State::of(&self.sim),
        };
        self.rebuild_from(&state)?;
        let on = match self.backend {
            BackendChoice::Gpu => "a new GPU device",
            BackendChoice::Cpu => "the CPU",
        };
        Ok(format!(
            "the simulation continues on {on} from t = {:.2} s, the state last read back",
            state.time
        ))
    }

    /// Moves the (synced) simulation to `choice`, or says why it stays on the CPU.
    fn move_to(&mut self, choice: BackendChoice) {
        self.notice = None;
        match choice {
            BackendChoice::Cpu => {
                if self.backend != BackendChoice::Cpu {
                    self.sim.rebuild_cpu();
                }
                self.backend = BackendChoice::Cpu;
            }
            BackendChoice::Gpu => {
                let sim = &self.sim;
                match gpu_backend(self.gpu.as_ref(), &sim.model, &sim.world, &sim.settings) {
                    Ok((gpu, notice)) => {
                        self.sim.replace_backend(gpu);
                        self.backend = BackendChoice::Gpu;
                        self.notice = notice;
                    }
                    Err(reason) => self.notice = Some(reason),
                }
            }
        }
    }

    /// The GPU backend's position buffer, when the simulation runs there.
    pub fn gpu_positions(&self) -> Option<&wgpu::Buffer> {
        self.sim
            .backend()
            .as_any()
            .downcast_ref::<GpuBackend>()
            .map(GpuBackend::positions)
    }
}

/// The scene's simulation on the backend `choice` (built once), or on the
/// CPU with the reason when the GPU cannot take it; the backend used and
/// a notice for the panel (after the warnings of the scene's crease
/// patterns' importers, if any).
fn build(
    scene: &Scene,
    files: &InMemory,
    file: &str,
    choice: BackendChoice,
    gpu: Option<&GpuContext>,
) -> Result<(Simulation, BackendChoice, Option<String>), SceneErrors> {
    let (model, world, warnings) = scene.model_and_warnings_with(files, file)?;
    let gpu = match choice {
        BackendChoice::Cpu => Err(None),
        BackendChoice::Gpu => gpu_backend(gpu, &model, &world, &scene.solver).map_err(Some),
    };
    let (sim, used, notice) = match gpu {
        Ok((backend, notice)) => (
            scene.simulation(model, world, backend),
            BackendChoice::Gpu,
            notice,
        ),
        Err(reason) => {
            let cpu = Box::new(CpuBackend::new(&model, &scene.solver));
            (
                scene.simulation(model, world, cpu),
                BackendChoice::Cpu,
                reason,
            )
        }
    };
    let notices: Vec<String> = warnings
        .iter()
        .map(|w| format!("warning: {w}"))
        .chain(notice)
        .collect();
    Ok((sim, used, (!notices.is_empty()).then(|| notices.join("; "))))
}

/// The GPU backend for `model`, with the notes of its building, or why
/// there is none (no compute shaders, a feature it does not have).
fn gpu_backend(
    context: Option<&GpuContext>,
    model: &Model,
    world: &World,
    settings: &SolverSettings,
) -> Result<(Box<dyn Backend>, Option<String>), String> {
    let context =
        context.ok_or(
        "this adapter has no compute shaders (WebGL?): simulating on the CPU, drawing without shadows or colliders",
    )?;
    let (gpu, notes) = GpuBackend::new(context, model, world, settings)
        .map_err(|e| format!("GPU backend refused: {e}; on the CPU"))?;
    Ok((Box::new(gpu), (!notes.is_empty()).then(|| notes.join("; "))))
}

/// The demo `id` on the CPU, for tests.
#[cfg(test)]
pub fn demo_on_cpu(id: &str) -> Session {
    use crate::demos::{shipped_files, Demo};
    let (scene, file) = Demo::find(id).unwrap().scene().unwrap();
    Session::new(scene, file, shipped_files(), BackendChoice::Cpu, None).unwrap()
}

#[cfg(test)]
mod tests {
    use super::demo_on_cpu as session;
    use super::*;

    #[test]
    fn a_rebuild_keeps_the_state() {
        let mut s = session("wind");
        for _ in 0..20 {
            s.step(1.0 / 60.0);
        }
        let before = s.sim.particles.x.clone();
        s.scene.cloths[0].material.bend_compliance *= 10.0;
        s.request(Pending::Rebuild);
        s.poll().unwrap();
        assert!(!s.is_pending());
        assert_eq!(s.sim.particles.x, before);
    }

    #[test]
    fn a_rebuild_asked_for_while_a_move_waits_makes_both() {
        // A move (refused here: no GPU) and a parameter's rebuild.
        let mut s = session("wind");
        s.request(Pending::Backend(BackendChoice::Gpu));
        s.scene.gravity = Vec3::new(0.0, 3.0, 0.0);
        s.request(Pending::Rebuild);
        assert_eq!(s.poll(), Ok(true), "rebuilt");
        assert!(!s.is_pending());
        assert_eq!(s.sim.world.gravity, Vec3::new(0.0, 3.0, 0.0));
        assert!(
            s.notice.as_deref().unwrap().contains("CPU"),
            "the move was tried"
        );
    }

    /// A crease pattern whose importer warns (a flat fold with no
    /// direction) says so on the panel.
    #[test]
    fn a_patterns_warning_is_noticed() {
        // A unit square folded flat along its diagonal, with neither a
        // label nor faceOrders to say which way.
        let fold = r#"{"frame_classes":["foldedForm"],
            "vertices_coords":[[0,0,0],[1,0,0],[0,0,0],[0,1,0]],
            "faces_vertices":[[0,1,3],[1,2,3]]}"#;
        let scene = Scene::parse(
            r#"{"name":"undirected","cloths":[{"mesh":{"pattern":{"path":"flat.fold"}}}]}"#,
            "undirected.json",
        )
        .unwrap();
        let mut files = InMemory::default();
        files.insert("flat.fold", fold.as_bytes().to_vec());
        let s = Session::new(
            scene,
            "undirected.json".into(),
            files,
            BackendChoice::Cpu,
            None,
        )
        .unwrap();
        let notice = s.notice.unwrap_or_default();
        assert!(
            notice.starts_with(
                "warning: undirected.json: cloths[0].mesh.pattern: flat.fold: 1 crease is folded flat"
            ),
            "{notice}"
        );
    }

    #[test]
    fn without_a_gpu_the_gpu_backend_is_refused_with_a_notice() {
        let mut s = session("wind");
        s.request(Pending::Backend(BackendChoice::Gpu));
        s.poll().unwrap();
        assert_eq!(s.backend, BackendChoice::Cpu);
        assert!(s.notice.as_deref().unwrap().contains("CPU"));
    }

    /// Polls until a read of the state has come back (a GPU session).
    fn read_back(s: &mut Session) {
        for _ in 0..100_000 {
            s.poll().unwrap();
            if s.sim.try_sync() {
                return;
            }
            std::thread::yield_now();
        }
        panic!("the state never came back");
    }

    #[test]
    fn a_lost_device_is_heard_and_the_run_goes_on_from_the_last_state_read_back() {
        use crate::demos::{shipped_files, Demo};
        use crate::device::DeviceWatch;
        let gpu = GpuContext::new().expect("a GPU adapter (in CI: Mesa lavapipe)");
        let watch = DeviceWatch::attach(&gpu.device);
        let (scene, file) = Demo::find("wind").unwrap().scene().unwrap();
        let mut s =
            Session::new(scene, file, shipped_files(), BackendChoice::Gpu, Some(gpu)).unwrap();
        assert_eq!(s.backend, BackendChoice::Gpu);
        for _ in 0..10 {
            s.step(1.0 / 60.0);
            read_back(&mut s);
        }
        let kept = s.sim.particles.x.clone();
        let time = s.sim.world.time;
        watch.destroy();
        // The steps and reads after the loss fail quietly (no panic).
        s.step(1.0 / 60.0);
        for _ in 0..1000 {
            let _ = s.poll();
            if watch.lost().is_some() {
                break;
            }
            std::thread::yield_now();
        }
        assert!(
            watch.lost().unwrap().starts_with("destroyed"),
            "{:?}",
            watch.lost()
        );
        let again = GpuContext::new().unwrap();
        let said = s.recover(Some(again)).unwrap();
        assert!(said.contains("a new GPU device"), "{said}");
        assert_eq!(s.backend, BackendChoice::Gpu);
        assert_eq!(s.sim.particles.x, kept);
        assert_eq!(s.sim.world.time, time);
        for _ in 0..10 {
            s.step(1.0 / 60.0);
            read_back(&mut s);
        }
        let x = &s.sim.particles.x;
        assert!(x.iter().all(|p| p.is_finite()));
        assert_ne!(*x, kept, "the run goes on");
        assert!(!s.sim.stability.is_unstable());
    }

    #[test]
    fn paper_folds_towards_the_target_at_the_set_speed() {
        let mut s = session("fold");
        assert!(s.is_paper());
        s.fold_target = 1.0;
        s.fold_speed = 0.5;
        s.step(0.1);
        assert!((s.sim.fold_progress() - 0.05).abs() < 1e-6);
        s.fold_target = 0.0;
        s.step(0.1);
        assert!(s.sim.fold_progress().abs() < 1e-6);
    }
}
