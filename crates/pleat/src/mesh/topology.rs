//! Mesh topology: unique edges, adjacent triangle pairs and the boundary.

use super::Mesh;
use rayon::prelude::*;

/// An edge with its (one or two) incident triangles' opposite vertices.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Edge {
    /// End points, `v[0] < v[1]`.
    pub v: [u32; 2],
    /// Vertex opposite the edge in each incident triangle; `None` on the boundary.
    pub opposite: [Option<u32>; 2],
}

/// Two triangles sharing an edge, as used by bending and hinge constraints.
///
/// `v[0]`, `v[1]` is the shared edge, ordered so that it runs counter-clockwise
/// in the triangle `(v[0], v[1], v[2])`; `v[3]` is the other wing, of the
/// triangle `(v[1], v[0], v[3])`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TrianglePair {
    /// The four vertices: the shared edge `v[0], v[1]`, then the wings `v[2]`
    /// and `v[3]`.
    pub v: [u32; 4],
}

/// Edges, adjacent pairs and boundary of a mesh.
#[derive(Clone, Debug, Default)]
pub struct Topology {
    /// The unique edges.
    pub edges: Vec<Edge>,
    /// The pairs of adjacent triangles, one per interior manifold edge.
    pub pairs: Vec<TrianglePair>,
    /// Per vertex: lies on a boundary edge.
    pub boundary: Vec<bool>,
    /// Edges with more than two incident triangles, which get no pair.
    pub non_manifold_edges: usize,
}

/// A triangle's view of one of its edges `(lo, hi)`.
#[derive(Clone, Copy, Debug)]
struct Incidence {
    opposite: u32,
    /// The triangle runs `lo -> hi` counter-clockwise.
    forward: bool,
}

impl Topology {
    /// Derives the topology of `mesh`. Edges come out sorted by vertex pair, so
    /// the result does not depend on hash order.
    pub fn new(mesh: &Mesh) -> Self {
        // Every triangle's three sides keyed by their sorted ends; a stable
        // sort groups each edge's sides, in triangle order. No map and no
        // allocation per edge: a million-vertex mesh has three million.
        let mut sides: Vec<([u32; 2], Incidence)> = mesh
            .triangles
            .par_iter()
            .flat_map_iter(|&[a, b, c]| {
                [(a, b, c), (b, c, a), (c, a, b)].map(|(p, q, opposite)| {
                    let side = Incidence {
                        opposite,
                        forward: p < q,
                    };
                    ([p.min(q), p.max(q)], side)
                })
            })
            .collect();
        sides.par_sort_by_key(|&(v, _)| v);
        let mut topo = Topology {
            boundary: vec![false; mesh.positions.len()],
            ..Default::default()
        };
        for edge in sides.chunk_by(|a, b| a.0 == b.0) {
            topo.add_edge(edge[0].0, edge);
        }
        topo
    }

    /// Adds the edge `v` with its triangles' sides `around`.
    fn add_edge(&mut self, v: [u32; 2], around: &[([u32; 2], Incidence)]) {
        let opposite = match around {
            [(_, one)] => {
                self.boundary[v[0] as usize] = true;
                self.boundary[v[1] as usize] = true;
                [Some(one.opposite), None]
            }
            [(_, first), (_, second)] => {
                let (f, s) = if first.forward {
                    (first, second)
                } else {
                    (second, first)
                };
                let [lo, hi] = v;
                let v = if f.forward {
                    [lo, hi, f.opposite, s.opposite]
                } else {
                    [hi, lo, f.opposite, s.opposite]
                };
                self.pairs.push(TrianglePair { v });
                [Some(first.opposite), Some(second.opposite)]
            }
            _ => {
                self.non_manifold_edges += 1;
                [None, None]
            }
        };
        self.edges.push(Edge { v, opposite });
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::GridSpec;

    #[test]
    fn grid_topology_counts() {
        let mesh = GridSpec::new(4, 3, [1.0, 1.0]).build();
        let topo = Topology::new(&mesh);
        // 3 per quad + right column + bottom row.
        assert_eq!(topo.edges.len(), 3 * 3 * 2 + 2 + 3);
        assert_eq!(topo.pairs.len(), topo.edges.len() - 10);
        assert_eq!(topo.boundary.iter().filter(|b| **b).count(), 10);
        assert_eq!(topo.non_manifold_edges, 0);
    }

    #[test]
    fn pairs_are_ordered_counter_clockwise() {
        let mesh = GridSpec::new(5, 5, [1.0, 1.0]).build();
        let has = |t: [u32; 3]| {
            mesh.triangles
                .iter()
                .any(|m| (0..3).any(|k| [m[k], m[(k + 1) % 3], m[(k + 2) % 3]] == t))
        };
        for p in Topology::new(&mesh).pairs {
            let [a, b, c, d] = p.v;
            assert!(has([a, b, c]) && has([b, a, d]), "{p:?}");
        }
    }
}
