//! XPBD with small steps (Macklin et al. 2016, 2019): each frame is cut into
//! substeps; each substep predicts positions from velocities and external
//! forces, projects the constraints (graph-coloured Gauss-Seidel, colours in
//! parallel) with compliance and Lagrange multipliers, resolves self-contacts
//! (when enabled) and collider contacts and derives velocities from the
//! change of position.

use super::collider_held::ColliderHeld;
use super::grab_reach::GrabReach;
use super::hierarchy::Hierarchy;
use super::momentum::FreeParts;
use super::parallel::ColoredConstraints;
use super::position_based::{attachments, inverse_masses, update_velocities, Contacts, Prediction};
use super::springs::skip_one_pairs;
use super::{SolverKind, SolverSettings, StageTimes};
use crate::collide::SelfContacts;
use crate::constraint::{
    Attachment, ComplianceKind, Compliances, DihedralBending, DistanceConstraint, IsometricBending,
    OrigamiHinge, Substep, Tether,
};
use crate::control::Control;
use crate::material::BendingModel;
use crate::model::{ClothPart, Model};
use crate::origami::Assignment;
use crate::paper::{full_angle, Paper};
use crate::particles::Particles;
use crate::world::World;
use glam::Vec3;
use rayon::iter::Either;
use rayon::prelude::*;

/// Pins a tethered particle hangs from (its nearest ones).
const TETHERS_PER_PARTICLE: usize = 2;

/// Sweeps of the strain limits alone after a substep's iterations (where
/// any edge has one): one sweep inside the iterations leaves a tense sheet
/// at twice its limit, since each edge's correction stretches its
/// neighbours.
pub const STRAIN_LIMIT_SWEEPS: u32 = 2;

/// Most sweeps of the strain limits in one substep: past the first
/// [`STRAIN_LIMIT_SWEEPS`], more follow while an edge is still beyond
/// [`STRAIN_LIMIT_SLACK`] times its limit (a sheet jammed by creases that
/// fight, where each edge's correction stretches its neighbours and two
/// sweeps leave the densest patterns at four to nine times the limit;
/// 24 left Sweet_Dreams_Opus_T-41 at 2.4 % under a first, always-on form
/// of the creases' stiffening, `crate::constraint::hinge::stiffened_error`;
/// 48 left it at 2.1 % once paper gives 20 times its limit while the fold
/// moves, [`MOVING_FOLD_STRAIN_SCALE`]; 96 left HexSpiralTess at 2.0 to
/// 2.2 % once held, on needle triangles where spiral arms meet the
/// sheet's edge at 3 degrees, and 384 at 1.34 %). Only a sheet whose
/// edges stay beyond the slack after the sweeps before pays for them.
pub const MAX_STRAIN_LIMIT_SWEEPS: u32 = 384;

/// How far past its limit an edge may be left at the end of a substep, as
/// a multiple of the limit, before more sweeps follow.
pub const STRAIN_LIMIT_SLACK: f32 = 1.8;

/// How many times its held limit a paper edge may stretch while a fold
/// progress moves (edges of other cloths keep theirs). Driving every
/// crease to `c` times its angle is not the rigid-folding path of a
/// rigidly foldable pattern, and paper held within 1 % jams on the way:
/// at 1 Moosers' train and HexTriFlatFoldableTess ended 180 and 149
/// degrees from their targets; at 2 they fold, but the box-pleated
/// patterns (BoxPleatTessellation, its waves and spiral pyramid, the
/// mazes helloworld and cross), whose right-angled vertices fold only one
/// line at a time rigidly, stay jammed 115 to 180 degrees off; at 20 they
/// fold within 3 degrees, as in Origami Simulator, whose paper stretches
/// by up to 18 % on the way. The limit is whole again once the fold is
/// held ([`FOLD_HOLD_SWEEPS`]).
pub const MOVING_FOLD_STRAIN_SCALE: f32 = 20.0;

