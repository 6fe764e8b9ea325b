//! Hierarchical position-based dynamics (Müller 2008): coarse levels of a
//! cloth's particles, solved coarsest first before the fine constraints, so
//! that a correction crosses the whole cloth within one sweep instead of one
//! edge per sweep. Without them a fine cloth hanging from its corners
//! stretches without bound at the pins (at 256 x 256, with one sweep per
//! substep, its edges there reach 200 times their length).
//!
//! Each level is a maximal independent set of the level below (pins first),
//! found greedily in index order, so the hierarchy is deterministic. Two
//! particles of a level are joined when a path of at most three edges of
//! the level below links them, and may be no farther apart than their rest
//! distance ([`LongRangeLimit`]; times one plus the cloth's strain limit,
//! if it has one). A cloth whose shear is soft
//! ([`HELD_SHEAR_COMPLIANCE`]) keeps its freedom to shear: its levels are
//! built on its stretch edges alone and each coarse edge may be as long as
//! the shortest path between its ends, which is the rest distance along a
//! straight thread and leaves slack across them. After a level is solved,
//! each particle of the level below that is not in it moves by the
//! weighted mean of what its nearest particles of the level moved since
//! the hierarchy began (the prolongation), and the next finer level is
//! solved. On a cloth nothing holds, a level weighs each of its particles
//! with the share of the finer particles that follow it, so that its
//! corrections, handed down, keep the cloth's momentum; on a held one, whose
//! pins take momentum anyway, each particle keeps its own mass, which
//! converges faster (max stretch 1.04 against 1.54 at 512 x 512 after 1 s).
//!
//! The limits are unilateral: they never push a pair apart beyond where it
//! was when the pass began (nor beyond the limit; level 1's, within the
//! fine sweep's reach, and a free cloth's never push), so a cloth folds
//! and crumples as before, and since no bending of a sheet moves two of its
//! points farther apart than at rest, they leave the state a converged
//! solve reaches on an inextensible cloth as it is. That floor matters: a
//! pull alone squeezes the cloth wherever it lifts one part and not the
//! part above it, which only compression holds up (on a sheet hanging
//! from its two top corners, the strip along the taut top edge rests on
//! the cloth below it, whose limits to the pins pull it up). The one fine
//! sweep of a substep moves such a squeeze an edge or two, so at 512 x 512
//! and finer the rows pass through one another, triangles turn over in
//! the plane and the fine sweep, pushing their compressed edges apart,
//! stretches their neighbours (a sheet of 1024 x 1024 reached 1.45 times
//! its edges' length after 1.5 s, 1.03 with the floor; 512 x 512: 1.11, 1.01). The
//! floor never undoes a squeeze the prediction brought (a fold), only the
//! pass's own. Every cloth but paper
//! has levels; they hold while its stretch compliance is zero (read live,
//! so a person who softens the cloth sees it stretch) or always where it
//! has a strain limit; a compliant cloth without one stretches as its
//! compliance says. Paper has none: its folds are driven, its edges
//! stretch while they move.

use super::momentum::FreeParts;
use super::parallel::ColoredConstraints;
use crate::constraint::{Compliances, LongRangeLimit, Substep};
use crate::model::{ClothPart, Model};
use glam::Vec3;
use rayon::prelude::*;

/// The largest shear compliance (m/N) at which the coarse levels hold rest
/// distances in every direction, the diagonals too: a hundred times the
/// default material's 1e-6. A softer cloth's coarse edges follow its threads alone
/// (paths of stretch edges), leaving it free to shear at every scale.
pub const HELD_SHEAR_COMPLIANCE: f32 = 1e-4;

/// Most particles of a level a finer particle takes its motion from.
pub const MAX_PARENTS: usize = 4;

/// The finest level of a held cloth whose limits keep their pairs'
/// distances from the pass's start ([`LongRangeLimit::floor`]): level 1's
/// pairs, two edges apart, lie within the fine sweep's reach, which
/// carries their squeeze.
const FLOOR_FROM_LEVEL: usize = 2;

