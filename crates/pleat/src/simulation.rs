//! A running simulation: the model, the world, the particles and the
//! backend that advances them, with per-stage timings and a watch for
//! instability.

use crate::backend::{Backend, CpuBackend};
use crate::constraint::{Compliances, FoldDrive, Grab};
use crate::control::Control;
use crate::fold_steps::{FoldSteps, HingeTargets};
use crate::metrics::Metrics;
use crate::model::Model;
use crate::paper::FoldRamp;
use crate::particles::Particles;
use crate::solver::{SolverKind, SolverSettings, StageTimes};
use crate::stability::{StabilityMonitor, Tearing};
use crate::world::World;
use glam::Vec3;

/// The fastest a grab's target moves (m/s), a quick hand's; with
/// self-collision, it also moves at most half the contact thickness a
/// substep, so that the contacts catch every layer it drags the cloth past.
/// A cursor that jumps (a slow frame, a flick) is followed over the frames
/// this takes: reached within one frame, a 0.5 m jump flung the drape
/// demo's inextensible cloth through itself (13,000 crossing triangle pairs,
/// and 10 GB of contact candidates); at a thickness a substep, it still
/// crossed where the lifted cloth came to rest.
pub const GRAB_SPEED: f32 = 5.0;

/// A running simulation: the model, the world, the particles and the backend
/// that advances them.
pub struct Simulation {
    /// The cloths: rest shapes, masses, topology, materials and pins.
    pub model: Model,
    /// Gravity, wind and colliders: read at every step.
    pub world: World,
    /// The state. With a backend that does not step in place (the GPU),
    /// current only after [`Simulation::sync`].
    pub particles: Particles,
    /// Read at every step: substeps, iterations and damping change live.
    pub settings: SolverSettings,
    /// Read at every step: each cloth's compliances (stretch, shear,
    /// bending, creases, facets) change live, keeping the state.
    pub compliances: Compliances,
    /// Wall-clock time per stage of the steps so far.
    pub stages: StageTimes,
    /// Fold progress animated over the first frames (origami); `None`
    /// leaves it where [`Simulation::set_fold_progress`] put it.
    pub fold_ramp: Option<FoldRamp>,
    /// A fold in steps ([`crate::fold_steps`]): when set, it drives the
    /// progress instead of [`Simulation::fold_ramp`], step after step.
    pub fold_steps: Option<FoldSteps>,
    /// The step of [`Simulation::fold_steps`] last handed to the backend,
    /// and its hinges' start and end angles.
    fold_step: Option<(usize, HingeTargets)>,
    fold_progress: f32,
    /// The fold progress of the last frame stepped (0, the flat sheet,
    /// before the first).
    stepped_progress: f32,
    frames_stepped: u32,
    /// The particle a person drags ([`Simulation::grab`]).
    grab: Option<Grab>,
    /// The grab of the last frame stepped, where its target moves on from.
    stepped_grab: Option<Grab>,
    /// Set when the solver first produces NaN/inf or runaway stretch.
    pub stability: StabilityMonitor,
    backend: Box<dyn Backend>,
    /// Whether `particles` holds the backend's current state.
    synced: bool,
}

impl Simulation {
    /// A simulation at rest on the CPU backend.
    pub fn new(model: Model, world: World, settings: SolverSettings) -> Self {
        let backend = Box::new(CpuBackend::new(&model, &settings));
        Self::with_backend(model, world, settings, backend)
    }

    /// A simulation at rest on the given backend (built for `model`).
    pub fn with_backend(
        model: Model,
        world: World,
        settings: SolverSettings,
        backend: Box<dyn Backend>,
    ) -> Self {
        let particles = Particles::new(model.rest.clone(), &model.mass);
        let compliances = Compliances::of(&model);
        let mut sim = Simulation {
            compliances,
            model,
            world,
            particles,
            settings,
            stages: StageTimes::default(),
            fold_ramp: None,
            fold_steps: None,
            fold_step: None,
            fold_progress: 0.0,
            stepped_progress: 0.0,
            frames_stepped: 0,
            grab: None,
            stepped_grab: None,
            stability: StabilityMonitor::default(),
            backend,
            synced: true,
        };
        sim.backend.upload(&sim.particles);
        sim
    }

    /// Moves the simulation onto another backend (built for this model),
    /// keeping its state, clock and fold progress.
    pub fn replace_backend(&mut self, backend: Box<dyn Backend>) {
        self.sync();
        self.backend = backend;
        self.backend.upload(&self.particles);
        if let Some((_, targets)) = &self.fold_step {
            self.backend.set_hinge_targets(targets);
        }
    }

    /// Rebuilds the CPU solver that [`Simulation::settings`] name (after a
    /// change of solver kind or of self-collision settings), keeping the state.
    pub fn rebuild_cpu(&mut self) {
        let backend = Box::new(CpuBackend::new(&self.model, &self.settings));
        self.replace_backend(backend);
    }

    /// The backend stepping the simulation.
    pub fn backend(&self) -> &dyn Backend {
        self.backend.as_ref()
    }

