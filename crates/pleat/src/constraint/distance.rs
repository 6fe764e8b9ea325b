//! Distance constraint `C = |x_a - x_b| - rest_length`: stretch and shear
//! edges, and the classic skip-one bending springs; with an optional strain
//! limit (Provot 1995), a hard bound `|C| <= max_stretch` on top of the
//! compliant constraint, so that a soft edge still cannot stretch far.

use super::positions::Positions;
use super::projection::{sealed::Sealed, Constraint, Substep};
use super::xpbd::{alpha_tilde, lagrange_update, position_step};
use glam::Vec3;

/// A distance constraint between two particles, with an optional strain limit.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct DistanceConstraint {
    /// The two end particles.
    pub v: [u32; 2],
    /// Distance at rest (m).
    pub rest_length: f32,
    /// Inverse stiffness (m/N), a factor of the table entry `slot`; zero is inextensible.
    pub compliance: f32,
    /// Entry of the live compliance table this constraint's compliance is
    /// a factor of ([`super::compliances`]; slot 0: the compliance as built).
    pub slot: u32,
    /// Largest change of length the edge may take, however hard it is
    /// pulled (m; [`NO_STRAIN_LIMIT`] for none).
    pub max_stretch: f32,
}

/// The `max_stretch` of an edge without a strain limit.
pub const NO_STRAIN_LIMIT: f32 = f32::MAX;

impl DistanceConstraint {
    /// A constraint at rest at the current distance between `a` and `b`.
    pub fn at_rest(v: [u32; 2], positions: &[Vec3], compliance: f32) -> Self {
        let rest_length = positions[v[0] as usize].distance(positions[v[1] as usize]);
        DistanceConstraint {
            v,
            rest_length,
            compliance,
            slot: 0,
            max_stretch: NO_STRAIN_LIMIT,
        }
    }

    /// The same edge kept within `max_strain` (a fraction of its rest
    /// length) of its rest length; `None` leaves it unlimited.
    pub fn with_strain_limit(self, max_strain: Option<f32>) -> Self {
        DistanceConstraint {
            max_stretch: max_strain.map_or(NO_STRAIN_LIMIT, |s| s * self.rest_length),
            ..self
        }
    }

    /// Whether the edge has a strain limit.
    pub fn is_limited(&self) -> bool {
        self.max_stretch < NO_STRAIN_LIMIT
    }

    /// Moves the two ends along the edge (`n`, from b to a) so that its
    /// `C` comes back within the limit: a hard projection of the excess
    /// alone, with no multiplier.
    #[inline]
    fn limit(&self, c: f32, n: Vec3, x: &Positions, (wa, wb): (f32, f32)) {
        let excess = c - c.clamp(-self.max_stretch, self.max_stretch);
        if excess != 0.0 {
            let s = excess / (wa + wb);
            x.add(self.v[0], n * (-wa * s));
            x.add(self.v[1], n * (wb * s));
        }
    }

    /// One strain-limit projection on its own (the sweeps after the
    /// iterations of a substep). Returns how far the edge was beyond
    /// `slack` times its limit before the projection, as a strain
    /// (negative within it): the sweeps go on while some edge is.
    pub fn project_limit(&self, x: &Positions, slack: f32) -> f32 {
        let [a, b] = self.v;
        let (wa, wb) = (x.inv_mass(a), x.inv_mass(b));
        if wa + wb == 0.0 || !self.is_limited() {
            return f32::NEG_INFINITY;
        }
        let Some((c, n)) = self.evaluate(x.get(a), x.get(b)) else {
            return f32::NEG_INFINITY;
        };
        self.limit(c, n, x, (wa, wb));
        (c.abs() - slack * self.max_stretch) / self.rest_length.max(f32::MIN_POSITIVE)
    }

    /// `C` and its gradient with respect to `x_a` (the gradient for `x_b` is its negative).
    pub fn evaluate(&self, xa: Vec3, xb: Vec3) -> Option<(f32, Vec3)> {
        let d = xa - xb;
        let len = d.length();
        (len > f32::EPSILON * self.rest_length.max(1e-6)).then(|| (len - self.rest_length, d / len))
    }
}

impl Sealed for DistanceConstraint {}

impl Constraint for DistanceConstraint {
    fn particles(&self) -> &[u32] {
        &self.v
    }