/// Most levels above a cloth's particles.
const MAX_LEVELS: usize = 16;

/// Most edges of the level below that a coarse edge's path may take.
const PATH_EDGES: usize = 3;

/// Smallest number of particles worth another level.
const MIN_LEVEL_PARTICLES: usize = 4;

/// A level stops the hierarchy when it keeps more than this fraction of the
/// level below (the coarsening no longer pays).
const MAX_KEPT_FRACTION: f32 = 0.9;

/// Smallest number of prolongations a rayon task takes on.
const MIN_TASK: usize = 1024;

/// How one particle of a finer level follows the level above it: by the
/// weighted mean of what its parents moved.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct Prolongation {
    /// The particle that follows.
    pub particle: u32,
    /// Its parents, particles of the level above; unused slots have weight 0.
    pub parents: [u32; MAX_PARENTS],
    /// The parents' weights, summing to 1.
    pub weights: [f32; MAX_PARENTS],
}

impl Prolongation {
    /// The weighted mean of what the parents moved from `start` to `x`.
    pub fn moved(&self, x: &[Vec3], start: &[Vec3]) -> Vec3 {
        self.parents
            .iter()
            .zip(self.weights)
            .fold(Vec3::ZERO, |sum, (&c, w)| {
                sum + w * (x[c as usize] - start[c as usize])
            })
    }
}

/// One level above the particles: its edges' limits and how the particles
/// of the level below, not in it, follow it.
#[derive(Clone, Debug, Default)]
pub struct Level {
    /// The level's edges, coloured.
    pub limits: ColoredConstraints<LongRangeLimit>,
    /// The particles of the level below that this level moves.
    pub prolongation: Vec<Prolongation>,
}

/// The levels of every cloth with one, finest first (level 1 above the
/// particles is `levels[0]`); levels of the same depth from different
/// cloths share an entry.
#[derive(Clone, Debug, Default)]
pub struct Hierarchy {
    levels: Vec<Level>,
    /// The positions when the hierarchy began (scratch).
    start: Vec<Vec3>,
    /// What the particles of a level's prolongation move by (scratch).
    moved: Vec<Vec3>,
}

impl Hierarchy {
    /// The hierarchy of every cloth of `model` but paper.
    pub fn new(model: &Model, inv_mass: &[f32]) -> Self {
        let n = model.particle_count();
        let mut levels: Vec<(Vec<LongRangeLimit>, Vec<Prolongation>)> = Vec::new();
        let free = FreeParts::new(model, inv_mass);
        let cloths = model.cloths.iter().enumerate();
        for (index, cloth) in cloths.filter(|(_, c)| c.paper.is_none()) {
            let is_free = free.ranges().contains(&cloth.particles());
            let slot = Compliances::held_slot(cloth, index);
            let built = cloth_levels(cloth, &model.rest, inv_mass, (slot, is_free));
            for (depth, (limits, prolongation)) in built.into_iter().enumerate() {
                if levels.len() == depth {
                    levels.push(Default::default());
                }
                levels[depth].0.extend(limits);
                levels[depth].1.extend(prolongation);
            }
        }
        Hierarchy {
            levels: levels
                .into_iter()
                .map(|(limits, prolongation)| Level {
                    limits: ColoredConstraints::new(limits, n),
                    prolongation,
                })
                .collect(),
            start: Vec::new(),
            moved: Vec::new(),
        }
    }

    /// The levels, finest first.
    pub fn levels(&self) -> &[Level] {
        &self.levels
    }

    /// Number of coarse edges over all levels.
    pub fn len(&self) -> usize {
        self.levels.iter().map(|l| l.limits.len()).sum()
    }

    /// Whether there is no level.
    pub fn is_empty(&self) -> bool {
        self.levels.is_empty()
    }

