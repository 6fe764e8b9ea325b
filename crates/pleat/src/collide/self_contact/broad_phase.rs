//! Broad phase of self-collision, run every substep: the swept boxes of the
//! clusters of patches ([`super::patches`]) go into a flat [`HashGrid`]; each
//! pair of clusters whose boxes overlap, then each pair of their patches, is
//! culled when it is one connected piece of surface with a narrow
//! [`NormalCone`] (it cannot touch itself), else its
//! vertex-triangle and particle pairs near enough, and the edge pairs that
//! may have crossed, become candidate contacts, less the pairs the rest mesh
//! excludes.
//!
//! Only candidates that can act are kept: a vertex-triangle pair when the
//! vertex projects inside the triangle, or near enough to get there within
//! the substep; an edge pair when the edges may cross, or lie near each
//! other at an angle. Layers of cloth that lie parallel are held apart by
//! their vertex-triangle contacts, both ways, and need no edge pairs
//! between them: stacked cloth had three times more edge pairs than
//! vertex-triangle ones, and ten times more vertex-triangle candidates than
//! contacts that acted. Paper keeps all its edge pairs near enough: they
//! carry its layer order.
//!
//! Boxes hold each particle's motion over the substep (its start and its
//! predicted end) grown by half the thickness, so two boxes overlap whenever
//! their contents may come within the thickness during the substep.
//!
//! Smooth cloth costs about one pass over its triangles per substep, however
//! fast it moves; crumpled or layered cloth costs in proportion to the surface
//! that lies close to other surface.
//!
//! Limit: the culling takes a connected piece with a narrow cone to be a
//! height field over its cone's axis. Provot's contour test (the piece's
//! border, projected along the axis, must not cross itself) is left out: a
//! piece would have to wind over itself like a spiral ramp within a few
//! patches while its normals stay within 60 degrees, which a cloth that
//! barely stretches cannot do at this scale.

use super::narrow_phase::{Contact, EdgePair};
use super::normal_cone::NormalCone;
use super::patches::Patches;
use super::rest::RestNeighbourhood;
use crate::collide::ccd;
use crate::collide::hash_grid::HashGrid;
use crate::math::Aabb;
use glam::Vec3;
use rayon::prelude::*;
use std::f32::consts::PI;

/// Widest normal cone of a connected patch (or two touching patches) that is
/// culled. Below 60 degrees a patch is a height field, which cannot pass
/// through itself; its points closer than the thickness are at most two
/// thicknesses apart along the surface, where contacts would only stiffen
/// its bending.
const FLAT_CONE: f32 = PI / 3.0;
/// Extra reach of proximity candidates, in thicknesses: room for the
/// contacts' own corrections within the substep.
const SLACK: f32 = 0.25;
/// Grid cell size, in mean patch boxes.
const CELL: f32 = 1.0;
/// Widest angle between the triangles of a flat edge, and between two flat
/// edges' normals (either way up) for them to lie in parallel layers.
const PARALLEL: f32 = PI / 12.0;

/// A patch over one substep.
#[derive(Clone, Copy, Debug, Default)]
struct PatchBound {
    /// Swept box of its corners, grown by half the thickness.
    aabb: Aabb,
    /// Cone of its triangle normals at the substep's end.
    cone: Smoothness,
    /// Cone of the normals of its edges' triangles (some in other patches).
    edge_cone: NormalCone,
}

/// A triangle over one substep.
#[derive(Clone, Copy, Debug, Default)]
struct TriangleBound {
    /// Swept box of its corners, grown by half the thickness.
    aabb: Aabb,
    /// How far its corners moved, at most.
    motion: f32,
    /// Per side (from corner `k` to the next), the unit normal in the
    /// triangle's plane that points inwards.
    inward: [Vec3; 3],
    /// How far outside an edge a point still projects "inside" the
    /// triangle ([`ccd::INSIDE_TOLERANCE`] times its longest side).
    inside: f32,
}