/// Most sweeps of the strain limits over the positions alone when a fold
/// comes to rest, before the next frame's prediction: the held limits are
/// met without the corrections becoming velocity. Left to the substeps'
/// sweeps, the snap from 20 times the limit to it set the crane moving
/// (0.95 J of kinetic energy in the frame after; its largest error ended
/// anywhere from 70 to 171 degrees with the number of sweeps). The sweeps
/// stop once no edge is beyond its limit; the crane, jammed, takes all.
pub const FOLD_HOLD_SWEEPS: u32 = 500;

/// Sweeps of the held strain limits between two checks by the self-contacts
/// when a fold comes to rest.
const HOLD_ROUND_SWEEPS: u32 = 10;

/// The XPBD solver: substeps of coloured, compliant constraint projections,
/// then self-contacts and collider contacts.
pub struct Xpbd {
    settings: SolverSettings,
    /// The live compliance table, copied in at every step.
    compliances: Vec<f32>,
    constraints: XpbdConstraints,
    /// Wind, prediction and the hard pins (attachments with compliance zero).
    prediction: Prediction,
    contacts: Contacts,
    /// The reach of a grabbed particle over its cloth.
    grab_reach: GrabReach,
    /// Self-collision and cloth-cloth contact, when enabled.
    self_contacts: Option<SelfContacts>,
    /// The particles the colliders held, which the self-contacts leave.
    collider_held: ColliderHeld,
}

/// The cloth's own constraints as XPBD projects them, each kind coloured
/// and sorted by colour: plain `#[repr(C)]` data that every backend
/// projects in the same order (hinges, distances, bending, isometric
/// bending, soft attachments, tethers), colour after colour.
pub struct XpbdConstraints {
    /// Stretch, shear and skip-one bending edges.
    pub distance: ColoredConstraints<DistanceConstraint>,
    /// Dihedral-angle bending of adjacent triangle pairs.
    pub bending: ColoredConstraints<DihedralBending>,
    /// Isometric bending of adjacent triangle pairs that are flat at rest.
    pub isometric: ColoredConstraints<IsometricBending>,
    /// Origami hinges of paper parts.
    pub hinges: ColoredConstraints<OrigamiHinge>,
    /// Long-range attachments from the pins.
    pub tethers: ColoredConstraints<Tether>,
    /// Attachments with compliance: solved with the other constraints.
    pub soft_attachments: ColoredConstraints<Attachment>,
    /// The coarse levels of the cloths that hold their length, solved
    /// before the rest in each iteration.
    pub hierarchy: Hierarchy,
    /// Sweeps of the distances' strain limits after the iterations, at the
    /// least: [`STRAIN_LIMIT_SWEEPS`] where an edge has a limit, else none.
    pub strain_limit_sweeps: u32,
    /// Whether the strain limits are swept again after a substep's
    /// contacts, where anything touches the cloth
    /// ([`Xpbd::limits_after_contacts`]): where an edge has a limit and no
    /// cloth is paper (whose folds hold their own limits).
    pub limits_after_contacts: bool,
    /// The cloths nothing outside holds, whose projection must not turn them.
    pub free_parts: FreeParts,
    /// The distances' strain limits for a held fold and a moving one.
    pub fold_limits: FoldLimits,
}

/// Each distance constraint's strain limit while the fold is held
/// (`max_stretch` as built) and while it moves (paper's,
/// [`MOVING_FOLD_STRAIN_SCALE`] times that), in the order of
/// [`XpbdConstraints::distance`], and which of them the constraints hold.
#[derive(Clone, Debug)]
pub struct FoldLimits {
    held: Vec<f32>,
    moving: Vec<f32>,
    /// What [`FoldLimits::apply`] last set (`None` before the first call).
    applied: Option<bool>,
    /// Whether the fold came to rest since [`FoldLimits::take_came_to_rest`]
    /// last looked.
    came_to_rest: bool,
}

