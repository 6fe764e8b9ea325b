//! Patches: the rest mesh cut into small connected pieces, the unit of the
//! self-collision broad phase. Each cloth's triangles are binned by their
//! rest centroid into cubes of [`PATCH_EDGES`] mean edge lengths; a patch is
//! one edge-connected component of a bin, so that a patch is a connected
//! piece of surface (what normal-cone culling needs).
//!
//! Patches group into clusters the same way, over bins [`CLUSTER_PATCHES`]
//! times as wide: culling first asks whether two patches lie in one smooth
//! cluster, or in two touching clusters that are smooth together.
//!
//! Every vertex and every edge belongs to exactly one patch (the patch of its
//! lowest-index triangle), so that a pair of patches tests each vertex-triangle,
//! particle and edge pair once.

use super::csr::{csr, row};
use super::rest::RestNeighbourhood;
use glam::IVec3;
use rayon::prelude::*;
use std::collections::HashMap;
use std::ops::Range;

/// Side of a patch's bin, in mean rest edges of its cloth.
const PATCH_EDGES: f32 = 3.0;
/// Side of a cluster's bin, in patch bins.
const CLUSTER_PATCHES: f32 = 3.0;

#[derive(Clone, Debug, Default)]
pub(super) struct Patches {
    /// Triangles of each patch (CSR).
    triangle_start: Vec<u32>,
    triangles: Vec<u32>,
    /// Corners of each patch's triangles, each once (CSR).
    corner_start: Vec<u32>,
    corners: Vec<u32>,
    /// Vertices owned by each patch (CSR).
    vertex_start: Vec<u32>,
    vertices: Vec<u32>,
    /// Edges owned by each patch (CSR).
    edge_start: Vec<u32>,
    edges: Vec<[u32; 2]>,
    /// Per edge of `edges`: its triangles (the first twice on a border),
    /// and its patch.
    edge_triangles: Vec<[u32; 2]>,
    edge_patch: Vec<u32>,
    /// Per triangle: its patch.
    patch_of: Vec<u32>,
    /// Triangles of other patches across each patch's edges (CSR, sorted).
    across_start: Vec<u32>,
    across: Vec<u32>,
    /// Patches that share a vertex with each patch, itself excluded (CSR, sorted).
    neighbour_start: Vec<u32>,
    neighbours: Vec<u32>,
    /// Patches of each cluster (CSR).
    member_start: Vec<u32>,
    members: Vec<u32>,
    /// Clusters that share a vertex with each cluster (CSR, sorted).
    cluster_neighbour_start: Vec<u32>,
    cluster_neighbours: Vec<u32>,
}

