//! Layers at rest: particle pairs of one cloth that lie close together in
//! space at rest but far apart along the cloth, as the two layers of a
//! napkin modelled folded in half or a garment's front and back panels.
//!
//! The rest exclusion keeps a cloth's own neighbours out of contact by their
//! rest distance. Measured straight through space that distance would also
//! switch off the contact between such layers, so a pair whose shortest path
//! along the mesh's edges is more than [`GEODESIC_SLACK`] times the
//! exclusion radius is kept apart by contacts like any other. On a flat or
//! smoothly curved sheet the path along the edges is at most about 1.5 times
//! the straight distance, so no pair of it is found here.
//!
//! Layers lie across the cloth, not along it: only a pair whose offset leaves
//! the first particle's tangent plane at more than [`LAYER_ANGLE`] is
//! followed along the edges, which keeps the search to folds and stacks.

use crate::collide::hash_grid::HashGrid;
use crate::export::vertex_normals;
use crate::math::Aabb;
use glam::Vec3;
use rayon::prelude::*;
use std::cmp::Reverse;
use std::collections::{BinaryHeap, HashMap};

/// A pair closer at rest than the exclusion radius is a pair of layers when
/// its path along the edges is longer than this many radii.
const GEODESIC_SLACK: f32 = 2.0;
/// Sine of the smallest angle between a particle's rest tangent plane and
/// the offset to a particle of another layer (30 degrees).
const LAYER_ANGLE: f32 = 0.5;

/// The rest mesh's particles with their one-rings, as the search needs them.
pub(super) struct RestGraph<'a> {
    pub rest: &'a [Vec3],
    /// Cloth index of each particle.
    pub cloth: &'a [u32],
    /// Sorted one-ring of each particle (CSR).
    pub ring_start: &'a [u32],
    pub ring: &'a [u32],
    pub triangles: &'a [[u32; 3]],
}

impl RestGraph<'_> {
    fn ring(&self, i: usize) -> &[u32] {
        super::csr::row(self.ring_start, self.ring, i)
    }

    /// For each particle, the sorted particles of its cloth closer than
    /// `radius[cloth]` at rest whose path along the edges is longer than
    /// [`GEODESIC_SLACK`] times that radius (CSR), the relation symmetric.
    /// Radii of zero skip a cloth.
    pub fn layer_pairs(&self, radius: &[f32]) -> (Vec<u32>, Vec<u32>) {
        let near = self.near_at_rest(radius);
        let normals = vertex_normals(self.rest, self.triangles);
        let rows: Vec<Vec<u32>> = (0..self.rest.len())
            .into_par_iter()
            .map(|i| {
                let r = radius[self.cloth[i] as usize];
                let (x, n) = (self.rest[i], normals[i]);
                let mut close = self.within(near.as_ref(), i, r);
                close.retain(|&j| {
                    let d = self.rest[j as usize] - x;
                    n.dot(d).abs() > LAYER_ANGLE * d.length()
                });
                if close.is_empty() {
                    return Vec::new();
                }
                let reached = self.reached_along_edges(i, GEODESIC_SLACK * r, &close);
                close.retain(|j| reached.binary_search(j).is_err());
                close
            })
            .collect();
        // Each pair both ways, once: the tangent plane seen from either
        // particle may find it.
        let mut pairs: Vec<(u32, u32)> = rows
            .iter()
            .enumerate()
            .flat_map(|(i, row)| {
                row.iter()
                    .flat_map(move |&j| [(i as u32, j), (j, i as u32)])
            })
            .collect();
        pairs.sort_unstable();
        pairs.dedup();
        super::csr::csr(self.rest.len(), pairs.into_iter())
    }

    /// Of `targets`, those reached from `source` along the edges within
    /// `limit` (Dijkstra, stopped when all are reached or the limit is).
    fn reached_along_edges(&self, source: usize, limit: f32, targets: &[u32]) -> Vec<u32> {
        let mut best: HashMap<u32, f32> = HashMap::from([(source as u32, 0.0)]);
        let mut queue = BinaryHeap::from([Reverse((Distance(0.0), source as u32))]);
        let mut reached = Vec::new();
        while let Some(Reverse((Distance(d), i))) = queue.pop() {
            if d > best[&i] {
                continue;
            }
            if targets.binary_search(&i).is_ok() {
                reached.push(i);
                if reached.len() == targets.len() {
                    break;
                }
            }
            for &j in self.ring(i as usize) {
                let dj = d + self.rest[i as usize].distance(self.rest[j as usize]);
                if dj <= limit && best.get(&j).is_none_or(|&b| dj < b) {
                    best.insert(j, dj);
                    queue.push(Reverse((Distance(dj), j)));
                }
            }
        }
        reached.sort_unstable();
        reached
    }

    /// The rest positions in a hash grid of cells of the largest radius;
    /// `None` when every radius is zero.
    fn near_at_rest(&self, radius: &[f32]) -> Option<HashGrid> {
        let size = radius.iter().copied().fold(0.0, f32::max);
        (size > 0.0).then(|| {
            let points: Vec<Aabb> = self.rest.iter().map(|&x| Aabb::around(x, x)).collect();
            let mut grid = HashGrid::default();
            grid.build(&points, size);
            grid
        })
    }

    /// The sorted other particles of `i`'s cloth closer than `r` to it at rest.
    fn within(&self, near: Option<&HashGrid>, i: usize, r: f32) -> Vec<u32> {
        let (Some(near), true) = (near, r > 0.0) else {
            return Vec::new();
        };
        let x = self.rest[i];
        let mut found = Vec::new();
        near.for_each_overlapping(&Aabb::around(x, x).expanded(r), |j| {
            let close = self.rest[j as usize].distance_squared(x) < r * r;
            if j as usize != i && self.cloth[j as usize] == self.cloth[i] && close {
                found.push(j);
            }
        });
        found.sort_unstable();
        found
    }
}

