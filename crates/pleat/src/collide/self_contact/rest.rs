//! The rest mesh as seen by self-contacts: which particle pairs, vertex-triangle
//! pairs and edge pairs never collide because they lie close together in the
//! rest mesh (a cloth's own neighbours touch all the time; they are held
//! apart by its stretch and bending constraints, not by contacts).
//!
//! - particle pairs that share an edge or lie closer at rest than the thickness;
//! - vertex-triangle and edge-edge pairs that share a particle, or whose
//!   features lie closer at rest than a radius: for cloth
//!   [`CLOTH_EXCLUSION`] times the thickness (the pairs in contact at rest),
//!   so that a soft cloth crumpled or folded sharply still meets its
//!   neighbours a few edges along; for paper (a crease pattern, whose
//!   triangles are large and whose layers fold flat onto their neighbours)
//!   [`PAPER_EXCLUSION`] times the thickness, so that a flap folded onto the
//!   facet next to it is held a thickness away;
//! - but never the layers of a cloth modelled folded over, close in space yet
//!   far apart along the cloth ([`super::folded`]): a pair with a corner in
//!   another layer than its other feature collides however close at rest.

use super::csr::{csr, row};
use super::folded::RestGraph;
use super::layer_sides::LayerSides;
use crate::collide::ccd;
use crate::model::Model;
use glam::Vec3;

/// A cloth's vertex-triangle and edge-edge pairs closer at rest than this
/// many thicknesses never collide.
pub const CLOTH_EXCLUSION: f32 = 1.0;
/// Paper's vertex-triangle and edge-edge pairs closer at rest than this many
/// thicknesses never collide.
pub const PAPER_EXCLUSION: f32 = 2.0;
/// A cloth's layers at rest are searched among particle pairs closer than
/// this many (thickness + longest edge): far enough to take in the corners
/// of a triangle in the layer under a particle.
const LAYER_SEARCH: f32 = 2.0;

#[derive(Clone, Debug, Default)]
pub(super) struct RestNeighbourhood {
    /// Cloth index of each particle.
    pub cloth: Vec<u32>,
    pub rest: Vec<Vec3>,
    /// Sorted one-ring of each particle (CSR).
    ring_start: Vec<u32>,
    ring: Vec<u32>,
    /// Each particle's sorted partners in another layer of its cloth at
    /// rest (CSR): close in space, far along the cloth.
    layer_start: Vec<u32>,
    layer: Vec<u32>,
    pub triangles: Vec<[u32; 3]>,
    /// Per cloth: mean rest edge length.
    pub mean_edge: Vec<f32>,
    /// Per cloth: rest distance of two features below which they never
    /// collide.
    exclusion: Vec<f32>,
    /// Per cloth: whether it is paper.
    paper: Vec<bool>,
    thickness: f32,
    /// The side each paper vertex belongs on of the triangles its facets
    /// overlap when folded flat, where the paper has a layer order.
    pub layers: Option<LayerSides>,
}

impl RestNeighbourhood {
    pub fn new(model: &Model, thickness: f32) -> Self {
        let n = model.particle_count();
        let mut cloth = vec![0; n];
        let mut exclusion = Vec::new();
        let mut layer_search = Vec::new();
        let mut mean_edge = Vec::new();
        let mut paper = Vec::new();
        for (k, part) in model.cloths.iter().enumerate() {
            cloth[part.particles()].fill(k as u32);
            let lengths = model
                .edges
                .iter()
                .filter(|e| part.particles().contains(&(e.v[0] as usize)))
                .map(|e| e.rest_length);
            let (count, sum, longest) =
                lengths.fold((0, 0.0, 0.0f32), |(c, s, l), x| (c + 1, s + x, l.max(x)));
            mean_edge.push(if count > 0 {
                sum / count as f32
            } else {
                thickness
            });
            let is_paper = part.paper.is_some();
            let factor = if is_paper {
                PAPER_EXCLUSION
            } else {
                CLOTH_EXCLUSION
            };
            exclusion.push(factor * thickness);
            // Paper is never modelled in layers: a crease pattern is flat.
            layer_search.push(if is_paper {
                0.0
            } else {
                LAYER_SEARCH * (thickness + longest)
            });
            paper.push(is_paper);
        }
        let edges: Vec<[u32; 2]> = model.edges.iter().map(|e| e.v).collect();
        let (ring_start, ring) = csr(n, edges.iter().flat_map(|&[a, b]| [(a, b), (b, a)]));
        let graph = RestGraph {
            rest: &model.rest,
            cloth: &cloth,
            ring_start: &ring_start,
            ring: &ring,
            triangles: &model.triangles,
        };
        let (layer_start, layer) = graph.layer_pairs(&layer_search);
        RestNeighbourhood {
            cloth,
            rest: model.rest.clone(),
            ring_start,
            ring,
            layer_start,
            layer,
            triangles: model.triangles.clone(),
            mean_edge,
            exclusion,
            paper,
            thickness,
            layers: LayerSides::new(model),
        }
    }

    fn rest_closer_than(&self, i: u32, j: u32, r: f32) -> bool {
        self.cloth[i as usize] == self.cloth[j as usize]
            && self.rest[i as usize].distance_squared(self.rest[j as usize]) < r * r
    }

