//! Instability detection and the mechanical energy of a state.
//!
//! A solver that produces non-finite positions or velocities, runaway
//! energy (the way an explicit mass-spring cloth explodes) or a tear (an
//! edge that may not stretch, far longer than it is), marks the
//! simulation unstable instead of crashing; reports carry the flag.
//!
//! The mechanical energy is kinetic plus gravitational potential energy
//! measured from the rest shape. A passive cloth starts at zero and can only
//! lose it (its elastic energy is never negative), so energy far above what
//! gravity, wind and moving pins or colliders could put in is runaway. Paper
//! is not passive: its driven creases store elastic energy that a flap
//! snapping flat turns into motion, and motion can never hold more than
//! that, so their energy at full progress
//! ([`crate::paper::Paper::crease_energy`]) is added to the runaway
//! threshold. The same figure lets solvers be compared on one scale
//! whatever their elastic model.

use crate::constraint::{Compliances, ALWAYS_HELD};
use crate::model::Model;
use crate::motion::Motion;
use crate::particles::Particles;
use crate::world::World;
use glam::Vec3;
use rayon::prelude::*;

/// Smallest number of edges a rayon task takes on in the tear check.
const MIN_TASK: usize = 4096;

/// Mechanical energy above this many times [`energy_scale`] (plus what
/// paper creases can release) is runaway.
pub const RUNAWAY_ENERGY: f32 = 100.0;

/// Speed (m/s) added to the world's own, so that a still, weightless scene has a scale.
const SPEED_FLOOR: f32 = 1.0;

/// Why a state is unstable.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Instability {
    /// A position or velocity is NaN or infinite.
    NonFinite,
    /// The mechanical energy exceeds [`RUNAWAY_ENERGY`] times [`energy_scale`].
    Runaway,
    /// An edge that may not stretch is longer than its rest length by
    /// more than its tear strain ([`TearEdge`]): the inextensible sheet
    /// has crumpled, or the solve blew the cloth apart.
    Torn,
}

impl Instability {
    /// The name reports use: `non_finite`, `runaway` or `torn`.
    pub fn name(self) -> &'static str {
        match self {
            Instability::NonFinite => "non_finite",
            Instability::Runaway => "runaway",
            Instability::Torn => "torn",
        }
    }
}

/// How long (s) paper must stay torn before the monitor counts it.
pub const TEAR_PERSISTENCE: f32 = 0.25;

/// Strain past which paper, whose edges have compliance zero, counts as
/// torn: a solve that leaves an edge a quarter longer than it is has failed.
pub const PAPER_TEAR_STRAIN: f32 = 0.25;

/// Strain past which an edge of a cloth that may not stretch (under the
/// XPBD solver, its live stretch compliance zero or a strain limit, which
/// adds to it) is torn: three times its length. The shipped scenes stay
/// below 2.2 at their own size: 1.34 at most where the solve works, 2.15
/// where thin parts of the bunny pass between two particles
/// (`bunny_sdf.json`: each of its most stretched edges runs through the
/// bunny, which contacts of particles alone cannot stop).
pub const CLOTH_TEAR_STRAIN: f32 = 2.0;

/// Share of a cloth's edges that may not stretch which, torn, tear the
/// cloth: a cloth blown apart, not a snag. `bunny_sdf.json` at the app's
/// 128 x 128 holds 13 to 20 of its 48,641 edges past three times their
/// length (up to 6.1) from frame 20 on; the default drape with stiff
/// dihedral bending, which blows apart, had 0.7 % of its edges torn at
/// frame 25 and 22 % at frame 30 (4.5 % with self-collision).
pub const CLOTH_TEAR_SHARE: f32 = 0.01;

/// An edge whose stretch beyond `tear_length` is a tear while it may not
/// stretch: always where `slot` is [`ALWAYS_HELD`] (paper, a cloth with a
/// strain limit), else while its cloth's live stretch compliance (the
/// table's entry `slot`) is zero.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TearEdge {
    /// The two particles.
    pub v: [u32; 2],
    /// Rest length times one plus the tear strain (m).
    pub tear_length: f32,
    /// The compliance slot that decides whether it may stretch
    /// ([`Compliances::held_slot`]).
    pub slot: u32,
    /// Whether it is paper's (a cloth's counts only under XPBD).
    pub paper: bool,
}