    /// `"cpu"` or `"gpu"`.
    pub fn backend_name(&self) -> &'static str {
        self.backend.name()
    }

    /// The device stepping the simulation (a GPU adapter's name).
    pub fn device(&self) -> String {
        self.backend.device()
    }

    /// Brings [`Simulation::particles`] up to date with the backend (a
    /// blocking read from a GPU) and checks the state for instability.
    pub fn sync(&mut self) -> &Particles {
        if !self.synced {
            self.backend.download(&mut self.particles);
            self.synced = true;
            self.check_stability();
        }
        &self.particles
    }

    /// Asks the backend for its state without waiting (the browser's way);
    /// [`Simulation::try_sync`] takes it when it has arrived.
    pub fn request_sync(&mut self) {
        if !self.synced {
            self.backend.request_download();
        }
    }

    /// Takes the state asked for by [`Simulation::request_sync`] if it has
    /// arrived (the state as it was when asked for) and checks it for
    /// instability; says whether [`Simulation::particles`] is now current.
    pub fn try_sync(&mut self) -> bool {
        self.observe_health();
        if !self.synced && self.backend.try_download(&mut self.particles) {
            self.synced = true;
            self.check_stability();
        }
        self.synced
    }

    /// Waits until the steps handed to the backend have run (GPU timing).
    pub fn finish(&mut self) {
        self.backend.finish(&mut self.stages);
        self.observe_health();
    }

    /// Checks the health summary the backend measured on its device, if
    /// one has arrived (a GPU backend's state is otherwise checked only
    /// when read back).
    fn observe_health(&mut self) {
        if let Some(health) = self.backend.health() {
            self.stability.observe(&self.model, &self.world, &health);
        }
    }

    /// Hands edited [`Simulation::particles`] back to the backend.
    pub fn upload(&mut self) {
        self.backend.upload(&self.particles);
        self.synced = true;
    }

    /// Drags `particle` towards `target` from the next step on (compliance
    /// zero puts it there), or lets go with `None`. Indices past the last
    /// particle are ignored.
    pub fn grab(&mut self, grab: Option<Grab>) {
        self.grab = grab.filter(|g| (g.particle as usize) < self.particles.len());
    }

    /// The grabbed particle and its target, if any.
    pub fn grabbed(&self) -> Option<Grab> {
        self.grab
    }

    /// The grab of a frame of `frame_dt`, and where its target starts: from
    /// where the last frame left it (on a new grab, from the particle),
    /// towards the grab's target as fast as [`GRAB_SPEED`] allows.
    fn grab_this_frame(&self, frame_dt: f32) -> Option<(Grab, Vec3)> {
        let grab = self.grab?;
        let from = match self.stepped_grab {
            Some(was) if was.particle == grab.particle => was.target,
            _ => self.particles.x[grab.particle as usize],
        };
        let contacts = &self.settings.self_collision;
        let mut reach = GRAB_SPEED * frame_dt;
        if contacts.enabled {
            reach = reach.min(0.5 * contacts.thickness * self.settings.substeps.max(1) as f32);
        }
        let target = from + (grab.target - from).clamp_length_max(reach);
        Some((Grab { target, ..grab }, from))
    }

    /// Advances by one frame of `frame_dt` seconds.
    pub fn step(&mut self, frame_dt: f32) {
        let mut new_step = false;
        if let Some(steps) = &self.fold_steps {
            let (step, progress) = steps.at(self.frames_stepped + 1);
            if self.fold_step.as_ref().map(|s| s.0) != Some(step) {
                let targets = steps.targets(&self.model, step);
                self.backend.set_hinge_targets(&targets);
                self.fold_step = Some((step, targets));
                new_step = true;
            }
            self.set_fold_progress(progress);
        } else if let Some(ramp) = self.fold_ramp {
            self.set_fold_progress(ramp.at(self.frames_stepped + 1));
        }
        let grab = self.grab_this_frame(frame_dt);
        let control = Control {
            frame_dt,
            fold: FoldDrive {
                progress: self.fold_progress,
                held: !new_step && self.stepped_progress == self.fold_progress,
                flat: self.settings.self_collision.enabled,
            },
            grab: grab.map(|(g, _)| g),
            grab_from: grab.map(|(_, from)| from),
        };
        self.stepped_progress = self.fold_progress;
        self.stepped_grab = control.grab;
        self.backend.step(
            &mut self.particles,
            &mut self.world,
            &self.settings,
            &self.compliances,
            &control,
            &mut self.stages,
        );
        self.world.time += frame_dt;
        self.frames_stepped += 1;
        if self.backend.steps_in_place() {
            self.check_stability();
        } else {
            self.synced = false;
            self.observe_health();
        }
    }

    /// Sets the fold progress `c` (clamped to `[0, 1]`): every origami
    /// hinge is driven to `c` times its full fold angle, without rebuilding.
    pub fn set_fold_progress(&mut self, c: f32) {
        self.fold_progress = if c.is_nan() { 0.0 } else { c.clamp(0.0, 1.0) };
    }

    /// The fold progress last set (within the current step of a fold in
    /// steps).
    pub fn fold_progress(&self) -> f32 {
        self.fold_progress
    }

    /// The step of [`Simulation::fold_steps`] now folding (counted from 0)
    /// and its hinges' start and end angles; `None` before the first frame
    /// or without steps.
    pub fn fold_step(&self) -> Option<(usize, &HingeTargets)> {
        self.fold_step.as_ref().map(|(k, t)| (*k, t))
    }

    /// Number of constraints (or springs) the backend projects per iteration.
    pub fn constraint_count(&self) -> usize {
        self.backend.constraint_count()
    }

    /// Quality figures of the state last synced ([`Simulation::sync`]).
    pub fn metrics(&self) -> Metrics {
        let mut m = Metrics::measure(&self.model, &self.world, &self.particles);
        m.unstable |= self.stability.verdict().is_some();
        m
    }

    /// Checks the state in `particles` for an instability. The edges that
    /// count as torn are cloths' too where the XPBD solver holds their
    /// stretch by their live compliances.
    fn check_stability(&mut self) {
        let tearing = Tearing {
            cloth: (self.settings.kind == SolverKind::Xpbd).then_some(&self.compliances),
        };
        self.stability
            .check(&self.model, &self.world, &self.particles, tearing);
    }
}
