//! Broad phase of self-collision, run every substep: the swept boxes of the
//! patches ([`super::patches`]) go into a flat [`HashGrid`]; each pair of
//! patches whose boxes overlap is culled when it is one connected piece of
//! surface with a narrow [`NormalCone`] (it cannot touch itself), else its
//! vertex-triangle, particle and edge pairs whose swept boxes overlap become
//! candidate contacts, less the pairs the rest mesh excludes.
//!
//! Boxes hold each particle's motion over the substep (its start and its
//! predicted end) grown by half the thickness, so two boxes overlap whenever
//! their contents may come within the thickness during the substep.
//!
//! Smooth cloth costs about one pass over its triangles per substep, however
//! fast it moves; crumpled or layered cloth costs in proportion to the surface
//! that lies close to other surface.

use super::narrow_phase::Contact;
use super::normal_cone::NormalCone;
use super::patches::Patches;
use super::rest::RestNeighbourhood;
use crate::collide::hash_grid::{Aabb, HashGrid};
use glam::Vec3;
use rayon::prelude::*;
use std::f32::consts::PI;

/// Widest normal cone of a connected patch (or two touching patches) that is
/// culled. Below 60 degrees a patch is a height field whose points closer
/// than the thickness are at most two thicknesses apart along the surface,
/// which the rest exclusions already cover.
const FLAT_CONE: f32 = PI / 3.0;
/// Grid cell size, in mean patch boxes.
const CELL: f32 = 1.0;

/// A patch over one substep.
#[derive(Clone, Copy, Debug, Default)]
struct PatchBound {
    /// Swept box of its corners, grown by half the thickness.
    aabb: Aabb,
    /// Cone of its triangle normals at the substep's end.
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

/// Per-substep bounds and the grid of patch boxes, kept between substeps.
#[derive(Clone, Debug, Default)]
pub(super) struct BroadPhase {
    patch: Vec<PatchBound>,
    cluster: Vec<Smoothness>,
    patch_box: Vec<Aabb>,
    grid: HashGrid,
    half_thickness: f32,
}

impl BroadPhase {
    /// Replaces `out` with the candidate contacts of the substep from
    /// `x_prev` to `x`, in an order that does not depend on the thread count.
    #[allow(clippy::too_many_arguments)]
    pub fn find(
        &mut self,
        rest: &RestNeighbourhood,
        patches: &Patches,
        x_prev: &[Vec3],
        x: &[Vec3],
        inv_mass: &[f32],
        thickness: f32,
        out: &mut Vec<Contact>,
    ) {
        self.half_thickness = 0.5 * thickness;
        self.refit(rest, patches, x_prev, x);
        // A sequential sum: the cell size, and so the order candidates are
        // found in, is the same for any thread count.
        let total: f32 = self.patch_box.iter().map(Aabb::extent).sum();
        let cell = (CELL * total / self.patch_box.len().max(1) as f32).max(thickness);
        self.grid.build(&self.patch_box, cell);
        let scan = Scan {
            rest,
            patches,
            bounds: self,
            x_prev,
            x,
            inv_mass,
        };
        out.clear();
        out.par_extend(
            (0..patches.len())
                .into_par_iter()
                .with_min_len(16)
                .flat_map_iter(|a| scan.candidates_of(a)),
        );
    }

    /// Swept boxes and normal cones of the patches.
    fn refit(&mut self, rest: &RestNeighbourhood, patches: &Patches, x_prev: &[Vec3], x: &[Vec3]) {
        let half = self.half_thickness;
        self.patch.resize(patches.len(), PatchBound::default());
        self.patch
            .par_iter_mut()
            .enumerate()
            .with_min_len(64)
            .for_each_init(Vec::new, |normals, (p, bound)| {
                let aabb = patches.corners(p).iter().fold(Aabb::EMPTY, |u, &k| {
                    u.union(Aabb::around(x_prev[k as usize], x[k as usize]))
                });
                normals.clear();
                normals.extend(
                    patches
                        .triangles(p)
                        .iter()
                        .map(|&t| unit_normal(&rest.triangles[t as usize], x)),
                );
                *bound = PatchBound {
                    aabb: aabb.expanded(half),
                    cone: Smoothness::new(NormalCone::around(normals.iter().copied())),
                };
            });
        self.patch_box.clear();
        self.patch_box.extend(self.patch.iter().map(|b| b.aabb));
        let patch = &self.patch;
        self.cluster
            .resize(patches.cluster_count(), Smoothness::default());
        self.cluster
            .par_iter_mut()
            .enumerate()
            .with_min_len(16)
            .for_each(|(c, cluster)| {
                let members = patches
                    .members(c)
                    .iter()
                    .map(|&p| patch[p as usize].cone.cone);
                *cluster = Smoothness::new(NormalCone::union_of(members));
            });
    }
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
    x_prev: &'a [Vec3],
    x: &'a [Vec3],
    inv_mass: &'a [f32],
}

impl Scan<'_> {
    /// Swept box of particle `k`, grown by half the thickness.
    fn vertex_box(&self, k: u32) -> Aabb {
        let k = k as usize;
        Aabb::around(self.x_prev[k], self.x[k]).expanded(self.bounds.half_thickness)
    }

