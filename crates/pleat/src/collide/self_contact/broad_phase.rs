//! Broad phase of self-collision: the boxes of the clusters of patches
//! ([`super::patches`]) go into a flat [`HashGrid`]; each pair of clusters
//! whose boxes overlap, then each pair of their patches, is culled when it is
//! one connected piece of surface with a narrow [`NormalCone`] (it cannot
//! touch itself), else its vertex-triangle, particle and edge pairs near
//! enough become candidate contacts, less the pairs the rest mesh excludes.
//!
//! The candidates serve several substeps (a Verlet list, Verlet 1967): they
//! are found at reference positions, the midpoints of one substep's motion,
//! each particle given a radius of [`MARGIN`] / 2 thicknesses plus half its
//! motion, and hold every pair that can come within reach while each
//! particle stays within its radius of its reference position;
//! [`BroadPhase::track`] tells when one has left it and they must be found
//! again. Boxes hold each particle's ball grown by half the reach, so two
//! boxes overlap whenever their contents may come within it. Each candidate
//! keeps its distance at the reference positions: while its particles have
//! moved little, that bounds its distance in the substep
//! ([`BroadPhase::may_reach`]), and most candidates are passed over without
//! their exact distance.
//!
//! Smooth cloth costs about one pass over its triangles per search, however
//! fast it moves; crumpled or layered cloth costs in proportion to the surface
//! that lies close to other surface.
//!
//! Limit: the culling takes a connected piece with a narrow cone to be a
//! height field over its cone's axis. Provot's contour test (the piece's
//! border, projected along the axis, must not cross itself) is left out: a
//! piece would have to wind over itself like a spiral ramp within a few
//! patches while its normals stay within 60 degrees, which a cloth that
//! barely stretches cannot do at this scale.

use super::narrow_phase::{Contact, SLACK};
use super::normal_cone::NormalCone;
use super::patches::Patches;
use super::rest::RestNeighbourhood;
use crate::collide::ccd;
use crate::collide::hash_grid::{Aabb, HashGrid};
use glam::Vec3;
use rayon::prelude::*;
use std::f32::consts::PI;

/// Widest normal cone of a connected patch (or two touching patches) that is
/// culled. Below 60 degrees a patch is a height field whose points closer
/// than the thickness are at most two thicknesses apart along the surface,
/// which the rest exclusions already cover.
const FLAT_CONE: f32 = PI / 3.0;
/// Room, in thicknesses, that the particles have to move before the
/// candidates are found again.
const MARGIN: f32 = 0.5;
/// Grid cell size, in mean patch boxes.
const CELL: f32 = 1.0;

/// A patch over one substep.
#[derive(Clone, Copy, Debug, Default)]
struct PatchBound {
    /// Box of its corners' boxes.
    aabb: Aabb,
    /// Cone of its triangle normals.
    cone: Smoothness,
}

/// The normal cone of a patch or a cluster over one substep, ready for
/// culling against [`FLAT_CONE`].
#[derive(Clone, Copy, Debug, Default)]
struct Smoothness {
    cone: NormalCone,
    /// [`NormalCone::union_cos`] of the cone.
    union_cos: f32,
}

impl Smoothness {
    fn new(cone: NormalCone) -> Self {
        Smoothness {
            cone,
            union_cos: cone.union_cos(FLAT_CONE),
        }
    }

    /// Whether the piece is smooth enough to be culled on its own.
    fn smooth(&self) -> bool {
        self.cone.narrower_than(FLAT_CONE)
    }

    /// Whether this piece and `o` are smooth together.
    fn smooth_with(&self, o: &Smoothness) -> bool {
        self.cone.axis.dot(o.cone.axis) > self.union_cos.max(o.union_cos)
    }
}

/// Bounds and the grid of cluster boxes, kept between substeps.
#[derive(Clone, Debug, Default)]
pub(super) struct BroadPhase {
    /// Per particle: where it was when the candidates were found, how far
    /// it may move from there, and its box.
    reference: Vec<Vec3>,
    radius: Vec<f32>,
    vertex_box: Vec<Aabb>,
    /// Per particle, in the current substep: the larger of how far it is
    /// from its reference position and how far it moves in the substep.
    drift: Vec<f32>,
    /// Per triangle: unit normal at the reference positions.
    normal: Vec<Vec3>,
    patch: Vec<PatchBound>,
    cluster: Vec<Smoothness>,
    cluster_box: Vec<Aabb>,
    grid: HashGrid,
    /// Per cluster: its candidates and buffers, kept so that a substep
    /// allocates nothing once they have grown.
    scratch: Vec<Scratch>,
}

