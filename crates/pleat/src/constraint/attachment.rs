//! Attachment of a particle to a target point: `C = |x - target|`.
//!
//! With compliance zero the particle becomes kinematic (inverse mass zero)
//! and the solver moves it onto the target every substep; with a positive
//! compliance it is pulled there as a soft XPBD constraint. Targets move on
//! a [`crate::collide::Motion`] script.

use crate::collide::Motion;
use crate::solver::parallel::{Constraint, SharedPositions};
use glam::Vec3;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Attachment {
    pub particle: [u32; 1],
    /// Target at time zero; it moves with `motion`.
    pub anchor: Vec3,
    pub motion: Motion,
    pub compliance: f32,
    /// Target at the end of the current substep (set by [`Attachment::update_target`]).
    pub target: Vec3,
}

impl Attachment {
    pub fn new(particle: u32, anchor: Vec3, motion: Motion, compliance: f32) -> Self {
        Attachment {
            particle: [particle],
            anchor,
            motion,
            compliance,
            target: anchor,
        }
    }

    /// Moves the target to where the script puts it at time `t`.
    pub fn update_target(&mut self, t: f32) {
        self.target = self.motion.pose_at(t).transform_point3(self.anchor);
    }

    /// Whether the particle is held exactly (kinematic) rather than pulled.
    pub fn is_hard(&self) -> bool {
        self.compliance == 0.0
    }
}

impl Constraint for Attachment {
    fn particles(&self) -> &[u32] {
        &self.particle
    }

    fn project(&self, lambda: &mut f32, x: SharedPositions, inv_mass: &[f32], inv_dt2: f32) {
        let i = self.particle[0];
        let w = inv_mass[i as usize];
        let d = x.get(i) - self.target;
        let c = d.length();
        if w == 0.0 || c <= f32::EPSILON {
            return;
        }
        let alpha = self.compliance * inv_dt2;
        let dlambda = (-c - alpha * *lambda) / (w + alpha);
        *lambda += dlambda;
        x.add(i, d / c * (w * dlambda));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn soft_attachment_pulls_part_way() {
        let mut a = Attachment::new(0, Vec3::ZERO, Motion::default(), 1e-3);
        a.update_target(0.0);
        let mut x = vec![Vec3::new(1.0, 0.0, 0.0)];
        let mut lambda = 0.0;
        a.project(&mut lambda, SharedPositions::new(&mut x), &[1.0], 3600.0);
        assert!(x[0].x > 0.0 && x[0].x < 1.0, "{x:?}");
    }

    #[test]
    fn target_follows_motion() {
        let motion = Motion {
            linear_velocity: Vec3::new(0.0, 2.0, 0.0),
            ..Motion::default()
        };
        let mut a = Attachment::new(0, Vec3::X, motion, 0.0);
        a.update_target(0.5);
        assert!(a.target.distance(Vec3::new(1.0, 1.0, 0.0)) < 1e-6);
    }
}
