//! A small deterministic random generator (xorshift) for tests, so that
//! they need no crate and give the same numbers everywhere.

use glam::Vec3;

pub(crate) struct Rng(pub u64);

impl Rng {
    /// A number in [0, 1).
    pub fn unit(&mut self) -> f32 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 40) as f32 / (1u64 << 24) as f32
    }

    /// A point in the unit cube.
    pub fn point(&mut self) -> [f32; 3] {
        [self.unit(), self.unit(), self.unit()]
    }

    pub fn vec3(&mut self) -> Vec3 {
        Vec3::from(self.point())
    }
}
