//! Angular momentum kept through a substep's own constraints.
//!
//! A cloth's own constraints (stretch, bending, hinges, strain limits)
//! exert internal forces, which cannot change its angular momentum. One
//! XPBD projection keeps it exactly: its correction is mass-weighted along
//! a gradient that no rotation changes. A Gauss-Seidel sweep of many does
//! not. Where constraints fight (creases whose targets disagree), the
//! sweep takes the sheet's shape around a small loop every substep, and a
//! loop of shape changes turns a body that holds no angular momentum, as
//! a falling cat turns itself over (the geometric phase). The velocity
//! update reads that turn as spin: a folded crane with every crease held
//! kept turning at about 2 rad/s, damping or not.
//!
//! [`FreeParts`] undoes it for every cloth on which nothing outside acts
//! during the projection (no pin, soft or hard, no zero mass): after the
//! projection, the angular impulse its corrections `D` carry,
//! `sum m (x_prev - c) x D / dt`, is taken back by the smallest rigid turn
//! about the centre of mass. The turn keeps the shape and the linear
//! momentum, and every constraint's value, since none changes under a
//! rotation. Contacts, the mouse grab and pins act outside it and keep
//! their torques.

use crate::model::Model;
use crate::particles::Particles;
use glam::{DMat3, DVec3, Vec3};
use rayon::prelude::*;
use std::ops::Range;

/// Smallest turn applied (radians a substep): smaller ones are the
/// round-off of the sums, a hundredth of single precision's resolution,
/// and skipped, so that backends which sum in different orders stay
/// identical where nothing turns (a falling sheet).
pub const SMALLEST_TURN: f64 = 1e-9;

/// Fewest particles a rayon task sums.
const MIN_TASK: usize = 2048;

/// The cloths nothing outside holds.
#[derive(Clone, Debug, Default)]
pub struct FreeParts {
    ranges: Vec<Range<usize>>,
    /// Per particle, what the last turn could not move it by: a turn of a
    /// few 1e-8 m rounds away in single precision, so what it missed
    /// counts in the next substep's correction.
    left: Vec<Vec3>,
}

impl FreeParts {
    /// The particle ranges of every cloth of `model` without a pin or a
    /// particle of zero mass (`inv_mass`, the solver's inverse masses).
    pub fn new(model: &Model, inv_mass: &[f32]) -> Self {
        let pinned = |range: &Range<usize>| {
            model
                .pins
                .iter()
                .any(|p| range.contains(&(p.particle as usize)))
                || inv_mass[range.clone()].iter().any(|&w| w <= 0.0)
        };
        let ranges: Vec<_> = model
            .cloths
            .iter()
            .map(|c| c.particles())
            .filter(|r| !r.is_empty() && !pinned(r))
            .collect();
        let left = vec![Vec3::ZERO; model.particle_count()];
        FreeParts { ranges, left }
    }

    /// Turns each free cloth back by the angle its substep turned it
    /// without cause: `x` projected from the prediction `x_prev + dt v`.
    pub fn restore(&mut self, p: &mut Particles, dt: f32) {
        let (x, x_prev, v, inv_mass) = (&mut p.x, &p.x_prev, &p.v, &p.inv_mass);
        for r in &self.ranges {
            let part = Part {
                x_prev: &x_prev[r.clone()],
                v: &v[r.clone()],
                dt: dt as f64,
                left: &self.left[r.clone()],
                inv_mass: &inv_mass[r.clone()],
            };
            let Some((turn, centre)) = part.spurious_turn(&x[r.clone()]) else {
                continue;
            };
            (&mut x[r.clone()], &mut self.left[r.clone()])
                .into_par_iter()
                .with_min_len(MIN_TASK)
                .for_each(|(xi, left)| {
                    let step = turn.cross(xi.as_dvec3() - centre).as_vec3();
                    let moved = *xi + step;
                    *left = step - (moved - *xi);
                    *xi = moved;
                });
        }
    }

