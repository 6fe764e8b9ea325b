//! The running simulation behind the app: a scene, the files it reads, the
//! simulation on the CPU or the GPU backend, the fold's progress, and the
//! changes that wait until the GPU's state has come back (in a browser the
//! state can only be read between frames, so nothing here ever blocks).

use pleat::scene::{InMemory, Scene, SceneErrors};
use pleat::Simulation;
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
        let mut sim = scene.build_with(&files, &file)?;
        let (fold_target, fold_speed) = match sim.fold_ramp.take() {
            Some(ramp) => (
                ramp.progress,
                ramp.progress / ramp.frames.max(1) as f32 * scene.fps,
            ),
            None => (0.0, 0.0),
        };
        let mut session = Session {
            scene,
            file,
            files,
            sim,
            backend: BackendChoice::Cpu,
            notice: None,
            fold_target,
            fold_speed,
            pending: None,
            gpu,
        };
        session.move_to(backend);
        Ok(session)
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
        let mut sim = self.scene.build_with(&self.files, &self.file)?;
        sim.fold_ramp = None;
        if sim.particles.len() == self.sim.particles.len() {
            sim.particles = self.sim.particles.clone();
            sim.world.time = self.sim.world.time;
            sim.set_fold_progress(self.sim.fold_progress());
            sim.upload();
        }
        self.sim = sim;
        let choice = self.backend;
        self.backend = BackendChoice::Cpu;
        self.move_to(choice);
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
                let Some(context) = &self.gpu else {
                    self.notice = Some(
                        "this adapter has no compute shaders (WebGL?): running on the CPU".into(),
                    );
                    return;
                };
                let sim = &self.sim;
                match GpuBackend::new(context, &sim.model, &sim.world, &sim.settings) {
                    Ok((gpu, notes)) => {
                        self.sim.replace_backend(Box::new(gpu));
                        self.backend = BackendChoice::Gpu;
                        self.notice = (!notes.is_empty()).then(|| notes.join("; "));
                    }
                    Err(e) => self.notice = Some(format!("GPU backend refused: {e}; on the CPU")),
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::demos::{shipped_files, Demo};

    fn session(id: &str) -> Session {
        let (scene, file) = Demo::find(id).unwrap().scene().unwrap();
        Session::new(scene, file, shipped_files(), BackendChoice::Cpu, None).unwrap()
    }

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
