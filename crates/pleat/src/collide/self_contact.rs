//! Self-collision and cloth-cloth collision with a thickness, as XPBD contact
//! constraints of compliance zero solved by Jacobi iteration (Macklin et al.
//! 2014, "Unified particle physics"):
//!
//! - particle-particle: `C = |x_i - x_j| - thickness >= 0`;
//! - vertex-triangle: `C = s n . (p - q) - thickness >= 0`, with `q` the
//!   contact point on the triangle and `s` the side the vertex came from; a
//!   vertex that crosses the triangle's plane within the substep is caught by
//!   continuous collision detection ([`super::ccd`]) and pulled back.
//!
//! Each contact also removes relative tangential motion (Coulomb friction,
//! static then kinetic, as for colliders). Every correction is equal and
//! opposite, weighted by inverse mass, so contacts keep linear momentum.
//!
//! Broad phase: a Verlet list. Each particle gets a ball that holds its
//! motion over the substep plus a skin (the larger of half a thickness and
//! twice its longest substep move since the last broad phase, so a fast
//! particle grows only its own ball); each triangle gets the box around its
//! corners' balls. The triangle boxes go into a [`HashGrid`] with cells the
//! size of a mean triangle box; each particle queries it with its own box
//! grown by the thickness, and keeps the triangles it comes within the
//! thickness of as vertex-triangle candidates and their corners it comes
//! within the thickness of as particle pairs. The list is kept until some
//! particle leaves its ball. A stretched triangle costs only its own size;
//! no bound is global. Neighbours in the rest mesh are excluded: particle
//! pairs that share an edge or whose rest distance is below the thickness,
//! and vertex-triangle pairs with a triangle corner closer at rest than the
//! thickness plus the cloth's longest rest edge (the particle pairs handle
//! those).
//!
//! Solve: each contact computes its corrections from the same positions
//! (in parallel); the few that act are then summed per particle in contact
//! order, and each particle applies their average times a relaxation factor
//! (Macklin et al. 2014, section 4.2) — no atomics, bit-identical for any
//! thread count; an iteration where no contact acts ends the solve. Each contact keeps momentum;
//! averaging over unequal contact counts keeps it only approximately.

use super::ccd::{self, Sweep};
use super::hash_grid::{Aabb, HashGrid};
use super::Friction;
use crate::model::Model;
use glam::Vec3;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

/// Candidates kept per particle per broad phase; more are dropped (counted).
const MAX_CANDIDATES: usize = 48;
/// Vertex-triangle pairs closer at rest than this many (thickness + longest
/// edge) never collide: sharp folds bring them near at odd angles.
const TRIANGLE_EXCLUSION: f32 = 2.0;
/// Smallest skin of the Verlet boxes, in thicknesses.
const SKIN: f32 = 0.5;
/// Skin of the Verlet boxes, in the particle's longest substep move since
/// the last broad phase: a box holds a few substeps of its motion.
const LOOKAHEAD: f32 = 2.0;
/// Grid cell size, in mean triangle boxes.
const CELL: f32 = 1.0;
/// Jacobi iterations per substep.
const ITERATIONS: usize = 3;
/// Jacobi over-relaxation of the gathered corrections.
const RELAXATION: f32 = 1.5;
/// Smallest rayon task, in particles or contacts.
const MIN_TASK: usize = 1024;

/// Scene settings of self-collision (per solver: all cloths collide with
/// themselves and with each other).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct SelfCollision {
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

/// A candidate contact: a particle pair or a vertex against a triangle.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
struct Contact {
    /// Particles: `[i, j, -, -]` for a pair, `[p, a, b, c]` for a vertex-triangle.
    v: [u32; 4],
    vertex_triangle: bool,
}

impl Contact {
    fn particles(&self) -> &[u32] {
        if self.vertex_triangle {
            &self.v
        } else {
            &self.v[..2]
        }
    }
}

/// Counts of the last solve, for profiles.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SelfContactStats {
    /// Contacts that pushed particles apart.
    pub active: usize,
    /// Candidate contacts in the Verlet list.
    pub candidates: usize,
    /// Whether the broad phase ran.
    pub rebuilt: bool,
    /// Candidates dropped because a particle had more than it can keep.
    pub dropped: usize,
}