    /// One pass down the hierarchy: each level, coarsest first, swept once
    /// and followed by the particles of the level below.
    pub fn solve(&mut self, x: &mut [Vec3], inv_mass: &[f32], step: &Substep) {
        if self.levels.is_empty() {
            return;
        }
        self.start.clear();
        self.start.extend_from_slice(x);
        let (start, moved) = (&self.start, &mut self.moved);
        for level in self.levels.iter().rev() {
            level.limits.sweep(x, inv_mass, |c, v| {
                if c.holds(step) {
                    let [a, b] = c.v.map(|i| start[i as usize]);
                    c.project_within(v, c.floor * a.distance(b))
                } else {
                    f32::NEG_INFINITY
                }
            });
            // Parents are particles of the level, never moved here: the
            // moves are found in parallel, then written.
            level
                .prolongation
                .par_iter()
                .with_min_len(MIN_TASK)
                .map(|p| p.moved(x, start))
                .collect_into_vec(moved);
            for (p, &d) in level.prolongation.iter().zip(moved.iter()) {
                x[p.particle as usize] += d;
            }
        }
    }
}

/// Whether a cloth's shear is stiff enough for the coarse levels to hold
/// their rest distances in every direction ([`HELD_SHEAR_COMPLIANCE`]).
fn holds_its_shear(cloth: &ClothPart) -> bool {
    cloth.material.shear_compliance <= HELD_SHEAR_COMPLIANCE
}

/// How far an edge may stretch, as a factor of its rest length.
pub(super) fn strain_scale(cloth: &ClothPart) -> f32 {
    1.0 + cloth.material.max_strain.unwrap_or(0.0)
}

/// A level's particles (global indices) and edges (local indices, limit),
/// each particle's edges a row of one list (a million-particle cloth's
/// levels would otherwise allocate a list per particle).
struct Graph {
    particles: Vec<u32>,
    /// Where each particle's row of `edges` starts, then where the last ends.
    start: Vec<usize>,
    edges: Vec<(usize, f32)>,
}

impl Graph {
    /// The edges of particle `i` of the level.
    fn row(&self, i: usize) -> &[(usize, f32)] {
        &self.edges[self.start[i]..self.start[i + 1]]
    }

    /// The graph of `particles` whose rows, of `lengths` edges in turn, lie
    /// end to end in `edges`.
    fn from_rows(particles: Vec<u32>, lengths: &[usize], edges: Vec<(usize, f32)>) -> Self {
        let mut start = Vec::with_capacity(lengths.len() + 1);
        start.push(0);
        for &n in lengths {
            start.push(start.last().expect("a start") + n);
        }
        Graph {
            particles,
            start,
            edges,
        }
    }
}

/// The levels above one cloth, finest first.
fn cloth_levels(
    cloth: &ClothPart,
    rest: &[Vec3],
    inv_mass: &[f32],
    (slot, free): (u32, bool),
) -> Vec<(Vec<LongRangeLimit>, Vec<Prolongation>)> {
    let mut graph = stretch_graph(cloth, rest);
    let first = cloth.particles().start;
    // Each particle's mass with the share of the finer particles that
    // follow it (infinite for a pin): the masses of a free cloth's levels.
    let mut mass: Vec<f64> = cloth
        .particles()
        .map(|i| match inv_mass[i] {
            0.0 => f64::INFINITY,
            w => 1.0 / w as f64,
        })
        .collect();
    let mut levels = Vec::new();
    while levels.len() < MAX_LEVELS && graph.particles.len() >= MIN_LEVEL_PARTICLES {
        let coarse = independent_set(&graph, inv_mass);
        let kept = coarse.iter().filter(|&&c| c).count();
        if kept as f32 > MAX_KEPT_FRACTION * graph.particles.len() as f32 {
            break;
        }
        let prolongation = prolongation(&graph, &coarse, inv_mass);
        let held = holds_its_shear(cloth).then_some((rest, strain_scale(cloth)));
        let next = coarse_graph(&graph, &coarse, held);
        for p in &prolongation {
            for (&c, &w) in p.parents.iter().zip(&p.weights) {
                let follower = mass[p.particle as usize - first];
                mass[c as usize - first] += w as f64 * follower;
            }
        }
        // A held cloth's levels keep what its squeeze needs; a free one's
        // only pull (pushes, handed down, would not keep its momentum).
        let floored = !free && levels.len() + 1 >= FLOOR_FROM_LEVEL;
        let floor = if floored { 1.0 } else { 0.0 };
        let limits = match free {
            true => limits_of(
                &next,
                |p| (1.0 / mass[p as usize - first]) as f32,
                (slot, floor),
            ),
            false => limits_of(&next, |p| inv_mass[p as usize], (slot, floor)),
        };
        if limits.is_empty() {
            break;
        }
        levels.push((limits, prolongation));
        graph = next;
    }
    levels
}