/// One cluster's candidates and its feature buffers.
#[derive(Clone, Debug, Default)]
struct Scratch {
    found: Vec<Candidate>,
    mine: Near,
    theirs: Near,
}

/// A candidate contact and the distance between its features at the
/// reference positions.
#[derive(Clone, Copy, Debug)]
pub(super) struct Candidate {
    pub contact: Contact,
    distance: f32,
}

impl BroadPhase {
    /// Measures how far each particle drifted for the substep from `x_prev`
    /// to `x`; returns whether the candidates last found still hold every
    /// contact of it: each particle stays within its radius of its reference
    /// position, at both ends (and so on the way).
    pub fn track(&mut self, x_prev: &[Vec3], x: &[Vec3]) -> bool {
        if self.reference.len() != x.len() {
            return false;
        }
        self.drift.resize(x.len(), 0.0);
        (&mut self.drift, &self.reference, &self.radius, (x_prev, x))
            .into_par_iter()
            .with_min_len(4096)
            .map(|(d, r, &radius, (p, q))| {
                *d = r.distance(*q).max(p.distance(*q));
                r.distance(*p) <= radius && r.distance(*q) <= radius
            })
            .reduce(|| true, |a, b| a && b)
    }

    /// Whether candidate `c` may come within `near` in the substep last
    /// tracked, or have moved as far as it is apart (all a contact needs to
    /// act): each of its features lies within the drift of its particles
    /// of where it was, and moved no further.
    pub fn may_reach(&self, c: &Candidate, near: f32) -> bool {
        let drift = c
            .contact
            .particles()
            .iter()
            .map(|&k| self.drift[k as usize])
            .fold(0.0, f32::max);
        c.distance - 4.0 * drift < near
    }

    /// Replaces `out` with the candidate contacts of the substeps to come,
    /// the first from `x_prev` to `x`, in an order that does not depend on
    /// the thread count.
    #[allow(clippy::too_many_arguments)]
    pub fn find(
        &mut self,
        rest: &RestNeighbourhood,
        patches: &Patches,
        x_prev: &[Vec3],
        x: &[Vec3],
        inv_mass: &[f32],
        thickness: f32,
        out: &mut Vec<Candidate>,
    ) {
        self.refit(rest, patches, x_prev, x, thickness);
        // A sequential sum: the cell size, and so the order candidates are
        // found in, is the same for any thread count.
        let total: f32 = self.cluster_box.iter().map(Aabb::extent).sum();
        let cell = (CELL * total / self.cluster_box.len().max(1) as f32).max(thickness);
        self.grid.build(&self.cluster_box, cell);
        let mut scratch = std::mem::take(&mut self.scratch);
        scratch.resize_with(patches.cluster_count(), Scratch::default);
        let scan = Scan {
            rest,
            patches,
            bounds: self,
            x: &self.reference,
            inv_mass,
            thickness,
        };
        scratch
            .par_iter_mut()
            .enumerate()
            .for_each(|(c, s)| scan.candidates_of(c, s));
        out.clear();
        for s in &scratch {
            out.extend_from_slice(&s.found);
        }
        self.scratch = scratch;
    }

