//! Graph-coloured constraint sets solved colour by colour, each colour in parallel.
//!
//! Constraints of one colour share no dynamic particle, so they can be
//! projected at the same time and in any order with bit-identical results:
//! the outcome does not depend on the number of threads.

use super::coloring::greedy_colors;
use glam::Vec3;
use rayon::prelude::*;
use std::ops::Range;

/// Smallest number of constraints a rayon task takes on, so that small colours
/// do not pay more in scheduling than they gain.
const MIN_TASK: usize = 512;

/// Positions shared between the tasks that solve one colour.
///
/// Safety contract: while a colour is solved, each particle with non-zero
/// inverse mass is written by at most one constraint, and no other task reads
/// it; particles with zero inverse mass are only read.
#[derive(Clone, Copy)]
pub struct SharedPositions {
    ptr: *mut Vec3,
    len: usize,
}

// SAFETY: access follows the contract above, guaranteed by the colouring.
unsafe impl Send for SharedPositions {}
unsafe impl Sync for SharedPositions {}

impl SharedPositions {
    pub fn new(x: &mut [Vec3]) -> Self {
        SharedPositions {
            ptr: x.as_mut_ptr(),
            len: x.len(),
        }
    }

    #[inline]
    pub fn get(&self, i: u32) -> Vec3 {
        assert!((i as usize) < self.len);
        // SAFETY: in bounds; no concurrent writer of this particle (contract).
        unsafe { *self.ptr.add(i as usize) }
    }

    #[inline]
    pub fn add(&self, i: u32, dx: Vec3) {
        assert!((i as usize) < self.len);
        // SAFETY: in bounds; this task is the particle's only writer (contract).
        unsafe { *self.ptr.add(i as usize) += dx }
    }
}

/// A constraint kind that can be coloured and projected with XPBD.
pub trait Constraint: Send + Sync {
    /// The dynamic particles the projection may move (used for colouring).
    fn particles(&self) -> &[u32];

    /// Projects the constraint once, updating its Lagrange multiplier.
    /// `alpha_tilde_scale` is `1 / dt^2` of the substep.
    fn project(&self, lambda: &mut f32, x: SharedPositions, inv_mass: &[f32], inv_dt2: f32);

    /// The entry of the live compliance table its compliance is a factor
    /// of ([`crate::constraint::compliances`]); 0, the compliance as built,
    /// for constraints that have none.
    fn compliance_slot(&self) -> u32 {
        0
    }
}

/// Constraints sorted by colour, with one Lagrange multiplier each.
#[derive(Clone, Debug, Default)]
pub struct ColoredConstraints<C> {
    pub items: Vec<C>,
    pub lambda: Vec<f32>,
    pub colors: Vec<Range<usize>>,
}

impl<C: Constraint> ColoredConstraints<C> {
    /// Colours `items` greedily and sorts them by colour.
    pub fn new(items: Vec<C>, particle_count: usize) -> Self {
        let (items, colors) = greedy_colors(items, particle_count, |c| c.particles());
        let lambda = vec![0.0; items.len()];
        ColoredConstraints {
            items,
            lambda,
            colors,
        }
    }

    pub fn len(&self) -> usize {
        self.items.len()
    }

    pub fn is_empty(&self) -> bool {
        self.items.is_empty()
    }

    /// Zeroes the multipliers (at the start of each substep).
    pub fn reset_lambda(&mut self) {
        self.lambda.fill(0.0);
    }

    /// One Gauss-Seidel sweep: colour after colour, each colour in parallel,
    /// each constraint's compliance scaled by its entry of `compliances`
    /// (the live table, or [`crate::constraint::compliances::AS_BUILT`]).
    pub fn solve(&mut self, x: &mut [Vec3], inv_mass: &[f32], inv_dt2: f32, compliances: &[f32]) {
        let shared = SharedPositions::new(x);
        for range in &self.colors {
            let items = &self.items[range.clone()];
            let lambda = &mut self.lambda[range.clone()];
            items
                .par_iter()
                .zip(lambda.par_iter_mut())
                .with_min_len(MIN_TASK)
                .for_each(|(c, l)| {
                    let scale = compliances[c.compliance_slot() as usize];
                    c.project(l, shared, inv_mass, inv_dt2 * scale)
                });
        }
    }

    /// One Gauss-Seidel sweep of a projection without multipliers (a hard
    /// bound such as a strain limit), colour after colour; returns the
    /// largest of what `project` returns (how far a constraint was from
    /// satisfied before its projection).
    pub fn sweep(
        &self,
        x: &mut [Vec3],
        project: impl Fn(&C, SharedPositions) -> f32 + Sync,
    ) -> f32 {
        let shared = SharedPositions::new(x);
        self.colors
            .iter()
            .map(|range| {
                self.items[range.clone()]
                    .par_iter()
                    .with_min_len(MIN_TASK)
                    .map(|c| project(c, shared))
                    .reduce(|| f32::NEG_INFINITY, f32::max)
            })
            .fold(f32::NEG_INFINITY, f32::max)
    }
}