/// A path length, ordered for the priority queue.
#[derive(Clone, Copy, PartialEq)]
struct Distance(f32);

impl Eq for Distance {}

impl PartialOrd for Distance {
    fn partial_cmp(&self, other: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for Distance {
    fn cmp(&self, other: &Self) -> std::cmp::Ordering {
        self.0.total_cmp(&other.0)
    }
}

#[cfg(test)]
mod tests {
    use super::super::rest::RestNeighbourhood;
    use crate::mesh::GridSpec;
    use crate::model::Model;
    use glam::Vec3;

    /// A 1 m x 0.2 m strip, flat or folded in half across its length with
    /// its halves 3 cm apart.
    fn strip(folded: bool) -> Model {
        let mut mesh = GridSpec::new(21, 5, [1.0, 0.2]).build();
        if folded {
            for x in &mut mesh.positions {
                if x.x > 1e-4 {
                    *x = Vec3::new(-x.x, x.y + 0.03, x.z);
                }
            }
        }
        let mut model = Model::default();
        model.add_cloth("strip", mesh, Default::default(), &[], false);
        model
    }

    #[test]
    fn a_cloth_modelled_folded_keeps_its_layers_in_contact() {
        let rest = RestNeighbourhood::new(&strip(true), 0.005);
        let x = &rest.rest;
        let (mut near_fold, mut apart) = (0, 0);
        for i in 0..x.len() as u32 {
            for j in 0..x.len() as u32 {
                let layers = (x[i as usize].y - x[j as usize].y).abs() > 0.02;
                let close = x[i as usize].distance(x[j as usize]) < 0.06;
                if !(layers && close) {
                    continue;
                }
                // Near the fold the layers are neighbours along the cloth
                // too; a quarter of the strip from it they are layers.
                let from_fold = x[i as usize].x.abs().min(x[j as usize].x.abs());
                assert_eq!(rest.layered(i, j), rest.layered(j, i), "{i} {j} both ways");
                if from_fold < 0.06 {
                    near_fold += 1;
                    assert!(!rest.layered(i, j), "{i} {j} by the fold");
                } else if from_fold > 0.25 {
                    apart += 1;
                    assert!(rest.layered(i, j), "{i} {j} in two layers");
                }
            }
        }
        assert!(near_fold > 0 && apart > 0, "{near_fold} {apart}");
    }

    #[test]
    fn a_flat_cloth_has_no_layers() {
        let model = strip(false);
        let rest = RestNeighbourhood::new(&model, 0.005);
        let n = model.rest.len() as u32;
        for i in 0..n {
            for j in 0..n {
                assert!(!rest.layered(i, j), "{i} {j}");
            }
        }
    }
}