    /// Reference positions, radii, boxes and normal cones of the patches.
    fn refit(
        &mut self,
        rest: &RestNeighbourhood,
        patches: &Patches,
        x_prev: &[Vec3],
        x: &[Vec3],
        thickness: f32,
    ) {
        let (margin, half) = (0.5 * MARGIN * thickness, 0.5 * reach(thickness, 0.0, 0.0));
        self.reference.resize(x.len(), Vec3::ZERO);
        self.radius.resize(x.len(), 0.0);
        self.vertex_box.resize(x.len(), Aabb::EMPTY);
        self.drift.resize(x.len(), 0.0);
        let bounds = (
            &mut self.reference,
            &mut self.radius,
            &mut self.vertex_box,
            &mut self.drift,
        );
        bounds
            .into_par_iter()
            .zip((x_prev, x))
            .with_min_len(1024)
            .for_each(|((m, r, b, d), (&p, &q))| {
                *m = p.midpoint(q);
                *d = p.distance(q);
                *r = margin + 0.5 * *d;
                *b = Aabb::around(*m, *m).expanded(half + *r);
            });
        let reference = &self.reference;
        self.normal.resize(rest.triangles.len(), Vec3::ZERO);
        (&mut self.normal, &rest.triangles)
            .into_par_iter()
            .with_min_len(1024)
            .for_each(|(n, t)| *n = unit_normal(t, reference));
        let (vertex_box, normal) = (&self.vertex_box, &self.normal);
        self.patch.resize(patches.len(), PatchBound::default());
        self.patch
            .par_iter_mut()
            .enumerate()
            .with_min_len(64)
            .for_each(|(p, bound)| {
                let aabb = patches
                    .corners(p)
                    .iter()
                    .fold(Aabb::EMPTY, |u, &k| u.union(vertex_box[k as usize]));
                let normals = patches.triangles(p).iter().map(|&t| normal[t as usize]);
                *bound = PatchBound {
                    aabb,
                    cone: Smoothness::new(NormalCone::around(normals)),
                };
            });
        let patch = &self.patch;
        let clusters = patches.cluster_count();
        self.cluster.resize(clusters, Smoothness::default());
        self.cluster_box.resize(clusters, Aabb::EMPTY);
        (&mut self.cluster, &mut self.cluster_box)
            .into_par_iter()
            .enumerate()
            .with_min_len(16)
            .for_each(|(c, (cluster, aabb))| {
                let members = patches.members(c).iter().map(|&p| &patch[p as usize]);
                *cluster =
                    Smoothness::new(NormalCone::union_of(members.clone().map(|p| p.cone.cone)));
                *aabb = members.fold(Aabb::EMPTY, |u, p| u.union(p.aabb));
            });
    }
}

/// How close two features must be to be kept: within the thickness (and
/// [`SLACK`] for what the contacts move them) once each has moved by up to
/// its radius (`radius_a`, `radius_b`).
fn reach(thickness: f32, radius_a: f32, radius_b: f32) -> f32 {
    (1.0 + SLACK) * thickness + radius_a + radius_b
}

/// Unit normal of triangle `t`, zero when it is degenerate.
fn unit_normal(t: &[u32; 3], x: &[Vec3]) -> Vec3 {
    let [a, b, c] = t.map(|k| x[k as usize]);
    (b - a).cross(c - a).normalize_or_zero()
}

/// What the per-patch candidate search reads.
struct Scan<'a> {
    rest: &'a RestNeighbourhood,
    patches: &'a Patches,
    bounds: &'a BroadPhase,
    x: &'a [Vec3],
    inv_mass: &'a [f32],
    thickness: f32,
}

/// The features of one patch whose boxes meet another patch's box, with
/// their boxes and the largest radius of their particles.
#[derive(Clone, Debug, Default)]
struct Near {
    vertices: Vec<(u32, Aabb, f32)>,
    triangles: Vec<([u32; 3], Aabb, f32)>,
    edges: Vec<([u32; 2], Aabb, f32)>,
}

impl Near {
    fn gather(&mut self, scan: &Scan, p: usize, other: &Aabb) {
        let (vertex_box, radius) = (&scan.bounds.vertex_box, &scan.bounds.radius);
        let feature = |v: &[u32]| {
            v.iter().fold((Aabb::EMPTY, 0.0f32), |(b, m), &k| {
                (b.union(vertex_box[k as usize]), m.max(radius[k as usize]))
            })
        };
        self.vertices.clear();
        self.triangles.clear();
        self.edges.clear();
        for &v in scan.patches.vertices(p) {
            let (b, m) = feature(&[v]);
            if b.overlaps(other) {
                self.vertices.push((v, b, m));
            }
        }
        for &t in scan.patches.triangles(p) {
            let tri = scan.rest.triangles[t as usize];
            let (b, m) = feature(&tri);
            if b.overlaps(other) {
                self.triangles.push((tri, b, m));
            }
        }
        for &e in scan.patches.edges(p) {
            let (b, m) = feature(&e);
            if b.overlaps(other) {
                self.edges.push((e, b, m));
            }
        }
    }
}