/// The rest mesh seen by contacts: which pairs never collide.
#[derive(Clone, Debug, Default)]
struct RestNeighbourhood {
    /// Cloth index of each particle.
    cloth: Vec<u32>,
    rest: Vec<Vec3>,
    /// Sorted one-ring of each particle (CSR).
    ring_start: Vec<u32>,
    ring: Vec<u32>,
    /// Triangles around each particle (CSR).
    fan_start: Vec<u32>,
    fan: Vec<u32>,
    triangles: Vec<[u32; 3]>,
    /// Per cloth: rest distance below which a triangle corner excludes a vertex.
    triangle_exclusion: Vec<f32>,
    thickness: f32,
}

impl RestNeighbourhood {
    fn new(model: &Model, thickness: f32) -> Self {
        let n = model.particle_count();
        let mut cloth = vec![0; n];
        let mut triangle_exclusion = Vec::new();
        for (k, part) in model.cloths.iter().enumerate() {
            cloth[part.particles()].fill(k as u32);
            let longest = model
                .edges
                .iter()
                .filter(|e| part.particles().contains(&(e.v[0] as usize)))
                .map(|e| e.rest_length)
                .fold(0.0, f32::max);
            triangle_exclusion.push(TRIANGLE_EXCLUSION * (thickness + longest));
        }
        let edges: Vec<[u32; 2]> = model.edges.iter().map(|e| e.v).collect();
        let (ring_start, ring) = csr(n, edges.iter().flat_map(|&[a, b]| [(a, b), (b, a)]));
        let (fan_start, fan) = csr(
            n,
            model
                .triangles
                .iter()
                .enumerate()
                .flat_map(|(t, tri)| tri.map(|v| (v, t as u32))),
        );
        RestNeighbourhood {
            cloth,
            rest: model.rest.clone(),
            ring_start,
            ring,
            fan_start,
            fan,
            triangles: model.triangles.clone(),
            triangle_exclusion,
            thickness,
        }
    }

    fn rest_closer_than(&self, i: u32, j: u32, r: f32) -> bool {
        self.cloth[i as usize] == self.cloth[j as usize]
            && self.rest[i as usize].distance_squared(self.rest[j as usize]) < r * r
    }

    /// Particles that never form a particle-particle contact.
    fn pair_excluded(&self, i: u32, j: u32) -> bool {
        let ring = &self.ring
            [self.ring_start[i as usize] as usize..self.ring_start[i as usize + 1] as usize];
        self.rest_closer_than(i, j, self.thickness) || ring.binary_search(&j).is_ok()
    }

    /// Whether a triangle with corner `j` never meets vertex `i`.
    fn corner_excludes(&self, i: u32, j: u32) -> bool {
        i == j
            || self.rest_closer_than(
                i,
                j,
                self.triangle_exclusion[self.cloth[i as usize] as usize],
            )
    }

    fn fan(&self, i: u32) -> &[u32] {
        &self.fan[self.fan_start[i as usize] as usize..self.fan_start[i as usize + 1] as usize]
    }
}

/// Compressed rows from `(row, value)` items, each row sorted.
fn csr(rows: usize, items: impl Iterator<Item = (u32, u32)> + Clone) -> (Vec<u32>, Vec<u32>) {
    let mut start = vec![0u32; rows + 1];
    for (r, _) in items.clone() {
        start[r as usize + 1] += 1;
    }
    for k in 1..=rows {
        start[k] += start[k - 1];
    }
    let mut cursor = start.clone();
    let mut values = vec![0u32; start[rows] as usize];
    for (r, v) in items {
        values[cursor[r as usize] as usize] = v;
        cursor[r as usize] += 1;
    }
    for r in 0..rows {
        values[start[r] as usize..start[r + 1] as usize].sort_unstable();
    }
    (start, values)
}

/// Verlet balls: where each particle may be until the next broad phase,
/// with their boxes and the boxes of the triangles.
#[derive(Clone, Debug, Default)]
struct VerletBalls {
    centre: Vec<Vec3>,
    radius: Vec<f32>,
    /// Per particle: its longest substep move since the last fit.
    travel: Vec<f32>,
    particle_box: Vec<Aabb>,
    triangle_box: Vec<Aabb>,
    /// Grid cell size: a multiple of the mean triangle box, at least the thickness.
    cell_size: f32,
}