impl FoldLimits {
    fn new(model: &Model, items: &[DistanceConstraint]) -> Self {
        FoldLimits {
            held: items.iter().map(|d| d.max_stretch).collect(),
            moving: moving_limits(model, items),
            applied: None,
            came_to_rest: false,
        }
    }

    /// Whether the limits of a moving fold differ from a held one's (some
    /// paper edge has a strain limit).
    pub fn differ(&self) -> bool {
        self.held != self.moving
    }

    /// The limits of a fold that is `held` or moves, in the order of the
    /// distance constraints they were built for; `None` where those were
    /// the last applied (nothing to write).
    pub fn apply(&mut self, held: bool) -> Option<&[f32]> {
        if self.applied == Some(held) {
            return None;
        }
        self.applied = Some(held);
        self.came_to_rest = held && self.differ();
        Some(if held { &self.held } else { &self.moving })
    }

    /// Whether the fold came to rest (its limits tightened) since the last
    /// call: the held limits are then to be met over the positions alone
    /// before the next prediction ([`FOLD_HOLD_SWEEPS`]).
    pub fn take_came_to_rest(&mut self) -> bool {
        std::mem::take(&mut self.came_to_rest)
    }
}

impl XpbdConstraints {
    /// Gives the hinges the start and end angles of a fold's step
    /// ([`crate::fold_steps`]), keeping their tracked angles.
    pub fn set_hinge_targets(&mut self, targets: &crate::fold_steps::HingeTargets) {
        self.hinges.update(|_, h| {
            targets.apply(h);
        });
    }

    /// Builds and colours the constraints of every cloth of `model`.
    pub fn new(model: &Model) -> Self {
        let n = model.particle_count();
        let inv_mass = inverse_masses(model);
        let mut distance = Vec::new();
        let mut bending = Vec::new();
        let mut isometric = Vec::new();
        let mut hinges = Vec::new();
        let mut tethers = Vec::new();
        for (index, cloth) in model.cloths.iter().enumerate() {
            distance.par_extend(edge_constraints(cloth, index, &model.rest));
            if let Some(paper) = &cloth.paper {
                hinges.extend(hinge_constraints(paper, cloth, index, &model.rest));
            } else {
                match cloth.material.bending {
                    BendingModel::Dihedral => {
                        bending.par_extend(dihedral_constraints(cloth, index, &model.rest))
                    }
                    BendingModel::Isometric => {
                        let (flat, curved): (Vec<_>, Vec<_>) =
                            dihedral_constraints(cloth, index, &model.rest).partition_map(|d| {
                                match isometric_if_flat(&d, &model.rest) {
                                    Some(c) => Either::Left(c),
                                    None => Either::Right(d),
                                }
                            });
                        append(&mut isometric, flat);
                        append(&mut bending, curved);
                    }
                    BendingModel::SkipOne => {
                        distance.extend(skip_one_constraints(cloth, index, &model.rest))
                    }
                }
            }
            if cloth.tethers {
                let pins = model.hard_pins_of(cloth);
                tethers.extend(Tether::from_pins(
                    &model.rest,
                    &inv_mass,
                    cloth.particles(),
                    &pins,
                    TETHERS_PER_PARTICLE,
                ));
            }
        }
        let (_, soft) = attachments(model);
        let distance = ColoredConstraints::new(distance, n);
        let fold_limits = FoldLimits::new(model, distance.items());
        let strain_limit_sweeps = if distance.items().iter().any(DistanceConstraint::is_limited) {
            STRAIN_LIMIT_SWEEPS
        } else {
            0
        };
        let paper = model.cloths.iter().any(|c| c.paper.is_some());
        XpbdConstraints {
            strain_limit_sweeps,
            limits_after_contacts: strain_limit_sweeps > 0 && !paper,
            free_parts: FreeParts::new(model, &inv_mass),
            hierarchy: Hierarchy::new(model, &inv_mass),
            fold_limits,
            distance,
            bending: ColoredConstraints::new(bending, n),
            isometric: ColoredConstraints::new(isometric, n),
            hinges: ColoredConstraints::new(hinges, n),
            tethers: ColoredConstraints::new(tethers, n),
            soft_attachments: ColoredConstraints::new(soft, n),
        }
    }

