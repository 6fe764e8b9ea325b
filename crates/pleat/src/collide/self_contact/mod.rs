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
//! Candidates are found within the thickness plus a margin and kept over
//! substeps until some particle has moved more than half the margin from
//! where it was at the build, relative to the middle of all displacements
//! (a pair's distance changes by at most the difference of its particles'
//! displacements, so no pair left out can have come within the thickness).
//! Paper, folding slowly over many substeps, keeps its candidates with a
//! margin of [`PAPER_MARGIN`] thicknesses; cloth builds them every substep
//! (a margin of zero), which measured faster on fast, crumpled cloth.
//!
//! Solve (Jacobi): each contact computes its corrections from the same
//! positions (in parallel); the few that act are then summed per particle in
//! contact order (in parallel, each task owning a range of particles and
//! reading every acting contact), each scaled by a relaxation factor over
//! the number of contacts that move its busiest particle (the averaging of
//! Macklin et al. 2014, section 4.2, with one scale per contact so that the
//! total momentum is kept): no atomics, bit-identical for any thread count.
//! After the first iteration only the contacts with a particle that the
//! last one moved are evaluated again (a contact's correction depends on
//! its particles' positions alone, so the others would find what they
//! found before: nothing); an iteration where no contact acts ends the solve.

mod broad_phase;
mod csr;
mod folded;
mod layer_sides;
mod narrow_phase;
mod normal_cone;
mod patches;
mod rest;

use super::Friction;
use crate::model::Model;
use broad_phase::BroadPhase;
use glam::Vec3;
use narrow_phase::Contact;
pub use narrow_phase::ContactMasses;
use patches::Patches;
use rayon::prelude::*;
use rest::RestNeighbourhood;
pub use rest::{CLOTH_EXCLUSION, PAPER_EXCLUSION};
use serde::{Deserialize, Serialize};
use std::time::Duration;
use web_time::Instant;

/// Jacobi iterations per substep over cloth's self-contacts, on both
/// backends. With three, a cloth of 128 x 128 crumpling as it landed
/// (`fold_onto_itself_128.json`, 10 substeps) was left crossing itself
/// 567 times at frame 30: a particle in many contacts moves by the average
/// of their corrections and ended the substep short of clearing them.
/// Four left 4, five none at any 10th frame of its 600.
pub const CLOTH_ITERATIONS: usize = 5;
/// Jacobi iterations per substep where every cloth is paper, which folds
/// with 16 times cloth's substeps (160 a frame): more made the folds that
/// jam strain further (Moosers' train 2.4 to 5.6 %) and freed none.
pub const PAPER_ITERATIONS: usize = 3;

/// The Jacobi iterations per substep of `model`'s self-contacts.
pub fn iterations(model: &Model) -> usize {
    if all_paper(model) {
        PAPER_ITERATIONS
    } else {
        CLOTH_ITERATIONS
    }
}

/// Whether every cloth of `model` is paper.
pub fn all_paper(model: &Model) -> bool {
    model.cloths.iter().all(|c| c.paper.is_some())
}

/// Jacobi over-relaxation of the gathered corrections.
const RELAXATION: f32 = 1.5;
/// Smallest rayon task, in contacts.
const MIN_TASK: usize = 1024;
/// Margin of the kept candidates when every cloth is paper, in thicknesses.
const PAPER_MARGIN: f32 = 1.0;

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
    /// Whether the substep built its candidates anew.
    pub built: bool,
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
    /// Jacobi iterations per substep ([`iterations`]).
    iterations: usize,
    rest: RestNeighbourhood,
    patches: Patches,
    broad_phase: BroadPhase,
    /// Reach of the kept candidates beyond the thickness (m); zero builds
    /// them every substep.
    margin: f32,
    /// Positions at the last build; empty before the first.
    x_build: Vec<Vec3>,
    contacts: Vec<Contact>,
    /// Contacts that acted in this iteration, in order, with the
    /// corrections of their particles.
    acting: Vec<Acted>,
    /// Per particle: sum and number of the corrections of this iteration
    /// (zero again once applied).
    sum: Vec<Vec3>,
    count: Vec<u32>,
    /// Per particle: whether the last iteration moved it.
    moved: Vec<bool>,
    /// Per acting contact: the scale of its corrections.
    scale: Vec<f32>,
}