impl TriangleBound {
    /// The bound of triangle `tri`, of unit normal `normal`.
    fn new(tri: [u32; 3], normal: Vec3, x: &[Vec3], vertex_box: &[Aabb], motion: &[f32]) -> Self {
        let [a, b, c] = tri.map(|k| x[k as usize]);
        let longest = (b - a).length().max((c - b).length()).max((a - c).length());
        TriangleBound {
            aabb: tri
                .iter()
                .fold(Aabb::EMPTY, |u, &k| u.union(vertex_box[k as usize])),
            motion: tri.iter().fold(0.0, |m, &k| m.max(motion[k as usize])),
            inward: [(a, b), (b, c), (c, a)].map(|(p, q)| normal.cross(q - p).normalize_or_zero()),
            inside: ccd::INSIDE_TOLERANCE as f32 * longest,
        }
    }
}

/// An edge over one substep.
#[derive(Clone, Copy, Debug, Default)]
struct EdgeBound {
    /// Swept box of its ends, grown by half the thickness.
    aabb: Aabb,
    /// How far its ends moved, at most.
    motion: f32,
    /// The unit normal of a flat edge (its triangles within [`PARALLEL`]
    /// of each other; none on paper).
    flat: Option<Vec3>,
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

/// Per-substep bounds and the grid of cluster boxes, kept between substeps.
#[derive(Clone, Debug, Default)]
pub(super) struct BroadPhase {
    /// Per particle: swept box grown by half the thickness, and how far it moved.
    vertex_box: Vec<Aabb>,
    motion: Vec<f32>,
    /// Per triangle: unit normal at the substep's end.
    normal: Vec<Vec3>,
    /// Per triangle, and per edge in the order of [`Patches::all_edges`]:
    /// bounds, filled only in patches that some pair of patches reads
    /// (`needed`).
    triangle: Vec<TriangleBound>,
    edge: Vec<EdgeBound>,
    needed: Vec<bool>,
    patch: Vec<PatchBound>,
    cluster: Vec<Smoothness>,
    cluster_box: Vec<Aabb>,
    grid: HashGrid,
    /// Per cluster: its candidates and buffers, kept so that a substep
    /// allocates nothing once they have grown.
    scratch: Vec<Scratch>,
}

/// One cluster's pairs of patches and candidates of a substep, and its
/// feature buffers.
#[derive(Clone, Debug, Default)]
struct Scratch {
    /// Pairs of patches that may touch, and whether their edge pairs may.
    pairs: Vec<(u32, u32, bool)>,
    found: Vec<Contact>,
    mine: Near,
    theirs: Near,
}

impl BroadPhase {
    /// Replaces `out` with the candidate contacts of the substep from
    /// `x_prev` to `x`, in an order that does not depend on the thread count:
    /// those within `thickness` plus `margin`, the candidates being kept
    /// while no two particles have moved more than `margin` relative to
    /// each other.
    #[allow(clippy::too_many_arguments)]
    pub fn find(
        &mut self,
        rest: &RestNeighbourhood,
        patches: &Patches,
        x_prev: &[Vec3],
        x: &[Vec3],
        inv_mass: &[f32],
        (thickness, margin): (f32, f32),
        out: &mut Vec<Contact>,
    ) {
        let thickness = thickness + margin;
        let parallel_cos = (!rest.has_paper()).then(|| PARALLEL.cos());
        self.refit(rest, patches, (x_prev, x), 0.5 * thickness);
        // A sequential sum: the cell size, and so the order candidates are
        // found in, is the same for any thread count.
        let total: f32 = self.cluster_box.iter().map(Aabb::extent).sum();
        let cell = (CELL * total / self.cluster_box.len().max(1) as f32).max(thickness);
        self.grid.build(&self.cluster_box, cell);
        let mut scratch = std::mem::take(&mut self.scratch);
        scratch.resize_with(patches.cluster_count(), Scratch::default);
        // Two scans around the feature bounds, each reading them as they are.
        macro_rules! scan {
            ($bounds:expr) => {
                Scan {
                    rest,
                    patches,
                    bounds: $bounds,
                    x,
                    inv_mass,
                    thickness,
                    margin,
                    cull_across: !rest.has_paper(),
                    parallel_cos,
                }
            };
        }
        let pairs = scan!(&*self);
        scratch
            .par_iter_mut()
            .enumerate()
            .for_each(|(c, s)| pairs.pairs_of(c, &mut s.pairs));
        self.bound_features(rest, patches, x, &scratch, parallel_cos);
        let candidates = scan!(&*self);
        scratch
            .par_iter_mut()
            .for_each(|s| candidates.candidates_of(s));
        out.clear();
        for s in &scratch {
            out.extend_from_slice(&s.found);
        }
        self.scratch = scratch;
    }

