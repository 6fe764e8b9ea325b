//! The world the cloth lives in: gravity, wind, colliders and the clock.

use crate::collide::Collider;
use crate::force::Wind;
use glam::Vec3;

#[derive(Clone, Debug)]
pub struct World {
    pub gravity: Vec3,
    pub wind: Option<Wind>,
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