impl Patches {
    pub fn new(rest: &RestNeighbourhood) -> Patches {
        let patch_of = components_in_bins(rest, PATCH_EDGES);
        let count = patch_of.iter().map(|&p| p as usize + 1).max().unwrap_or(0);
        let (triangle_start, triangles) = csr(
            count,
            patch_of.iter().enumerate().map(|(t, &p)| (p, t as u32)),
        );
        let mut vertex_owner: HashMap<u32, u32> = HashMap::new();
        let mut edge_owner: HashMap<[u32; 2], (u32, [u32; 2])> = HashMap::new();
        for (t, (tri, &p)) in rest.triangles.iter().zip(&patch_of).enumerate() {
            let t = t as u32;
            for k in 0..3 {
                vertex_owner.entry(tri[k]).or_insert(p);
                let (a, b) = (tri[k], tri[(k + 1) % 3]);
                edge_owner
                    .entry([a.min(b), a.max(b)])
                    .and_modify(|(_, faces)| faces[1] = t)
                    .or_insert((p, [t, t]));
            }
        }
        let (vertex_start, vertices) = csr(count, vertex_owner.iter().map(|(&v, &p)| (p, v)));
        let (edge_start, edges) = csr(count, edge_owner.iter().map(|(&e, &(p, _))| (p, e)));
        let edge_triangles: Vec<[u32; 2]> = edges.iter().map(|e| edge_owner[e].1).collect();
        let edge_patch: Vec<u32> = edges.iter().map(|e| edge_owner[e].0).collect();
        let mut across_pairs = Vec::new();
        for p in 0..count {
            let rows = edge_start[p] as usize..edge_start[p + 1] as usize;
            for &t in edge_triangles[rows].iter().flatten() {
                if patch_of[t as usize] != p as u32 {
                    across_pairs.push((p as u32, t));
                }
            }
        }
        across_pairs.sort_unstable();
        across_pairs.dedup();
        let (across_start, across) = csr(count, across_pairs.into_iter());
        let (neighbour_start, neighbours) = touching_pieces(rest, &patch_of, count);
        // Patch bins nest in cluster bins, so a patch lies in one cluster.
        let cluster_of_triangle = components_in_bins(rest, PATCH_EDGES * CLUSTER_PATCHES);
        let mut cluster_of = vec![0u32; count];
        for (&p, &c) in patch_of.iter().zip(&cluster_of_triangle) {
            cluster_of[p as usize] = c;
        }
        let clusters = cluster_of
            .iter()
            .map(|&c| c as usize + 1)
            .max()
            .unwrap_or(0);
        let (member_start, members) = csr(
            clusters,
            cluster_of.iter().enumerate().map(|(p, &c)| (c, p as u32)),
        );
        let (cluster_neighbour_start, cluster_neighbours) =
            touching_pieces(rest, &cluster_of_triangle, clusters);
        let mut corner_pairs: Vec<(u32, u32)> = rest
            .triangles
            .iter()
            .zip(&patch_of)
            .flat_map(|(tri, &p)| tri.map(|v| (p, v)))
            .collect();
        corner_pairs.sort_unstable();
        corner_pairs.dedup();
        let (corner_start, corners) = csr(count, corner_pairs.into_iter());
        Patches {
            triangle_start,
            triangles,
            corner_start,
            corners,
            vertex_start,
            vertices,
            edge_start,
            edges,
            edge_triangles,
            edge_patch,
            patch_of,
            across_start,
            across,
            neighbour_start,
            neighbours,
            member_start,
            members,
            cluster_neighbour_start,
            cluster_neighbours,
        }
    }

    pub fn len(&self) -> usize {
        self.triangle_start.len().saturating_sub(1)
    }

    pub fn triangles(&self, p: usize) -> &[u32] {
        row(&self.triangle_start, &self.triangles, p)
    }

    pub fn corners(&self, p: usize) -> &[u32] {
        row(&self.corner_start, &self.corners, p)
    }

    pub fn vertices(&self, p: usize) -> &[u32] {
        row(&self.vertex_start, &self.vertices, p)
    }

    pub fn edges(&self, p: usize) -> &[[u32; 2]] {
        row(&self.edge_start, &self.edges, p)
    }

    /// Every patch's edges, patch after patch, each with its triangles (a
    /// border edge's one triangle twice) and its patch: item `k` of
    /// [`Patches::edge_range`]`(p)` is edge `k` of [`Patches::edges`]`(p)`.
    pub fn all_edges(&self) -> impl IndexedParallelIterator<Item = (&[u32; 2], &[u32; 2], &u32)> {
        (&self.edges, &self.edge_triangles, &self.edge_patch).into_par_iter()
    }

    /// The patch of each triangle.
    pub fn patch_of_triangles(&self) -> &[u32] {
        &self.patch_of
    }

    /// Where patch `p`'s edges lie in [`Patches::all_edges`].
    pub fn edge_range(&self, p: usize) -> Range<usize> {
        self.edge_start[p] as usize..self.edge_start[p + 1] as usize
    }

    /// The triangles of other patches that share an edge of patch `p`:
    /// with its own, every triangle of its edges.
    pub fn triangles_across(&self, p: usize) -> &[u32] {
        row(&self.across_start, &self.across, p)
    }

    pub fn cluster_count(&self) -> usize {
        self.member_start.len().saturating_sub(1)
    }

    /// Patches of cluster `c`.
    pub fn members(&self, c: usize) -> &[u32] {
        row(&self.member_start, &self.members, c)
    }