impl SelfContacts {
    /// Self-contact state for the particles of `model` under `settings`, with
    /// the rest neighbourhood measured once.
    pub fn new(model: &Model, settings: SelfCollision) -> Self {
        let n = model.particle_count();
        let rest = RestNeighbourhood::new(model, settings.thickness);
        SelfContacts {
            settings,
            iterations: iterations(model),
            margin: if all_paper(model) {
                PAPER_MARGIN * settings.thickness
            } else {
                0.0
            },
            x_build: Vec::new(),
            patches: Patches::new(&rest),
            rest,
            broad_phase: BroadPhase::default(),
            contacts: Vec::new(),
            acting: Vec::new(),
            sum: vec![Vec3::ZERO; n],
            count: vec![0; n],
            moved: vec![false; n],
            scale: Vec::new(),
        }
    }

    /// Resolves contacts between the substep's start `x_prev` and its
    /// predicted positions `x` (moved in place), weighing the particles by
    /// `masses`.
    pub fn project(
        &mut self,
        x: &mut [Vec3],
        x_prev: &[Vec3],
        masses: ContactMasses<'_>,
    ) -> SelfContactStats {
        let start = Instant::now();
        let built = self.needs_build(x);
        if built {
            self.broad_phase.find(
                &self.rest,
                &self.patches,
                x_prev,
                x,
                masses.inv_mass,
                (self.settings.thickness, self.margin),
                &mut self.contacts,
            );
            self.x_build.clear();
            self.x_build.extend_from_slice(x);
        }
        let broad_phase = start.elapsed();
        let xs: &[Vec3] = x;
        self.contacts
            .par_iter_mut()
            .with_min_len(MIN_TASK)
            .for_each(|c| {
                if !built {
                    c.refresh(xs, x_prev);
                }
                c.detect_crossing(xs, x_prev)
            });
        let mut stats = SelfContactStats {
            candidates: self.contacts.len(),
            built,
            broad_phase,
            ..SelfContactStats::default()
        };
        for iteration in 0..self.iterations {
            let all = iteration == 0;
            stats.active = self.solve(x, x_prev, masses, all, &mut stats.solve);
            // Nothing moved: the next iterations would find the same.
            if stats.active == 0 {
                break;
            }
        }
        stats.narrow_phase = start.elapsed() - broad_phase - stats.solve;
        stats
    }

    /// Whether the kept candidates may miss a contact at positions `x`: some
    /// particle moved more than half the margin from its place at the
    /// build, relative to the middle of all displacements (always, with no
    /// margin or no build yet).
    fn needs_build(&self, x: &[Vec3]) -> bool {
        if self.margin == 0.0 || self.x_build.len() != x.len() {
            return true;
        }
        let displacement = |k: usize| x[k] - self.x_build[k];
        let (low, high) = (0..x.len()).fold((Vec3::MAX, Vec3::MIN), |(l, h), k| {
            (l.min(displacement(k)), h.max(displacement(k)))
        });
        let middle = 0.5 * (low + high);
        let limit = (0.5 * self.margin).powi(2);
        (0..x.len()).any(|k| (displacement(k) - middle).length_squared() > limit)
    }