/// The cloth's edges at their rest lengths times [`strain_scale`]: all of
/// them where it holds its shear, else its stretch edges alone (not the
/// diagonals of a grid, which shear).
fn stretch_graph(cloth: &ClothPart, rest: &[Vec3]) -> Graph {
    let range = cloth.particles();
    let scale = strain_scale(cloth);
    let shear = holds_its_shear(cloth);
    let kept: Vec<[usize; 2]> = cloth
        .topology
        .edges
        .iter()
        .filter(|e| shear || !cloth.mesh.is_grid_diagonal(e.v[0], e.v[1]))
        .map(|e| e.v.map(|v| v as usize))
        .collect();
    let mut lengths = vec![0; range.len()];
    for &[a, b] in &kept {
        lengths[a] += 1;
        lengths[b] += 1;
    }
    let particles = range.clone().map(|i| i as u32).collect();
    let mut graph = Graph::from_rows(particles, &lengths, vec![(0, 0.0); 2 * kept.len()]);
    // Each row in the order of the cloth's edges.
    let mut next = graph.start.clone();
    for [a, b] in kept {
        let length = scale * rest[range.start + a].distance(rest[range.start + b]);
        graph.edges[next[a]] = (b, length);
        graph.edges[next[b]] = (a, length);
        next[a] += 1;
        next[b] += 1;
    }
    graph
}

/// A maximal independent set of the level, pins first, then in index order.
fn independent_set(graph: &Graph, inv_mass: &[f32]) -> Vec<bool> {
    let pinned = |i: usize| inv_mass[graph.particles[i] as usize] == 0.0;
    let n = graph.particles.len();
    let order = (0..n)
        .filter(|&i| pinned(i))
        .chain((0..n).filter(|&i| !pinned(i)));
    let mut coarse = vec![false; n];
    for i in order {
        if !graph.row(i).iter().any(|&(j, _)| coarse[j]) {
            coarse[i] = true;
        }
    }
    coarse
}

/// How each moving particle of the level that is not coarse follows its
/// nearest coarse neighbours (weights inversely as the edges' limits), in
/// the level's order (each particle is found on its own, in parallel).
fn prolongation(graph: &Graph, coarse: &[bool], inv_mass: &[f32]) -> Vec<Prolongation> {
    (0..graph.particles.len())
        .into_par_iter()
        .with_min_len(MIN_TASK)
        .filter_map(|i| {
            let (particle, edges) = (graph.particles[i], graph.row(i));
            if coarse[i] || inv_mass[particle as usize] == 0.0 {
                return None;
            }
            let mut parents: Vec<(f32, usize)> = edges
                .iter()
                .filter(|&&(j, _)| coarse[j])
                .map(|&(j, limit)| (limit, j))
                .collect();
            parents.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
            parents.truncate(MAX_PARENTS);
            let total: f32 = parents.iter().map(|&(l, _)| 1.0 / l).sum();
            if parents.is_empty() || !total.is_finite() {
                return None;
            }
            let mut p = Prolongation {
                particle,
                parents: [particle; MAX_PARENTS],
                weights: [0.0; MAX_PARENTS],
            };
            for (k, &(limit, j)) in parents.iter().enumerate() {
                p.parents[k] = graph.particles[j];
                p.weights[k] = (1.0 / limit) / total;
            }
            Some(p)
        })
        .collect()
}

