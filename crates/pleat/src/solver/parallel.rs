//! Graph-coloured constraint sets solved colour by colour, each colour in parallel.
//!
//! Constraints of one colour share no particle, so they can be projected at
//! the same time and in any order with bit-identical results: the outcome
//! does not depend on the number of threads. Each projection gets a view
//! of the positions ([`Positions`]) that keeps it to its own particles;
//! the set keeps its items and colours private, so the colouring holds for
//! as long as the set lives.

use super::coloring::greedy_colors;
use crate::constraint::positions::SharedPositions;
use crate::constraint::{Constraint, Positions, Substep, MAX_PARTICLES};
use glam::Vec3;
use rayon::prelude::*;
use std::ops::Range;

/// Smallest number of constraints a rayon task takes on, so that small colours
/// do not pay more in scheduling than they gain.
const MIN_TASK: usize = 512;

/// Smallest number of constraints a task updates in [`ColoredConstraints::update`].
const MIN_UPDATE_TASK: usize = 2048;

/// Constraints sorted by colour, with one Lagrange multiplier each.
#[derive(Clone, Debug)]
pub struct ColoredConstraints<C> {
    items: Vec<C>,
    lambda: Vec<f32>,
    colors: Vec<Range<usize>>,
}

impl<C> Default for ColoredConstraints<C> {
    fn default() -> Self {
        ColoredConstraints {
            items: Vec::new(),
            lambda: Vec::new(),
            colors: Vec::new(),
        }
    }
}

impl<C> ColoredConstraints<C> {
    /// The constraints, sorted by colour.
    pub fn items(&self) -> &[C] {
        &self.items
    }

    /// The ranges of [`ColoredConstraints::items`] of one colour each.
    pub fn colors(&self) -> &[Range<usize>] {
        &self.colors
    }

    /// The Lagrange multipliers, one per item.
    pub fn lambda(&self) -> &[f32] {
        &self.lambda
    }

    /// Number of constraints.
    pub fn len(&self) -> usize {
        self.items.len()
    }

    /// Whether there are no constraints.
    pub fn is_empty(&self) -> bool {
        self.items.is_empty()
    }
}

impl<C: Constraint + Copy> ColoredConstraints<C> {
    /// Colours `items` greedily and sorts them by colour.
    pub fn new(items: Vec<C>, particle_count: usize) -> Self {
        assert!(
            items.iter().all(|c| c.particles().len() <= MAX_PARTICLES),
            "a constraint on more than {MAX_PARTICLES} particles"
        );
        let (items, colors) = greedy_colors(items, particle_count, |c| c.particles());
        let lambda = vec![0.0; items.len()];
        let set = ColoredConstraints {
            items,
            lambda,
            colors,
        };
        debug_assert!(set.colors_are_independent(particle_count));
        set
    }

    /// Zeroes the multipliers (at the start of each substep).
    pub fn reset_lambda(&mut self) {
        self.lambda.fill(0.0);
    }

    /// Changes each item with `f` (given its index), in parallel; an item
    /// keeps its particles (checked: the colouring rests on them).
    pub fn update(&mut self, f: impl Fn(usize, &mut C) + Sync) {
        self.items
            .par_iter_mut()
            .enumerate()
            .with_min_len(MIN_UPDATE_TASK)
            .for_each(|(i, c)| {
                let mut before = [0; MAX_PARTICLES];
                let n = c.particles().len();
                before[..n].copy_from_slice(c.particles());
                f(i, c);
                assert_eq!(
                    c.particles(),
                    &before[..n],
                    "a constraint's particles changed"
                );
            });
    }

    /// One Gauss-Seidel sweep: colour after colour, each colour in parallel,
    /// each constraint projected with the substep's `1 / dt^2`, live
    /// compliances and fold drive.
    pub fn solve(&mut self, x: &mut [Vec3], inv_mass: &[f32], step: &Substep) {
        let shared = SharedPositions::new(x, inv_mass);
        for range in &self.colors {
            let items = &self.items[range.clone()];
            let lambda = &mut self.lambda[range.clone()];
            items
                .par_iter()
                .zip(lambda.par_iter_mut())
                .with_min_len(MIN_TASK)
                .for_each(|(c, l)| {
                    // SAFETY: the constraints of one colour share no
                    // particle (`colors_are_independent`, and `update`
                    // keeps each item's particles), so no two views of
                    // this colour name one particle.
                    let view = unsafe { shared.view(c.particles()) };
                    c.project(l, &view, step)
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
        inv_mass: &[f32],
        project: impl Fn(&C, &Positions) -> f32 + Sync,
    ) -> f32 {
        let shared = SharedPositions::new(x, inv_mass);
        self.colors
            .iter()
            .map(|range| {
                self.items[range.clone()]
                    .par_iter()
                    .with_min_len(MIN_TASK)
                    .map(|c| {
                        // SAFETY: as in `solve`, one colour's constraints
                        // share no particle.
                        let view = unsafe { shared.view(c.particles()) };
                        project(c, &view)
                    })
                    .reduce(|| f32::NEG_INFINITY, f32::max)
            })
            .fold(f32::NEG_INFINITY, f32::max)
    }

    /// Whether no two constraints of one colour share a particle.
    fn colors_are_independent(&self, particle_count: usize) -> bool {
        let mut last_color = vec![usize::MAX; particle_count];
        self.colors.iter().enumerate().all(|(color, range)| {
            self.items[range.clone()].iter().all(|c| {
                c.particles()
                    .iter()
                    .all(|&p| std::mem::replace(&mut last_color[p as usize], color) != color)
            })
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::constraint::DistanceConstraint;

    fn chain(n: u32) -> ColoredConstraints<DistanceConstraint> {
        let x: Vec<Vec3> = (0..=n).map(|i| Vec3::X * i as f32).collect();
        let edges = (0..n)
            .map(|i| DistanceConstraint::at_rest([i, i + 1], &x, 0.0))
            .collect();
        ColoredConstraints::new(edges, x.len())
    }

    #[test]
    fn colours_share_no_particle() {
        let set = chain(100);
        assert_eq!(set.colors().len(), 2);
        assert!(set.colors_are_independent(101));
    }

    #[test]
    fn updates_keep_the_colouring() {
        let mut set = chain(10);
        set.update(|i, c| c.rest_length = i as f32);
        assert_eq!(set.items()[3].rest_length, 3.0);
    }

    #[test]
    #[should_panic(expected = "particles changed")]
    fn an_update_that_moves_a_constraint_panics() {
        chain(10).update(|_, c| c.v[0] = 0);
    }
}
