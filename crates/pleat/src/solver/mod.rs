//! Solvers: each advances the particles by one frame behind the same
//! [`Solver`] interface, so scenes choose one by name.

pub mod coloring;
pub mod parallel;
pub mod xpbd;

pub use xpbd::Xpbd;

use crate::collide::SelfCollision;
use crate::model::Model;
use crate::particles::Particles;
use crate::world::World;
use serde::{Deserialize, Serialize};
use std::time::{Duration, Instant};

/// Which algorithm steps the cloth.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SolverKind {
    /// Extended position-based dynamics with small steps.
    #[default]
    Xpbd,
}

/// Settings shared by the solvers.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct SolverSettings {
    pub kind: SolverKind,
    /// Substeps per frame.
    pub substeps: u32,
    /// Constraint iterations per substep.
    pub iterations: u32,
    /// Velocity damping rate (1/s): velocities lose `damping * dt` of themselves each substep.
    pub damping: f32,
    /// Self-collision and cloth-cloth contact between all cloths.
    pub self_collision: SelfCollision,
}

impl Default for SolverSettings {
    fn default() -> Self {
        SolverSettings {
            kind: SolverKind::Xpbd,
            substeps: 10,
            iterations: 1,
            damping: 0.1,
            self_collision: SelfCollision::default(),
        }
    }
}

/// Wall-clock time spent per stage of the step, summed over steps.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StageTimes {
    pub forces: Duration,
    pub predict: Duration,
    pub constraints: Duration,
    pub collisions: Duration,
    /// Particle-collider contacts found, summed over substeps.
    pub contacts: u64,
    /// Self-collision and cloth-cloth contacts (broad and narrow phase).
    pub self_collision: Duration,
    /// Self-contacts that acted, summed over substeps.
    pub self_contacts: u64,
}

impl StageTimes {
    /// Runs `f` and adds its duration to `stage`.
    pub fn time<R>(stage: &mut Duration, f: impl FnOnce() -> R) -> R {
        let start = Instant::now();
        let r = f();
        *stage += start.elapsed();
        r
    }
}

/// One algorithm that advances cloth in time.
pub trait Solver: Send {
    fn kind(&self) -> SolverKind;

    /// Number of constraints (or springs) the solver projects per iteration.
    fn constraint_count(&self) -> usize;

    /// Advances `particles` by `frame_dt` in `world`, starting at `world.time`.
    fn step(
        &mut self,
        particles: &mut Particles,
        world: &World,
        frame_dt: f32,
        stages: &mut StageTimes,
    );
}

/// Builds the solver that `settings` name for `model`.
pub fn build(model: &Model, settings: &SolverSettings) -> Box<dyn Solver> {
    match settings.kind {
        SolverKind::Xpbd => Box::new(Xpbd::new(model, settings)),
    }
}