    /// Swept boxes of the particles, normals of the triangles, and swept
    /// boxes and normal cones of the patches and clusters.
    fn refit(
        &mut self,
        rest: &RestNeighbourhood,
        patches: &Patches,
        (x_prev, x): (&[Vec3], &[Vec3]),
        half: f32,
    ) {
        self.vertex_box.resize(x.len(), Aabb::EMPTY);
        self.motion.resize(x.len(), 0.0);
        (&mut self.vertex_box, &mut self.motion, (x_prev, x))
            .into_par_iter()
            .with_min_len(1024)
            .for_each(|(b, m, (&p, &q))| {
                *b = Aabb::around(p, q).expanded(half);
                *m = p.distance(q);
            });
        self.normal.resize(rest.triangles.len(), Vec3::ZERO);
        (&mut self.normal, &rest.triangles)
            .into_par_iter()
            .with_min_len(1024)
            .for_each(|(n, t)| {
                let [a, b, c] = t.map(|k| x[k as usize]);
                *n = (b - a).cross(c - a).normalize_or_zero();
            });
        let (vertex_box, normal) = (&self.vertex_box, &self.normal);
        let normal = |t: &u32| normal[*t as usize];
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
                let normals = patches.triangles(p).iter().map(normal);
                let cone = NormalCone::around(normals);
                let across = patches.triangles_across(p);
                let edge_cone = if across.is_empty() {
                    cone
                } else {
                    let normals = across.iter().map(normal);
                    NormalCone::union_of([cone, NormalCone::around(normals)].into_iter())
                };
                *bound = PatchBound {
                    aabb,
                    cone: Smoothness::new(cone),
                    edge_cone,
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

    /// Bounds of the triangles and edges of the patches in `scratch`'s
    /// pairs, and those alone: smooth cloth, whose pairs of patches are
    /// nearly all culled, pays for few. Edges are flat within
    /// `parallel_cos` (none if `None`).
    fn bound_features(
        &mut self,
        rest: &RestNeighbourhood,
        patches: &Patches,
        x: &[Vec3],
        scratch: &[Scratch],
        parallel_cos: Option<f32>,
    ) {
        self.needed.clear();
        self.needed.resize(patches.len(), false);
        for &(a, q, _) in scratch.iter().flat_map(|s| &s.pairs) {
            self.needed[a as usize] = true;
            self.needed[q as usize] = true;
        }
        let (vertex_box, motion, normal, needed) =
            (&self.vertex_box, &self.motion, &self.normal, &self.needed);
        self.triangle
            .resize(rest.triangles.len(), TriangleBound::default());
        (
            &mut self.triangle,
            &rest.triangles,
            normal,
            patches.patch_of_triangles(),
        )
            .into_par_iter()
            .with_min_len(1024)
            .filter(|(_, _, _, &p)| needed[p as usize])
            .for_each(|(b, &t, &n, _)| *b = TriangleBound::new(t, n, x, vertex_box, motion));
        self.edge
            .resize(patches.all_edges().len(), EdgeBound::default());
        (&mut self.edge, patches.all_edges())
            .into_par_iter()
            .with_min_len(1024)
            .filter(|(_, (_, _, &p))| needed[p as usize])
            .for_each(|(b, (e, &[s, t], _))| {
                let (ns, nt) = (normal[s as usize], normal[t as usize]);
                let flat = parallel_cos.is_some_and(|cos| ns.dot(nt) > cos);
                let [p, q] = e.map(|k| k as usize);
                *b = EdgeBound {
                    aabb: vertex_box[p].union(vertex_box[q]),
                    motion: motion[p].max(motion[q]),
                    flat: flat.then_some(ns),
                };
            });
    }
}

/// What the per-patch candidate search reads.
struct Scan<'a> {
    rest: &'a RestNeighbourhood,
    patches: &'a Patches,
    bounds: &'a BroadPhase,
    x: &'a [Vec3],
    inv_mass: &'a [f32],
    /// The thickness plus the margin.
    thickness: f32,
    /// How far two particles may move relative to each other while the
    /// candidates are kept.
    margin: f32,
    /// Whether two touching pieces may be culled together (not where a
    /// cloth is paper, see [`Scan::patches_culled`]).
    cull_across: bool,
    /// Cosine of [`PARALLEL`], below which two flat edges lie in parallel
    /// layers; `None` on paper, whose edge pairs carry its layer order
    /// ([`super::layer_sides`]) and are all kept.
    parallel_cos: Option<f32>,
}

/// The features of one patch whose boxes meet another patch's box, with
/// their bounds over the substep.
#[derive(Clone, Debug, Default)]
struct Near {
    /// Vertex, box, motion.
    vertices: Vec<(u32, Aabb, f32)>,
    /// Corners, global index, bound.
    triangles: Vec<([u32; 3], u32, TriangleBound)>,
    edges: Vec<([u32; 2], EdgeBound)>,
}

impl Near {
    /// Gathers the features of patch `p` whose boxes meet `other`, its
    /// edges only if `edges`.
    fn gather(&mut self, scan: &Scan, p: usize, other: &Aabb, edges: bool) {
        let bounds = scan.bounds;
        self.vertices.clear();
        self.triangles.clear();
        self.edges.clear();
        self.vertices
            .extend(scan.patches.vertices(p).iter().filter_map(|&v| {
                let b = bounds.vertex_box[v as usize];
                b.overlaps(other).then(|| (v, b, bounds.motion[v as usize]))
            }));
        self.triangles
            .extend(scan.patches.triangles(p).iter().filter_map(|&t| {
                let b = bounds.triangle[t as usize];
                b.aabb
                    .overlaps(other)
                    .then(|| (scan.rest.triangles[t as usize], t, b))
            }));
        if edges {
            let range = scan.patches.edge_range(p);
            self.edges.extend(
                scan.patches
                    .edges(p)
                    .iter()
                    .zip(&bounds.edge[range])
                    .filter(|(_, b)| b.aabb.overlaps(other))
                    .map(|(&e, &b)| (e, b)),
            );
        }
    }
}

impl Scan<'_> {
    /// Pairs of patches of cluster `c` with itself and with the clusters
    /// after it whose boxes overlap and which are not culled, with whether
    /// their edge pairs may be candidates.
    fn pairs_of(&self, c: usize, pairs: &mut Vec<(u32, u32, bool)>) {
        pairs.clear();
        let (patch, cluster_box) = (&self.bounds.patch, &self.bounds.cluster_box);
        self.bounds.grid.for_each_overlapping(&cluster_box[c], |d| {
            let d = d as usize;
            if d < c || self.clusters_culled(c, d) {
                return;
            }
            for &a in self.patches.members(c) {
                for &q in self.patches.members(d) {
                    let (a, q) = (a as usize, q as usize);
                    if (c == d && q < a)
                        || !patch[a].aabb.overlaps(&patch[q].aabb)
                        || self.patches_culled(a, q)
                    {
                        continue;
                    }
                    pairs.push((a as u32, q as u32, !self.edges_apart(a, q)));
                }
            }
        });
    }