/// The coarse particles, joined where a path of at most [`PATH_EDGES`]
/// edges links them, with their rest distance (times the scale) as the
/// limit where `rest` is given (a cloth that holds its shear), else the
/// shortest such path's limit.
fn coarse_graph(graph: &Graph, coarse: &[bool], rest: Option<(&[Vec3], f32)>) -> Graph {
    let mut index = vec![usize::MAX; coarse.len()];
    let mut particles = Vec::new();
    let mut of_level = Vec::new();
    for (i, _) in coarse.iter().enumerate().filter(|(_, &c)| c) {
        index[i] = particles.len();
        particles.push(graph.particles[i]);
        of_level.push(i);
    }
    // The coarse particles in a few chunks a thread, each chunk with its
    // own scratch of the level's size.
    let chunk = of_level
        .len()
        .div_ceil(4 * rayon::current_num_threads())
        .max(MIN_TASK);
    let chunks: Vec<Rows> = of_level
        .par_chunks(chunk)
        .map(|chunk| {
            let mut scratch = PathScratch::new(coarse.len());
            let mut rows = Rows::default();
            for &i in chunk {
                shortest_paths(graph, i, PATH_EDGES, &mut scratch);
                let (lengths, edges) = (&mut rows.lengths, &mut rows.edges);
                let first = edges.len();
                let PathScratch { best, touched, .. } = &mut scratch;
                for &j in touched.iter() {
                    if j != i && coarse[j] {
                        let limit = match rest {
                            Some((rest, scale)) => {
                                let [a, b] = [i, j].map(|k| rest[graph.particles[k] as usize]);
                                scale * a.distance(b)
                            }
                            None => best[j],
                        };
                        edges.push((index[j], limit));
                    }
                    best[j] = f32::INFINITY;
                }
                touched.clear();
                edges[first..].sort_by_key(|&(j, _)| j);
                lengths.push(edges.len() - first);
            }
            rows
        })
        .collect();
    let lengths: Vec<usize> = chunks.iter().flat_map(|r| &r.lengths).copied().collect();
    let edges = chunks.into_iter().flat_map(|r| r.edges).collect();
    Graph::from_rows(particles, &lengths, edges)
}

/// Rows of a graph's edges, of `lengths` edges in turn, end to end.
#[derive(Default)]
struct Rows {
    lengths: Vec<usize>,
    edges: Vec<(usize, f32)>,
}

/// What [`shortest_paths`] works in, kept from one search to the next:
/// the best limit found to each particle of the level (infinite where
/// none), the particles reached, and the two frontiers of its rounds.
struct PathScratch {
    best: Vec<f32>,
    touched: Vec<usize>,
    frontier: Vec<(usize, f32)>,
    next: Vec<(usize, f32)>,
}

impl PathScratch {
    fn new(particles: usize) -> Self {
        PathScratch {
            best: vec![f32::INFINITY; particles],
            touched: Vec::new(),
            frontier: Vec::new(),
            next: Vec::new(),
        }
    }
}

/// The shortest path limits from `from` over at most `hops` edges
/// (Bellman-Ford rounds), into `scratch.best`; the nodes reached into
/// `scratch.touched`.
fn shortest_paths(graph: &Graph, from: usize, hops: usize, scratch: &mut PathScratch) {
    let PathScratch {
        best,
        touched,
        frontier,
        next,
    } = scratch;
    best[from] = 0.0;
    touched.push(from);
    frontier.clear();
    frontier.push((from, 0.0));
    for _ in 0..hops {
        next.clear();
        for &(i, d) in frontier.iter() {
            for &(j, limit) in graph.row(i) {
                let via = d + limit;
                if via < best[j] {
                    if best[j] == f32::INFINITY {
                        touched.push(j);
                    }
                    best[j] = via;
                    next.push((j, via));
                }
            }
        }
        std::mem::swap(frontier, next);
    }
}

