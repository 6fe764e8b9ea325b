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
//!
//! A cloth built in code, dropped onto a sphere and stepped on the CPU:
//!
//! ```
//! use pleat::collide::{Collider, Friction, Motion, Shape};
//! use pleat::glam::Vec3;
//! use pleat::mesh::GridSpec;
//! use pleat::{Material, Model, Simulation, SolverSettings, World};
//!
//! // A 1 m square of 16 x 16 vertices, 0.5 m above a sphere of radius 0.3 m.
//! let mut model = Model::default();
//! let grid = GridSpec {
//!     center: Vec3::new(0.0, 0.5, 0.0),
//!     ..GridSpec::new(16, 16, [1.0, 1.0])
//! };
//! model.add_cloth("cloth", grid.build(), Material::default(), &[], false);
//! let sphere = Shape::Sphere { center: Vec3::ZERO, radius: 0.3 };
//! let world = World {
//!     colliders: vec![Collider::scripted(sphere, Motion::default(), Friction::default())],
//!     ..World::default()
//! };
//! let mut sim = Simulation::new(model, world, SolverSettings::default());
//! for _ in 0..30 {
//!     sim.step(1.0 / 60.0);
//! }
//! let x = &sim.sync().x;
//! // The cloth fell and lies on the sphere (the sphere's top is at 0.3 m).
//! let top = x.iter().map(|p| p.y).fold(f32::MIN, f32::max);
//! assert!(top < 0.5 && top > 0.29, "{top}");
//! let metrics = sim.metrics();
//! assert!(!metrics.nan && metrics.max_stretch < 1.1);
//! ```

#![warn(missing_docs)]

pub mod backend;
pub mod collide;
pub mod constraint;
pub mod control;
pub mod export;
pub mod fold_steps;
pub mod folding;
pub mod force;
pub mod material;
pub mod math;
pub mod mesh;
pub mod metrics;
pub mod model;
pub mod motion;
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
pub use simulation::{Simulation, GRAB_SPEED};
pub use solver::{SolverKind, SolverSettings};
pub use world::World;