    /// Candidates of a cluster's pairs of patches.
    fn candidates_of(&self, scratch: &mut Scratch) {
        let Scratch {
            pairs,
            found: out,
            mine,
            theirs,
        } = scratch;
        out.clear();
        let patch = &self.bounds.patch;
        for &(a, q, edges) in pairs.iter() {
            let (a, q) = (a as usize, q as usize);
            mine.gather(self, a, &patch[q].aabb, edges);
            let same = q == a;
            if !same {
                theirs.gather(self, q, &patch[a].aabb, edges);
            }
            let (mine, other) = (&*mine, if same { &*mine } else { &*theirs });
            self.vertex_triangle(mine, other, out);
            if !same {
                self.vertex_triangle(other, mine, out);
            }
            self.particle_pairs(mine, other, same, out);
            if edges {
                self.edge_pairs(mine, other, same, out);
            }
        }
    }

    /// Whether clusters `c <= d` lie in one smooth piece of surface: one
    /// cluster, or two touching clusters, with a narrow cone.
    fn clusters_culled(&self, c: usize, d: usize) -> bool {
        let cluster = &self.bounds.cluster;
        if c == d {
            cluster[c].smooth()
        } else {
            self.cull_across
                && cluster[c].smooth_with(&cluster[d])
                && self.patches.clusters_touch(c, d)
        }
    }

