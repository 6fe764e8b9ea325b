//! The classic mass-spring cloth (Provot 1995) with Verlet integration, as
//! course projects build it: structural, shear and bending springs with
//! stiffness ks and damping kd per kind, and a global damping that keeps
//! `1 - global_damping / 100` of the velocity each step:
//! `x_next = x + (x - x_prev) (1 - global_damping / 100) + a dt^2`,
//! with `a` from gravity, wind and the springs at `x`.
//!
//! The velocity `v = (x - x_prev) / dt` is kept in the particles for wind,
//! damping springs and metrics. Soft pins are zero-length springs of
//! stiffness `1 / compliance` to their target; hard pins follow their motion.
//! Explicit integration is only conditionally stable: it needs
//! `dt < 2 / omega_max`, with `omega_max^2` about twice the sum of the `ks`
//! around a particle over its mass; past that the cloth explodes, which is
//! what this solver is here to show.

use super::position_based::{attachments, Contacts, HardPins};
use super::springs::{spring_pairs, SpringKind};
use super::{SolverKind, SolverSettings, StageTimes};
use crate::constraint::Attachment;
use crate::control::Control;
use crate::force::{Spring, WindForces};
use crate::material::SpringCoefficients;
use crate::mesh::incidence::Incidence;
use crate::model::Model;
use crate::particles::Particles;
use crate::world::World;
use glam::Vec3;
use rayon::prelude::*;

/// Smallest number of items a rayon task takes on.
const MIN_TASK: usize = 1024;

/// The classic mass-spring cloth with Verlet integration.
pub struct MassSpring {
    substeps: u32,
    /// Fraction of the velocity kept each step.
    keep: f32,
    springs: Vec<Spring>,
    /// Force of each spring on its first particle in the current step.
    spring_force: Vec<Vec3>,
    incidence: Incidence,
    acceleration: Vec<Vec3>,
    hard_pins: HardPins,
    soft_pins: Vec<Attachment>,
    contacts: Contacts,
    triangles: Vec<[u32; 3]>,
    wind: WindForces,
}

impl MassSpring {
    /// The solver for `model`, its springs at rest at the rest shape.
    pub fn new(model: &Model, settings: &SolverSettings) -> Self {
        let n = model.particle_count();
        let springs: Vec<Spring> = model
            .cloths
            .iter()
            .flat_map(|cloth| {
                let (ks, kd) = (
                    cloth.material.spring_stiffness,
                    cloth.material.spring_damping,
                );
                spring_pairs(cloth).into_iter().map(move |pair| {
                    let (k, d) = (coefficient(ks, pair.kind), coefficient(kd, pair.kind));
                    Spring::at_rest(pair.v, &model.rest, k * pair.weight, d)
                })
            })
            .collect();
        let (hard_pins, soft_pins) = attachments(model);
        MassSpring {
            substeps: settings.substeps.max(1),
            keep: 1.0 - settings.global_damping / 100.0,
            spring_force: vec![Vec3::ZERO; springs.len()],
            incidence: Incidence::new(&springs, n, |s| &s.v),
            springs,
            acceleration: vec![Vec3::ZERO; n],
            hard_pins,
            soft_pins,
            contacts: Contacts::new(model),
            triangles: model.triangles.clone(),
            wind: WindForces::new(&model.triangles, n),
        }
    }

    /// One Verlet step from time `t` to `t + dt`.
    fn verlet_step(
        &mut self,
        p: &mut Particles,
        (world, control): (&mut World, &Control),
        t: f32,
        dt: f32,
        stages: &mut StageTimes,
    ) {
        StageTimes::time(&mut stages.forces, || {
            if let Some(wind) = &world.wind {
                self.wind.apply(wind, &self.triangles, p, t, dt);
            }
            self.accumulate_accelerations(p, world.gravity, t);
        });
        StageTimes::time(&mut stages.predict, || {
            self.integrate(p, dt);
            self.hard_pins.place(&mut p.x, t + dt);
            if let Some(grab) = &control.grab {
                grab.project(&mut p.x, &p.inv_mass, dt);
            }
        });
        self.contacts.resolve(p, world, t, dt, stages);
        let inv_dt = 1.0 / dt;
        (&p.x, &p.x_prev, &mut p.v)
            .into_par_iter()
            .with_min_len(MIN_TASK)
            .for_each(|(x, x_prev, v)| *v = (*x - *x_prev) * inv_dt);
    }

    /// `a_i = g + w_i (sum of spring forces + soft pin pull)`, gathered per particle.
    fn accumulate_accelerations(&mut self, p: &Particles, gravity: Vec3, t: f32) {
        let (x, v, inv_mass) = (&p.x, &p.v, &p.inv_mass);
        let springs = &self.springs;
        self.spring_force
            .par_iter_mut()
            .zip(springs)
            .with_min_len(MIN_TASK)
            .for_each(|(f, s)| *f = s.force(x, v));
        let (forces, incidence) = (&self.spring_force, &self.incidence);
        self.acceleration
            .par_iter_mut()
            .enumerate()
            .with_min_len(MIN_TASK)
            .for_each(|(i, a)| {
                let f: Vec3 = incidence
                    .of(i)
                    .iter()
                    .map(|s| {
                        let f = forces[s.element as usize];
                        if s.end == 0 {
                            f
                        } else {
                            -f
                        }
                    })
                    .sum();
                *a = gravity + f * inv_mass[i];
            });
        for pin in &mut self.soft_pins {
            pin.update_target(t);
            let i = pin.particle[0] as usize;
            self.acceleration[i] += (pin.target - x[i]) * (inv_mass[i] / pin.compliance);
        }
    }

    /// `x_next = x + (x - x_prev) keep + a dt^2` for every dynamic particle.
    fn integrate(&self, p: &mut Particles, dt: f32) {
        let (keep, dt2) = (self.keep, dt * dt);
        (
            &mut p.x,
            &mut p.x_prev,
            &p.v,
            &p.inv_mass,
            &self.acceleration,
        )
            .into_par_iter()
            .with_min_len(MIN_TASK)
            .for_each(|(x, x_prev, v, &w, a)| {
                *x_prev = *x;
                if w > 0.0 {
                    *x += *v * (dt * keep) + *a * dt2;
                }
            });
    }
}

/// The coefficient of the springs of `kind`.
fn coefficient(c: SpringCoefficients, kind: SpringKind) -> f32 {
    match kind {
        SpringKind::Structural => c.structural,
        SpringKind::Shear => c.shear,
        SpringKind::Bend => c.bend,
    }
}

impl super::Solver for MassSpring {
    fn kind(&self) -> SolverKind {
        SolverKind::MassSpring
    }

    fn constraint_count(&self) -> usize {
        self.springs.len() + self.hard_pins.len() + self.soft_pins.len()
    }

    fn set_settings(&mut self, settings: &SolverSettings) {
        self.substeps = settings.substeps.max(1);
        self.keep = 1.0 - settings.global_damping / 100.0;
    }

    fn step(
        &mut self,
        particles: &mut Particles,
        world: &mut World,
        control: &Control,
        stages: &mut StageTimes,
    ) {
        for (t, dt, control) in super::substep_times(world.time, control, self.substeps) {
            self.verlet_step(particles, (world, &control), t, dt, stages);
        }
    }
}
