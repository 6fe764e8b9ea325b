//! Self-collision and cloth-cloth collision with a thickness, solved inside
//! each XPBD substep after the cloth constraints:
//!
//! - `broad_phase`: the rest mesh is cut into small connected `patches`;
//!   each substep their swept boxes go into a flat hash grid, pairs of
//!   patches that are one smooth piece of surface are culled by their
//!   `normal_cone`s, and the rest give candidate particle-particle,
//!   vertex-triangle and edge-edge contacts, less the pairs the `rest` mesh
//!   keeps apart;
//! - `narrow_phase`: each candidate's correction, with continuous
//!   collision detection over the substep's motion and friction between layers.
//!
//! Solve (Jacobi): each contact computes its corrections from the same
//! positions (in parallel); the few that act are then summed per particle,
//! each scaled by a relaxation factor over the number of contacts that move
//! its busiest particle (the averaging of Macklin et al. 2014, section 4.2,
//! with one scale per contact so that the total momentum is kept). The sums
//! are taken in parallel in fixed point (integer atomics, 2^-32 m: far
//! finer than an f32 position), whose result does not depend on the order,
//! so a run is bit-identical for any thread count. An iteration where no
//! contact acts ends the solve.

mod broad_phase;
mod narrow_phase;
mod normal_cone;
mod patches;
mod rest;

use super::Friction;
use crate::model::Model;
use broad_phase::BroadPhase;
use glam::Vec3;
use narrow_phase::Contact;
use patches::Patches;
use rayon::prelude::*;
use rest::RestNeighbourhood;
use serde::{Deserialize, Serialize};
use std::sync::atomic::{AtomicI64, AtomicU32, Ordering::Relaxed};
use std::time::Duration;
use web_time::Instant;

/// Jacobi iterations per substep.
const ITERATIONS: usize = 3;
/// Jacobi over-relaxation of the gathered corrections.
const RELAXATION: f32 = 1.5;
/// Smallest rayon task, in contacts.
const MIN_TASK: usize = 1024;

/// Scene settings of self-collision (per solver: all cloths collide with
/// themselves and with each other).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct SelfCollision {
    /// Whether the cloths collide with themselves and each other; default
    /// false.
    pub enabled: bool,
    /// Distance kept between two layers of cloth (m).
    pub thickness: f32,
    /// Coulomb friction between layers.
    pub friction: Friction,
}

impl Default for SelfCollision {
    fn default() -> Self {
        SelfCollision {
            enabled: false,
            thickness: 0.005,
            friction: Friction {
                static_coefficient: 0.3,
                kinetic_coefficient: 0.2,
            },
        }
    }
}

/// Counts and times of the last solve, for profiles.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SelfContactStats {
    /// Contacts that pushed particles apart (in the last iteration that acted).
    pub active: usize,
    /// Candidate contacts of the substep.
    pub candidates: usize,
    /// Broad phase: bounds, grid and candidate search.
    pub broad_phase: Duration,
    /// Narrow phase: continuous detection of the candidates and their
    /// corrections, every iteration.
    pub narrow_phase: Duration,
    /// Solve: the acting corrections gathered per particle and applied.
    pub solve: Duration,
}

/// Self-contact solver state: settings, rest neighbourhood, patches, broad
/// phase buffers and per-contact corrections, all kept between substeps.
#[derive(Clone, Debug)]
pub struct SelfContacts {
    settings: SelfCollision,
    rest: RestNeighbourhood,
    patches: Patches,
    broad_phase: BroadPhase,
    contacts: Vec<Contact>,
    /// Per contact: corrections of its particles, and whether it acted.
    delta: Vec<[Vec3; 4]>,
    active: Vec<bool>,
    /// Per particle: sum and number of the corrections of this iteration
    /// (zero again once applied).
    sums: Sums,
}

/// Units of a correction in the fixed-point sums, per metre.
const FIXED: f32 = 4_294_967_296.0;

/// Per particle: the sum of its corrections in fixed point, and their
/// number, added to from many threads at once; all zero between iterations.
#[derive(Debug, Default)]
struct Sums {
    sum: Vec<[AtomicI64; 3]>,
    count: Vec<AtomicU32>,
}

impl Sums {
    fn new(n: usize) -> Self {
        Sums {
            sum: (0..n).map(|_| Default::default()).collect(),
            count: (0..n).map(|_| AtomicU32::new(0)).collect(),
        }
    }

    /// Adds `d` to particle `p`'s sum.
    fn add(&self, p: u32, d: Vec3) {
        let sum = &self.sum[p as usize];
        for (s, d) in sum.iter().zip(d.to_array()) {
            s.fetch_add((d * FIXED).round() as i64, Relaxed);
        }
    }