    /// Whether patches `a` and `q` lie in one smooth piece of surface.
    /// Paper's patches are culled one by one only: around a vertex folded
    /// flat, facets that touch at the vertex alone and face the same way
    /// lie on top of one another (a flat-folded quarter of a square and the
    /// opposite quarter), which two narrow cones do not rule out.
    fn patches_culled(&self, a: usize, q: usize) -> bool {
        let (pa, pq) = (&self.bounds.patch[a].cone, &self.bounds.patch[q].cone);
        if a == q {
            pa.smooth()
        } else {
            self.cull_across && pa.smooth_with(pq) && self.patches.touch(a, q as u32)
        }
    }

    /// Whether no edge pair of patches `a` and `q` can be a candidate
    /// ([`Scan::edge_pairs`]): all their edges are flat and parallel to one
    /// another (each cone twice, and both cones and the angle between them,
    /// within [`PARALLEL`]), and their swept boxes, grown by half the margin
    /// instead of half the thickness and margin, do not overlap.
    fn edges_apart(&self, a: usize, q: usize) -> bool {
        if self.parallel_cos.is_none() {
            return false;
        }
        let (ca, cq) = (
            self.bounds.patch[a].edge_cone,
            self.bounds.patch[q].edge_cone,
        );
        let between = ca.axis.dot(cq.axis).abs().min(1.0).acos();
        2.0 * ca.angle.max(cq.angle) < PARALLEL
            && ca.angle + cq.angle + between < PARALLEL
            && !self.bounds.patch[a]
                .aabb
                .overlaps_by(&self.bounds.patch[q].aabb, self.thickness - self.margin)
    }

    fn dynamic(&self, v: &[u32]) -> bool {
        v.iter().any(|&k| self.inv_mass[k as usize] > 0.0)
    }

    /// How close two features must be at the substep's end to be kept as a
    /// proximity contact: within the thickness (and [`SLACK`] for what the
    /// contacts move them), or further by as much as their particles moved
    /// in the substep (each in a line), since they may have met on the way.
    fn reach(&self, motion_a: f32, motion_b: f32) -> f32 {
        (1.0 + SLACK) * self.thickness + motion_a + motion_b
    }