/// A level's edges as limits, each pair once, with the inverse masses
/// `inv_mass` gives the particles, the compliance slot and the floor.
fn limits_of(
    graph: &Graph,
    inv_mass: impl Fn(u32) -> f32,
    (slot, floor): (u32, f32),
) -> Vec<LongRangeLimit> {
    let mut limits = Vec::new();
    for i in 0..graph.particles.len() {
        for &(j, max_length) in graph.row(i).iter().filter(|&&(j, _)| j > i) {
            let v = [graph.particles[i], graph.particles[j]];
            limits.push(LongRangeLimit {
                v,
                max_length,
                inv_mass: v.map(&inv_mass),
                slot,
                floor,
            });
        }
    }
    limits
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::constraint::{ComplianceKind, ALWAYS_HELD};
    use crate::material::Material;
    use crate::mesh::GridSpec;
    use crate::model::Pin;
    use crate::solver::position_based::inverse_masses;

    /// An `n x n` cloth of `material`, pinned at its two top corners.
    fn cloth(n: u32, material: Material) -> (Model, Vec<f32>) {
        let mut model = Model::default();
        let pins = [0, n - 1].map(|particle| Pin {
            particle,
            compliance: 0.0,
            motion: Default::default(),
        });
        let grid = GridSpec::new(n as usize, n as usize, [1.0, 1.0]).build();
        model.add_cloth("cloth", grid, material, &pins, false);
        let inv_mass = inverse_masses(&model);
        (model, inv_mass)
    }

    fn particles_of(level: &Level) -> Vec<u32> {
        let mut p: Vec<u32> = level.limits.items().iter().flat_map(|c| c.v).collect();
        p.sort_unstable();
        p.dedup();
        p
    }

    #[test]
    fn each_level_is_coarser_keeps_the_pins_and_moves_the_rest() {
        let (model, inv_mass) = cloth(33, Material::default());
        let h = Hierarchy::new(&model, &inv_mass);
        assert!(h.levels().len() >= 4, "{} levels", h.levels().len());
        let mut below: Vec<u32> = (0..model.particle_count() as u32).collect();
        for level in h.levels() {
            let here = particles_of(level);
            assert!(here.len() as f32 <= MAX_KEPT_FRACTION * below.len() as f32);
            assert!(
                here.contains(&0) && here.contains(&32),
                "pins on every level"
            );
            // Every moving particle of the level below that the level does
            // not hold follows it, by weights that sum to one.
            let mut followers: Vec<u32> = level.prolongation.iter().map(|p| p.particle).collect();
            followers.sort_unstable();
            let expected: Vec<u32> = below
                .iter()
                .copied()
                .filter(|p| here.binary_search(p).is_err() && inv_mass[*p as usize] > 0.0)
                .collect();
            assert_eq!(followers, expected);
            for p in &level.prolongation {
                assert!((p.weights.iter().sum::<f32>() - 1.0).abs() < 1e-5);
                for (c, w) in p.parents.iter().zip(p.weights).filter(|(_, w)| *w > 0.0) {
                    assert!(here.binary_search(c).is_ok() && w <= 1.0);
                }
            }
            below = here;
        }
    }

    #[test]
    fn limits_hold_rest_distances_or_thread_paths_on_soft_shear() {
        let stiff = Hierarchy::new(
            &cloth(17, Material::default()).0,
            &cloth(17, Material::default()).1,
        );
        let soft_material = Material {
            shear_compliance: 1e-2,
            ..Material::default()
        };
        let (model, inv_mass) = cloth(17, soft_material);
        let soft = Hierarchy::new(&model, &inv_mass);
        let rest =
            |c: &LongRangeLimit| model.rest[c.v[0] as usize].distance(model.rest[c.v[1] as usize]);
        for c in stiff.levels().iter().flat_map(|l| l.limits.items()) {
            assert!((c.max_length - rest(c)).abs() < 1e-5 * rest(c));
        }
        // Along threads the rest distance, across them the path's slack.
        let limits: Vec<_> = soft
            .levels()
            .iter()
            .flat_map(|l| l.limits.items())
            .collect();
        assert!(limits
            .iter()
            .all(|c| c.max_length >= rest(c) * (1.0 - 1e-5)));
        assert!(limits.iter().any(|c| c.max_length > 1.2 * rest(c)));
        assert!(limits.iter().any(|c| (c.max_length - rest(c)).abs() < 1e-5));
    }

    #[test]
    fn levels_hold_while_the_cloth_is_inextensible_or_strain_limited() {
        let compliant = Material {
            stretch_compliance: 1e-3,
            ..Material::default()
        };
        let (model, inv_mass) = cloth(9, compliant);
        let h = Hierarchy::new(&model, &inv_mass);
        let slot = Compliances::slot(0, ComplianceKind::Stretch);
        assert!(h
            .levels()
            .iter()
            .flat_map(|l| l.limits.items())
            .all(|c| c.slot == slot));
        let limited = Material {
            max_strain: Some(0.05),
            ..compliant
        };
        let (model, inv_mass) = cloth(9, limited);
        let h = Hierarchy::new(&model, &inv_mass);
        let c = h.levels()[0].limits.items()[0];
        assert_eq!(c.slot, ALWAYS_HELD);
        let rest = model.rest[c.v[0] as usize].distance(model.rest[c.v[1] as usize]);
        assert!(
            (c.max_length - 1.05 * rest).abs() < 1e-5,
            "the strain limit's slack"
        );
    }

    #[test]
    fn one_pass_pulls_a_fallen_cloth_back_within_its_limits() {
        let (model, inv_mass) = cloth(33, Material::default());
        let mut h = Hierarchy::new(&model, &inv_mass);
        // Everything but the pins dropped 1 m: far beyond every limit.
        let mut x: Vec<Vec3> = model.rest.clone();
        for (p, w) in x.iter_mut().zip(&inv_mass) {
            if *w > 0.0 {
                p.y -= 1.0;
            }
        }
        let dropped = x.clone();
        let table: Vec<f32> = Compliances::of(&model).table().collect();
        let step = Substep::new(1.0 / 600.0, &table, Default::default());
        h.solve(&mut x, &inv_mass, &step);
        let coarsest = h.levels().last().unwrap().limits.items();
        let worst = coarsest
            .iter()
            .map(|c| x[c.v[0] as usize].distance(x[c.v[1] as usize]) / c.max_length)
            .fold(0.0, f32::max);
        assert!(worst < 1.0 + 1e-4, "coarsest level {worst}");
        // The particles of the finest level came along: the drop put those
        // next to a pin 16 times as far from it as at rest; after one pass
        // none is more than 2.5 times (the fine sweeps do the rest).
        let pins = [0, 32];
        let level_1 = particles_of(&h.levels()[0]);
        let reach = |x: &[Vec3]| {
            level_1
                .iter()
                .map(|&i| i as usize)
                .filter(|&i| inv_mass[i] > 0.0)
                .map(|i| {
                    let d = |p: &[Vec3], k: usize| p[i].distance(p[k]);
                    let now = pins.iter().map(|&k| d(x, k)).fold(f32::MAX, f32::min);
                    let rest = pins
                        .iter()
                        .map(|&k| d(&model.rest, k))
                        .fold(f32::MAX, f32::min);
                    now / rest
                })
                .fold(0.0, f32::max)
        };
        assert!(reach(&dropped) > 10.0, "{}", reach(&dropped));
        assert!(reach(&x) < 2.5, "{}", reach(&x));
    }
}