    /// Particles that never form a particle-particle contact.
    pub fn pair_excluded(&self, i: u32, j: u32) -> bool {
        let ring = &self.ring
            [self.ring_start[i as usize] as usize..self.ring_start[i as usize + 1] as usize];
        self.rest_closer_than(i, j, self.thickness) || ring.binary_search(&j).is_ok()
    }

    /// Whether particles `i` and `j` lie in two layers of a cloth modelled
    /// folded over.
    pub fn layered(&self, i: u32, j: u32) -> bool {
        row(&self.layer_start, &self.layer, i as usize)
            .binary_search(&j)
            .is_ok()
    }

    /// Whether any cloth is paper.
    pub fn has_paper(&self) -> bool {
        self.paper.iter().any(|&p| p)
    }

    /// The exclusion radius of a pair of features of particles `p` and `q`:
    /// `None` when they belong to two cloths, which always collide.
    fn exclusion_of(&self, p: u32, q: u32) -> Option<f32> {
        let cloth = self.cloth[p as usize];
        (cloth == self.cloth[q as usize]).then(|| self.exclusion[cloth as usize])
    }

    /// Whether vertex `p` never meets triangle `t`.
    pub fn vertex_triangle_excluded(&self, p: u32, t: [u32; 3]) -> bool {
        if t.contains(&p) {
            return true;
        }
        let Some(radius) = self.exclusion_of(p, t[0]) else {
            return false;
        };
        !t.iter().any(|&k| self.layered(p, k)) && {
            let [a, b, c] = t.map(|k| self.rest[k as usize]);
            ccd::point_triangle_distance(self.rest[p as usize], a, b, c) < radius
        }
    }

    /// Whether edges `e` and `f` never meet.
    pub fn edge_edge_excluded(&self, e: [u32; 2], f: [u32; 2]) -> bool {
        if e.iter().any(|k| f.contains(k)) {
            return true;
        }
        let Some(radius) = self.exclusion_of(e[0], f[0]) else {
            return false;
        };
        !e.iter().any(|&a| f.iter().any(|&b| self.layered(a, b))) && {
            let [a0, a1, b0, b1] = [e[0], e[1], f[0], f[1]].map(|k| self.rest[k as usize]);
            ccd::segment_distance(a0, a1, b0, b1) < radius
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rest_neighbours_are_excluded() {
        let mesh = crate::mesh::GridSpec::new(4, 4, [0.3, 0.3]).build();
        let mut model = Model::default();
        model.add_cloth("c", mesh, Default::default(), &[], false);
        let rest = RestNeighbourhood::new(&model, 0.01);
        assert!(rest.pair_excluded(0, 1), "edge");
        assert!(!rest.pair_excluded(0, 15), "far");
        assert!(rest.edge_edge_excluded([0, 1], [1, 2]), "shared particle");
        let triangle = *model.triangles.iter().find(|t| t.contains(&5)).unwrap();
        assert!(rest.vertex_triangle_excluded(5, triangle), "own triangle");
        // A cell (10 cm) apart: in contact at rest only when the cloth is
        // thicker than that.
        let far = *model.triangles.iter().find(|t| t.contains(&15)).unwrap();
        assert!(!rest.edge_edge_excluded([0, 1], [4, 5]));
        assert!(!rest.vertex_triangle_excluded(0, far));
        let thick = RestNeighbourhood::new(&model, 0.15);
        assert!(thick.edge_edge_excluded([0, 1], [4, 5]));
        assert!(!thick.edge_edge_excluded([0, 1], [12, 13]));
    }

    /// Paper excludes a vertex-triangle or edge-edge pair exactly when it
    /// shares a particle or lies closer at rest than two thicknesses, so
    /// that a flap folded flat meets the facet next to it.
    #[test]
    fn paper_excludes_only_what_touches_at_rest() {
        use crate::origami::{builtin, Sheet, SheetOptions};
        let pattern = builtin("waterbomb-base").unwrap();
        let sheet = Sheet::from_pattern(&pattern, &SheetOptions::default()).unwrap();
        let (model, _) = crate::folding::paper_model(&sheet);
        let x = &model.rest;
        let edges: Vec<[u32; 2]> = model.edges.iter().map(|e| e.v).collect();
        for thickness in [5e-4, 0.2] {
            let rest = RestNeighbourhood::new(&model, thickness);
            let limit = PAPER_EXCLUSION * thickness;
            let mut colliding = 0;
            for p in 0..x.len() as u32 {
                for &t in &model.triangles {
                    let [a, b, c] = t.map(|k| x[k as usize]);
                    let near = t.contains(&p)
                        || ccd::point_triangle_distance(x[p as usize], a, b, c) < limit;
                    assert_eq!(rest.vertex_triangle_excluded(p, t), near, "{p} {t:?}");
                    colliding += usize::from(!near);
                }
            }
            for &e in &edges {
                for &f in &edges {
                    let [a0, a1, b0, b1] = [e[0], e[1], f[0], f[1]].map(|k| x[k as usize]);
                    let near = e.iter().any(|k| f.contains(k))
                        || ccd::segment_distance(a0, a1, b0, b1) < limit;
                    assert_eq!(rest.edge_edge_excluded(e, f), near, "{e:?} {f:?}");
                }
            }
            assert!(colliding > 0, "some pairs collide");
        }
    }
}