    /// The particle ranges of the free cloths.
    pub fn ranges(&self) -> &[Range<usize>] {
        &self.ranges
    }
}

/// One free cloth's particles at the start of the substep, its time
/// step, and what the last turn left.
struct Part<'a> {
    x_prev: &'a [Vec3],
    v: &'a [Vec3],
    dt: f64,
    left: &'a [Vec3],
    inv_mass: &'a [f32],
}

impl Part<'_> {
    /// The rotation vector `theta` whose turn `x += theta x (x - c)` about
    /// the centre of mass `c` cancels the angular impulse of the
    /// projection and of what the last turn left, with `c`; `None` for a
    /// cloth whose particles lie on a line (no turn is defined).
    fn spurious_turn(&self, x: &[Vec3]) -> Option<(DVec3, DVec3)> {
        let mass = self.sum(0.0, |m, _| m);
        let centre = self.sum(DVec3::ZERO, |m, i| x[i].as_dvec3() * m) / mass;
        let centre_prev = self.sum(DVec3::ZERO, |m, i| self.x_prev[i].as_dvec3() * m) / mass;
        let p = |i: usize| self.x_prev[i].as_dvec3() - centre_prev;
        // sum m p x D (the angular impulse times dt), with p the positions
        // before the substep about their centre and D how far x is from
        // the exact prediction, with what the last turn left (so the
        // prediction's round-off is taken back too).
        let impulse = self.sum(DVec3::ZERO, |m, i| {
            let moved = (x[i] - self.x_prev[i]).as_dvec3();
            let d = moved - self.v[i].as_dvec3() * self.dt - self.left[i].as_dvec3();
            p(i).cross(d) * m
        });
        // theta -> sum m p x (theta x r), r the positions now about theirs.
        let map = self.sum(DMat3::ZERO, |m, i| {
            let r = x[i].as_dvec3() - centre;
            (DMat3::from_diagonal(DVec3::splat(p(i).dot(r))) - outer(r, p(i))) * m
        });
        let scale = map.x_axis.x + map.y_axis.y + map.z_axis.z;
        let det = map.determinant();
        if det.is_nan() || det.abs() <= 1e-9 * scale.powi(3) {
            return None;
        }
        let turn = -(map.inverse() * impulse);
        (turn.length() > SMALLEST_TURN).then_some((turn, centre))
    }

    /// `zero + sum_i f(m_i, i)` over the particles, `m_i` the mass.
    fn sum<T>(&self, zero: T, f: impl Fn(f64, usize) -> T + Sync) -> T
    where
        T: Copy + Send + Sync + std::ops::Add<Output = T>,
    {
        (0..self.x_prev.len())
            .into_par_iter()
            .with_min_len(MIN_TASK)
            .map(|i| f(1.0 / self.inv_mass[i] as f64, i))
            .reduce(|| zero, |a, b| a + b)
    }
}

