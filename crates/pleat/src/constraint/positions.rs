//! The particle positions as one constraint's projection sees them, and
//! the shared view the parallel solver hands out one colour at a time.
//!
//! A projection reads its own particles and any pinned particle (inverse
//! mass zero), and moves its own dynamic particles: [`Positions`] never
//! writes a pinned particle, and checks the rest in debug builds (every
//! test run; the checks cost a projection three times its time in a
//! release build). That is what makes the parallel Gauss-Seidel sweep
//! sound: within one colour no two constraints share a particle, pinned
//! particles are never written, so no particle is written by one task
//! while another reads it. Only the core's constraint kinds project
//! ([`super::Constraint`] is sealed), and the tests run each of them.

use glam::Vec3;
use std::cell::Cell;
use std::marker::PhantomData;

/// The positions one constraint's projection reads and moves.
///
/// Built over a whole slice with [`Positions::new`] (one thread), or by the
/// parallel solver for each constraint of a colour. Reading a dynamic
/// particle that is not the constraint's own, or moving any particle that
/// is not, panics in a debug build; moving a pinned particle does nothing.
pub struct Positions<'a> {
    x: &'a [Cell<Vec3>],
    inv_mass: &'a [f32],
    own: &'a [u32],
}

impl<'a> Positions<'a> {
    /// The view of a constraint on `own` over all of `x` (exclusively
    /// borrowed, so on this thread alone), with the particles' `inv_mass`.
    pub fn new(x: &'a mut [Vec3], inv_mass: &'a [f32], own: &'a [u32]) -> Self {
        assert_eq!(x.len(), inv_mass.len(), "one inverse mass per position");
        Positions {
            x: Cell::from_mut(x).as_slice_of_cells(),
            inv_mass,
            own,
        }
    }

    /// The inverse mass of particle `i` (zero for a pinned particle).
    #[inline(always)]
    pub fn inv_mass(&self, i: u32) -> f32 {
        self.inv_mass[i as usize]
    }

    /// The position of particle `i`: one of the constraint's own, or a
    /// pinned one.
    #[inline(always)]
    pub fn get(&self, i: u32) -> Vec3 {
        debug_assert!(
            self.own.contains(&i) || self.inv_mass(i) == 0.0,
            "a projection read particle {i}, neither its own nor pinned"
        );
        self.x[i as usize].get()
    }

    /// Moves particle `i`, one of the constraint's own, by `dx`; a pinned
    /// particle stays where it is.
    #[inline(always)]
    pub fn add(&self, i: u32, dx: Vec3) {
        debug_assert!(
            self.own.contains(&i),
            "a projection moved particle {i}, not its own"
        );
        if self.inv_mass(i) > 0.0 {
            let x = &self.x[i as usize];
            x.set(x.get() + dx);
        }
    }
}

/// The positions shared by the tasks that project one colour of
/// constraints at the same time; each task takes its constraint's view
/// with [`SharedPositions::view`].
pub(crate) struct SharedPositions<'a> {
    x: *const Cell<Vec3>,
    len: usize,
    inv_mass: &'a [f32],
    /// The positions stay exclusively borrowed while views exist.
    _x: PhantomData<&'a mut [Vec3]>,
}

// SAFETY: the views handed to other threads access the positions only as
// `SharedPositions::view` requires: no particle is written by one view
// while another view reads or writes it.
unsafe impl Sync for SharedPositions<'_> {}

impl<'a> SharedPositions<'a> {
    /// Shares `x` (exclusively borrowed for `'a`) between the tasks of a colour.
    pub(crate) fn new(x: &'a mut [Vec3], inv_mass: &'a [f32]) -> Self {
        assert_eq!(x.len(), inv_mass.len(), "one inverse mass per position");
        SharedPositions {
            x: Cell::from_mut(x).as_slice_of_cells().as_ptr(),
            len: inv_mass.len(),
            inv_mass,
            _x: PhantomData,
        }
    }

    /// The view of the constraint on the particles `own`.
    ///
    /// # Safety
    ///
    /// While the view lives, no view made from the same `SharedPositions`
    /// and used on another thread may name in its `own` a particle that
    /// this one names, and the view's user reads only its own particles
    /// and pinned ones and writes only its own. The parallel solver
    /// guarantees the first by colouring: the constraints of one colour
    /// share no particle ([`crate::solver::coloring`], checked in debug
    /// builds when a constraint set is built); the second holds for every
    /// constraint kind (checked by [`Positions`] in debug builds), and
    /// pinned particles are never written, so no particle is written on
    /// one thread while read on another.
    #[inline]
    pub(crate) unsafe fn view<'s>(&'s self, own: &'s [u32]) -> Positions<'s> {
        Positions {
            // SAFETY: `x` points to `len` cells borrowed for 'a, which
            // outlives 's; concurrent views access disjoint cells (above).
            x: unsafe { std::slice::from_raw_parts(self.x, self.len) },
            inv_mass: self.inv_mass,
            own,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_view_moves_its_own_dynamic_particles_only() {
        let mut x = vec![Vec3::ZERO, Vec3::X, Vec3::Y];
        let w = [1.0, 0.0, 1.0];
        let view = Positions::new(&mut x, &w, &[0, 1]);
        view.add(0, Vec3::Z);
        view.add(1, Vec3::Z);
        assert_eq!(view.get(0), Vec3::Z);
        assert_eq!(view.get(1), Vec3::X, "pinned: stays");
        assert_eq!(x, [Vec3::Z, Vec3::X, Vec3::Y]);
    }

    #[test]
    #[cfg(debug_assertions)]
    #[should_panic(expected = "moved particle 2, not its own")]
    fn moving_another_constraints_particle_panics() {
        let mut x = vec![Vec3::ZERO; 3];
        Positions::new(&mut x, &[1.0; 3], &[0, 1]).add(2, Vec3::X);
    }

    #[test]
    #[cfg(debug_assertions)]
    #[should_panic(expected = "read particle 2, neither its own nor pinned")]
    fn reading_another_dynamic_particle_panics() {
        let mut x = vec![Vec3::ZERO; 3];
        Positions::new(&mut x, &[1.0; 3], &[0]).get(2);
    }

    #[test]
    fn any_view_reads_a_pinned_particle() {
        let mut x = vec![Vec3::ZERO, Vec3::X];
        assert_eq!(Positions::new(&mut x, &[1.0, 0.0], &[0]).get(1), Vec3::X);
    }
}