    /// Particle `p`'s sum, set back to zero with its count; `None` if
    /// nothing moved it.
    fn take(&self, p: usize) -> Option<Vec3> {
        if self.count[p].swap(0, Relaxed) == 0 {
            return None;
        }
        let [x, y, z] = self.sum[p]
            .each_ref()
            .map(|s| (s.swap(0, Relaxed) as f64 / FIXED as f64) as f32);
        Some(Vec3::new(x, y, z))
    }
}

impl Clone for Sums {
    /// Zero sums of the same size (they are zero between iterations).
    fn clone(&self) -> Self {
        Sums::new(self.count.len())
    }
}

impl SelfContacts {
    /// Self-contact state for the particles of `model` under `settings`, with
    /// the rest neighbourhood measured once.
    pub fn new(model: &Model, settings: SelfCollision) -> Self {
        let n = model.particle_count();
        let rest = RestNeighbourhood::new(model, settings.thickness);
        SelfContacts {
            settings,
            patches: Patches::new(&rest),
            rest,
            broad_phase: BroadPhase::default(),
            contacts: Vec::new(),
            delta: Vec::new(),
            active: Vec::new(),
            sums: Sums::new(n),
        }
    }

    /// Resolves contacts between the substep's start `x_prev` and its
    /// predicted positions `x` (moved in place).
    pub fn project(
        &mut self,
        x: &mut [Vec3],
        x_prev: &[Vec3],
        inv_mass: &[f32],
    ) -> SelfContactStats {
        let start = Instant::now();
        self.broad_phase.find(
            &self.rest,
            &self.patches,
            x_prev,
            x,
            inv_mass,
            self.settings.thickness,
            &mut self.contacts,
        );
        let broad_phase = start.elapsed();
        let xs: &[Vec3] = x;
        self.contacts
            .par_iter_mut()
            .with_min_len(MIN_TASK)
            .for_each(|c| c.detect_crossing(xs, x_prev));
        self.delta.resize(self.contacts.len(), [Vec3::ZERO; 4]);
        self.active.resize(self.contacts.len(), false);
        let mut stats = SelfContactStats {
            candidates: self.contacts.len(),
            broad_phase,
            ..SelfContactStats::default()
        };
        for _ in 0..ITERATIONS {
            stats.active = self.solve(x, x_prev, inv_mass, &mut stats.solve);
            // Nothing moved: the next iterations would find the same.
            if stats.active == 0 {
                break;
            }
        }
        stats.narrow_phase = start.elapsed() - broad_phase - stats.solve;
        stats
    }

    /// One Jacobi iteration over the candidates; returns the active count
    /// and adds the time spent applying their corrections to `solve`.
    fn solve(
        &mut self,
        x: &mut [Vec3],
        x_prev: &[Vec3],
        inv_mass: &[f32],
        solve: &mut Duration,
    ) -> usize {
        let s = self.settings;
        let xs: &[Vec3] = x;
        let sums = &self.sums;
        let found: usize = (&self.contacts, &mut self.delta, &mut self.active)
            .into_par_iter()
            .with_min_len(MIN_TASK)
            .map(|(c, delta, active)| {
                let r = c.correction(xs, x_prev, inv_mass, &s);
                *active = r.is_some();
                *delta = r.unwrap_or_default();
                for (&p, d) in c.particles().iter().zip(*delta) {
                    if d != Vec3::ZERO {
                        sums.count[p as usize].fetch_add(1, Relaxed);
                    }
                }
                usize::from(*active)
            })
            .sum();
        if found == 0 {
            return 0;
        }
        let start = Instant::now();
        self.gather(x);
        *solve += start.elapsed();
        found
    }

    /// Moves the particles by the acting contacts' corrections, each
    /// contact scaled by the relaxation over the largest number of acting
    /// contacts that move one of its particles (Macklin et al. 2014 average per
    /// particle; a common scale per contact keeps its corrections equal and
    /// opposite, so the total momentum is kept). Summed in fixed point, so
    /// the result does not depend on the order or the thread count.
    fn gather(&mut self, x: &mut [Vec3]) {
        let sums = &self.sums;
        (&self.contacts, &self.delta, &self.active)
            .into_par_iter()
            .with_min_len(MIN_TASK)
            .filter(|(_, _, &active)| active)
            .for_each(|(c, delta, _)| {
                let particles = c.particles();
                let most = particles
                    .iter()
                    .map(|&p| sums.count[p as usize].load(Relaxed))
                    .max()
                    .unwrap_or(1)
                    .max(1);
                let scale = RELAXATION / most as f32;
                for (&p, d) in particles.iter().zip(delta) {
                    if *d != Vec3::ZERO {
                        sums.add(p, *d * scale);
                    }
                }
            });
        x.par_iter_mut()
            .enumerate()
            .with_min_len(MIN_TASK)
            .for_each(|(p, x)| {
                if let Some(d) = sums.take(p) {
                    *x += d;
                }
            });
    }
}