impl VerletBalls {
    fn fit(&mut self, x_prev: &[Vec3], x: &[Vec3], d: f32, triangles: &[[u32; 3]]) {
        let n = x.len();
        self.centre.resize(n, Vec3::ZERO);
        self.radius.resize(n, 0.0);
        self.travel.resize(n, 0.0);
        self.particle_box.resize(n, Aabb::EMPTY);
        (
            &mut self.centre,
            &mut self.radius,
            &mut self.travel,
            &mut self.particle_box,
            (x_prev, x),
        )
            .into_par_iter()
            .with_min_len(MIN_TASK)
            .for_each(|(c, r, travel, b, (&p, &q))| {
                let skin = (SKIN * d).max(LOOKAHEAD * travel.max(p.distance(q)));
                *c = 0.5 * (p + q);
                *r = 0.5 * p.distance(q) + skin;
                *b = Aabb::around(*c, *c).expanded(*r);
                *travel = 0.0;
            });
        let particle = &self.particle_box;
        self.triangle_box.resize(triangles.len(), Aabb::EMPTY);
        self.triangle_box
            .par_iter_mut()
            .zip(triangles)
            .with_min_len(MIN_TASK)
            .for_each(|(b, t)| {
                *b = t
                    .iter()
                    .fold(Aabb::EMPTY, |u, &k| u.union(particle[k as usize]))
            });
        // A sequential sum: the cell size, and so the order candidates are
        // found in, is the same for any thread count.
        let total: f32 = self.triangle_box.iter().map(Aabb::extent).sum();
        self.cell_size = (CELL * total / triangles.len().max(1) as f32).max(d);
    }

    /// Whether every particle is still inside its ball; records how far each
    /// moved (every particle, even past the first that left).
    fn hold(&mut self, x_prev: &[Vec3], x: &[Vec3]) -> bool {
        (&self.centre, &self.radius, &mut self.travel, (x_prev, x))
            .into_par_iter()
            .with_min_len(MIN_TASK)
            .map(|(&c, &r, travel, (&p, &q))| {
                *travel = travel.max(p.distance(q));
                c.distance(p) <= r && c.distance(q) <= r
            })
            .reduce(|| true, |a, b| a && b)
    }
}

/// Self-contact solver state: settings, rest neighbourhood, broad phase
/// buffers and per-contact corrections, all kept between substeps.
#[derive(Clone, Debug)]
pub struct SelfContacts {
    settings: SelfCollision,
    rest: RestNeighbourhood,
    grid: HashGrid,
    balls: VerletBalls,
    built: bool,
    /// `MAX_CANDIDATES` slots per particle, filled in parallel.
    slots: Vec<Contact>,
    slot_len: Vec<u32>,
    contacts: Vec<Contact>,
    /// Per contact: corrections of its particles, and whether it acted.
    delta: Vec<[Vec3; 4]>,
    active: Vec<bool>,
    /// Contacts that acted in this iteration, in order.
    acting: Vec<u32>,
    /// Per particle: sum and number of the corrections of this iteration
    /// (zero again once applied).
    sum: Vec<Vec3>,
    count: Vec<u32>,
}

