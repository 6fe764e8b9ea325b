//! Normal cones (Provot 1997; Volino and Magnenat-Thalmann 1994): a bound on
//! the directions of a patch's triangle normals, an axis and a half-angle.
//! A connected patch whose normals all lie within a cone narrower than a
//! right angle is a height field over the plane across the axis, so it cannot
//! fold onto itself: self-collision culling skips it.

use glam::Vec3;
use std::f32::consts::PI;

/// A cone of directions around `axis` (unit) of half-angle `angle` (radians);
/// `angle >= PI` holds every direction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NormalCone {
    pub axis: Vec3,
    pub angle: f32,
}

impl Default for NormalCone {
    fn default() -> Self {
        NormalCone::ALL
    }
}

impl NormalCone {
    /// The cone of every direction.
    pub const ALL: NormalCone = NormalCone {
        axis: Vec3::Z,
        angle: PI,
    };

    /// The cone around the mean of unit `normals`; every direction when one
    /// of them is not a unit vector (a degenerate triangle) or they cancel.
    pub fn around(normals: impl Iterator<Item = Vec3> + Clone) -> NormalCone {
        let mut sum = Vec3::ZERO;
        for n in normals.clone() {
            if !n.is_normalized() {
                return NormalCone::ALL;
            }
            sum += n;
        }
        let Some(axis) = sum.try_normalize() else {
            return NormalCone::ALL;
        };
        let min_cos = normals.map(|n| n.dot(axis)).fold(1.0, f32::min);
        NormalCone {
            axis,
            angle: min_cos.clamp(-1.0, 1.0).acos(),
        }
    }

    /// A cone that holds every cone of `cones`.
    pub fn union_of(cones: impl Iterator<Item = NormalCone> + Clone) -> NormalCone {
        let mut sum = Vec3::ZERO;
        for c in cones.clone() {
            if c.angle >= PI {
                return NormalCone::ALL;
            }
            sum += c.axis;
        }
        let Some(axis) = sum.try_normalize() else {
            return NormalCone::ALL;
        };
        let angle = cones
            .map(|c| c.angle + c.axis.dot(axis).clamp(-1.0, 1.0).acos())
            .fold(0.0, f32::max);
        NormalCone {
            axis,
            angle: angle.min(PI),
        }
    }

    /// The union of this cone and a cone `o` (both no wider than a right
    /// angle) lies within `max_angle` of the bisector of their axes when
    /// `axis . o.axis` exceeds both cones' `union_cos(max_angle)`: the union
    /// spreads `max(angle, o.angle)` plus half the angle between the axes.
    pub fn union_cos(&self, max_angle: f32) -> f32 {
        let room = 2.0 * (max_angle - self.angle);
        if room <= 0.0 {
            f32::INFINITY
        } else {
            room.min(PI).cos()
        }
    }

    /// Whether every direction in the cone is within `max_angle` of the axis.
    pub fn narrower_than(&self, max_angle: f32) -> bool {
        self.angle < max_angle
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_rng::Rng;

    fn contains(cone: &NormalCone, n: Vec3) -> bool {
        n.dot(cone.axis).clamp(-1.0, 1.0).acos() <= cone.angle + 1e-5
    }

    fn random_unit(rng: &mut Rng, around: Vec3, spread: f32) -> Vec3 {
        (around + (rng.vec3() * 2.0 - 1.0) * spread).normalize()
    }

    #[test]
    fn cones_hold_their_normals_and_narrow_unions_hold_both() {
        let mut rng = Rng(5);
        let max = PI / 3.0;
        let mut narrow = 0;
        for k in 0..400 {
            let spread = 0.05 + 0.002 * k as f32;
            let tilt = Vec3::new(rng.unit() * 0.6, 1.0, 0.0);
            let a: Vec<Vec3> = (0..8)
                .map(|_| random_unit(&mut rng, Vec3::Y, spread))
                .collect();
            let b: Vec<Vec3> = (0..8)
                .map(|_| random_unit(&mut rng, tilt, spread))
                .collect();
            let (ca, cb) = (
                NormalCone::around(a.iter().copied()),
                NormalCone::around(b.iter().copied()),
            );
            assert!(a.iter().all(|&n| contains(&ca, n)));
            if ca.axis.dot(cb.axis) > ca.union_cos(max).max(cb.union_cos(max)) {
                narrow += 1;
                let bisector = NormalCone {
                    axis: (ca.axis + cb.axis).normalize(),
                    angle: max,
                };
                assert!(a.iter().chain(&b).all(|&n| contains(&bisector, n)));
            }
        }
        assert!(narrow > 50 && narrow < 400, "{narrow}");
    }

    #[test]
    fn union_of_cones_holds_their_normals() {
        let mut rng = Rng(6);
        for k in 0..100 {
            let spread = 0.05 + 0.01 * k as f32;
            let sets: Vec<Vec<Vec3>> = (0..4)
                .map(|_| {
                    let around = rng.vec3() * 2.0 - 1.0 + Vec3::Y * 2.0;
                    (0..6)
                        .map(|_| random_unit(&mut rng, around, spread))
                        .collect()
                })
                .collect();
            let cones = sets.iter().map(|s| NormalCone::around(s.iter().copied()));
            let u = NormalCone::union_of(cones);
            assert!(sets.iter().flatten().all(|&n| contains(&u, n)), "{u:?}");
        }
    }

    #[test]
    fn flat_patch_is_narrow_and_folded_patch_is_not() {
        let flat = NormalCone::around([Vec3::Y, Vec3::new(0.1, 1.0, 0.0).normalize()].into_iter());
        assert!(flat.narrower_than(0.2));
        let folded = NormalCone::around([Vec3::Y, -Vec3::Y].into_iter());
        assert!(!folded.narrower_than(PI / 2.0));
        let degenerate = NormalCone::around([Vec3::Y, Vec3::ZERO].into_iter());
        assert_eq!(degenerate, NormalCone::ALL);
    }
}
