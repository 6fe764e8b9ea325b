//! What the solvers share around their own force or constraint
//! step: hard pins that follow their motion, contacts with the colliders,
//! and the plain position-based dynamics loop (Müller et al. 2007) that the
//! shape-matching and Jacobi solvers run: per substep, predict positions
//! from velocities, gravity and wind, put hard pins on their targets, let
//! the solver project its constraints for a number of iterations, resolve
//! contacts and derive velocities from the change of position.

use super::parallel::ColoredConstraints;
use super::{SolverSettings, StageTimes};
use crate::collide::body_contact::BodyContacts;
use crate::collide::{project_contacts, ColliderPose};
use crate::constraint::compliances::AS_BUILT;
use crate::constraint::{Attachment, Substep};
use crate::control::Control;
use crate::force::WindForces;
use crate::model::Model;
use crate::particles::Particles;
use crate::world::World;
use glam::Vec3;
use rayon::prelude::*;

/// Inverse particle masses of the model; zero for hard-pinned particles.
pub fn inverse_masses(model: &Model) -> Vec<f32> {
    model
        .mass
        .iter()
        .map(|&m| if m > 0.0 { 1.0 / m } else { 0.0 })
        .collect()
}

/// Attachments of the model, split into hard ones (kinematic particles put
/// on their targets) and soft ones (pulled with a compliance).
pub fn attachments(model: &Model) -> (HardPins, Vec<Attachment>) {
    let (hard, soft) = model
        .pins
        .iter()
        .map(|p| {
            Attachment::new(
                p.particle,
                model.rest[p.particle as usize],
                p.motion,
                p.compliance,
            )
        })
        .partition(Attachment::is_hard);
    (HardPins(hard), soft)
}

/// Particles pinned with compliance zero: moved onto their targets.
pub struct HardPins(Vec<Attachment>);

impl HardPins {
    /// Number of hard pins.
    pub fn len(&self) -> usize {
        self.0.len()
    }

    /// Whether there are no hard pins.
    pub fn is_empty(&self) -> bool {
        self.0.is_empty()
    }

    /// The pins, in the order their targets are placed.
    pub fn attachments(&self) -> &[Attachment] {
        &self.0
    }

    /// Puts every pinned particle where its motion has its target at time `t`.
    pub fn place(&mut self, x: &mut [Vec3], t: f32) {
        for a in &mut self.0 {
            a.update_target(t);
            x[a.particle[0] as usize] = a.target;
        }
    }
}

/// The start of a substep: wind on the velocities, then the prediction
/// `x += dt v` with gravity and damping, then hard pins on their targets.
pub struct Prediction {
    triangles: Vec<[u32; 3]>,
    wind: WindForces,
    hard_pins: HardPins,
}

impl Prediction {
    /// The prediction stage of `model`, and its soft attachments for the
    /// solver to project.
    pub fn new(model: &Model) -> (Self, Vec<Attachment>) {
        let (hard_pins, soft) = attachments(model);
        let prediction = Prediction {
            triangles: model.triangles.clone(),
            wind: WindForces::new(&model.triangles, model.particle_count()),
            hard_pins,
        };
        (prediction, soft)
    }

    /// Number of hard pins the prediction places.
    pub fn hard_pin_count(&self) -> usize {
        self.hard_pins.len()
    }

    /// Predicts the positions at `t + dt` from the state at `t`.
    pub fn run(
        &mut self,
        p: &mut Particles,
        world: &World,
        damping: f32,
        t: f32,
        dt: f32,
        stages: &mut StageTimes,
    ) {
        if let Some(wind) = &world.wind {
            StageTimes::time(&mut stages.forces, || {
                self.wind.apply(wind, &self.triangles, p, t, dt)
            });
        }
        StageTimes::time(&mut stages.predict, || {
            predict(p, world.gravity, damping, dt);
            self.hard_pins.place(&mut p.x, t + dt);
        });
    }
}

/// Cloth-collider contacts with friction, over one step at a time, and the
/// dynamic rigid bodies: they are predicted, pushed by the cloth and by the
/// static colliders and given their new velocities here, so that every
/// solver moves them with its own substeps.
pub struct Contacts {
    thickness: Vec<f32>,
    poses: Vec<ColliderPose>,
    bodies: BodyContacts,
}

impl Contacts {
    /// Contacts with the model's colliders, with each particle's thickness.
    pub fn new(model: &Model) -> Self {
        Contacts {
            thickness: model.thickness.clone(),
            poses: Vec::new(),
            bodies: BodyContacts::default(),
        }
    }

