//! The world the cloth lives in: gravity, wind, colliders and the clock.

use crate::collide::Collider;
use crate::force::Wind;
use glam::Vec3;

/// The world the cloth lives in: gravity, wind, colliders and the clock.
#[derive(Clone, Debug)]
pub struct World {
    /// Gravitational acceleration (m/s^2).
    pub gravity: Vec3,
    /// Wind on the cloth; `None` for still air.
    pub wind: Option<Wind>,
    /// The rigid obstacles: static, kinematic or dynamic.
    pub colliders: Vec<Collider>,
    /// Simulated time at the start of the next step (s).
    pub time: f32,
}

impl Default for World {
    fn default() -> Self {
        World {
            gravity: Vec3::new(0.0, -9.81, 0.0),
            wind: None,
            colliders: Vec::new(),
            time: 0.0,
        }
    }
}

impl World {
    /// Whether every dynamic body's state is finite.
    pub fn bodies_are_finite(&self) -> bool {
        self.colliders
            .iter()
            .filter_map(|c| c.body.as_ref())
            .all(|b| b.is_finite())
    }

    /// Total mass of the dynamic bodies (kg).
    pub fn body_mass(&self) -> f32 {
        self.colliders
            .iter()
            .filter_map(|c| c.body.as_ref())
            .map(|b| b.mass)
            .sum()
    }
}