    #[inline]
    fn project(&self, lambda: &mut f32, x: &Positions, step: &Substep) {
        let [a, b] = self.v;
        let (wa, wb) = (x.inv_mass(a), x.inv_mass(b));
        let w = wa + wb;
        if w == 0.0 {
            return;
        }
        let Some((c, n)) = self.evaluate(x.get(a), x.get(b)) else {
            return;
        };
        // |grad C| = 1 for both ends: sum w |grad C|^2 = w.
        let alpha = alpha_tilde(self.compliance, self.slot, step);
        let Some(dlambda) = lagrange_update(c, w, alpha, lambda) else {
            return;
        };
        position_step(x, a, wa, n, dlambda);
        position_step(x, b, -wb, n, dlambda);
        // The projection moved the ends along n: C is now c + w dlambda.
        self.limit(c + w * dlambda, n, x, (wa, wb));
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::constraint::bending::tests::finite_difference;
    use crate::constraint::projection::project_once;

    #[test]
    fn gradient_matches_finite_differences() {
        let c = DistanceConstraint {
            v: [0, 1],
            rest_length: 0.7,
            compliance: 0.0,
            slot: 0,
            max_stretch: NO_STRAIN_LIMIT,
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
            max_stretch: NO_STRAIN_LIMIT,
        };
        let mut lambda = 0.0;
        let step = Substep::as_built(3600.0, 0.0);
        project_once(&c, &mut lambda, &mut x, &[1.0, 3.0], &step);
        assert!((x[0].distance(x[1]) - 1.0).abs() < 1e-6);
        // The lighter particle (inverse mass 3) moves three times as far.
        assert!(
            (x[0].x - 0.25).abs() < 1e-6 && (x[1].x - 1.25).abs() < 1e-6,
            "{x:?}"
        );
    }

    #[test]
    fn a_soft_edge_stops_at_its_strain_limit() {
        // So soft that one projection alone would hardly move it.
        let soft = DistanceConstraint::at_rest([0, 1], &[Vec3::ZERO, Vec3::X], 1e3);
        let project = |c: DistanceConstraint, stretched: f32| {
            let mut x = vec![Vec3::ZERO, Vec3::X * stretched];
            let step = Substep::as_built(3600.0, 0.0);
            project_once(&c, &mut 0.0, &mut x, &[1.0, 1.0], &step);
            x[0].distance(x[1])
        };
        assert!(project(soft, 1.2) > 1.19, "unlimited, it stays stretched");
        let limited = soft.with_strain_limit(Some(0.01));
        assert!((project(limited, 1.2) - 1.01).abs() < 1e-5);
        assert!((project(limited, 0.7) - 0.99).abs() < 1e-5, "compressed");
        // Within the limit, the constraint is as compliant as before.
        assert_eq!(project(limited, 1.005), project(soft, 1.005));
        // The limit alone: light ends move more, the edge ends at the bound.
        let mut x = vec![Vec3::ZERO, Vec3::X * 1.5];
        let beyond = limited.project_limit(&Positions::new(&mut x, &[1.0, 3.0], &[0, 1]), 2.0);
        assert!((x[0].distance(x[1]) - 1.01).abs() < 1e-5);
        assert!((x[1].x - 1.5 + 3.0 * x[0].x).abs() < 1e-5, "{x:?}");
        // It was 50 % long: 48 % beyond twice its limit.
        assert!((beyond - 0.48).abs() < 1e-5, "{beyond}");
    }

    #[test]
    fn the_limit_alone_says_how_far_beyond_its_slack_an_edge_was() {
        let edge = DistanceConstraint::at_rest([0, 1], &[Vec3::ZERO, Vec3::X * 2.0], 0.0)
            .with_strain_limit(Some(0.01));
        let beyond = |length: f32| {
            let mut x = vec![Vec3::ZERO, Vec3::X * length];
            edge.project_limit(&Positions::new(&mut x, &[1.0, 1.0], &[0, 1]), 1.8)
        };
        // Within 1.8 times its 1 % limit, stretched or compressed: negative.
        assert!((beyond(2.02) + 0.008).abs() < 1e-5);
        assert!((beyond(1.95) - 0.007).abs() < 1e-5);
        assert!(beyond(2.0) < 0.0);
        // An edge with no limit never asks for another sweep.
        let free = DistanceConstraint::at_rest([0, 1], &[Vec3::ZERO, Vec3::X], 0.0);
        let mut x = vec![Vec3::ZERO, Vec3::X * 3.0];
        let never = free.project_limit(&Positions::new(&mut x, &[1.0, 1.0], &[0, 1]), 1.8);
        assert_eq!(never, f32::NEG_INFINITY);
        assert_eq!(x[1], Vec3::X * 3.0);
    }
}