    /// Whether clusters `c` and `d` (distinct) share a vertex.
    pub fn clusters_touch(&self, c: usize, d: usize) -> bool {
        row(&self.cluster_neighbour_start, &self.cluster_neighbours, c)
            .binary_search(&(d as u32))
            .is_ok()
    }

    /// Whether patches `p` and `q` (distinct) share a vertex.
    pub fn touch(&self, p: usize, q: u32) -> bool {
        row(&self.neighbour_start, &self.neighbours, p)
            .binary_search(&q)
            .is_ok()
    }
}

/// The piece of each triangle: triangles binned by rest centroid into cubes
/// of `edges` mean edge lengths, split into edge-connected components;
/// numbered in order of (cloth, bin, lowest triangle).
fn components_in_bins(rest: &RestNeighbourhood, edges: f32) -> Vec<u32> {
    let mut order: Vec<(u32, IVec3, u32)> = rest
        .triangles
        .iter()
        .enumerate()
        .map(|(t, tri)| {
            let cloth = rest.cloth[tri[0] as usize];
            let side = edges * rest.mean_edge[cloth as usize];
            let centroid = tri
                .iter()
                .map(|&v| rest.rest[v as usize])
                .sum::<glam::Vec3>()
                / 3.0;
            (cloth, (centroid / side).floor().as_ivec3(), t as u32)
        })
        .collect();
    order.sort_unstable_by_key(|&(cloth, c, t)| (cloth, c.x, c.y, c.z, t));
    let mut patch_of = vec![0u32; rest.triangles.len()];
    let mut next = 0u32;
    for bin in order.chunk_by(|a, b| (a.0, a.1) == (b.0, b.1)) {
        let members: Vec<u32> = bin.iter().map(|&(_, _, t)| t).collect();
        let component = edge_components(&members, &rest.triangles);
        let mut id_of_root: HashMap<usize, u32> = HashMap::new();
        for (k, &t) in members.iter().enumerate() {
            patch_of[t as usize] = *id_of_root.entry(component[k]).or_insert_with(|| {
                next += 1;
                next - 1
            });
        }
    }
    patch_of
}

/// For triangles `members` (sorted), the root of the edge-connected
/// component of each (union-find over shared edges).
fn edge_components(members: &[u32], triangles: &[[u32; 3]]) -> Vec<usize> {
    fn find(parent: &mut [usize], mut k: usize) -> usize {
        while parent[k] != k {
            parent[k] = parent[parent[k]];
            k = parent[k];
        }
        k
    }
    let mut parent: Vec<usize> = (0..members.len()).collect();
    let mut first_with_edge: HashMap<[u32; 2], usize> = HashMap::new();
    for (k, &t) in members.iter().enumerate() {
        let tri = triangles[t as usize];
        for e in 0..3 {
            let (a, b) = (tri[e], tri[(e + 1) % 3]);
            let other = *first_with_edge.entry([a.min(b), a.max(b)]).or_insert(k);
            let (ra, rb) = (find(&mut parent, k), find(&mut parent, other));
            // The smaller index becomes the root: roots are each component's first member.
            parent[ra.max(rb)] = ra.min(rb);
        }
    }
    (0..members.len()).map(|k| find(&mut parent, k)).collect()
}

