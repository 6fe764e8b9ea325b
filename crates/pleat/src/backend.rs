//! The seam between a simulation and the device that steps it.
//!
//! Scene building, constraint construction and colouring, metrics and
//! export stay in the core; a [`Backend`] owns the particle state while it
//! steps. The CPU backend ([`CpuBackend`]) steps the [`Particles`] in place
//! with any [`Solver`]; a GPU backend keeps the state in device buffers and
//! copies it back only when asked ([`Backend::download`]), since reading a
//! GPU buffer is slow and, in a browser, possible only between turns of the
//! event loop.
//!
//! Parameters a person tunes while the simulation runs (compliances,
//! damping, substeps, gravity, wind) and the frame's [`Control`] (its
//! length, the fold's drive, the grabbed particle) reach the backend at
//! every step, by reference: changing one needs no rebuild, and no backend
//! keeps a copy of its own.

use crate::constraint::Compliances;
use crate::control::Control;
use crate::model::Model;
use crate::particles::Particles;
use crate::solver::{self, Solver, SolverSettings, StageTimes};
use crate::stability::Health;
use crate::world::World;

/// `Send` where threads exist; nothing on wasm32, whose WebGPU handles
/// stay on the thread that made them.
#[cfg(not(target_arch = "wasm32"))]
pub trait MaybeSend: Send {}
#[cfg(not(target_arch = "wasm32"))]
impl<T: Send> MaybeSend for T {}
/// `Send` where threads exist; nothing on wasm32, whose WebGPU handles
/// stay on the thread that made them.
#[cfg(target_arch = "wasm32")]
pub trait MaybeSend {}
#[cfg(target_arch = "wasm32")]
impl<T> MaybeSend for T {}

/// Where a simulation's particles live while it steps.
pub trait Backend: MaybeSend {
    /// `"cpu"` or `"gpu"`: the name reports use.
    fn name(&self) -> &'static str;

    /// The device that runs the steps (a GPU adapter's name), for reports.
    fn device(&self) -> String;

    /// Number of constraints projected per iteration.
    fn constraint_count(&self) -> usize;

    /// Advances the state by `control.frame_dt` in `world` from
    /// `world.time`, with the current `settings` and `compliances`, driven
    /// by `control` (the fold's progress and whether it is held, the
    /// grabbed particle). A backend whose state lives elsewhere leaves
    /// `particles` as they were: [`Backend::download`] brings them up to
    /// date.
    fn step(
        &mut self,
        particles: &mut Particles,
        world: &mut World,
        settings: &SolverSettings,
        compliances: &Compliances,
        control: &Control,
        stages: &mut StageTimes,
    );

    /// Waits until every step handed to the device has run (for timing),
    /// adding the device's per-stage times to `stages` where it measures
    /// them; nothing to wait for on the CPU.
    fn finish(&mut self, stages: &mut StageTimes);

    /// Whether the state lives in the `particles` passed to [`Backend::step`].
    fn steps_in_place(&self) -> bool;

    /// Copies the backend's state into `particles` (positions and
    /// velocities); nothing to do for a backend that steps in place.
    fn download(&mut self, particles: &mut Particles);

    /// Starts copying the backend's state back without waiting for it
    /// (WebGPU maps buffers only between turns of the event loop); see
    /// [`Backend::try_download`].
    fn request_download(&mut self) {}

    /// Puts the state asked for by [`Backend::request_download`] into
    /// `particles` if it has arrived, and says whether it did. A backend
    /// that steps in place has it at once.
    fn try_download(&mut self, particles: &mut Particles) -> bool {
        self.download(particles);
        true
    }

    /// The latest [`Health`] summary of the state measured on the device
    /// that has arrived since the last call, without waiting; `None` from
    /// a backend that steps in place (the caller checks its particles).
    fn health(&mut self) -> Option<Health> {
        None
    }

    /// Replaces the backend's state by `particles` (after the caller edited
    /// them); nothing to do for a backend that steps in place.
    fn upload(&mut self, particles: &Particles);

    /// Compute dispatches the last frame took on a GPU; `None` on the CPU.
    fn dispatches_per_frame(&self) -> Option<u32> {
        None
    }

    /// The backend as `Any`, so that a caller that knows the concrete type
    /// (a renderer drawing from a GPU backend's buffers) can reach it.
    fn as_any(&self) -> &dyn std::any::Any;

    /// Gives the origami hinges the start and end angles of a fold's step
    /// ([`crate::fold_steps`]), keeping their tracked angles; a backend
    /// without hinges ignores it.
    fn set_hinge_targets(&mut self, _targets: &crate::fold_steps::HingeTargets) {}
}

/// The CPU backend: any solver stepping the particles in place on rayon's threads.
pub struct CpuBackend {
    solver: Box<dyn Solver>,
}

impl CpuBackend {
    /// The solver `settings` name, built for `model`.
    pub fn new(model: &Model, settings: &SolverSettings) -> Self {
        CpuBackend {
            solver: solver::build(model, settings),
        }
    }
}

impl Backend for CpuBackend {
    fn name(&self) -> &'static str {
        "cpu"
    }

    fn device(&self) -> String {
        format!("cpu, {} threads", rayon::current_num_threads())
    }

    fn constraint_count(&self) -> usize {
        self.solver.constraint_count()
    }

    fn step(
        &mut self,
        particles: &mut Particles,
        world: &mut World,
        settings: &SolverSettings,
        compliances: &Compliances,
        control: &Control,
        stages: &mut StageTimes,
    ) {
        self.solver.set_settings(settings);
        self.solver.set_compliances(compliances);
        self.solver.step(particles, world, control, stages);
    }

    fn finish(&mut self, _stages: &mut StageTimes) {}

    fn steps_in_place(&self) -> bool {
        true
    }

    fn download(&mut self, _particles: &mut Particles) {}

    fn upload(&mut self, _particles: &Particles) {}

    fn set_hinge_targets(&mut self, targets: &crate::fold_steps::HingeTargets) {
        self.solver.set_hinge_targets(targets);
    }

    fn as_any(&self) -> &dyn std::any::Any {
        self
    }
}