    /// Whether vertex `p` (which moved `pm` in the substep) and triangle
    /// `t` (corners `tri`) may make a contact that acts in the substep: the
    /// vertex lies within reach ([`Scan::reach`]) of the triangle's plane,
    /// and its projection onto that plane within the contacts' slack, the
    /// margin, the slack of "inside" and the features' motion of the lines
    /// of the triangle's sides (a contact acts only where the vertex
    /// projects inside; a vertex beside a triangle is held by the triangle
    /// next to it, or by an edge pair where the surface bends).
    fn may_act(&self, p: Vec3, tri: [Vec3; 3], t: u32, bound: &TriangleBound, pm: f32) -> bool {
        let [a, b, c] = tri;
        let (n, tm, t) = (self.bounds.normal[t as usize], bound.motion, bound);
        let (height, reach) = (n.dot(p - a), self.reach(pm, tm));
        if height.abs() >= reach {
            return false;
        }
        // How far the projection lies outside the triangle: at least as
        // far as outside the line of any side.
        let beside = [a, b, c]
            .iter()
            .zip(t.inward)
            .map(|(&corner, m)| m.dot(corner - p))
            .fold(0.0, f32::max);
        beside <= SLACK * self.thickness + self.margin + t.inside + pm + tm
            && height * height + beside * beside < reach * reach
    }

    /// Vertices of `a` against triangles of `b`.
    fn vertex_triangle(&self, a: &Near, b: &Near, out: &mut Vec<Contact>) {
        for &(p, pb, pm) in &a.vertices {
            for (tri, t, tb) in &b.triangles {
                let (tri, t) = (*tri, *t);
                let v = [p, tri[0], tri[1], tri[2]];
                if !pb.overlaps(&tb.aabb) || !self.dynamic(&v) {
                    continue;
                }
                let [xp, xa, xb, xc] = v.map(|k| self.x[k as usize]);
                // The rest exclusion last: it costs more than the distance
                // on paper, whose pairs are mostly far apart.
                if self.may_act(xp, [xa, xb, xc], t, tb, pm)
                    && !self.rest.vertex_triangle_excluded(p, tri)
                {
                    let side = self
                        .rest
                        .layers
                        .as_ref()
                        .map_or(0, |l| l.vertex_triangle(p, t));
                    out.push(Contact::VertexTriangle(v, side));
                }
            }
        }
    }

    /// Particle pairs of `a` and `b`, each once (`same`: one patch).
    fn particle_pairs(&self, a: &Near, b: &Near, same: bool, out: &mut Vec<Contact>) {
        for (k, &(i, ib, im)) in a.vertices.iter().enumerate() {
            let from = if same { k + 1 } else { 0 };
            for &(j, jb, jm) in &b.vertices[from..] {
                if ib.overlaps(&jb)
                    && self.x[i as usize].distance(self.x[j as usize]) < self.reach(im, jm)
                    && self.dynamic(&[i, j])
                    && !self.rest.pair_excluded(i, j)
                {
                    out.push(Contact::Pair([i, j]));
                }
            }
        }
    }