impl Scan<'_> {
    /// Candidates of cluster `c` with itself and with the clusters after it.
    fn candidates_of(&self, c: usize, scratch: &mut Scratch) {
        let Scratch {
            found: out,
            mine,
            theirs,
        } = scratch;
        out.clear();
        let (patch, cluster_box) = (&self.bounds.patch, &self.bounds.cluster_box);
        self.bounds.grid.for_each_overlapping(&cluster_box[c], |d| {
            let d = d as usize;
            if d < c || self.clusters_culled(c, d) {
                return;
            }
            for &a in self.patches.members(c) {
                let a = a as usize;
                for &q in self.patches.members(d) {
                    let q = q as usize;
                    if (c == d && q < a)
                        || !patch[a].aabb.overlaps(&patch[q].aabb)
                        || self.patches_culled(a, q)
                    {
                        continue;
                    }
                    mine.gather(self, a, &patch[q].aabb);
                    let same = q == a;
                    if !same {
                        theirs.gather(self, q, &patch[a].aabb);
                    }
                    let (mine, other) = (&*mine, if same { &*mine } else { &*theirs });
                    self.vertex_triangle(mine, other, out);
                    if !same {
                        self.vertex_triangle(other, mine, out);
                    }
                    self.particle_pairs(mine, other, same, out);
                    self.edge_pairs(mine, other, same, out);
                }
            }
        });
    }

    /// Whether clusters `c <= d` lie in one smooth piece of surface: one
    /// cluster, or two touching clusters, with a narrow cone.
    fn clusters_culled(&self, c: usize, d: usize) -> bool {
        let cluster = &self.bounds.cluster;
        if c == d {
            cluster[c].smooth()
        } else {
            cluster[c].smooth_with(&cluster[d]) && self.patches.clusters_touch(c, d)
        }
    }

    /// Whether patches `a` and `q` lie in one smooth piece of surface.
    fn patches_culled(&self, a: usize, q: usize) -> bool {
        let (pa, pq) = (&self.bounds.patch[a].cone, &self.bounds.patch[q].cone);
        if a == q {
            pa.smooth()
        } else {
            pa.smooth_with(pq) && self.patches.touch(a, q as u32)
        }
    }

    fn dynamic(&self, v: &[u32]) -> bool {
        v.iter().any(|&k| self.inv_mass[k as usize] > 0.0)
    }

    /// How close two features of radii `radius_a` and `radius_b` must be to
    /// be kept.
    fn reach(&self, radius_a: f32, radius_b: f32) -> f32 {
        reach(self.thickness, radius_a, radius_b)
    }

    /// Vertices of `a` against triangles of `b`.
    fn vertex_triangle(&self, a: &Near, b: &Near, out: &mut Vec<Candidate>) {
        for &(p, pb, pm) in &a.vertices {
            for &(tri, tb, tm) in &b.triangles {
                let v = [p, tri[0], tri[1], tri[2]];
                if pb.overlaps(&tb)
                    && !self.rest.vertex_triangle_excluded(p, tri)
                    && self.dynamic(&v)
                {
                    let [xp, xa, xb, xc] = v.map(|k| self.x[k as usize]);
                    let distance = ccd::point_triangle_distance(xp, xa, xb, xc);
                    if distance < self.reach(pm, tm) {
                        out.push(Candidate {
                            contact: Contact::VertexTriangle(v),
                            distance,
                        });
                    }
                }
            }
        }
    }

    /// Particle pairs of `a` and `b`, each once (`same`: one patch).
    fn particle_pairs(&self, a: &Near, b: &Near, same: bool, out: &mut Vec<Candidate>) {
        for (k, &(i, ib, im)) in a.vertices.iter().enumerate() {
            let from = if same { k + 1 } else { 0 };
            for &(j, jb, jm) in &b.vertices[from..] {
                if !ib.overlaps(&jb) || !self.dynamic(&[i, j]) || self.rest.pair_excluded(i, j) {
                    continue;
                }
                let distance = self.x[i as usize].distance(self.x[j as usize]);
                if distance < self.reach(im, jm) {
                    out.push(Candidate {
                        contact: Contact::Pair([i, j]),
                        distance,
                    });
                }
            }
        }
    }

    /// Edge pairs of `a` and `b` near enough, each once (`same`: one patch).
    fn edge_pairs(&self, a: &Near, b: &Near, same: bool, out: &mut Vec<Candidate>) {
        for (k, &(e, eb, em)) in a.edges.iter().enumerate() {
            let from = if same { k + 1 } else { 0 };
            for &(f, fb, fm) in &b.edges[from..] {
                let v = [e[0], e[1], f[0], f[1]];
                if !eb.overlaps(&fb) || self.rest.edge_edge_excluded(e, f) || !self.dynamic(&v) {
                    continue;
                }
                let [a0, a1, b0, b1] = v.map(|k| self.x[k as usize]);
                let distance = ccd::segment_distance(a0, a1, b0, b1);
                if distance < self.reach(em, fm) {
                    out.push(Candidate {
                        contact: Contact::edge_edge(e, f),
                        distance,
                    });
                }
            }
        }
    }
}