    /// One Jacobi iteration over the candidates (`all`), or over those with
    /// a particle the last iteration moved; returns the active count and
    /// adds the time spent applying their corrections to `solve`.
    fn solve(
        &mut self,
        x: &mut [Vec3],
        x_prev: &[Vec3],
        masses: ContactMasses<'_>,
        all: bool,
        solve: &mut Duration,
    ) -> usize {
        let s = self.settings;
        let xs: &[Vec3] = x;
        let moved = &self.moved;
        // Only the few that act are kept: writing every contact's
        // corrections cost more than computing them.
        self.acting.clear();
        self.acting.par_extend(
            self.contacts
                .par_iter()
                .with_min_len(MIN_TASK)
                .filter(|c| all || c.particles().iter().any(|&p| moved[p as usize]))
                .filter_map(|c| {
                    let delta = c.correction(xs, x_prev, masses, &s)?;
                    Some(Acted::new(c.particles(), delta))
                }),
        );
        let found = self.acting.len();
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
    /// opposite, so the total momentum is kept). Each task owns a range of
    /// particles and sums their corrections in contact order, so the result
    /// does not depend on the thread count.
    fn gather(&mut self, x: &mut [Vec3]) {
        let chunk = x.len().div_ceil(rayon::current_num_threads()).max(1);
        let acting = &self.acting;
        self.count
            .par_chunks_mut(chunk)
            .enumerate()
            .for_each(|(c, count)| {
                for_each_in(acting, c * chunk, count.len(), |_, p, d| {
                    count[p] += u32::from(d != Vec3::ZERO);
                });
            });
        let count = &self.count;
        self.scale.clear();
        self.scale.par_extend(acting.par_iter().map(|a| {
            let most = a
                .particles()
                .map(|p| count[p as usize])
                .max()
                .unwrap_or(1)
                .max(1);
            RELAXATION / most as f32
        }));
        let scale = &self.scale;
        let ranges = (
            x.par_chunks_mut(chunk),
            self.sum.par_chunks_mut(chunk),
            self.count.par_chunks_mut(chunk),
            self.moved.par_chunks_mut(chunk),
        );
        ranges
            .into_par_iter()
            .enumerate()
            .for_each(|(c, (x, sum, count, moved))| {
                for_each_in(acting, c * chunk, x.len(), |i, p, d| sum[p] += d * scale[i]);
                // A particle that no correction moved has a count of zero
                // and a sum of zero.
                for (((x, sum), count), moved) in x.iter_mut().zip(sum).zip(count).zip(moved) {
                    *moved = *count > 0;
                    if *moved {
                        *x += *sum;
                        (*sum, *count) = (Vec3::ZERO, 0);
                    }
                }
            });
    }
}

/// A contact that acted in an iteration: its particles and their
/// corrections, copied out of the candidates so that the passes over the
/// acting contacts read them in order.
#[derive(Clone, Copy, Debug)]
struct Acted {
    /// The contact's particles, [`Acted::NONE`] past the last.
    particles: [u32; 4],
    delta: [Vec3; 4],
}

impl Acted {
    /// Marks the slots of a contact of fewer than four particles.
    const NONE: u32 = u32::MAX;

    fn new(particles: &[u32], delta: [Vec3; 4]) -> Self {
        let mut all = [Self::NONE; 4];
        all[..particles.len()].copy_from_slice(particles);
        Acted {
            particles: all,
            delta,
        }
    }

    fn particles(&self) -> impl Iterator<Item = u32> + '_ {
        self.particles.iter().copied().filter(|&p| p != Self::NONE)
    }
}