impl SelfContacts {
    pub fn new(model: &Model, settings: SelfCollision) -> Self {
        let n = model.particle_count();
        SelfContacts {
            settings,
            rest: RestNeighbourhood::new(model, settings.thickness),
            grid: HashGrid::default(),
            balls: VerletBalls::default(),
            built: false,
            slots: vec![Contact::default(); n * MAX_CANDIDATES],
            slot_len: vec![0; n],
            contacts: Vec::with_capacity(n * 4),
            delta: Vec::with_capacity(n * 4),
            active: Vec::with_capacity(n * 4),
            acting: Vec::with_capacity(n),
            sum: vec![Vec3::ZERO; n],
            count: vec![0; n],
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
        let mut stats = SelfContactStats::default();
        if !self.built || !self.balls.hold(x_prev, x) {
            stats.dropped = self.broad_phase(x_prev, x, inv_mass);
            stats.rebuilt = true;
            self.built = true;
        }
        stats.candidates = self.contacts.len();
        for _ in 0..ITERATIONS {
            stats.active = self.solve(x, x_prev, inv_mass);
            // Nothing moved: the next iterations would find the same.
            if stats.active == 0 {
                break;
            }
        }
        stats
    }

    /// Rebuilds the Verlet list; returns the number of dropped candidates.
    fn broad_phase(&mut self, x_prev: &[Vec3], x: &[Vec3], inv_mass: &[f32]) -> usize {
        let d = self.settings.thickness;
        self.balls.fit(x_prev, x, d, &self.rest.triangles);
        self.grid
            .build(&self.balls.triangle_box, self.balls.cell_size);
        let (rest, grid, balls) = (&self.rest, &self.grid, &self.balls);
        let dropped: usize = self
            .slots
            .par_chunks_mut(MAX_CANDIDATES)
            .zip(self.slot_len.par_iter_mut())
            .enumerate()
            .with_min_len(256)
            .map(|(i, (slots, len))| {
                let mut out = SlotWriter {
                    slots,
                    len: 0,
                    dropped: 0,
                };
                candidates_of(i as u32, rest, grid, balls, inv_mass, d, &mut out);
                *len = out.len as u32;
                out.dropped
            })
            .sum();
        self.contacts.clear();
        for (slots, &len) in self.slots.chunks(MAX_CANDIDATES).zip(&self.slot_len) {
            self.contacts.extend_from_slice(&slots[..len as usize]);
        }
        self.delta.resize(self.contacts.len(), [Vec3::ZERO; 4]);
        self.active.resize(self.contacts.len(), false);
        dropped
    }

    /// One Jacobi iteration over the candidates; returns the active count.
    fn solve(&mut self, x: &mut [Vec3], x_prev: &[Vec3], inv_mass: &[f32]) -> usize {
        let s = self.settings;
        let xs: &[Vec3] = x;
        let found: usize = (&self.contacts, &mut self.delta, &mut self.active)
            .into_par_iter()
            .with_min_len(MIN_TASK)
            .map(|(c, delta, active)| {
                let r = if c.vertex_triangle {
                    vertex_triangle_correction(c.v, xs, x_prev, inv_mass, &s)
                } else {
                    pair_correction([c.v[0], c.v[1]], xs, x_prev, inv_mass, &s)
                };
                *active = r.is_some();
                *delta = r.unwrap_or_default();
                usize::from(*active)
            })
            .sum();
        if found == 0 {
            return 0;
        }
        self.acting.clear();
        self.acting
            .extend((0..self.contacts.len() as u32).filter(|&k| self.active[k as usize]));
        self.gather(x);
        found
    }

    /// Moves each particle by the average of the corrections of the acting
    /// contacts, times the relaxation: summed in contact order, so the result
    /// does not depend on the thread count.
    fn gather(&mut self, x: &mut [Vec3]) {
        for &k in &self.acting {
            let c = &self.contacts[k as usize];
            for (&p, d) in c.particles().iter().zip(self.delta[k as usize]) {
                self.sum[p as usize] += d;
                self.count[p as usize] += 1;
            }
        }
        for &k in &self.acting {
            for &p in self.contacts[k as usize].particles() {
                let p = p as usize;
                if self.count[p] > 0 {
                    x[p] += self.sum[p] * (RELAXATION / self.count[p] as f32);
                    self.sum[p] = Vec3::ZERO;
                    self.count[p] = 0;
                }
            }
        }
    }
}

/// Fixed-size candidate slots of one particle.
struct SlotWriter<'a> {
    slots: &'a mut [Contact],
    len: usize,
    dropped: usize,
}

impl SlotWriter<'_> {
    fn push(&mut self, c: Contact) {
        match self.slots.get_mut(self.len) {
            Some(slot) => {
                *slot = c;
                self.len += 1;
            }
            None => self.dropped += 1,
        }
    }
}

/// Candidate contacts owned by particle `i`: pairs with larger-index
/// particles, and `i` as the vertex of vertex-triangle contacts, whose balls
/// come within the thickness `d`, among the triangles the grid finds.
fn candidates_of(
    i: u32,
    rest: &RestNeighbourhood,
    grid: &HashGrid,
    balls: &VerletBalls,
    inv_mass: &[f32],
    d: f32,
    out: &mut SlotWriter,
) {
    let (ci, ri) = (balls.centre[i as usize], balls.radius[i as usize]);
    let query = balls.particle_box[i as usize].expanded(d);
    let near = |j: u32| ci.distance(balls.centre[j as usize]) < ri + balls.radius[j as usize] + d;
    let dynamic = |v: &[u32]| v.iter().any(|&k| inv_mass[k as usize] > 0.0);
    grid.for_each_overlapping(&query, |t| {
        let tri = rest.triangles[t as usize];
        for j in tri {
            if j > i
                && near(j)
                && first_meeting(t, j, &query, rest, balls)
                && dynamic(&[i, j])
                && !rest.pair_excluded(i, j)
            {
                out.push(Contact {
                    v: [i, j, 0, 0],
                    vertex_triangle: false,
                });
            }
        }
        let v = [i, tri[0], tri[1], tri[2]];
        if !tri.iter().any(|&k| rest.corner_excludes(i, k))
            && ball_meets_triangle(i, tri, balls, d)
            && dynamic(&v)
        {
            out.push(Contact {
                v,
                vertex_triangle: true,
            });
        }
    });
}