    /// Pushes the particles out of the colliders as they move from `t` to
    /// `t + dt`, with friction on the motion since `x_prev`; adds the contacts to `stages`.
    /// Dynamic bodies take their substep from `t` to `t + dt` here.
    pub fn resolve(
        &mut self,
        p: &mut Particles,
        world: &mut World,
        t: f32,
        dt: f32,
        stages: &mut StageTimes,
    ) {
        let contacts = StageTimes::time(&mut stages.collisions, || {
            let dynamic = world.colliders.iter().any(|c| c.is_dynamic());
            if dynamic {
                for c in &mut world.colliders {
                    if let Some(body) = &mut c.body {
                        body.predict(world.gravity, dt);
                    }
                }
            }
            self.poses.clear();
            self.poses.extend(
                world
                    .colliders
                    .iter()
                    .map(|c| ColliderPose::over(c, t, t + dt)),
            );
            let mut found = project_contacts(
                &mut p.x,
                &p.x_prev,
                &p.inv_mass,
                &self.thickness,
                &world.colliders,
                &self.poses,
            );
            if dynamic {
                found += self.resolve_bodies(p, world, dt);
            }
            found
        });
        stages.contacts += contacts as u64;
    }

    /// Cloth-body then body-static contacts of every dynamic body, then
    /// the bodies' velocities.
    fn resolve_bodies(&mut self, p: &mut Particles, world: &mut World, dt: f32) -> usize {
        let mut found = 0;
        for j in 0..world.colliders.len() {
            let Some(mut body) = world.colliders[j].body.take() else {
                continue;
            };
            found += self.bodies.cloth_body(
                &mut p.x,
                &p.x_prev,
                &p.inv_mass,
                &self.thickness,
                &mut body,
                j,
                &world.colliders,
                &self.poses,
            );
            found += self
                .bodies
                .body_static(&mut body, j, &world.colliders, &self.poses);
            body.update_velocities(dt);
            world.colliders[j].body = Some(body);
        }
        found
    }
}

/// The PBD frame loop around a solver's constraint projection.
pub struct PbdLoop {
    settings: SolverSettings,
    prediction: Prediction,
    /// Solved with their XPBD compliance after each constraint iteration.
    soft_pins: ColoredConstraints<Attachment>,
    contacts: Contacts,
}

impl PbdLoop {
    /// The loop for `model`: its prediction, soft pins and contacts.
    pub fn new(model: &Model, settings: &SolverSettings) -> Self {
        let n = model.particle_count();
        let (prediction, soft) = Prediction::new(model);
        PbdLoop {
            settings: *settings,
            prediction,
            soft_pins: ColoredConstraints::new(soft, n),
            contacts: Contacts::new(model),
        }
    }

    /// Takes new substep, iteration and damping settings for the next step.
    pub fn set_settings(&mut self, settings: &SolverSettings) {
        self.settings = *settings;
    }

    /// Pins of both kinds.
    pub fn pin_count(&self) -> usize {
        self.prediction.hard_pin_count() + self.soft_pins.len()
    }

    /// Advances one frame; `project` runs one iteration of the solver's constraints.
    pub fn step(
        &mut self,
        p: &mut Particles,
        (world, control): (&mut World, &Control),
        stages: &mut StageTimes,
        mut project: impl FnMut(&mut Particles),
    ) {
        let substeps = self.settings.substeps;
        for (t, dt, control) in super::substep_times(world.time, control, substeps) {
            self.substep(p, (world, &control), (t, dt), stages, &mut project);
        }
    }

    fn substep(
        &mut self,
        p: &mut Particles,
        (world, control): (&mut World, &Control),
        (t, dt): (f32, f32),
        stages: &mut StageTimes,
        project: &mut impl FnMut(&mut Particles),
    ) {
        self.prediction
            .run(p, world, self.settings.damping, t, dt, stages);
        StageTimes::time(&mut stages.constraints, || {
            self.soft_pins.update(|_, a| a.update_target(t + dt));
            self.soft_pins.reset_lambda();
            let step = Substep::new(dt, AS_BUILT, control.fold);
            for _ in 0..self.settings.iterations {
                project(p);
                self.soft_pins.solve(&mut p.x, &p.inv_mass, &step);
            }
            if let Some(grab) = &control.grab {
                grab.project(&mut p.x, &p.inv_mass, dt);
            }
        });
        self.contacts.resolve(p, world, t, dt, stages);
        StageTimes::time(&mut stages.predict, || update_velocities(p, dt));
    }
}

/// `v += dt g`, damping, `x_prev = x`, `x += dt v` for every dynamic particle.
pub(super) fn predict(p: &mut Particles, gravity: Vec3, damping: f32, dt: f32) {
    let keep = (1.0 - damping * dt).max(0.0);
    (&mut p.x, &mut p.x_prev, &mut p.v, &p.inv_mass)
        .into_par_iter()
        .with_min_len(2048)
        .for_each(|(x, x_prev, v, &w)| {
            *x_prev = *x;
            if w > 0.0 {
                *v = (*v + gravity * dt) * keep;
                *x += *v * dt;
            }
        });
}

/// `v = (x - x_prev) / dt`.
pub(super) fn update_velocities(p: &mut Particles, dt: f32) {
    let inv_dt = 1.0 / dt;
    (&p.x, &p.x_prev, &mut p.v)
        .into_par_iter()
        .with_min_len(2048)
        .for_each(|(x, x_prev, v)| *v = (*x - *x_prev) * inv_dt);
}
