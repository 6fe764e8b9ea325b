//! The running simulation behind the app: a scene, the files it reads, the
//! simulation on the CPU or the GPU backend, the fold's progress, and the
//! changes that wait until the GPU's state has come back (in a browser the
//! state can only be read between frames, so nothing here ever blocks).

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
    pending: Option<Pending>,
    gpu: Option<GpuContext>,
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
            pending: None,
            gpu,
        })
    }

    /// Whether the model is paper (a crease pattern) that folds.
    pub fn is_paper(&self) -> bool {
        self.sim.model.cloths.iter().any(|c| c.paper.is_some())
    }

    /// Asks for `change` once the state is on the CPU.
    pub fn request(&mut self, change: Pending) {
        self.pending = Some(change);
    }

    /// Whether a change waits for the state.
    pub fn is_pending(&self) -> bool {
        self.pending.is_some()
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
    /// and then makes the change that waited for it. Says whether the
    /// model was rebuilt, or why the change failed.
    pub fn poll(&mut self) -> Result<bool, String> {
        self.sim.request_sync();
        if !self.sim.try_sync() {
            return Ok(false);
        }
        match self.pending.take() {
            None => Ok(false),
            Some(Pending::Backend(choice)) => {
                self.move_to(choice);
                Ok(false)
            }
            Some(Pending::Rebuild) => self.rebuild().map(|()| true).map_err(|e| e.to_string()),
        }
    }

    /// Rebuilds from the edited scene, keeping the state (same particles).
    fn rebuild(&mut self) -> Result<(), SceneErrors> {
        let (mut sim, used, notice) = build(
            &self.scene,
            &self.files,
            &self.file,
            self.backend,
            self.gpu.as_ref(),
        )?;
        sim.fold_ramp = None;
        if sim.particles.len() == self.sim.particles.len() {
            // The state goes on; masses are the rebuilt model's.
            let (new, old) = (&mut sim.particles, &self.sim.particles);
            new.x.clone_from(&old.x);
            new.x_prev.clone_from(&old.x_prev);
            new.v.clone_from(&old.v);
            sim.world.time = self.sim.world.time;
            sim.grab(self.sim.grabbed());
            for (new, old) in sim
                .world
                .colliders
                .iter_mut()
                .zip(&self.sim.world.colliders)
            {
                new.body.clone_from(&old.body);
            }
            sim.set_fold_progress(self.sim.fold_progress());
            sim.upload();
        }
        self.sim = sim;
        self.backend = used;
        self.notice = notice;
        Ok(())
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
/// a notice for the panel.
fn build(
    scene: &Scene,
    files: &InMemory,
    file: &str,
    choice: BackendChoice,
    gpu: Option<&GpuContext>,
) -> Result<(Simulation, BackendChoice, Option<String>), SceneErrors> {
    let (model, world) = scene.model_with(files, file)?;
    let gpu = match choice {
        BackendChoice::Cpu => Err(None),
        BackendChoice::Gpu => gpu_backend(gpu, &model, &world, &scene.solver).map_err(Some),
    };
    Ok(match gpu {
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
    })
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
    fn without_a_gpu_the_gpu_backend_is_refused_with_a_notice() {
        let mut s = session("wind");
        s.request(Pending::Backend(BackendChoice::Gpu));
        s.poll().unwrap();
        assert_eq!(s.backend, BackendChoice::Cpu);
        assert!(s.notice.as_deref().unwrap().contains("CPU"));
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
