//! Which side of a layer a feature belongs on, from the layer order of
//! paper folded flat ([`crate::origami::FlatFolded`]): a vertex or an edge
//! of facet `f` against a triangle or an edge of facet `g` that `f`
//! overlaps when folded flat belongs on the side of `g` the order gives.
//! A feature on the creases between several facets belongs there when
//! they all agree.
//!
//! Contacts use it as a one-way wall: a feature that came from the side it
//! belongs on is held there, as any contact holds it; one that came from
//! the other side is let through, so that a flap that started around the
//! wrong way can end in order instead of jamming.

use crate::model::Model;
use crate::origami::FacetSides;

use super::csr::row;

/// Facets of the paper parts, numbered across parts, and their sides.
#[derive(Clone, Debug)]
pub(super) struct LayerSides {
    /// Per global triangle, its facet.
    facet_of: Vec<Option<u32>>,
    /// Per facet, one of its triangles (global corners).
    triangle_of: Vec<[u32; 3]>,
    /// First facet of each part, and one past the last part's.
    first_facet: Vec<u32>,
    /// Per part, its order (`None` where it has none).
    parts: Vec<Option<FacetSides>>,
    /// Per global particle, the sorted facets around it (CSR).
    start: Vec<u32>,
    facets: Vec<u32>,
}

impl LayerSides {
    /// The sides of `model`'s paper; `None` when no part has an order.
    pub(super) fn new(model: &Model) -> Option<Self> {
        let parts: Vec<Option<FacetSides>> = model
            .cloths
            .iter()
            .map(|c| c.paper.as_ref().and_then(|p| p.layers.clone()))
            .collect();
        if parts.iter().all(Option::is_none) {
            return None;
        }
        let mut first_facet = vec![0u32];
        let mut facet_of = Vec::with_capacity(model.triangles.len());
        let mut triangle_of = Vec::new();
        let mut around: Vec<Vec<u32>> = vec![Vec::new(); model.particle_count()];
        for (cloth, sides) in model.cloths.iter().zip(&parts) {
            let first = *first_facet.last().expect("first facet");
            let count = sides
                .as_ref()
                .and_then(|s| s.facet_of.iter().max())
                .map_or(0, |&f| f + 1);
            triangle_of.resize(first as usize + count as usize, [0; 3]);
            for (t, tri) in cloth.mesh.triangles.iter().enumerate() {
                let facet = sides
                    .as_ref()
                    .and_then(|s| s.facet_of.get(t))
                    .map(|&f| first + f);
                facet_of.push(facet);
                if let Some(f) = facet {
                    let corners = tri.map(|v| cloth.global(v));
                    triangle_of[f as usize] = corners;
                    for v in corners {
                        around[v as usize].push(f);
                    }
                }
            }
            first_facet.push(first + count);
        }
        let mut start = vec![0u32];
        let mut facets = Vec::new();
        for mut list in around {
            list.sort_unstable();
            list.dedup();
            facets.extend(list);
            start.push(facets.len() as u32);
        }
        Some(LayerSides {
            facet_of,
            triangle_of,
            first_facet,
            parts,
            start,
            facets,
        })
    }

    /// The side of facet `g` that facet `f` lies on when folded flat.
    fn side(&self, f: u32, g: u32) -> Option<i8> {
        let part = self.first_facet.partition_point(|&first| first <= g) - 1;
        let (first, end) = (self.first_facet[part], self.first_facet[part + 1]);
        if !(first..end).contains(&f) {
            return None;
        }
        self.parts[part].as_ref()?.side(f - first, g - first)
    }

    /// The one side that every facet of `mine` gives against facet `g`, if
    /// any gives one and none lies in `g` itself.
    fn agreed(&self, mine: impl IntoIterator<Item = u32>, g: u32) -> Option<i8> {
        let mut side = None;
        for f in mine {
            if f == g {
                return None;
            }
            match (side, self.side(f, g)) {
                (_, None) => {}
                (None, s) => side = s,
                (Some(a), Some(b)) if a != b => return None,
                _ => {}
            }
        }
        side
    }

    fn around(&self, v: u32) -> &[u32] {
        row(&self.start, &self.facets, v as usize)
    }

    /// The side of global triangle `t` (along its normal) that particle `v`
    /// belongs on: 1, -1, or 0 where the order says nothing.
    pub(super) fn vertex_triangle(&self, v: u32, t: u32) -> i8 {
        let Some(Some(g)) = self.facet_of.get(t as usize).copied() else {
            return 0;
        };
        self.agreed(self.around(v).iter().copied(), g).unwrap_or(0)
    }

    /// For edge `a` against edge `b`: a triangle of one of `b`'s facets
    /// (global corners) and the side of it (along its normal) that `a`
    /// belongs on, where the order gives one.
    pub(super) fn edge_edge(&self, a: [u32; 2], b: [u32; 2]) -> Option<([u32; 3], i8)> {
        let on_edge = |e: [u32; 2]| {
            let second = self.around(e[1]);
            self.around(e[0])
                .iter()
                .copied()
                .filter(move |f| second.binary_search(f).is_ok())
        };
        on_edge(b).find_map(|g| {
            self.agreed(on_edge(a), g)
                .map(|side| (self.triangle_of[g as usize], side))
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::folding::{paper_material, PaperStiffness};
    use crate::origami::pattern::PatternBuilder;
    use crate::origami::{Assignment, Sheet, SheetOptions};
    use glam::DVec2;

    /// A 2 x 1 sheet with one crease down its middle, as a paper part.
    fn folded_once(assignment: Assignment) -> (Model, LayerSides) {
        let mut b = PatternBuilder::default();
        let corners = [[0.0, 0.0], [2.0, 0.0], [2.0, 1.0], [0.0, 1.0]].map(DVec2::from);
        for k in 0..4 {
            b.segment(corners[k], corners[(k + 1) % 4], Assignment::Boundary, None);
        }
        b.segment(DVec2::new(1.0, 0.0), DVec2::new(1.0, 1.0), assignment, None);
        let sheet = Sheet::from_pattern(&b.finish(), &SheetOptions::default()).unwrap();
        let mut model = Model::default();
        model.add_paper("p", &sheet, paper_material(), PaperStiffness::default());
        let sides = LayerSides::new(&model).expect("an order");
        (model, sides)
    }

    #[test]
    fn a_valley_flap_belongs_on_its_neighbours_front_and_a_mountain_flap_behind() {
        for (assignment, expected) in [(Assignment::Valley, 1), (Assignment::Mountain, -1)] {
            let (model, sides) = folded_once(assignment);
            let x = &model.rest;
            // A corner of the right half, against every triangle of the left.
            let corner = x.iter().position(|p| p.x > 0.4).unwrap() as u32;
            let left: Vec<u32> = (0..model.triangles.len() as u32)
                .filter(|&t| {
                    model.triangles[t as usize]
                        .iter()
                        .all(|&v| x[v as usize].x < 1e-6)
                })
                .collect();
            assert!(!left.is_empty());
            for t in left {
                assert_eq!(sides.vertex_triangle(corner, t), expected, "{assignment:?}");
            }
            // A vertex on the crease lies in both halves: nothing to say.
            let on_crease = x.iter().position(|p| p.x.abs() < 1e-6).unwrap() as u32;
            let t = (0..model.triangles.len() as u32)
                .find(|&t| !model.triangles[t as usize].contains(&on_crease))
                .unwrap();
            assert_eq!(sides.vertex_triangle(on_crease, t), 0);
        }
    }
}