/// Whether `i`'s ball comes within `d` of the triangle swept by its corners' balls.
fn ball_meets_triangle(i: u32, tri: [u32; 3], balls: &VerletBalls, d: f32) -> bool {
    let [a, b, c] = tri.map(|k| balls.centre[k as usize]);
    let rt = tri
        .map(|k| balls.radius[k as usize])
        .into_iter()
        .fold(0.0, f32::max);
    let (ci, ri) = (balls.centre[i as usize], balls.radius[i as usize]);
    point_triangle_distance(ci, a, b, c) < ri + rt + d
}

/// Whether `j`'s box meets `query` and `t` is the first triangle around `j`
/// whose box does: a pair is met through every such triangle, kept from one.
fn first_meeting(
    t: u32,
    j: u32,
    query: &Aabb,
    rest: &RestNeighbourhood,
    balls: &VerletBalls,
) -> bool {
    balls.particle_box[j as usize].overlaps(query)
        && rest
            .fan(j)
            .iter()
            .find(|&&s| balls.triangle_box[s as usize].overlaps(query))
            == Some(&t)
}

/// Share of a tangential slide `slide` that friction removes, given the
/// normal correction `depth` (Macklin et al. 2014, static then kinetic).
fn friction_share(slide: f32, depth: f32, f: &Friction) -> f32 {
    if slide < f.static_coefficient * depth {
        1.0
    } else if slide > 0.0 {
        (f.kinetic_coefficient * depth / slide).min(1.0)
    } else {
        0.0
    }
}

/// The tangential part of `u` removed by friction.
fn friction_removal(u: Vec3, normal: Vec3, depth: f32, f: &Friction) -> Vec3 {
    let tangential = u - normal * u.dot(normal);
    tangential * friction_share(tangential.length(), depth, f)
}

/// Corrections of a particle pair closer than the thickness.
fn pair_correction(
    v: [u32; 2],
    x: &[Vec3],
    x_prev: &[Vec3],
    inv_mass: &[f32],
    s: &SelfCollision,
) -> Option<[Vec3; 4]> {
    let [i, j] = v.map(|k| k as usize);
    let diff = x[i] - x[j];
    let dist = diff.length();
    let w = inv_mass[i] + inv_mass[j];
    if dist >= s.thickness || dist == 0.0 || w == 0.0 {
        return None;
    }
    let normal = diff / dist;
    let depth = s.thickness - dist;
    let slip = friction_removal(
        (x[i] - x_prev[i]) - (x[j] - x_prev[j]),
        normal,
        depth,
        &s.friction,
    );
    let g = (normal * depth - slip) / w;
    Some([g * inv_mass[i], -g * inv_mass[j], Vec3::ZERO, Vec3::ZERO])
}

/// Corrections of a vertex closer to a triangle than the thickness, or that
/// crossed it during the substep (kept on the side it came from).
fn vertex_triangle_correction(
    v: [u32; 4],
    x: &[Vec3],
    x_prev: &[Vec3],
    inv_mass: &[f32],
    s: &SelfCollision,
) -> Option<[Vec3; 4]> {
    let [p, a, b, c] = v.map(|k| x[k as usize]);
    let [p0, a0, b0, c0] = v.map(|k| x_prev[k as usize]);
    let normal = (b - a).cross(c - a).try_normalize()?;
    let start_height = (b0 - a0).cross(c0 - a0).dot(p0 - a0);
    let side = if start_height != 0.0 {
        start_height.signum()
    } else {
        normal.dot(p - a).signum()
    };
    let height = side * normal.dot(p - a);
    if height >= s.thickness {
        return None;
    }
    let beta = if height < 0.0 {
        let sweep = |k: u32| Sweep {
            start: x_prev[k as usize],
            end: x[k as usize],
        };
        ccd::vertex_triangle(sweep(v[0]), sweep(v[1]), sweep(v[2]), sweep(v[3]))?.barycentric
    } else {
        ccd::projection_inside(p, a, b, c)?
    };
    let w = v.map(|k| inv_mass[k as usize]);
    let weight =
        w[0] + beta[0] * beta[0] * w[1] + beta[1] * beta[1] * w[2] + beta[2] * beta[2] * w[3];
    if weight == 0.0 {
        return None;
    }
    let n = side * normal;
    let depth = s.thickness - height;
    let moved = |k: usize| x[v[k] as usize] - x_prev[v[k] as usize];
    let u = moved(0) - beta[0] * moved(1) - beta[1] * moved(2) - beta[2] * moved(3);
    let g = (n * depth - friction_removal(u, n, depth, &s.friction)) / weight;
    Some([
        g * w[0],
        -g * beta[0] * w[1],
        -g * beta[1] * w[2],
        -g * beta[2] * w[3],
    ])
}

