//! A running simulation: the model, the world, the particles and the solver
//! that advances them, with per-stage timings and a watch for instability.

use crate::metrics::Metrics;
use crate::model::Model;
use crate::origami::FoldRamp;
use crate::particles::Particles;
use crate::solver::{self, Solver, SolverSettings, StageTimes};
use crate::stability::StabilityMonitor;
use crate::world::World;

pub struct Simulation {
    pub model: Model,
    pub world: World,
    pub particles: Particles,
    pub settings: SolverSettings,
    pub stages: StageTimes,
    /// Fold progress animated over the first frames (origami); `None`
    /// leaves it where [`Simulation::set_fold_progress`] put it.
    pub fold_ramp: Option<FoldRamp>,
    fold_progress: f32,
    frames_stepped: u32,
    /// Set when the solver first produces NaN/inf or runaway stretch.
    pub stability: StabilityMonitor,
    solver: Box<dyn Solver>,
}

impl Simulation {
    pub fn new(model: Model, world: World, settings: SolverSettings) -> Self {
        let solver = solver::build(&model, &settings);
        let particles = Particles::new(model.rest.clone(), &model.mass);
        Simulation {
            model,
            world,
            particles,
            settings,
            stages: StageTimes::default(),
            fold_ramp: None,
            fold_progress: 0.0,
            frames_stepped: 0,
            stability: StabilityMonitor::default(),
            solver,
        }
    }

    /// Advances by one frame of `frame_dt` seconds.
    pub fn step(&mut self, frame_dt: f32) {
        if let Some(ramp) = self.fold_ramp {
            self.set_fold_progress(ramp.at(self.frames_stepped + 1));
        }
        self.solver.step(
            &mut self.particles,
            &mut self.world,
            frame_dt,
            &mut self.stages,
        );
        self.world.time += frame_dt;
        self.frames_stepped += 1;
        self.stability
            .check(&self.model, &self.world, &self.particles);
    }

    /// Sets the fold progress `c` (clamped to `[0, 1]`): every origami
    /// hinge is driven to `c` times its full fold angle, without rebuilding.
    pub fn set_fold_progress(&mut self, c: f32) {
        self.fold_progress = if c.is_nan() { 0.0 } else { c.clamp(0.0, 1.0) };
        self.solver.set_fold_progress(self.fold_progress);
    }

    /// The fold progress last set.
    pub fn fold_progress(&self) -> f32 {
        self.fold_progress
    }

    pub fn constraint_count(&self) -> usize {
        self.solver.constraint_count()
    }

    /// Quality figures of the current state.
    pub fn metrics(&self) -> Metrics {
        let mut m = Metrics::measure(&self.model, &self.world, &self.particles);
        m.unstable |= self.stability.is_unstable();
        m
    }
}