/// Pieces sharing a vertex with each piece (CSR, sorted, without itself),
/// given the piece of each triangle.
fn touching_pieces(
    rest: &RestNeighbourhood,
    patch_of: &[u32],
    count: usize,
) -> (Vec<u32>, Vec<u32>) {
    let (fan_start, fan) = csr(
        rest.rest.len(),
        rest.triangles
            .iter()
            .zip(patch_of)
            .flat_map(|(tri, &p)| tri.map(|v| (v, p))),
    );
    let mut pairs = Vec::new();
    for v in 0..rest.rest.len() {
        let around = row(&fan_start, &fan, v);
        for &p in around {
            pairs.extend(around.iter().filter(|&&q| q != p).map(|&q| (p, q)));
        }
    }
    pairs.sort_unstable();
    pairs.dedup();
    csr(count, pairs.into_iter())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::Model;
    use std::collections::HashSet;

    fn grid_patches(n: u32) -> (Patches, RestNeighbourhood) {
        let mesh = crate::mesh::GridSpec::new(n as usize, n as usize, [1.0, 1.0]).build();
        let mut model = Model::default();
        model.add_cloth("c", mesh, Default::default(), &[], false);
        let rest = RestNeighbourhood::new(&model, 0.01);
        (Patches::new(&rest), rest)
    }

    #[test]
    fn every_triangle_vertex_and_edge_belongs_to_one_patch() {
        let (patches, rest) = grid_patches(13);
        assert!(patches.len() > 4 && patches.len() < rest.triangles.len() / 4);
        let mut triangles = HashSet::new();
        let mut vertices = HashSet::new();
        let mut edges = HashSet::new();
        for p in 0..patches.len() {
            assert!(patches.triangles(p).iter().all(|&t| triangles.insert(t)));
            assert!(patches.vertices(p).iter().all(|&v| vertices.insert(v)));
            assert!(patches.edges(p).iter().all(|&e| edges.insert(e)));
            // Owned vertices and edges lie on the patch's own triangles.
            let corners: HashSet<u32> = patches
                .triangles(p)
                .iter()
                .flat_map(|&t| rest.triangles[t as usize])
                .collect();
            assert_eq!(patches.corners(p).len(), corners.len());
            assert!(patches.corners(p).iter().all(|v| corners.contains(v)));
            assert!(patches.vertices(p).iter().all(|v| corners.contains(v)));
            assert!(patches
                .edges(p)
                .iter()
                .flatten()
                .all(|v| corners.contains(v)));
        }
        assert_eq!(triangles.len(), rest.triangles.len());
        assert_eq!(vertices.len(), rest.rest.len());
        assert_eq!(edges.len(), 3 * 12 * 12 + 12 * 2);
    }

    /// Each edge's triangles are its own, one triangle on the border; those
    /// of other patches are the patch's triangles across its edges.
    #[test]
    fn an_edge_knows_its_triangles() {
        let (patches, rest) = grid_patches(13);
        let all: Vec<_> = patches.all_edges().collect();
        for p in 0..patches.len() {
            let own: HashSet<u32> = patches.triangles(p).iter().copied().collect();
            let mut across = HashSet::new();
            let mine = &all[patches.edge_range(p)];
            assert!(mine.iter().map(|(e, _, _)| *e).eq(patches.edges(p)));
            assert!(mine.iter().all(|&(_, _, &q)| q as usize == p));
            for &(e, faces, _) in mine {
                for &t in faces {
                    assert!(rest.triangles[t as usize].contains(&e[0]));
                    assert!(rest.triangles[t as usize].contains(&e[1]));
                    if !own.contains(&t) {
                        across.insert(t);
                    }
                }
                let on_border = [e[0], e[1]].iter().all(|&v| {
                    let (r, c) = (v / 13, v % 13);
                    r == 0 || r == 12 || c == 0 || c == 12
                }) && (e[0] / 13 == e[1] / 13 || e[0] % 13 == e[1] % 13);
                assert_eq!(faces[0] == faces[1], on_border, "edge {e:?}");
            }
            let listed: HashSet<u32> = patches.triangles_across(p).iter().copied().collect();
            assert_eq!(listed, across);
        }
    }

    #[test]
    fn clusters_hold_whole_patches() {
        let (patches, _) = grid_patches(40);
        assert!(patches.cluster_count() > 4 && patches.cluster_count() < patches.len() / 4);
        let mut seen = HashSet::new();
        for c in 0..patches.cluster_count() {
            for &p in patches.members(c) {
                assert!(seen.insert(p));
            }
        }
        assert_eq!(seen.len(), patches.len());
    }

    #[test]
    fn patches_that_share_a_vertex_touch() {
        let (patches, rest) = grid_patches(9);
        let corners = |p: usize| -> HashSet<u32> {
            patches
                .triangles(p)
                .iter()
                .flat_map(|&t| rest.triangles[t as usize])
                .collect()
        };
        for p in 0..patches.len() {
            for q in 0..patches.len() {
                let shared = p != q && !corners(p).is_disjoint(&corners(q));
                assert_eq!(patches.touch(p, q as u32), shared, "{p} {q}");
            }
        }
    }
}
