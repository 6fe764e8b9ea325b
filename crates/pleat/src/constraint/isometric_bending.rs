//! Isometric bending (Bergou et al. 2006, "A quadratic bending model for
//! inextensible surfaces") for a pair of adjacent triangles that is flat at rest.
//!
//! With cotangent weights `K` of the rest stencil (`v[0], v[1]` the shared
//! edge, `v[2], v[3]` the wings), the vector `b = sum_i K_i x_i` vanishes on
//! every isometric (bending-free) deformation and has length
//! `|e| * 2 sin(phi / 2)` for a fold of angle `phi`. The constraint
//! `C = |b| / |e_rest|` therefore equals the fold angle for small folds (the
//! same compliance means the same stiffness as [`super::DihedralBending`]),
//! and its gradient `grad_i C = K_i b / (|b| |e_rest|)` costs no more than a
//! distance constraint: no trigonometry, no cross products.

use super::positions::Positions;
use super::projection::{sealed::Sealed, Constraint, Substep};
use super::xpbd::{alpha_tilde, lagrange_update, position_step};
use glam::{Vec3, Vec3A};

/// Folds below this (radians) are left alone: their direction is round-off.
const FLAT_ENOUGH: f32 = 1e-6;

/// Isometric bending of a pair of adjacent triangles, flat at rest.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct IsometricBending {
    /// The stencil: the shared edge `v[0], v[1]`, then the wings `v[2], v[3]`.
    pub v: [u32; 4],
    /// Cotangent weights divided by the rest edge length.
    pub k: [f32; 4],
    /// Inverse stiffness, a factor of the table entry `slot`.
    pub compliance: f32,
    /// Entry of the live compliance table this constraint's compliance is
    /// a factor of ([`super::compliances`]; slot 0: the compliance as built).
    pub slot: u32,
}

impl IsometricBending {
    /// The constraint for a pair at rest in `positions`, or `None` if the pair
    /// is degenerate (a zero angle has no cotangent).
    pub fn at_rest(v: [u32; 4], positions: &[Vec3], compliance: f32) -> Option<Self> {
        let [x0, x1, x2, x3] = v.map(|i| positions[i as usize]);
        let e0 = x1 - x0;
        let cot = |a: Vec3, b: Vec3| {
            let sin = a.cross(b).length();
            (sin > 1e-12 * a.length_squared().max(b.length_squared())).then(|| a.dot(b) / sin)
        };
        let c01 = cot(e0, x2 - x0)?;
        let c02 = cot(e0, x3 - x0)?;
        let c03 = cot(-e0, x2 - x1)?;
        let c04 = cot(-e0, x3 - x1)?;
        let len = e0.length();
        let k = [c03 + c04, c01 + c02, -c01 - c03, -c02 - c04].map(|c| c / len);
        Some(IsometricBending {
            v,
            k,
            compliance,
            slot: 0,
        })
    }

    /// `C` and its gradient for the four positions.
    pub fn evaluate(&self, p: [Vec3A; 4]) -> Option<(f32, Vec3A)> {
        // sum_i k_i = 0, so measuring from p[0] changes nothing but the round-off.
        let b = (p[1] - p[0]) * self.k[1] + (p[2] - p[0]) * self.k[2] + (p[3] - p[0]) * self.k[3];
        let c = b.length();
        (c > FLAT_ENOUGH).then(|| (c, b / c))
    }
}

impl Sealed for IsometricBending {}

impl Constraint for IsometricBending {
    fn particles(&self) -> &[u32] {
        &self.v
    }

    #[inline]
    fn project(&self, lambda: &mut f32, x: &Positions, step: &Substep) {
        let Some((c, dir)) = self.evaluate(self.v.map(|i| Vec3A::from(x.get(i)))) else {
            return;
        };
        // grad_i C = k_i dir, |dir| = 1: sum w |grad C|^2 = sum w k^2.
        let w = self.v.map(|i| x.inv_mass(i));
        let norm: f32 = w.iter().zip(&self.k).map(|(w, k)| w * k * k).sum();
        let alpha = alpha_tilde(self.compliance, self.slot, step);
        let Some(dlambda) = lagrange_update(c, norm, alpha, lambda) else {
            return;
        };
        for ((&i, &w), &k) in self.v.iter().zip(&w).zip(&self.k) {
            if w > 0.0 {
                position_step(x, i, w * k, Vec3::from(dir), dlambda);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::constraint::bending::dihedral_angle;
    use crate::constraint::bending::tests::finite_difference;

    fn rest() -> [Vec3; 4] {
        [
            Vec3::ZERO,
            Vec3::new(1.0, 0.1, 0.0),
            Vec3::new(0.3, 0.8, 0.0),
            Vec3::new(0.6, -0.9, 0.0),
        ]
    }

    fn folded(fold: f32) -> [Vec3; 4] {
        let mut p = rest();
        // Rotate the first wing about the edge line by `fold`.
        let axis = (p[1] - p[0]).normalize();
        let r = glam::Quat::from_axis_angle(axis, fold);
        p[2] = p[0] + r * (p[2] - p[0]);
        p
    }

    #[test]
    fn zero_on_isometric_motion_and_equal_to_small_fold_angle() {
        let c = IsometricBending::at_rest([0, 1, 2, 3], &rest(), 0.0).unwrap();
        let moved = rest().map(|p| glam::Quat::from_rotation_y(0.7) * p + Vec3::new(1.0, 2.0, 3.0));
        let unbent = c
            .evaluate(moved.map(Vec3A::from))
            .map_or(0.0, |(value, _)| value);
        assert!(unbent < 1e-5, "rigid motion does not bend: {unbent}");
        for fold in [0.01f32, 0.05, 0.2] {
            let (value, _) = c.evaluate(folded(fold).map(Vec3A::from)).unwrap();
            let angle = dihedral_angle(folded(fold)).unwrap().0.abs();
            assert!(
                (value - 2.0 * (angle / 2.0).sin()).abs() < 1e-4,
                "fold {fold}: {value} vs {angle}"
            );
        }
    }

    #[test]
    fn gradient_matches_finite_differences() {
        let c = IsometricBending::at_rest([0, 1, 2, 3], &rest(), 0.0).unwrap();
        let p = folded(0.6);
        let (_, dir) = c.evaluate(p.map(Vec3A::from)).unwrap();
        let fd = finite_difference(&p, |q| {
            c.evaluate([q[0], q[1], q[2], q[3]].map(Vec3A::from))
                .unwrap()
                .0
        });
        for (i, (fd, k)) in fd.iter().zip(c.k).enumerate() {
            let grad = Vec3::from(dir * k);
            assert!(
                fd.distance(grad) < 2e-3 * grad.length().max(1.0),
                "vertex {i}: {fd} vs {grad}"
            );
        }
    }
}