/// Calls `f(i, p - start, d)` for each particle `p` in `start..start + len`
/// of the `i`-th acting contact and its correction `d`, in contact order
/// ([`Acted::NONE`] lies past any range).
fn for_each_in(acting: &[Acted], start: usize, len: usize, mut f: impl FnMut(usize, usize, Vec3)) {
    for (i, a) in acting.iter().enumerate() {
        for (&p, d) in a.particles.iter().zip(a.delta) {
            let p = (p as usize).wrapping_sub(start);
            if p < len {
                f(i, p, d);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::origami::{builtin, Sheet, SheetOptions};

    fn paper_contacts() -> (SelfContacts, Vec<Vec3>) {
        let pattern = builtin("waterbomb-base").unwrap();
        let sheet = Sheet::from_pattern(&pattern, &SheetOptions::default()).unwrap();
        let (model, _) = crate::folding::paper_model(&sheet);
        let settings = SelfCollision {
            enabled: true,
            ..SelfCollision::default()
        };
        (SelfContacts::new(&model, settings), model.rest.clone())
    }

    /// Kept candidates are built again once two particles may have come a
    /// margin closer: not for a motion of the whole sheet, and not for
    /// relative motion within half the margin a particle.
    #[test]
    fn paper_builds_its_candidates_again_only_after_relative_motion() {
        let (mut contacts, rest) = paper_contacts();
        let margin = contacts.margin;
        assert!(margin > 0.0);
        assert!(contacts.needs_build(&rest), "no build yet");
        contacts.x_build = rest.clone();
        let carried: Vec<Vec3> = rest
            .iter()
            .map(|&p| p + Vec3::new(3.0, -1.0, 2.0))
            .collect();
        assert!(!contacts.needs_build(&carried), "carried whole");
        let mut x = rest.clone();
        x[0].z += 0.9 * margin;
        assert!(
            !contacts.needs_build(&x),
            "within half the margin of the middle"
        );
        x[0].z += 0.2 * margin;
        assert!(
            contacts.needs_build(&x),
            "one particle a margin away from the rest"
        );
    }

    /// Two cloths pressed into each other, the upper one's heights jittered: a
    /// substep's solve, evaluating after the first iteration only the
    /// contacts whose particles moved, ends bit for bit where evaluating
    /// every contact every iteration ends.
    #[test]
    fn iterations_over_the_moved_contacts_end_where_iterations_over_all_do() {
        let spec = crate::mesh::GridSpec::new(12, 12, [0.3, 0.3]);
        let mut model = Model::default();
        model.add_cloth("below", spec.build(), Default::default(), &[], false);
        let mut above = spec.build();
        let mut rng = crate::test_rng::Rng(7);
        for p in &mut above.positions {
            *p += Vec3::new(0.004, 0.002 + 0.004 * rng.unit(), 0.003);
        }
        model.add_cloth("above", above, Default::default(), &[], false);
        let settings = SelfCollision {
            enabled: true,
            thickness: 0.01,
            ..SelfCollision::default()
        };
        let inv_mass: Vec<f32> = model.mass.iter().map(|m| 1.0 / m).collect();
        let masses = ContactMasses::free(&inv_mass);
        let x_prev = model.rest.clone();
        let mut fast = x_prev.clone();
        let mut contacts = SelfContacts::new(&model, settings);
        let stats = contacts.project(&mut fast, &x_prev, masses);
        assert!(stats.active > 0, "the last iteration still acted");
        let mut every = x_prev.clone();
        let mut reference = SelfContacts::new(&model, settings);
        reference.broad_phase.find(
            &reference.rest,
            &reference.patches,
            &x_prev,
            &every,
            &inv_mass,
            (settings.thickness, 0.0),
            &mut reference.contacts,
        );
        let mut solve = Duration::ZERO;
        let mut acted = 0;
        for _ in 0..reference.iterations {
            acted = reference.solve(&mut every, &x_prev, masses, true, &mut solve);
        }
        assert_eq!(acted, stats.active);
        assert!(fast.iter().zip(&x_prev).any(|(a, b)| a != b), "moved");
        assert_eq!(fast, every);
    }

    /// Cloth builds its candidates every substep.
    #[test]
    fn cloth_builds_its_candidates_every_substep() {
        let mesh = crate::mesh::GridSpec::new(4, 4, [0.3, 0.3]).build();
        let mut model = Model::default();
        model.add_cloth("c", mesh, Default::default(), &[], false);
        let mut contacts = SelfContacts::new(&model, SelfCollision::default());
        contacts.x_build = model.rest.clone();
        assert!(contacts.needs_build(&model.rest));
    }
}
