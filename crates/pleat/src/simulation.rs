//! A running simulation: the model, the world, the particles and the solver
//! that advances them, with per-stage timings and a watch for instability.

use crate::metrics::Metrics;
use crate::model::Model;
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
            stability: StabilityMonitor::default(),
            solver,
        }
    }

    /// Advances by one frame of `frame_dt` seconds.
    pub fn step(&mut self, frame_dt: f32) {
        self.solver
            .step(&mut self.particles, &self.world, frame_dt, &mut self.stages);
        self.world.time += frame_dt;
        self.stability
            .check(&self.model, &self.world, &self.particles);
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