impl TearEdge {
    /// Its length in `x` over its tear length: beyond 1, torn.
    pub fn tear(&self, x: &[Vec3]) -> f32 {
        x[self.v[0] as usize].distance(x[self.v[1] as usize]) / self.tear_length
    }
}

/// The edges of `model` that can tear, each with its tear length: paper's
/// at [`PAPER_TEAR_STRAIN`], cloths' at [`CLOTH_TEAR_STRAIN`] plus their
/// strain limit.
pub fn tear_edges(model: &Model) -> impl Iterator<Item = TearEdge> + '_ {
    let cloths: Vec<_> = model
        .cloths
        .iter()
        .enumerate()
        .map(|(index, c)| match c.paper {
            Some(_) => (c.particles(), PAPER_TEAR_STRAIN, ALWAYS_HELD, true),
            None => {
                let strain = CLOTH_TEAR_STRAIN + c.material.max_strain.unwrap_or(0.0);
                (
                    c.particles(),
                    strain,
                    Compliances::held_slot(c, index),
                    false,
                )
            }
        })
        .collect();
    model.edges.iter().filter_map(move |e| {
        let (_, strain, slot, paper) = cloths
            .iter()
            .find(|(range, ..)| range.contains(&(e.v[0] as usize)))?;
        (e.rest_length > 0.0).then(|| TearEdge {
            v: e.v,
            tear_length: (1.0 + strain) * e.rest_length,
            slot: *slot,
            paper: *paper,
        })
    })
}

/// Which edges count as torn in a check: paper's always, and cloths'
/// under `compliances` where the solver (XPBD) holds their stretch by them.
#[derive(Clone, Copy, Debug)]
pub struct Tearing<'a> {
    /// The live compliances, where cloths can tear; `None`: paper alone.
    pub cloth: Option<&'a Compliances>,
}

impl Tearing<'_> {
    /// Paper alone.
    pub const PAPER: Tearing<'static> = Tearing { cloth: None };

    /// Whether `edge` may not stretch now.
    pub fn counts(&self, edge: &TearEdge) -> bool {
        edge.paper || self.cloth.is_some_and(|c| c.holds(edge.slot))
    }
}

/// The first instability a simulation ran into, when and where.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct StabilityMonitor {
    /// Simulated time (s) and kind of the first instability.
    pub first: Option<(f32, Instability)>,
    /// Where it showed: the first non-finite particle, else the fastest.
    pub particle: Option<u32>,
    /// The model's part of the energy scale, measured at the first check.
    extent: Option<RestExtent>,
    /// The edges that can tear, found at the first check.
    tear_edges: Option<Vec<TearEdge>>,
    /// Since when (s), and where, an edge has been torn without a break,
    /// and whether a check of the state itself found it (a cloth's tear,
    /// which a health summary does not measure and so cannot end).
    torn_since: Option<(f32, Option<u32>, bool)>,
}

impl StabilityMonitor {
    /// Checks the state at the world's time; the first instability found is
    /// kept. A tear counts once it has lasted [`TEAR_PERSISTENCE`]: a flap
    /// that snaps through stretches an edge for a frame or two and heals,
    /// a crumpled sheet stays torn.
    pub fn check(
        &mut self,
        model: &Model,
        world: &World,
        particles: &Particles,
        tearing: Tearing<'_>,
    ) {
        if self.first.is_some() {
            return;
        }
        let extent = *self.extent.get_or_insert_with(|| RestExtent::of(model));
        let edges = self
            .tear_edges
            .get_or_insert_with(|| tear_edges(model).collect());
        let found = instability_within(extent, (model, edges, tearing), world, particles);
        self.record((world.time, true), found, || culprit(particles));
    }

