//! pleat: cloth and origami simulation.
//!
//! The core holds everything that does not need a GPU or a window: meshes and
//! their topology ([`mesh`]), materials, constraints with their projections
//! ([`constraint`]), the solvers ([`solver`]), forces ([`force`]), collisions
//! ([`collide`]), origami crease patterns ([`origami`], formats only), paper
//! as a part of the model ([`paper`]) and the wiring of a fold
//! ([`folding`]), the per-frame inputs of a step ([`control`]), scene files
//! ([`scene`]), quality metrics ([`metrics`]), instability detection
//! ([`stability`]), the small linear algebra glam lacks ([`math`]) and mesh
//! export ([`export`]).

#![warn(missing_docs)]

pub mod backend;
pub mod collide;
pub mod constraint;
pub mod control;
pub mod export;
pub mod folding;
pub mod force;
pub mod material;
pub mod math;
pub mod mesh;
pub mod metrics;
pub mod model;
pub mod origami;
pub mod paper;
pub mod particles;
pub mod scene;
pub mod simulation;
pub mod solver;
pub mod stability;
#[cfg(test)]
mod test_rng;
pub mod world;

pub use backend::{Backend, CpuBackend};
pub use glam;
pub use material::Material;
pub use model::Model;
pub use particles::Particles;
pub use simulation::Simulation;
pub use solver::{SolverKind, SolverSettings};
pub use world::World;