    /// Number of constraints projected per iteration.
    pub fn len(&self) -> usize {
        self.distance.len()
            + self.bending.len()
            + self.isometric.len()
            + self.hinges.len()
            + self.tethers.len()
            + self.soft_attachments.len()
            + self.hierarchy.len()
    }

    /// Whether there is no constraint at all.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Gives paper's strain limits those of a fold that is `held` or moves:
    /// while it moves, they allow [`MOVING_FOLD_STRAIN_SCALE`] times their
    /// stretch. Returns whether anything changed ([`FoldLimits::apply`]).
    pub fn hold_fold(&mut self, held: bool) -> bool {
        let Some(limits) = self.fold_limits.apply(held) else {
            return false;
        };
        self.distance.update(|i, d| d.max_stretch = limits[i]);
        true
    }

    /// One substep's projection: `iterations` Gauss-Seidel sweeps from zero
    /// multipliers with the soft attachments' targets at `t_end`, the
    /// strain limits' own sweeps, the free cloths turned back by the angle
    /// the sweeps turned them ([`super::momentum`]), then the hinges'
    /// tracked angles. The substep is `dt` long and ends at `t_end`.
    fn project(
        &mut self,
        p: &mut Particles,
        iterations: u32,
        step: &Substep,
        (t_end, dt): (f32, f32),
    ) {
        self.soft_attachments.update(|_, a| a.update_target(t_end));
        self.distance.reset_lambda();
        self.bending.reset_lambda();
        self.isometric.reset_lambda();
        self.hinges.reset_lambda();
        self.soft_attachments.reset_lambda();
        for _ in 0..iterations {
            let (x, w) = (&mut p.x, &p.inv_mass);
            self.hierarchy.solve(x, w, step);
            self.hinges.solve(x, w, step);
            self.distance.solve(x, w, step);
            self.bending.solve(x, w, step);
            self.isometric.solve(x, w, step);
            self.soft_attachments.solve(x, w, step);
            self.tethers.solve(x, w, step);
        }
        self.sweep_strain_limits(p);
        self.free_parts.restore(p, dt);
        let x = &p.x;
        self.hinges.update(|_, h| h.track(|i| x[i as usize]));
    }

    /// Sweeps the strain limits over the positions, up to
    /// [`FOLD_HOLD_SWEEPS`] times or until no edge is beyond its limit,
    /// leaving the velocities as they are: a fold that came to rest meets
    /// its held limits without the corrections becoming motion.
    pub fn meet_held_limits(&self, p: &mut Particles) {
        self.sweep_held_limits(p, FOLD_HOLD_SWEEPS);
    }

    /// Up to `sweeps` sweeps of the held strain limits over the positions
    /// alone; returns whether they stopped with every edge within its limit.
    fn sweep_held_limits(&self, p: &mut Particles, sweeps: u32) -> bool {
        (0..sweeps).any(|_| {
            let beyond = self
                .distance
                .sweep(&mut p.x, &p.inv_mass, |c, x| c.project_limit(x, 1.0));
            beyond <= 0.0
        })
    }

    /// The strain limits' own sweeps: [`STRAIN_LIMIT_SWEEPS`], then more
    /// while the last found an edge beyond [`STRAIN_LIMIT_SLACK`] times
    /// its limit, up to [`MAX_STRAIN_LIMIT_SWEEPS`].
    fn sweep_strain_limits(&self, p: &mut Particles) {
        if self.strain_limit_sweeps == 0 {
            return;
        }
        for sweep in 1..=MAX_STRAIN_LIMIT_SWEEPS {
            let beyond = self.distance.sweep(&mut p.x, &p.inv_mass, |c, x| {
                c.project_limit(x, STRAIN_LIMIT_SLACK)
            });
            if sweep >= self.strain_limit_sweeps && beyond <= 0.0 {
                break;
            }
        }
    }
}