    /// Checks a [`Health`] summary measured where the state lives (a GPU
    /// backend's reduction) by the criteria of [`StabilityMonitor::check`].
    pub fn observe(&mut self, model: &Model, world: &World, health: &Health) {
        if self.first.is_some() {
            return;
        }
        let extent = *self.extent.get_or_insert_with(|| RestExtent::of(model));
        let found = classify(
            extent,
            model,
            world,
            Measures {
                non_finite: &|| health.non_finite,
                torn: &|| health.tear > 1.0,
                energy: &|| health.mechanical_energy,
            },
        );
        self.record((health.time, false), found, || health.culprit);
    }

    /// Keeps what was `found` at `time` by a check of the state itself
    /// (`full`) or of a health summary (a tear only once it lasts).
    fn record(
        &mut self,
        (time, full): (f32, bool),
        found: Option<Instability>,
        culprit: impl FnOnce() -> Option<u32>,
    ) {
        match found {
            Some(Instability::Torn) => {
                let (since, particle, _) = *self
                    .torn_since
                    .get_or_insert_with(|| (time, culprit(), full));
                if time - since >= TEAR_PERSISTENCE {
                    self.first = Some((since, Instability::Torn));
                    self.particle = particle;
                }
            }
            Some(kind) => {
                self.first = Some((time, kind));
                self.particle = culprit();
            }
            None => {
                if full || self.torn_since.is_some_and(|(.., by_state)| !by_state) {
                    self.torn_since = None;
                }
            }
        }
    }

    /// Whether an instability has been found.
    pub fn is_unstable(&self) -> bool {
        self.first.is_some()
    }

    /// What a report says: the first instability, when and where, else a
    /// tear still open (a run that ends torn counts as torn from when the
    /// tear began, however short).
    pub fn verdict(&self) -> Option<(f32, Instability, Option<u32>)> {
        self.first
            .map(|(time, kind)| (time, kind, self.particle))
            .or_else(|| {
                self.torn_since
                    .map(|(time, particle, _)| (time, Instability::Torn, particle))
            })
    }
}

/// The first particle whose position or velocity is not finite, else the
/// fastest; `None` without particles.
fn culprit(particles: &Particles) -> Option<u32> {
    let finite = |i: &usize| particles.x[*i].is_finite() && particles.v[*i].is_finite();
    let index = (0..particles.len()).find(|i| !finite(i)).or_else(|| {
        (0..particles.len()).max_by(|&a, &b| {
            particles.v[a]
                .length_squared()
                .total_cmp(&particles.v[b].length_squared())
        })
    })?;
    u32::try_from(index).ok()
}

/// The instability of a state, if any, with paper alone able to tear.
pub fn instability(model: &Model, world: &World, particles: &Particles) -> Option<Instability> {
    let edges: Vec<_> = tear_edges(model).filter(|e| e.paper).collect();
    instability_within(
        RestExtent::of(model),
        (model, &edges, Tearing::PAPER),
        world,
        particles,
    )
}

fn instability_within(
    extent: RestExtent,
    (model, edges, tearing): (&Model, &[TearEdge], Tearing<'_>),
    world: &World,
    particles: &Particles,
) -> Option<Instability> {
    classify(
        extent,
        model,
        world,
        Measures {
            non_finite: &|| particles.has_non_finite(),
            torn: &|| is_torn(edges, tearing, &particles.x),
            energy: &|| mechanical_energy(model, world, particles),
        },
    )
}

/// Whether positions `x` tear: an edge of paper past its tear length, or
/// more than [`CLOTH_TEAR_SHARE`] of the cloth edges that may not stretch.
fn is_torn(edges: &[TearEdge], tearing: Tearing<'_>, x: &[Vec3]) -> bool {
    let (paper, cloth, cloth_torn) = edges
        .par_iter()
        .with_min_len(MIN_TASK)
        .filter(|e| tearing.counts(e))
        .map(|e| {
            let torn = e.tear(x) > 1.0;
            (
                e.paper && torn,
                usize::from(!e.paper),
                usize::from(!e.paper && torn),
            )
        })
        .reduce(|| (false, 0, 0), |a, b| (a.0 || b.0, a.1 + b.1, a.2 + b.2));
    paper || cloth_torn as f32 > CLOTH_TEAR_SHARE * cloth as f32
}

/// The three measures of a state the criteria read, each taken only when
/// the one before it found nothing.
struct Measures<'a> {
    non_finite: &'a dyn Fn() -> bool,
    torn: &'a dyn Fn() -> bool,
    energy: &'a dyn Fn() -> f32,
}

