//! pleat: cloth and origami simulation.
//!
//! The core holds everything that does not need a GPU or a window: meshes and
//! their topology, constraints with their projections, the solvers, forces,
//! collisions, origami crease patterns, scene files and quality metrics.

pub mod export;
pub mod metrics;
pub mod origami;