    /// Edge pairs of `a` and `b` near enough, each once (`same`: one patch).
    /// Two flat edges in parallel layers that cannot cross in the substep
    /// are left to the vertex-triangle contacts, which hold such layers
    /// apart (a layer's vertices a thickness from the other's plane keep
    /// its edges there too); stacked cloth has several times more of these
    /// pairs than vertex-triangle ones. Where the candidates are found every
    /// substep (cloth, no margin), so are pairs that cannot cross, lie
    /// beyond the thickness and are closest at an end of either edge: that
    /// end's vertex-triangle contacts hold them (crumpled cloth has several
    /// times more edge pairs within reach than acting contacts, most of
    /// them such).
    fn edge_pairs(&self, a: &Near, b: &Near, same: bool, out: &mut Vec<Contact>) {
        for (k, &(e, eb)) in a.edges.iter().enumerate() {
            let from = if same { k + 1 } else { 0 };
            for &(f, fb) in &b.edges[from..] {
                let (en, fnormal) = (eb.flat, fb.flat);
                let (em, fm, eb, fb) = (eb.motion, fb.motion, eb.aabb, fb.aabb);
                let v = [e[0], e[1], f[0], f[1]];
                if !eb.overlaps(&fb) || !self.dynamic(&v) {
                    continue;
                }
                let parallel = match (en, fnormal, self.parallel_cos) {
                    (Some(n), Some(m), Some(cos)) => n.dot(m).abs() > cos,
                    _ => false,
                };
                // Edges can only cross while the candidates are kept if
                // their swept boxes, grown by half the margin, overlap.
                if parallel && !eb.overlaps_by(&fb, self.thickness - self.margin) {
                    continue;
                }
                let [a0, a1, b0, b1] = v.map(|k| self.x[k as usize]);
                let (s, u) = ccd::segment_closest_params(a0, a1, b0, b1);
                let distance = a0.lerp(a1, s).distance(b0.lerp(b1, u));
                let may_cross = distance <= em + fm;
                let interior = s > 0.0 && s < 1.0 && u > 0.0 && u < 1.0;
                let near =
                    !parallel && (interior || self.margin > 0.0 || distance < self.thickness);
                if distance < self.reach(em, fm)
                    && (may_cross || near)
                    && !self.rest.edge_edge_excluded(e, f)
                {
                    out.push(Contact::EdgeEdge(EdgePair {
                        v,
                        s,
                        u,
                        may_cross,
                        crossed: None,
                        belongs: self.rest.layers.as_ref().and_then(|l| l.edge_edge(e, f)),
                    }));
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::GridSpec;
    use crate::model::Model;

    const THICKNESS: f32 = 0.02;

    /// The candidates, at rest, between a 9 x 9 sheet of 5 cm edges and a
    /// second one lying over it: shifted a third of an edge along both
    /// sides, and turned by `tilt` (radians) about the line, along x,
    /// where it passes 0.6 thicknesses over the first.
    fn stacked(tilt: f32) -> Vec<Contact> {
        let spec = GridSpec::new(9, 9, [0.4, 0.4]);
        let mut model = Model::default();
        model.add_cloth("below", spec.build(), Default::default(), &[], false);
        let mut above = spec.build();
        let turn = glam::Quat::from_rotation_x(tilt);
        for p in &mut above.positions {
            *p = turn * *p + Vec3::new(0.05 / 3.0, 0.6 * THICKNESS, 0.05 / 3.0);
        }
        model.add_cloth("above", above, Default::default(), &[], false);
        let rest = RestNeighbourhood::new(&model, THICKNESS);
        let patches = Patches::new(&rest);
        let x = model.rest.clone();
        let inv_mass: Vec<f32> = model.mass.iter().map(|m| 1.0 / m).collect();
        let mut out = Vec::new();
        BroadPhase::default().find(
            &rest,
            &patches,
            &x,
            &x,
            &inv_mass,
            (THICKNESS, 0.0),
            &mut out,
        );
        out
    }

    fn edge_pairs(contacts: &[Contact]) -> usize {
        contacts
            .iter()
            .filter(|c| matches!(c, Contact::EdgeEdge(_)))
            .count()
    }

    /// Parallel layers are held by vertex-triangle contacts alone, one
    /// triangle or two a vertex (the one it lies over, and a neighbour
    /// within the slack); layers at an angle keep their edge pairs.
    #[test]
    fn parallel_layers_leave_their_edge_pairs_to_vertex_triangle_contacts() {
        let flat = stacked(0.0);
        assert_eq!(edge_pairs(&flat), 0);
        let mut per_vertex = std::collections::HashMap::<u32, usize>::new();
        for c in &flat {
            if let Contact::VertexTriangle(v, _) = c {
                *per_vertex.entry(v[0]).or_default() += 1;
            }
        }
        // Every vertex of the upper sheet over the lower one, and back.
        assert!(per_vertex.len() > 2 * 7 * 7, "{}", per_vertex.len());
        assert!(per_vertex.values().all(|&n| n <= 2), "{per_vertex:?}");
        let tilted = stacked(0.6);
        assert!(edge_pairs(&tilted) > 0);
    }
}