/// The instability the measures show, if any: the criteria in one place.
fn classify(
    extent: RestExtent,
    model: &Model,
    world: &World,
    m: Measures<'_>,
) -> Option<Instability> {
    if (m.non_finite)() || !world.bodies_are_finite() {
        Some(Instability::NonFinite)
    } else if (m.torn)() {
        Some(Instability::Torn)
    } else if (m.energy)()
        > RUNAWAY_ENERGY * energy_scale(extent, model, world) + extent.crease_energy
    {
        Some(Instability::Runaway)
    } else {
        None
    }
}

/// What the instability criteria need from a state, measured where the
/// state lives (a GPU backend reduces it on the device and reads back only
/// this), with the simulated time it describes.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Health {
    /// Simulated time (s) of the state.
    pub time: f32,
    /// A position or velocity is NaN or infinite.
    pub non_finite: bool,
    /// [`mechanical_energy`] of the state (J).
    pub mechanical_energy: f32,
    /// Largest length over tear length of a paper edge ([`TearEdge::tear`];
    /// beyond 1, torn); zero without paper. A cloth's tear is checked on
    /// the state itself ([`StabilityMonitor::check`]).
    pub tear: f32,
    /// The first non-finite particle, else the fastest.
    pub culprit: Option<u32>,
}

/// The energy a scene can plausibly hold (J): `M (|g| L + v^2 / 2)`, with `M`
/// the dynamic mass (cloth and rigid bodies, which can hand theirs to the cloth), `L` the diagonal of the rest shape's bounding box and
/// `v` the fastest the world moves (wind with its turbulence, scripted pins
/// and colliders) plus one metre per second.
pub fn energy_scale(extent: RestExtent, model: &Model, world: &World) -> f32 {
    let RestExtent {
        mass, size, centre, ..
    } = extent;
    let wind = world.wind.map_or(0.0, |w| {
        w.velocity.length() * (1.0 + w.turbulence * 3f32.sqrt())
    });
    let motions = model
        .pins
        .iter()
        .map(|p| p.motion)
        .chain(world.colliders.iter().map(|c| c.motion));
    let moving = motions
        .map(|m| motion_speed(&m, centre, size))
        .fold(0.0, f32::max);
    let v = SPEED_FLOOR + wind + moving;
    let mass = mass + world.body_mass();
    mass * (world.gravity.length() * size + 0.5 * v * v)
}

/// What the energy scale needs from the rest shape: it does not change while
/// a simulation runs, so a monitor measures it once.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RestExtent {
    /// Dynamic mass (kg).
    pub mass: f32,
    /// Diagonal of the rest shape's bounding box (m).
    pub size: f32,
    /// Centre of the rest shape's bounding box (m).
    pub centre: Vec3,
    /// Elastic energy the driven creases of paper parts can release (J).
    pub crease_energy: f32,
}