impl Xpbd {
    /// The solver for `model`, its constraints built at the rest shape.
    pub fn new(model: &Model, settings: &SolverSettings) -> Self {
        let (prediction, _) = Prediction::new(model);
        Xpbd {
            settings: *settings,
            compliances: Compliances::of(model).table().collect(),
            constraints: XpbdConstraints::new(model),
            prediction,
            contacts: Contacts::new(model),
            grab_reach: GrabReach::new(model),
            self_contacts: settings
                .self_collision
                .enabled
                .then(|| SelfContacts::new(model, settings.self_collision)),
            collider_held: ColliderHeld::default(),
        }
    }

    /// One substep from time `t` to `t + dt`, driven by `control`.
    fn substep(
        &mut self,
        p: &mut Particles,
        world: &mut World,
        control: &Control,
        (t, dt): (f32, f32),
        stages: &mut StageTimes,
    ) {
        self.prediction
            .run(p, world, self.settings.damping, t, dt, stages);
        StageTimes::time(&mut stages.constraints, || {
            let step = Substep::new(dt, &self.compliances, control.fold);
            let iterations = self.settings.iterations;
            self.constraints.project(p, iterations, &step, (t + dt, dt));
            if let Some(grab) = &control.grab {
                grab.project(&mut p.x, &p.inv_mass, dt);
                let (x, w) = (&mut p.x, &p.inv_mass);
                self.grab_reach
                    .project(x, w, grab.particle, &self.compliances);
            }
        });
        if let Some(self_contacts) = &mut self.self_contacts {
            let found = StageTimes::time(&mut stages.self_collision, || {
                let masses = self.collider_held.masses(&p.inv_mass);
                self_contacts.project(&mut p.x, &p.x_prev, masses)
            });
            stages.self_contacts += found.active as u64;
            stages.self_contact_candidates += found.candidates as u64;
            stages.self_contact_builds += u64::from(found.built);
            stages.self_broad_phase += found.broad_phase;
            stages.self_narrow_phase += found.narrow_phase;
            stages.self_solve += found.solve;
        }
        self.resolve_contacts(p, world, (t, dt), stages);
        if self.limits_after_contacts(world) {
            StageTimes::time(&mut stages.constraints, || {
                self.constraints.sweep_strain_limits(p)
            });
        }
        StageTimes::time(&mut stages.predict, || update_velocities(p, dt));
    }

    /// The colliders' contacts, noting the particles they held where the
    /// self-contacts are on.
    fn resolve_contacts(
        &mut self,
        p: &mut Particles,
        world: &mut World,
        (t, dt): (f32, f32),
        stages: &mut StageTimes,
    ) {
        let noted = self.self_contacts.is_some();
        if noted {
            self.collider_held.before_colliders(&p.x);
        }
        self.contacts.resolve(p, world, t, dt, stages);
        if noted {
            let thickness = self.settings.self_collision.thickness;
            self.collider_held
                .after_colliders(&p.x, &p.x_prev, thickness);
        }
    }

    /// Meets the held strain limits over the positions alone
    /// ([`FOLD_HOLD_SWEEPS`]), where the paper has self-contacts in rounds of
    /// [`HOLD_ROUND_SWEEPS`] sweeps, each round's motion then checked by the
    /// contacts as a substep's is, so that no layer is carried through
    /// another while the limits tighten.
    fn meet_held_limits(&mut self, p: &mut Particles) {
        let Some(self_contacts) = &mut self.self_contacts else {
            self.constraints.meet_held_limits(p);
            return;
        };
        let mut start = p.x.clone();
        for _ in 0..FOLD_HOLD_SWEEPS.div_ceil(HOLD_ROUND_SWEEPS) {
            start.copy_from_slice(&p.x);
            let met = self.constraints.sweep_held_limits(p, HOLD_ROUND_SWEEPS);
            let masses = self.collider_held.masses(&p.inv_mass);
            self_contacts.project(&mut p.x, &start, masses);
            if met {
                break;
            }
        }
    }

