//! Forces on the cloth: aerodynamic wind with turbulence, and the damped
//! springs of the mass-spring solver. Gravity is a constant acceleration
//! applied by the solvers' prediction step.

pub mod noise;
pub mod spring;
pub mod wind;

pub use spring::Spring;
pub use wind::{Wind, WindForces};