impl RestExtent {
    /// The extent of `model`'s rest shape.
    pub fn of(model: &Model) -> Self {
        let (lo, hi) = model.rest.iter().fold(
            (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
            |(lo, hi), x| (lo.min(*x), hi.max(*x)),
        );
        let crease_energy = model
            .cloths
            .iter()
            .filter_map(|c| Some(c.paper.as_ref()?.crease_energy(&model.rest[c.particles()])))
            .sum();
        RestExtent {
            mass: model.mass.iter().sum(),
            size: (hi - lo).length().max(0.0),
            centre: (lo + hi) / 2.0,
            crease_energy,
        }
    }
}

/// A bound on the speed of a point of the scene (within `size` of `centre`) under `m`.
fn motion_speed(m: &Motion, centre: Vec3, size: f32) -> f32 {
    m.linear_velocity.length() + m.angular_velocity.length() * (size + m.pivot.distance(centre))
}

/// Kinetic energy plus gravitational potential energy relative to the rest
/// shape, `sum m_i (v_i^2 / 2 - g . (x_i - rest_i))` over the dynamic particles (J).
pub fn mechanical_energy(model: &Model, world: &World, particles: &Particles) -> f32 {
    let potential: f32 = particles
        .x
        .iter()
        .zip(&model.rest)
        .zip(&particles.inv_mass)
        .filter(|(_, &w)| w > 0.0)
        .map(|((x, rest), w)| -world.gravity.dot(*x - *rest) / w)
        .sum();
    particles.kinetic_energy() + potential
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::Material;
    use crate::mesh::GridSpec;
    use glam::Vec3;

    fn sheet() -> (Model, Particles) {
        let mut model = Model::default();
        model.add_cloth(
            "sheet",
            GridSpec::new(3, 3, [1.0, 1.0]).build(),
            Material::default(),
            &[],
            false,
        );
        let particles = Particles::new(model.rest.clone(), &model.mass);
        (model, particles)
    }

    #[test]
    fn rest_state_is_stable_and_has_no_energy() {
        let (model, particles) = sheet();
        let world = World::default();
        assert_eq!(instability(&model, &world, &particles), None);
        assert_eq!(mechanical_energy(&model, &world, &particles), 0.0);
    }

    #[test]
    fn non_finite_and_runaway_states_are_caught_once() {
        let (model, mut particles) = sheet();
        let mut world = World {
            time: 0.5,
            ..World::default()
        };
        particles.v[4] = Vec3::new(0.0, 300.0, 0.0);
        let mut monitor = StabilityMonitor::default();
        monitor.check(&model, &world, &particles, Tearing::PAPER);
        particles.v[0].x = f32::NAN;
        world.time = 1.0;
        monitor.check(&model, &world, &particles, Tearing::PAPER);
        assert_eq!(monitor.first, Some((0.5, Instability::Runaway)));
        assert_eq!(monitor.particle, Some(4), "the fast particle");
        assert_eq!(
            instability(&model, &world, &particles),
            Some(Instability::NonFinite)
        );
    }

    #[test]
    fn a_health_summary_is_judged_as_the_state_it_summarises() {
        let (model, mut particles) = sheet();
        let world = World {
            time: 0.5,
            ..World::default()
        };
        let summary = |p: &Particles| Health {
            time: world.time,
            non_finite: p.has_non_finite(),
            mechanical_energy: mechanical_energy(&model, &world, p),
            tear: 0.0,
            culprit: Some(4),
        };
        let calm = summary(&particles);
        particles.v[4] = Vec3::new(0.0, 300.0, 0.0);
        let fast = summary(&particles);
        particles.v[0].x = f32::NAN;
        let broken = summary(&particles);
        for (health, expected) in [
            (calm, None),
            (fast, Some(Instability::Runaway)),
            (broken, Some(Instability::NonFinite)),
        ] {
            let mut monitor = StabilityMonitor::default();
            monitor.observe(&model, &world, &health);
            assert_eq!(monitor.first, expected.map(|k| (0.5, k)));
            assert_eq!(monitor.particle, expected.and(Some(4)));
        }
    }

    #[test]
    fn creases_of_paper_raise_the_threshold_by_the_energy_they_hold() {
        use crate::origami::{builtin, Sheet, SheetOptions};
        use crate::paper::{paper_material, PaperStiffness};
        let sheet = Sheet::from_pattern(&builtin("single-line").unwrap(), &SheetOptions::default())
            .unwrap();
        let mut model = Model::default();
        model.add_paper("p", &sheet, paper_material(), PaperStiffness::default());
        let world = World::default();
        let extent = RestExtent::of(&model);
        // One crease 1 m long folded by pi: L pi^2 / (2 alpha).
        let alpha = PaperStiffness::default().crease_compliance;
        let expected = std::f32::consts::PI.powi(2) / (2.0 * alpha);
        assert!((extent.crease_energy - expected).abs() < 1e-3 * expected);
        let threshold = RUNAWAY_ENERGY * energy_scale(extent, &model, &world) + expected;
        let mut particles = Particles::new(model.rest.clone(), &model.mass);
        let mass: f32 = model.mass.iter().sum();
        for factor in [0.9f32, 1.1] {
            let speed = (2.0 * factor * threshold / mass).sqrt();
            particles.v.fill(Vec3::new(0.0, 0.0, speed));
            let unstable = instability(&model, &world, &particles).is_some();
            assert_eq!(unstable, factor > 1.0, "{factor}");
        }
    }

    #[test]
    fn stretched_paper_is_torn_and_stretched_cloth_is_not() {
        use crate::origami::{builtin, Sheet, SheetOptions};
        use crate::paper::{paper_material, PaperStiffness};
        let paper = Sheet::from_pattern(&builtin("single-line").unwrap(), &SheetOptions::default())
            .unwrap();
        let mut model = Model::default();
        model.add_paper("p", &paper, paper_material(), PaperStiffness::default());
        let world = World::default();
        let mut particles = Particles::new(model.rest.clone(), &model.mass);
        for (factor, torn) in [(1.2, false), (1.3, true)] {
            for (x, rest) in particles.x.iter_mut().zip(&model.rest) {
                *x = *rest * factor;
            }
            let found = instability(&model, &world, &particles);
            assert_eq!(found == Some(Instability::Torn), torn, "{factor}");
        }
        // A monitor counts a tear only once it lasts.
        let mut monitor = StabilityMonitor::default();
        let mut world = World::default();
        for _ in 0..10 {
            world.time += 1.0 / 60.0;
            monitor.check(&model, &world, &particles, Tearing::PAPER);
        }
        assert!(!monitor.is_unstable(), "a tear of 10 frames");
        for (x, rest) in particles.x.iter_mut().zip(&model.rest) {
            *x = *rest;
        }
        monitor.check(&model, &world, &particles, Tearing::PAPER);
        for (x, rest) in particles.x.iter_mut().zip(&model.rest) {
            *x = *rest * 1.3;
        }
        let start = world.time + 1.0 / 60.0;
        for _ in 0..20 {
            world.time += 1.0 / 60.0;
            monitor.check(&model, &world, &particles, Tearing::PAPER);
        }
        assert_eq!(monitor.first, Some((start, Instability::Torn)));
        // The same stretch of a cloth (not paper) is not a tear.
        let (cloth, mut particles) = sheet();
        for (x, rest) in particles.x.iter_mut().zip(&cloth.rest) {
            *x = *rest * 1.3;
        }
        assert_eq!(instability(&cloth, &world, &particles), None);
    }

    /// The monitor's verdict on `model` held at `factor` times its rest
    /// shape for half a second, with `tearing`.
    fn held_stretched(model: &Model, factor: f32, tearing: Tearing<'_>) -> Option<Instability> {
        let mut particles = Particles::new(model.rest.clone(), &model.mass);
        for (x, rest) in particles.x.iter_mut().zip(&model.rest) {
            *x = *rest * factor;
        }
        let (mut monitor, mut world) = (StabilityMonitor::default(), World::default());
        for _ in 0..30 {
            world.time += 1.0 / 60.0;
            monitor.check(model, &world, &particles, tearing);
        }
        monitor.first.map(|(_, kind)| kind)
    }

    #[test]
    fn a_cloth_that_may_not_stretch_tears_at_three_times_its_length() {
        let (model, _) = sheet();
        let mut compliances = Compliances::of(&model);
        fn xpbd(c: &Compliances) -> Tearing<'_> {
            Tearing { cloth: Some(c) }
        }
        assert_eq!(held_stretched(&model, 2.9, xpbd(&compliances)), None);
        assert_eq!(
            held_stretched(&model, 3.1, xpbd(&compliances)),
            Some(Instability::Torn)
        );
        // Where other solvers stretch it, or its stretch compliance is
        // not zero now, it may stretch.
        assert_eq!(held_stretched(&model, 3.1, Tearing::PAPER), None);
        let stretch = crate::constraint::ComplianceKind::Stretch;
        *compliances.get_mut(0, stretch).unwrap() = 1e-3;
        assert_eq!(held_stretched(&model, 3.1, xpbd(&compliances)), None);
        // A strain limit adds to the tear strain, whatever the compliance.
        let mut limited = Model::default();
        let material = Material {
            max_strain: Some(0.5),
            stretch_compliance: 1e-3,
            ..Material::default()
        };
        let grid = GridSpec::new(3, 3, [1.0, 1.0]).build();
        limited.add_cloth("limited", grid, material, &[], false);
        let compliances = Compliances::of(&limited);
        assert_eq!(held_stretched(&limited, 3.4, xpbd(&compliances)), None);
        assert_eq!(
            held_stretched(&limited, 3.6, xpbd(&compliances)),
            Some(Instability::Torn)
        );
    }