    /// Whether the strain limits are swept again after the contacts: where
    /// cloth that is not paper has them and something touches it (a
    /// collider, itself). Contacts with friction hold particles back where
    /// the sweeps before had pulled them, and the cloth around them on:
    /// five one-second drags of the spinning-sphere demo with a 3 % limit
    /// reached 1.10 to 2.98 times their edges' length with the sweeps
    /// before the contacts alone, 1.054 with these (the limit and its
    /// slack, [`STRAIN_LIMIT_SLACK`]).
    fn limits_after_contacts(&self, world: &World) -> bool {
        self.constraints.limits_after_contacts
            && (self.self_contacts.is_some() || !world.colliders.is_empty())
    }
}

impl super::Solver for Xpbd {
    fn kind(&self) -> SolverKind {
        SolverKind::Xpbd
    }

    fn constraint_count(&self) -> usize {
        self.constraints.len() + self.prediction.hard_pin_count()
    }

    fn set_settings(&mut self, settings: &SolverSettings) {
        // The self-collision settings shape the broad phase: kept as built.
        self.settings = SolverSettings {
            self_collision: self.settings.self_collision,
            ..*settings
        };
    }

    fn set_compliances(&mut self, compliances: &Compliances) {
        compliances.write_to(&mut self.compliances);
    }

    fn set_hinge_targets(&mut self, targets: &crate::fold_steps::HingeTargets) {
        self.constraints.set_hinge_targets(targets);
    }

    fn step(
        &mut self,
        particles: &mut Particles,
        world: &mut World,
        control: &Control,
        stages: &mut StageTimes,
    ) {
        self.constraints.hold_fold(control.fold.held);
        if self.constraints.fold_limits.take_came_to_rest() {
            StageTimes::time(&mut stages.constraints, || self.meet_held_limits(particles));
        }
        let substeps = self.settings.substeps;
        for (t, dt, control) in super::substep_times(world.time, control, substeps) {
            self.substep(particles, world, &control, (t, dt), stages);
        }
    }
}

/// Each limited paper edge's strain limit while a fold moves
/// ([`MOVING_FOLD_STRAIN_SCALE`] times its own); other edges keep theirs.
fn moving_limits(model: &Model, items: &[DistanceConstraint]) -> Vec<f32> {
    let mut paper = vec![false; model.particle_count()];
    for cloth in model.cloths.iter().filter(|c| c.paper.is_some()) {
        paper[cloth.particles()].fill(true);
    }
    items
        .iter()
        .map(|d| {
            if d.is_limited() && paper[d.v[0] as usize] {
                d.max_stretch * MOVING_FOLD_STRAIN_SCALE
            } else {
                d.max_stretch
            }
        })
        .collect()
}

/// Stretch and shear constraints on every mesh edge of cloth `index`,
/// reading the cloth's live stretch and shear compliances (per unit of
/// edge length on paper, so that its stretch stiffness does not depend on
/// the mesh).
fn edge_constraints<'a>(
    cloth: &'a ClothPart,
    index: usize,
    rest: &'a [Vec3],
) -> impl IndexedParallelIterator<Item = DistanceConstraint> + 'a {
    cloth.topology.edges.par_iter().map(move |e| {
        let kind = if cloth.mesh.is_grid_diagonal(e.v[0], e.v[1]) {
            ComplianceKind::Shear
        } else {
            ComplianceKind::Stretch
        };
        let c = DistanceConstraint::at_rest(e.v.map(|i| cloth.global(i)), rest, 1.0)
            .with_strain_limit(cloth.material.max_strain);
        // Paper's stretch compliance is per unit of edge length.
        let compliance = if cloth.paper.is_some() {
            c.rest_length
        } else {
            1.0
        };
        DistanceConstraint {
            slot: Compliances::slot(index, kind),
            compliance,
            ..c
        }
    })
}

