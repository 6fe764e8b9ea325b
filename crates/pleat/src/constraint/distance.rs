//! Distance constraint `C = |x_a - x_b| - rest_length`: stretch and shear
//! edges, and the classic skip-one bending springs.

use crate::solver::parallel::{Constraint, SharedPositions};
use glam::Vec3;

#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct DistanceConstraint {
    pub v: [u32; 2],
    pub rest_length: f32,
    /// Inverse stiffness (m/N), a factor of the table entry `slot`; zero is inextensible.
    pub compliance: f32,
    /// Entry of the live compliance table this constraint's compliance is
    /// a factor of ([`super::compliances`]; slot 0: the compliance as built).
    pub slot: u32,
}

impl DistanceConstraint {
    /// A constraint at rest at the current distance between `a` and `b`.
    pub fn at_rest(v: [u32; 2], positions: &[Vec3], compliance: f32) -> Self {
        let rest_length = positions[v[0] as usize].distance(positions[v[1] as usize]);
        DistanceConstraint {
            v,
            rest_length,
            compliance,
            slot: 0,
        }
    }

    /// `C` and its gradient with respect to `x_a` (the gradient for `x_b` is its negative).
    pub fn evaluate(&self, xa: Vec3, xb: Vec3) -> Option<(f32, Vec3)> {
        let d = xa - xb;
        let len = d.length();
        (len > f32::EPSILON * self.rest_length.max(1e-6)).then(|| (len - self.rest_length, d / len))
    }
}

impl Constraint for DistanceConstraint {
    fn particles(&self) -> &[u32] {
        &self.v
    }

    fn compliance_slot(&self) -> u32 {
        self.slot
    }

    #[inline]
    fn project(&self, lambda: &mut f32, x: SharedPositions, inv_mass: &[f32], inv_dt2: f32) {
        let [a, b] = self.v;
        let (wa, wb) = (inv_mass[a as usize], inv_mass[b as usize]);
        let w = wa + wb;
        if w == 0.0 {
            return;
        }
        let Some((c, n)) = self.evaluate(x.get(a), x.get(b)) else {
            return;
        };
        let alpha = self.compliance * inv_dt2;
        let dlambda = (-c - alpha * *lambda) / (w + alpha);
        *lambda += dlambda;
        x.add(a, n * (wa * dlambda));
        x.add(b, n * (-wb * dlambda));
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::constraint::bending::tests::finite_difference;

    #[test]
    fn gradient_matches_finite_differences() {
        let c = DistanceConstraint {
            v: [0, 1],
            rest_length: 0.7,
            compliance: 0.0,
            slot: 0,
        };
        let x = [Vec3::new(0.1, 0.2, -0.3), Vec3::new(0.9, -0.4, 0.5)];
        let (_, ga) = c.evaluate(x[0], x[1]).unwrap();
        let fd = finite_difference(&x, |p| c.evaluate(p[0], p[1]).unwrap().0);
        assert!(fd[0].distance(ga) < 1e-3, "{:?} vs {ga}", fd[0]);
        assert!(fd[1].distance(-ga) < 1e-3, "{:?} vs {}", fd[1], -ga);
    }

    #[test]
    fn compliance_zero_projects_to_rest_length() {
        let mut x = vec![Vec3::ZERO, Vec3::new(2.0, 0.0, 0.0)];
        let c = DistanceConstraint {
            v: [0, 1],
            rest_length: 1.0,
            compliance: 0.0,
            slot: 0,
        };
        let mut lambda = 0.0;
        c.project(
            &mut lambda,
            SharedPositions::new(&mut x),
            &[1.0, 3.0],
            3600.0,
        );
        assert!((x[0].distance(x[1]) - 1.0).abs() < 1e-6);
        // The lighter particle (inverse mass 3) moves three times as far.
        assert!(
            (x[0].x - 0.25).abs() < 1e-6 && (x[1].x - 1.25).abs() < 1e-6,
            "{x:?}"
        );
    }
}