/// The matrix `a b^T`.
fn outer(a: DVec3, b: DVec3) -> DMat3 {
    DMat3::from_cols(a * b.x, a * b.y, a * b.z)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_rng::Rng;

    const DT: f32 = 1e-3;

    /// Particles far from the origin, predicted from random velocities over
    /// [`DT`], then moved by pairs pushing each other apart (internal
    /// forces) and by a spurious turn of `turn` about their centre.
    fn projected(turn: Vec3) -> Particles {
        let mut rng = Rng(7);
        let (dt, n) = (DT, 40);
        let mut p = Particles::default();
        for _ in 0..n {
            p.inv_mass.push(0.5 + rng.unit() * 4.0);
            p.x_prev.push(rng.vec3() + Vec3::new(3.0, -2.0, 5.0));
            p.v.push(rng.vec3() - 0.5);
        }
        p.x = (0..n).map(|i| p.x_prev[i] + p.v[i] * dt).collect();
        for i in (0..n).step_by(2) {
            let push = (p.x_prev[i] - p.x_prev[i + 1]) * (rng.unit() - 0.5) * 1e-3;
            p.x[i] += push * p.inv_mass[i];
            p.x[i + 1] -= push * p.inv_mass[i + 1];
        }
        let centre = mass_centre(&p.x, &p.inv_mass);
        for x in &mut p.x {
            *x += turn.cross(*x - centre);
        }
        p
    }

    fn mass_centre(x: &[Vec3], inv_mass: &[f32]) -> Vec3 {
        let mass: f32 = inv_mass.iter().map(|w| 1.0 / w).sum();
        x.iter().zip(inv_mass).map(|(x, w)| *x / *w).sum::<Vec3>() / mass
    }

    /// Which velocities [`momenta`] reads.
    enum Ends<'a> {
        /// The predicted ones.
        Predicted,
        /// Those the substep ends with, `(x - x_prev) / dt`, had each
        /// particle moved by this much more.
        After(&'a [Vec3]),
    }

    /// Angular momentum about the centre of mass and linear momentum of
    /// the velocities `ends` (for those the substep ends with, `x_prev`
    /// and `x` about their centres are equal lever arms).
    fn momenta(p: &Particles, dt: f32, ends: Ends) -> (DVec3, DVec3) {
        let m = |i: usize| 1.0 / p.inv_mass[i] as f64;
        let mass: f64 = (0..p.len()).map(m).sum();
        let centre = (0..p.len())
            .map(|i| p.x_prev[i].as_dvec3() * m(i))
            .sum::<DVec3>()
            / mass;
        let v = |i: usize| match ends {
            Ends::Predicted => p.v[i].as_dvec3(),
            Ends::After(more) => {
                ((p.x[i] - p.x_prev[i]).as_dvec3() + more[i].as_dvec3()) / dt as f64
            }
        };
        let angular = (0..p.len())
            .map(|i| (p.x_prev[i].as_dvec3() - centre).cross(v(i)) * m(i))
            .sum();
        let linear = (0..p.len()).map(|i| v(i) * m(i)).sum();
        (angular, linear)
    }

    fn free(p: &Particles) -> FreeParts {
        FreeParts {
            ranges: std::iter::once(0..p.len()).collect(),
            left: vec![Vec3::ZERO; p.len()],
        }
    }

    #[test]
    fn the_turn_takes_back_a_spurious_rotation_and_keeps_the_rest() {
        let (mut p, dt) = (projected(Vec3::new(2e-4, -1e-4, 3e-4)), DT);
        let before = p.x.clone();
        let exact = momenta(&p, dt, Ends::Predicted);
        let (spun, pushed) = momenta(&p, dt, Ends::After(&vec![Vec3::ZERO; p.len()]));
        let mut parts = free(&p);
        parts.restore(&mut p, dt);
        // What the turn could not move a particle by (round-off, 5e-7 m
        // this far out) is taken back at the next substep: count it here.
        let (angular, linear) = momenta(&p, dt, Ends::After(&parts.left));
        let scale = exact.0.length();

        assert!(
            spun.distance(exact.0) > 0.1 * scale,
            "the turn made a difference to begin with"
        );
        assert!(
            angular.distance(exact.0) < 1e-4 * scale,
            "angular momentum {angular} after the turn, {} predicted",
            exact.0
        );
        assert!(
            linear.distance(pushed) < 1e-6 * pushed.length(),
            "linear momentum {pushed} became {linear}"
        );
        for i in 0..p.len() {
            for j in 0..i {
                let (was, is) = (before[i].distance(before[j]), p.x[i].distance(p.x[j]));
                assert!(
                    (was - is).abs() < 1e-5 * was,
                    "distance {i} {j}: {was} -> {is}"
                );
            }
        }
    }

    #[test]
    fn a_sheet_on_a_line_is_not_turned() {
        let mut p = projected(Vec3::ZERO);
        for x in p.x.iter_mut().chain(&mut p.x_prev) {
            *x = Vec3::new(x.x, 0.0, 0.0);
        }
        let before = p.x.clone();
        free(&p).restore(&mut p, DT);
        assert_eq!(p.x, before);
    }
}
