//! External forces on the cloth: aerodynamic wind with turbulence. Gravity is
//! a constant acceleration applied by the solvers' prediction step.

pub mod noise;
pub mod wind;

pub use wind::{Wind, WindForces};
