//! Solvers: each advances the particles by one frame behind the same
//! [`Solver`] interface, so scenes choose one by name.

pub mod collider_held;
pub mod coloring;
pub mod grab_reach;
pub mod hierarchy;
pub mod jacobi;
pub mod mass_spring;
pub mod momentum;
pub mod parallel;
pub mod position_based;
pub mod shape_matching;
pub mod springs;
pub mod xpbd;

pub use jacobi::JacobiPbd;
pub use mass_spring::MassSpring;
pub use shape_matching::PbdShapeMatching;
pub use xpbd::Xpbd;

use crate::collide::SelfCollision;
use crate::constraint::Compliances;
use crate::control::Control;
use crate::model::Model;
use crate::particles::Particles;
use crate::world::World;
use serde::{Deserialize, Serialize};
use std::time::Duration;
use web_time::Instant;

/// Which algorithm steps the cloth.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SolverKind {
    /// Extended position-based dynamics with small steps.
    #[default]
    Xpbd,
    /// Mass-spring system with damped Verlet integration.
    MassSpring,
    /// Position-based dynamics with triangle and triangle-pair shape matching.
    PbdShapeMatching,
    /// Position-based dynamics with averaged, relaxed Jacobi corrections.
    JacobiPbd,
}

impl SolverKind {
    /// Every solver, XPBD first.
    pub const ALL: [SolverKind; 4] = [
        SolverKind::Xpbd,
        SolverKind::MassSpring,
        SolverKind::PbdShapeMatching,
        SolverKind::JacobiPbd,
    ];

    /// The name scene files and reports use.
    pub fn name(self) -> &'static str {
        match self {
            SolverKind::Xpbd => "xpbd",
            SolverKind::MassSpring => "mass_spring",
            SolverKind::PbdShapeMatching => "pbd_shape_matching",
            SolverKind::JacobiPbd => "jacobi_pbd",
        }
    }
}

/// Settings shared by the solvers.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct SolverSettings {
    /// Which solver advances the cloth: `xpbd` (the default), `mass_spring`,
    /// `pbd_shape_matching` or `jacobi_pbd`.
    pub kind: SolverKind,
    /// Substeps per frame.
    pub substeps: u32,
    /// Constraint iterations per substep.
    pub iterations: u32,
    /// Velocity damping rate (1/s): velocities lose `damping * dt` of themselves each substep
    /// (the position-based solvers).
    pub damping: f32,
    /// Mass-spring only: percent of the velocity removed each Verlet step, as
    /// in the classic course cloth (`x += (x - x_prev) * (1 - global_damping / 100)`).
    pub global_damping: f32,
    /// Jacobi PBD only: relaxation factor omega in (0, 2] applied to the averaged corrections.
    pub relaxation: f32,
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
            global_damping: 1.0,
            relaxation: 1.5,
            self_collision: SelfCollision::default(),
        }
    }
}

/// Wall-clock time spent per stage of the step, summed over steps.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StageTimes {
    /// External forces: the wind.
    pub forces: Duration,
    /// Prediction of positions, hard pins placed on their targets, and
    /// velocities from positions.
    pub predict: Duration,
    /// The solver's constraint (or spring) projections.
    pub constraints: Duration,
    /// Collider contacts, rigid bodies included.
    pub collisions: Duration,
    /// Particle-collider contacts found, summed over substeps.
    pub contacts: u64,
    /// Self-collision and cloth-cloth contacts (broad and narrow phase).
    pub self_collision: Duration,
    /// Self-contacts that acted, summed over substeps.
    pub self_contacts: u64,
    /// Self-contact candidates from the broad phase, summed over substeps.
    pub self_contact_candidates: u64,
    /// Builds of the self-contact candidates (one a substep where the
    /// backend does not keep them), summed over frames.
    pub self_contact_builds: u64,
    /// Compute dispatches recorded, summed over frames (a GPU backend's).
    pub dispatches: u64,
    /// The parts of `self_collision`, where the backend measures them: its
    /// broad phase (candidate search), its narrow phase (detection and
    /// corrections of the candidates) and its solve (the corrections
    /// applied).
    pub self_broad_phase: Duration,
    /// See `self_broad_phase`.
    pub self_narrow_phase: Duration,
    /// See `self_broad_phase`.
    pub self_solve: Duration,
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

/// Each of the `substeps` equal substeps (one at least) of the frame that
/// `control` drives from time `start`: its start time and length, and its
/// own control ([`Control::at_substep`]: the grab's target part way).
pub fn substep_times(
    start: f32,
    control: &Control,
    substeps: u32,
) -> impl Iterator<Item = (f32, f32, Control)> + '_ {
    let n = substeps.max(1);
    let dt = control.frame_dt / n as f32;
    (0..n).map(move |s| (start + s as f32 * dt, dt, control.at_substep(s, n)))
}

/// One algorithm that advances cloth in time.
pub trait Solver: Send {
    /// Which solver this is.
    fn kind(&self) -> SolverKind;

    /// Number of constraints (or springs) the solver projects per iteration.
    fn constraint_count(&self) -> usize;

    /// Takes the settings a person changed while the simulation runs
    /// (substeps, iterations, damping, relaxation) for the next step;
    /// self-collision settings need a rebuild.
    fn set_settings(&mut self, settings: &SolverSettings);

    /// Advances `particles` by `control.frame_dt` in `world`, starting at
    /// `world.time`, driven by `control` (the fold, the grab).
    fn step(
        &mut self,
        particles: &mut Particles,
        world: &mut World,
        control: &Control,
        stages: &mut StageTimes,
    );

    /// Takes the live compliance table for the next step; solvers without
    /// compliances ignore it.
    fn set_compliances(&mut self, _compliances: &Compliances) {}

    /// Gives the origami hinges the start and end angles of a fold's step
    /// ([`crate::fold_steps`]); solvers without hinges ignore it.
    fn set_hinge_targets(&mut self, _targets: &crate::fold_steps::HingeTargets) {}
}

/// Builds the solver that `settings` name for `model`.
pub fn build(model: &Model, settings: &SolverSettings) -> Box<dyn Solver> {
    match settings.kind {
        SolverKind::Xpbd => Box::new(Xpbd::new(model, settings)),
        SolverKind::MassSpring => Box::new(MassSpring::new(model, settings)),
        SolverKind::PbdShapeMatching => Box::new(PbdShapeMatching::new(model, settings)),
        SolverKind::JacobiPbd => Box::new(JacobiPbd::new(model, settings)),
    }
}
