//! The unilateral distance constraint of the coarse levels of hierarchical
//! position-based dynamics (Müller 2008): two particles of a coarse level
//! may be no farther apart than the rest length of the shortest path of
//! finer edges between them, `C = |x_a - x_b| - max_length <= 0`. It never
//! pushes a pair apart beyond where it was when the hierarchy's pass began
//! (a cloth folds and crumples freely; only the pass's own squeeze is
//! undone) and, where the path bends, leaves the slack that shear needs.

use super::compliances::ALWAYS_HELD;
use super::positions::Positions;
use super::projection::{sealed::Sealed, Constraint, Substep};
use glam::Vec3;

/// A coarse edge: two particles kept within `max_length` of each other.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct LongRangeLimit {
    /// The two end particles.
    pub v: [u32; 2],
    /// The farthest apart the ends may be (m).
    pub max_length: f32,
    /// The ends' inverse masses as the level sees them (0 for a pin): on a
    /// free cloth each particle with the share of the finer particles that
    /// follow it, so that a level's corrections, handed down, keep the
    /// momentum ([`crate::solver::hierarchy`]).
    pub inv_mass: [f32; 2],
    /// The live stretch compliance of the cloth ([`super::compliances`]):
    /// the limit holds while it is zero; [`ALWAYS_HELD`] for a cloth with a
    /// strain limit, whose limit always holds.
    pub slot: u32,
    /// The share of their distance when the hierarchy's pass began that
    /// the ends keep ([`LongRangeLimit::project_within`]): 1 on the levels
    /// of a held cloth whose pairs lie beyond the fine sweep's reach, 0
    /// (never pushed) on the finest and on a free cloth
    /// ([`crate::solver::hierarchy`]).
    pub floor: f32,
}

impl LongRangeLimit {
    /// Whether the limit holds in this substep: its cloth is inextensible
    /// now, or has a strain limit.
    pub fn holds(&self, step: &Substep) -> bool {
        self.slot == ALWAYS_HELD || step.compliances[self.slot as usize] == 0.0
    }

    /// Moves the ends together, by the level's inverse masses, until they
    /// are no farther apart than the limit (a hard projection, no
    /// multiplier). Returns how far beyond it they were, as a strain
    /// (negative within it).
    pub fn project_limit(&self, x: &Positions) -> f32 {
        self.project_within(x, 0.0)
    }

    /// As [`LongRangeLimit::project_limit`], and where the ends are closer
    /// than `floor` (capped at the limit), pushes them apart to it: the
    /// hierarchy's floor is how far apart they were when its pass began,
    /// so that its pulls, handed down, never squeeze the cloth (a fold the
    /// prediction brought is kept; only the pass's own compression is
    /// undone). Returns how far beyond the limit they were, as a strain.
    pub fn project_within(&self, x: &Positions, floor: f32) -> f32 {
        let [a, b] = self.v;
        let [wa, wb] = self.inv_mass;
        let d = x.get(a) - x.get(b);
        let len = d.length();
        let excess = len - self.max_length;
        let short = len - floor.min(self.max_length);
        let c = if excess > 0.0 { excess } else { short.min(0.0) };
        if c != 0.0 && len > 0.0 && wa + wb > 0.0 {
            let n: Vec3 = d / len;
            let s = c / (wa + wb);
            x.add(a, n * (-wa * s));
            x.add(b, n * (wb * s));
        }
        excess / self.max_length
    }
}

impl Sealed for LongRangeLimit {}

impl Constraint for LongRangeLimit {
    fn particles(&self) -> &[u32] {
        &self.v
    }

    #[inline]
    fn project(&self, _lambda: &mut f32, x: &Positions, step: &Substep) {
        if self.holds(step) {
            self.project_limit(x);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::constraint::project_once;

    fn project(length: f32, inv_mass: [f32; 2]) -> Vec<Vec3> {
        let limit = LongRangeLimit {
            v: [0, 1],
            max_length: 2.0,
            inv_mass,
            slot: ALWAYS_HELD,
            floor: 0.0,
        };
        let mut x = vec![Vec3::ZERO, Vec3::X * length];
        project_once(
            &limit,
            &mut 0.0,
            &mut x,
            &inv_mass,
            &Substep::as_built(3600.0, 0.0),
        );
        x
    }

    #[test]
    fn pulls_a_stretched_pair_back_to_its_limit_by_inverse_mass() {
        let x = project(3.0, [1.0, 3.0]);
        assert!((x[0].distance(x[1]) - 2.0).abs() < 1e-6);
        assert!((x[0].x - 0.25).abs() < 1e-6, "{x:?}");
        let pinned = project(3.0, [0.0, 1.0]);
        assert_eq!(pinned[0], Vec3::ZERO);
        assert!((pinned[1].x - 2.0).abs() < 1e-6);
    }

    #[test]
    fn holds_while_its_cloth_is_inextensible() {
        let limit = |slot| LongRangeLimit {
            v: [0, 1],
            max_length: 1.0,
            inv_mass: [1.0, 1.0],
            slot,
            floor: 0.0,
        };
        let table = [1.0, 0.0, 1e-3];
        let step = |t: &'static [f32]| Substep {
            compliances: t,
            ..Substep::as_built(1.0, 0.0)
        };
        let step = step(Box::leak(Box::new(table)));
        assert!(limit(1).holds(&step));
        assert!(!limit(2).holds(&step), "a compliant cloth stretches");
        assert!(
            limit(ALWAYS_HELD).holds(&step),
            "a strain limit always holds"
        );
    }

    #[test]
    fn never_pushes() {
        assert_eq!(project(1.0, [1.0, 1.0]), vec![Vec3::ZERO, Vec3::X]);
        assert_eq!(project(2.0, [1.0, 1.0]), vec![Vec3::ZERO, Vec3::X * 2.0]);
    }

    #[test]
    fn pushes_apart_to_its_floor_and_never_past_the_limit() {
        let limit = LongRangeLimit {
            v: [0, 1],
            max_length: 2.0,
            inv_mass: [1.0, 1.0],
            slot: ALWAYS_HELD,
            floor: 1.0,
        };
        let within = |length: f32, floor: f32| {
            let mut x = vec![Vec3::ZERO, Vec3::X * length];
            limit.project_within(&Positions::new(&mut x, &[1.0, 1.0], &limit.v), floor);
            x[0].distance(x[1])
        };
        assert!((within(1.0, 1.5) - 1.5).abs() < 1e-6, "up to the floor");
        assert!((within(1.0, 3.0) - 2.0).abs() < 1e-6, "the floor capped");
        assert_eq!(within(1.0, 0.5), 1.0, "above its floor: left as it is");
        assert!((within(3.0, 3.0) - 2.0).abs() < 1e-6, "still pulled");
    }
}