/// The hinge constraints of the paper of `cloth` (global indices, the
/// model's cloth `index`), their compliances read live from the crease and
/// facet slots of the cloth ([`Compliances`]) per unit length; unassigned
/// hinges get none.
fn hinge_constraints(
    paper: &Paper,
    cloth: &ClothPart,
    index: usize,
    rest: &[Vec3],
) -> Vec<OrigamiHinge> {
    paper
        .hinges
        .iter()
        .filter_map(|h| {
            let full_angle = full_angle(h)?;
            let v = h.v.map(|i| cloth.global(i));
            let length = rest[v[0] as usize].distance(rest[v[1] as usize]);
            let kind = match h.assignment {
                Assignment::Flat => ComplianceKind::Facet,
                _ => ComplianceKind::Crease,
            };
            let per_length = 1.0 / length.max(f32::MIN_POSITIVE);
            Some(OrigamiHinge {
                slot: Compliances::slot(index, kind),
                ..OrigamiHinge::new(v, full_angle, per_length, rest)
            })
        })
        .collect()
}

/// Dihedral bending on every pair of adjacent triangles of cloth `index`,
/// reading the cloth's live bending compliance.
fn dihedral_constraints<'a>(
    cloth: &'a ClothPart,
    index: usize,
    rest: &'a [Vec3],
) -> impl IndexedParallelIterator<Item = DihedralBending> + 'a {
    cloth
        .topology
        .pairs
        .par_iter()
        .map(move |pair| DihedralBending {
            slot: Compliances::slot(index, ComplianceKind::Bend),
            ..DihedralBending::at_rest(pair.v.map(|i| cloth.global(i)), rest, 1.0)
        })
}

/// `items` after those of `all`, moved without a copy where `all` is empty
/// (a single cloth's hundreds of megabytes of bending constraints).
fn append<C>(all: &mut Vec<C>, mut items: Vec<C>) {
    if all.is_empty() {
        *all = items;
    } else {
        all.append(&mut items);
    }
}

/// The isometric form of a dihedral constraint whose pair is flat at rest.
fn isometric_if_flat(d: &DihedralBending, rest: &[Vec3]) -> Option<IsometricBending> {
    const FLAT: f32 = 1e-4;
    (d.rest_angle.abs() < FLAT)
        .then(|| IsometricBending::at_rest(d.v, rest, d.compliance))
        .flatten()
        .map(|c| IsometricBending { slot: d.slot, ..c })
}