    #[test]
    fn a_snag_of_a_few_edges_does_not_tear_a_cloth() {
        let mut model = Model::default();
        let grid = GridSpec::new(20, 20, [1.0, 1.0]).build();
        model.add_cloth("sheet", grid, Material::default(), &[], false);
        let mut particles = Particles::new(model.rest.clone(), &model.mass);
        // One particle pulled 0.5 m out of the plane: its six edges, of
        // about 1,100, far past three times their 5 cm.
        particles.x[210].y += 0.5;
        let compliances = Compliances::of(&model);
        let tearing = Tearing {
            cloth: Some(&compliances),
        };
        let edges: Vec<_> = tear_edges(&model).collect();
        let torn = edges.iter().filter(|e| e.tear(&particles.x) > 1.0).count();
        assert!(torn >= 4, "{torn} edges torn");
        assert!(!is_torn(&edges, tearing, &particles.x));
    }

    #[test]
    fn a_health_summary_does_not_end_a_tear_it_cannot_see() {
        // The GPU's summary measures paper alone; a cloth's tear, found
        // on the state read back every fifth frame, lasts through it.
        let (model, mut particles) = sheet();
        for (x, rest) in particles.x.iter_mut().zip(&model.rest) {
            *x = *rest * 3.1;
        }
        let compliances = Compliances::of(&model);
        let tearing = Tearing {
            cloth: Some(&compliances),
        };
        let (mut monitor, mut world) = (StabilityMonitor::default(), World::default());
        for frame in 0..30 {
            world.time += 1.0 / 60.0;
            let summary = Health {
                time: world.time,
                mechanical_energy: mechanical_energy(&model, &world, &particles),
                ..Health::default()
            };
            monitor.observe(&model, &world, &summary);
            if frame % 5 == 0 {
                monitor.check(&model, &world, &particles, tearing);
            }
        }
        assert_eq!(
            monitor.first,
            Some((1.0 / 60.0, Instability::Torn)),
            "torn since the first check"
        );
    }

    #[test]
    fn strong_wind_raises_the_scale() {
        let (model, mut particles) = sheet();
        particles.v.fill(Vec3::new(0.0, 0.0, 60.0));
        let mut world = World::default();
        assert!(instability(&model, &world, &particles).is_some());
        world.wind = Some(crate::force::Wind {
            velocity: Vec3::new(0.0, 0.0, 60.0),
            ..Default::default()
        });
        assert_eq!(instability(&model, &world, &particles), None);
    }

    #[test]
    fn falling_trades_potential_for_kinetic_energy() {
        let (model, mut particles) = sheet();
        let world = World::default();
        let (h, total_mass) = (2.0, 0.2);
        for (x, v) in particles.x.iter_mut().zip(&mut particles.v) {
            x.y -= h;
            *v = Vec3::new(0.0, -(2.0 * 9.81 * h).sqrt(), 0.0);
        }
        let e = mechanical_energy(&model, &world, &particles);
        assert!(e.abs() < 1e-4 * total_mass * 9.81 * h, "{e}");
    }
}
