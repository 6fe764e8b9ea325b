//! Jacobi position-based dynamics, the textbook GPU form (Macklin et al.
//! 2014): every distance constraint (stretch, shear and skip-one bending) is
//! projected against the same positions; the corrections are gathered per
//! particle, averaged over the constraints that touch it and applied all at
//! once, scaled by the relaxation factor omega:
//! `x_i += omega / n_i * sum_j dx_ij`. With a PBD stiffness k in [0, 1], the
//! correction of a constraint `C = |x_a - x_b| - rest_length` is
//! `dx_a = -k w_a / (w_a + w_b) C n`, `dx_b = +k w_b / (w_a + w_b) C n`.
//!
//! Both passes run in parallel without write conflicts: one result per
//! constraint, then one gather per particle over its incident constraints in
//! a fixed order, so the result does not depend on the thread count.

use super::position_based::PbdLoop;
use super::springs::{spring_pairs, SpringKind};
use super::{SolverKind, SolverSettings, StageTimes};
use crate::constraint::DistanceConstraint;
use crate::control::Control;
use crate::mesh::incidence::Incidence;
use crate::model::Model;
use crate::particles::Particles;
use crate::world::World;
use glam::Vec3;
use rayon::prelude::*;

/// Smallest number of items a rayon task takes on.
const MIN_TASK: usize = 1024;

/// Jacobi PBD: every distance constraint projected against the same positions,
/// corrections averaged per particle and relaxed.
pub struct JacobiPbd {
    frame: PbdLoop,
    relaxation: f32,
    set: JacobiConstraints,
    /// Corrections of each constraint's two particles in the current iteration.
    corrections: Vec<[Vec3; 2]>,
}

/// The constraints Jacobi PBD projects, shared by the backends.
pub struct JacobiConstraints {
    /// Distance constraints; their compliance is unused.
    pub constraints: Vec<DistanceConstraint>,
    /// PBD stiffness in [0, 1] of each constraint.
    pub stiffness: Vec<f32>,
    /// The constraints at each particle, for the gather.
    pub incidence: Incidence,
}

impl JacobiConstraints {
    /// Stretch, shear and skip-one bending constraints of every cloth.
    pub fn new(model: &Model) -> Self {
        let mut constraints = Vec::new();
        let mut stiffness = Vec::new();
        for cloth in &model.cloths {
            let k = cloth.material.pbd_stiffness;
            for pair in spring_pairs(cloth) {
                constraints.push(DistanceConstraint::at_rest(pair.v, &model.rest, 0.0));
                let base = match pair.kind {
                    SpringKind::Structural | SpringKind::Shear => k.stretch,
                    SpringKind::Bend => k.bend,
                };
                stiffness.push((base * pair.weight).min(1.0));
            }
        }
        let incidence = Incidence::new(&constraints, model.particle_count(), |c| &c.v);
        JacobiConstraints {
            constraints,
            stiffness,
            incidence,
        }
    }
}

impl JacobiPbd {
    /// The solver for `model`, its constraints at the rest shape.
    pub fn new(model: &Model, settings: &SolverSettings) -> Self {
        let set = JacobiConstraints::new(model);
        JacobiPbd {
            frame: PbdLoop::new(model, settings),
            relaxation: settings.relaxation,
            corrections: vec![[Vec3::ZERO; 2]; set.constraints.len()],
            set,
        }
    }
}

impl super::Solver for JacobiPbd {
    fn kind(&self) -> SolverKind {
        SolverKind::JacobiPbd
    }

    fn constraint_count(&self) -> usize {
        self.set.constraints.len() + self.frame.pin_count()
    }

    fn set_settings(&mut self, settings: &SolverSettings) {
        self.frame.set_settings(settings);
        self.relaxation = settings.relaxation;
    }

    fn step(
        &mut self,
        particles: &mut Particles,
        world: &mut World,
        control: &Control,
        stages: &mut StageTimes,
    ) {
        let mut sweep = Sweep {
            constraints: &self.set.constraints,
            stiffness: &self.set.stiffness,
            corrections: &mut self.corrections,
            incidence: &self.set.incidence,
            relaxation: self.relaxation,
        };
        self.frame
            .step(particles, (world, control), stages, |p| sweep.iterate(p));
    }
}

/// One Jacobi iteration's data, borrowed from the solver.
struct Sweep<'a> {
    constraints: &'a [DistanceConstraint],
    stiffness: &'a [f32],
    corrections: &'a mut [[Vec3; 2]],
    incidence: &'a Incidence,
    relaxation: f32,
}

impl Sweep<'_> {
    /// Projects every constraint against the same positions, then applies
    /// the averaged, relaxed corrections.
    fn iterate(&mut self, p: &mut Particles) {
        let (x, inv_mass) = (&p.x, &p.inv_mass);
        self.corrections
            .par_iter_mut()
            .zip(self.constraints)
            .zip(self.stiffness)
            .with_min_len(MIN_TASK)
            .for_each(|((dx, c), &k)| *dx = correction(c, k, x, inv_mass));
        let (corrections, incidence, omega) = (&*self.corrections, self.incidence, self.relaxation);
        p.x.par_iter_mut()
            .enumerate()
            .with_min_len(MIN_TASK)
            .for_each(|(i, xi)| {
                let slots = incidence.of(i);
                if inv_mass[i] == 0.0 || slots.is_empty() {
                    return;
                }
                let sum: Vec3 = slots
                    .iter()
                    .map(|s| corrections[s.element as usize][s.end as usize])
                    .sum();
                *xi += sum * (omega / slots.len() as f32);
            });
    }
}

/// The PBD corrections of the two particles of `c` with stiffness `k`.
#[inline]
fn correction(c: &DistanceConstraint, k: f32, x: &[Vec3], inv_mass: &[f32]) -> [Vec3; 2] {
    let [a, b] = c.v.map(|i| i as usize);
    let (wa, wb) = (inv_mass[a], inv_mass[b]);
    let w = wa + wb;
    match c.evaluate(x[a], x[b]) {
        Some((value, n)) if w > 0.0 => {
            let s = k * value / w;
            [n * (-s * wa), n * (s * wb)]
        }
        _ => [Vec3::ZERO; 2],
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn correction_restores_rest_length_at_full_stiffness() {
        let c = DistanceConstraint::at_rest([0, 1], &[Vec3::ZERO, Vec3::X], 0.0);
        let x = [Vec3::ZERO, Vec3::new(2.0, 0.0, 0.0)];
        let [da, db] = correction(&c, 1.0, &x, &[1.0, 3.0]);
        assert!(((x[1] + db).distance(x[0] + da) - 1.0).abs() < 1e-6);
        // The lighter particle moves three times as far.
        assert!((db.length() - 3.0 * da.length()).abs() < 1e-6);
    }
}