    fn edge_box(&self, e: [u32; 2]) -> Aabb {
        self.vertex_box(e[0]).union(self.vertex_box(e[1]))
    }

    fn triangle_box(&self, t: [u32; 3]) -> Aabb {
        self.edge_box([t[0], t[1]]).union(self.vertex_box(t[2]))
    }

    /// Candidates of patch `a` with itself and with the patches after it.
    fn candidates_of(&self, a: usize) -> Vec<Contact> {
        let mut out = Vec::new();
        let b = &self.bounds;
        b.grid.for_each_overlapping(&b.patch[a].aabb, |q| {
            let q = q as usize;
            if q < a || self.culled(a, q) {
                return;
            }
            self.vertex_triangle(a, q, &mut out);
            if q != a {
                self.vertex_triangle(q, a, &mut out);
            }
            self.particle_pairs(a, q, &mut out);
            self.edge_pairs(a, q, &mut out);
        });
        out
    }

    /// Whether patches `a <= q` lie in one piece of surface with a narrow
    /// cone: one cluster, two touching clusters, one patch or two touching
    /// patches.
    fn culled(&self, a: usize, q: usize) -> bool {
        let (ca, cq) = (self.patches.cluster_of(a), self.patches.cluster_of(q));
        let cluster = &self.bounds.cluster;
        let clusters_smooth = if ca == cq {
            cluster[ca].smooth()
        } else {
            cluster[ca].smooth_with(&cluster[cq]) && self.patches.clusters_touch(ca, cq)
        };
        if clusters_smooth {
            return true;
        }
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

    /// Vertices owned by patch `a` against the triangles of patch `q`.
    fn vertex_triangle(&self, a: usize, q: usize, out: &mut Vec<Contact>) {
        let target = &self.bounds.patch[q].aabb;
        for &p in self.patches.vertices(a) {
            let pb = self.vertex_box(p);
            if !pb.overlaps(target) {
                continue;
            }
            for &t in self.patches.triangles(q) {
                let tri = self.rest.triangles[t as usize];
                let v = [p, tri[0], tri[1], tri[2]];
                if pb.overlaps(&self.triangle_box(tri))
                    && !self.rest.vertex_triangle_excluded(p, tri)
                    && self.dynamic(&v)
                {
                    out.push(Contact::VertexTriangle(v));
                }
            }
        }
    }

    /// Particles owned by patches `a <= q`, each pair once.
    fn particle_pairs(&self, a: usize, q: usize, out: &mut Vec<Contact>) {
        for &i in self.patches.vertices(a) {
            let ib = self.vertex_box(i);
            for &j in self.patches.vertices(q) {
                if (a == q && j <= i) || !ib.overlaps(&self.vertex_box(j)) {
                    continue;
                }
                if self.dynamic(&[i, j]) && !self.rest.pair_excluded(i, j) {
                    out.push(Contact::Pair([i, j]));
                }
            }
        }
    }

    /// Edges owned by patches `a <= q`, each pair once.
    fn edge_pairs(&self, a: usize, q: usize, out: &mut Vec<Contact>) {
        let target = &self.bounds.patch[q].aabb;
        let theirs = self.patches.edges(q);
        for (k, &e) in self.patches.edges(a).iter().enumerate() {
            let eb = self.edge_box(e);
            if !eb.overlaps(target) {
                continue;
            }
            let from = if a == q { k + 1 } else { 0 };
            for &f in &theirs[from..] {
                let v = [e[0], e[1], f[0], f[1]];
                if eb.overlaps(&self.edge_box(f))
                    && !self.rest.edge_edge_excluded(e, f)
                    && self.dynamic(&v)
                {
                    out.push(Contact::EdgeEdge { v, crossing: None });
                }
            }
        }
    }
}
