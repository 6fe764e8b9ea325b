//! Scripted rigid motion: constant linear velocity plus constant angular
//! velocity about a pivot, so that a sphere can spin in place or a pin can
//! travel along a line.

use glam::{Affine3A, Quat, Vec3};

/// Scripted rigid motion: constant linear velocity plus constant angular
/// velocity about a pivot.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Motion {
    /// Metres per second.
    pub linear_velocity: Vec3,
    /// Radians per second, as an axis scaled by the rate.
    pub angular_velocity: Vec3,
    /// Point the rotation turns about, at time zero.
    pub pivot: Vec3,
}

impl Motion {
    /// Whether the motion leaves everything in place.
    pub fn is_static(&self) -> bool {
        self.linear_velocity == Vec3::ZERO && self.angular_velocity == Vec3::ZERO
    }

    /// The rigid transform from time-zero placement to time `t`.
    pub fn pose_at(&self, t: f32) -> Affine3A {
        let rotation = Quat::from_scaled_axis(self.angular_velocity * t);
        Affine3A::from_translation(self.pivot + self.linear_velocity * t)
            * Affine3A::from_quat(rotation)
            * Affine3A::from_translation(-self.pivot)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f32::consts::PI;

    #[test]
    fn spins_about_pivot() {
        let m = Motion {
            angular_velocity: Vec3::new(0.0, PI, 0.0),
            pivot: Vec3::new(1.0, 0.0, 0.0),
            ..Motion::default()
        };
        // Half a turn about the y axis through (1, 0, 0) takes (2, 0, 0) to (0, 0, 0).
        let p = m.pose_at(1.0).transform_point3(Vec3::new(2.0, 0.0, 0.0));
        assert!(p.length() < 1e-5, "{p}");
    }
}
