//! Attachment of a particle to a target point: `C = |x - target|`.
//!
//! With compliance zero the particle becomes kinematic (inverse mass zero)
//! and the solver moves it onto the target every substep; with a positive
//! compliance it is pulled there as a soft XPBD constraint. Targets move on
//! a [`crate::motion::Motion`] script.

use super::positions::Positions;
use super::projection::{sealed::Sealed, Constraint, Substep};
use super::xpbd::{lagrange_update, position_step};
use crate::motion::Motion;
use glam::Vec3;

/// A particle attached to a scripted target (a pin), hard or soft.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Attachment {
    /// The attached particle.
    pub particle: [u32; 1],
    /// Target at time zero; it moves with `motion`.
    pub anchor: Vec3,
    /// Script that moves the target from `anchor`.
    pub motion: Motion,
    /// Inverse stiffness (m/N); zero holds the particle on the target exactly.
    pub compliance: f32,
    /// Target at the end of the current substep (set by [`Attachment::update_target`]).
    pub target: Vec3,
}

impl Attachment {
    /// An attachment of `particle` to `anchor`, moved by `motion`, with
    /// `compliance` (m/N).
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

impl Sealed for Attachment {}

impl Constraint for Attachment {
    fn particles(&self) -> &[u32] {
        &self.particle
    }

    fn project(&self, lambda: &mut f32, x: &Positions, step: &Substep) {
        let i = self.particle[0];
        let w = x.inv_mass(i);
        let d = x.get(i) - self.target;
        let c = d.length();
        if w == 0.0 || c <= f32::EPSILON {
            return;
        }
        // An attachment's compliance is its own, not a live table's.
        let alpha = self.compliance * step.inv_dt2;
        if let Some(dlambda) = lagrange_update(c, w, alpha, lambda) {
            position_step(x, i, w, d / c, dlambda);
        }
    }
}

/// A particle dragged towards a target that the caller moves (a point of
/// the cloth grabbed with the mouse): one XPBD attachment step per substep,
/// after the cloth's constraints, from a zero multiplier. A pinned particle
/// stays where its pin holds it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Grab {
    /// The grabbed particle.
    pub particle: u32,
    /// Where the particle is pulled (m, world).
    pub target: Vec3,
    /// Inverse stiffness (m/N); zero puts the particle on the target.
    pub compliance: f32,
}

impl Grab {
    /// Pulls the grabbed particle towards the target over a substep of
    /// `dt`: one XPBD update from a zero multiplier.
    pub fn project(&self, x: &mut [Vec3], inv_mass: &[f32], dt: f32) {
        let i = self.particle as usize;
        if i >= x.len() || i >= inv_mass.len() {
            return;
        }
        let d = x[i] - self.target;
        let c = d.length();
        let w = inv_mass[i];
        if w == 0.0 || c <= f32::EPSILON {
            return;
        }
        let alpha = self.compliance / (dt * dt);
        if let Some(dlambda) = lagrange_update(c, w, alpha, &mut 0.0) {
            x[i] += d / c * (w * dlambda);
        }
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
        let step = Substep::as_built(3600.0, 0.0);
        crate::constraint::projection::project_once(&a, &mut lambda, &mut x, &[1.0], &step);
        assert!(x[0].x > 0.0 && x[0].x < 1.0, "{x:?}");
    }

    #[test]
    fn grab_pulls_stiffly_or_softly_and_leaves_pins() {
        let mut x = vec![Vec3::X, Vec3::Y];
        let hard = Grab {
            particle: 0,
            target: Vec3::ZERO,
            compliance: 0.0,
        };
        hard.project(&mut x, &[1.0, 0.0], 0.01);
        assert!(x[0].length() < 1e-6, "{x:?}");
        let soft = Grab {
            particle: 1,
            target: Vec3::ZERO,
            compliance: 1e-4,
        };
        soft.project(&mut x, &[1.0, 0.0], 0.01);
        assert_eq!(x[1], Vec3::Y, "a pinned particle stays");
        soft.project(&mut x, &[1.0, 1.0], 0.01);
        assert!(x[1].y > 0.0 && x[1].y < 1.0, "{x:?}");
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