/// Distance from `p` to the triangle `abc` (Ericson, Real-Time Collision Detection 5.1.5).
fn point_triangle_distance(p: Vec3, a: Vec3, b: Vec3, c: Vec3) -> f32 {
    let (ab, ac, ap) = (b - a, c - a, p - a);
    let (d1, d2) = (ab.dot(ap), ac.dot(ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return ap.length();
    }
    let bp = p - b;
    let (d3, d4) = (ab.dot(bp), ac.dot(bp));
    if d3 >= 0.0 && d4 <= d3 {
        return bp.length();
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return p.distance(a + ab * (d1 / (d1 - d3)));
    }
    let cp = p - c;
    let (d5, d6) = (ab.dot(cp), ac.dot(cp));
    if d6 >= 0.0 && d5 <= d6 {
        return cp.length();
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        return p.distance(a + ac * (d2 / (d2 - d6)));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        return p.distance(b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6))));
    }
    let denom = 1.0 / (va + vb + vc);
    p.distance(a + ab * (vb * denom) + ac * (vc * denom))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `sum m_k dx_k` of a contact's corrections.
    fn momentum_change(v: &[u32], delta: [Vec3; 4], inv_mass: &[f32]) -> Vec3 {
        v.iter()
            .zip(delta)
            .map(|(&k, d)| d / inv_mass[k as usize])
            .sum()
    }

    #[test]
    fn pair_contact_keeps_momentum_and_separates() {
        let x = [Vec3::ZERO, Vec3::new(0.002, 0.001, 0.0)];
        let x_prev = [Vec3::new(0.0, 0.01, 0.0), Vec3::new(0.005, 0.0, 0.0)];
        let inv_mass = [1.0, 3.0];
        let s = SelfCollision::default();
        let d = pair_correction([0, 1], &x, &x_prev, &inv_mass, &s).expect("touching");
        assert!(momentum_change(&[0, 1], d, &inv_mass).length() < 1e-6);
        let gap = (x[0] + d[0]).distance(x[1] + d[1]);
        assert!(gap >= s.thickness - 1e-3, "gap {gap}");
    }

    #[test]
    fn vertex_triangle_contact_keeps_momentum_and_the_side() {
        let tri = [
            Vec3::ZERO,
            Vec3::new(0.1, 0.0, 0.0),
            Vec3::new(0.0, 0.0, 0.1),
        ];
        // The vertex came from above and ended below the triangle.
        let x = [
            Vec3::new(0.02, -0.01, 0.03),
            tri[0],
            tri[1],
            tri[2] + Vec3::Y * 0.001,
        ];
        let x_prev = [Vec3::new(0.02, 0.01, 0.03), tri[0], tri[1], tri[2]];
        let inv_mass = [1.0, 2.0, 0.5, 1.0];
        let s = SelfCollision::default();
        let v = [0, 1, 2, 3];
        let d = vertex_triangle_correction(v, &x, &x_prev, &inv_mass, &s).expect("crossed");
        assert!(momentum_change(&v, d, &inv_mass).length() < 1e-6);
        let moved: Vec<Vec3> = x.iter().zip(d).map(|(x, d)| *x + d).collect();
        let normal = (moved[2] - moved[1]).cross(moved[3] - moved[1]).normalize();
        let side = normal.dot(moved[0] - moved[1]) * normal.dot(x_prev[0] - x_prev[1]).signum();
        assert!(side > 0.9 * s.thickness, "height {side}");
    }

    #[test]
    fn rest_neighbours_are_excluded() {
        let mesh = crate::mesh::GridSpec::new(4, 4, [0.3, 0.3]).build();
        let mut model = Model::default();
        model.add_cloth("c", mesh, Default::default(), &[], false);
        let rest = RestNeighbourhood::new(&model, 0.01);
        assert!(rest.pair_excluded(0, 1), "edge");
        assert!(!rest.pair_excluded(0, 15), "far");
        assert!(rest.corner_excludes(0, 5));
        assert!(!rest.corner_excludes(0, 15));
    }
}