/// Skip-one bending: along grid rows and columns, or wing to wing on other
/// meshes, reading cloth `index`'s live bending compliance.
fn skip_one_constraints(cloth: &ClothPart, index: usize, rest: &[Vec3]) -> Vec<DistanceConstraint> {
    skip_one_pairs(cloth)
        .into_iter()
        .map(|v| DistanceConstraint {
            slot: Compliances::slot(index, ComplianceKind::Bend),
            ..DistanceConstraint::at_rest(v.map(|i| cloth.global(i)), rest, 1.0)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A waterbomb base stretched by 10 % about its centre, at rest, after
    /// its fold moved (limits 20 %) and came to rest (limits 1 %), with the
    /// held limits met before the substeps (`hold_sweeps`) or by them
    /// alone: its largest strain and fastest particle after one substep.
    fn stretched_paper_comes_to_rest(hold_sweeps: bool) -> (f32, f32) {
        let mut model = Model::default();
        let pattern = crate::origami::builtin("waterbomb-base").unwrap();
        let sheet = crate::origami::Sheet::from_pattern(&pattern, &Default::default()).unwrap();
        model.add_paper(
            "paper",
            &sheet,
            crate::paper::paper_material(),
            crate::paper::PaperStiffness::default(),
        );
        let mut solver = Xpbd::new(&model, &crate::folding::paper_solver_settings());
        let mut p = Particles::new(model.rest.clone(), &model.mass);
        for x in &mut p.x {
            *x *= 1.1;
        }
        solver.constraints.hold_fold(false);
        solver.constraints.hold_fold(true);
        assert!(solver.constraints.fold_limits.came_to_rest);
        if hold_sweeps {
            let v = p.v.clone();
            solver.constraints.meet_held_limits(&mut p);
            assert_eq!(p.v, v, "the velocities are left as they are");
        }
        let mut world = World {
            gravity: Vec3::ZERO,
            ..World::default()
        };
        let dt = 1.0 / (60.0 * solver.settings.substeps as f32);
        let control = Control::frame(1.0 / 60.0);
        solver.substep(
            &mut p,
            &mut world,
            &control,
            (0.0, dt),
            &mut StageTimes::default(),
        );
        let strain = |d: &DistanceConstraint| {
            p.x[d.v[0] as usize].distance(p.x[d.v[1] as usize]) / d.rest_length - 1.0
        };
        let items = solver.constraints.distance.items();
        let largest = items.iter().map(strain).fold(0.0, f32::max);
        let fastest = p.v.iter().map(|v| v.length()).fold(0.0, f32::max);
        (largest, fastest)
    }

    #[test]
    fn a_fold_that_comes_to_rest_meets_its_held_limits_without_a_jolt() {
        let (strain, speed) = stretched_paper_comes_to_rest(true);
        let (_, snapped_speed) = stretched_paper_comes_to_rest(false);
        assert!(strain < 0.011, "held strain {strain}");
        // The substep's own sweeps meet the limits as well, but their
        // corrections become motion.
        assert!(
            speed < 0.01 * snapped_speed,
            "fastest particle at {speed} m/s after the hold sweeps, {snapped_speed} after a snap"
        );
    }

    #[test]
    fn paper_limits_give_more_while_the_fold_moves_and_are_whole_when_held() {
        // A paper sheet and a strain-limited cloth in one scene: only the
        // paper's limits give while the fold moves.
        let scene = crate::scene::Scene::parse(
            r#"{ "cloths": [
                { "mesh": { "pattern": { "builtin": "waterbomb-base", "size": 1.0 } },
                  "material": { "max_strain": 0.01 } },
                { "mesh": { "grid": { "resolution": [4, 4], "size": [1, 1], "center": [0, 2, 0] } },
                  "material": { "max_strain": 0.05 } } ] }"#,
            "t.json",
        )
        .unwrap();
        let model = scene
            .build(std::path::Path::new("."), "t.json")
            .unwrap()
            .model;
        let mut c = XpbdConstraints::new(&model);
        let held: Vec<f32> = c.distance.items().iter().map(|d| d.max_stretch).collect();
        let paper = model.cloths[0].particles();
        let on_paper = |d: &DistanceConstraint| paper.contains(&(d.v[0] as usize));
        assert!(c
            .distance
            .items()
            .iter()
            .all(DistanceConstraint::is_limited));
        assert!(c.distance.items().iter().any(|d| !on_paper(d)));
        for _ in 0..3 {
            assert!(c.hold_fold(false));
            assert!(!c.hold_fold(false), "nothing to write again");
            for (d, h) in c.distance.items().iter().zip(&held) {
                let scale = if on_paper(d) {
                    MOVING_FOLD_STRAIN_SCALE
                } else {
                    1.0
                };
                assert_eq!(d.max_stretch, h * scale);
            }
            assert!(c.hold_fold(true));
            let now: Vec<f32> = c.distance.items().iter().map(|d| d.max_stretch).collect();
            assert_eq!(now, held, "whole again, to the bit");
        }
    }
}
