//! The flat-folded state of a crease pattern and its layer order: where
//! every facet lands when every crease folds to 180 degrees, and which of
//! two overlapping facets lies above the other (the flat-folding problem
//! that ORIPA and Rabbit Ear solve; Justin 1997, Bern and Hayes 1996).
//!
//! The sheet's facets are folded by reflecting them about their creases
//! ([`geometry`]); every pair of facets that then overlap gets an unknown,
//! which the creases fix for neighbours and Justin's conditions bind for
//! the rest ([`constraints`]); a depth-first search with propagation finds
//! one order that meets them all ([`search`]), or says that none does. Where
//! several orders are possible the search keeps the first it finds, so the
//! order is one valid order, not the only one.
//!
//! The order is written as FOLD's `faceOrders` over the sheet's triangles:
//! `[f, g, s]`, `f` on the side `g`'s normal points to when `s` is 1. A
//! folded state from elsewhere (a simulation's end) is checked against the
//! same conditions with [`FlatFolded::check`].

mod constraints;
mod geometry;
mod overlap;
mod search;

use glam::DVec2;
use serde::Serialize;

use super::{PatternError, Sheet};
use constraints::Problem;
use geometry::FoldedGeometry;
use search::Unsolved;

/// A crease pattern folded flat, with a layer order.
#[derive(Clone, Debug)]
pub struct FlatFolded {
    geometry: FoldedGeometry,
    problem: Problem,
    /// One value per pair of [`Problem::pairs`]: true when the first facet
    /// lies above the second.
    above: Vec<bool>,
    /// Per pair, whether every valid order has it so: forced by the creases
    /// and conditions alone, not by a choice of the search.
    forced: Vec<bool>,
    /// Where each of the sheet's vertices lands (metres, in the plane of
    /// the first facet).
    positions: Vec<DVec2>,
}

/// A layer order as the simulation uses it: the facet of each triangle, and
/// for each ordered pair of overlapping facets `[f, g]` the side of `g`
/// that `f` lies on when folded flat (1: the side `g`'s normal points to,
/// -1: the other), sorted.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FacetSides {
    /// The facet of each triangle of the sheet.
    pub facet_of: Vec<u32>,
    /// `([f, g], side)`, sorted by pair.
    pub sides: Vec<([u32; 2], i8)>,
}

impl FacetSides {
    /// The side of facet `g` that facet `f` lies on, if they overlap.
    pub fn side(&self, f: u32, g: u32) -> Option<i8> {
        self.sides
            .binary_search_by_key(&[f, g], |&(pair, _)| pair)
            .ok()
            .map(|k| self.sides[k].1)
    }
}

/// How a given order of stacked triangles (a simulation's end) agrees with
/// the conditions of a flat fold ([`FlatFolded::check`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
pub struct LayerCheck {
    /// Pairs of overlapping facets the given order decides.
    pub pairs: usize,
    /// Of those, the ones that lie as in the order the solver found (where
    /// several orders are valid, a valid order may differ in some).
    pub as_solved: usize,
    /// Pairs of facets the given order decides both ways (two of their
    /// triangles stacked one way, two the other).
    pub both_ways: usize,
    /// Creases whose facets lie the wrong way round: a valley's facets
    /// stacked as a mountain's, or the reverse.
    pub creases_broken: usize,
    /// Conditions (taco-taco, taco-tortilla, transitivity) the given order
    /// decides, and those it breaks.
    pub conditions_checked: usize,
    /// Conditions broken.
    pub conditions_broken: usize,
    /// True when nothing is broken ([`LayerCheck::is_valid`]).
    pub valid: bool,
}

impl LayerCheck {
    /// True when nothing is broken: the given order is a valid layer order
    /// wherever it decides one.
    pub fn is_valid(&self) -> bool {
        self.both_ways == 0 && self.creases_broken == 0 && self.conditions_broken == 0
    }
}

impl FlatFolded {
    /// Folds `sheet` flat and finds a layer order. Fails, saying why, when a
    /// crease does not fold to 180 degrees, when a vertex breaks Kawasaki's
    /// theorem, when the creases do not close, or when no order of the
    /// layers meets the conditions.
    pub fn solve(sheet: &Sheet) -> Result<FlatFolded, PatternError> {
        let geometry = FoldedGeometry::of(sheet)?;
        let problem = Problem::of(&geometry);
        let solution = search::solve(&problem).map_err(|why| unsolved(&geometry, why))?;
        let mut positions = vec![DVec2::ZERO; sheet.positions.len()];
        for (t, tri) in sheet.triangles.iter().enumerate() {
            let motion = &geometry.motion[geometry.facet_of[t] as usize];
            for &v in tri {
                let p = sheet.positions[v as usize];
                positions[v as usize] = motion.apply(DVec2::new(p.x.into(), p.y.into()));
            }
        }
        Ok(FlatFolded {
            geometry,
            problem,
            above: solution.values,
            forced: solution.forced,
            positions,
        })
    }

    /// Number of facets: pieces of paper between creases.
    pub fn facet_count(&self) -> usize {
        self.geometry.facet_count()
    }

    /// Number of pairs of facets that overlap when folded.
    pub fn overlapping_pairs(&self) -> usize {
        self.problem.pairs.len()
    }

    /// Number of conditions (taco-taco, taco-tortilla, transitivity) the
    /// order meets.
    pub fn condition_count(&self) -> usize {
        self.problem.conditions.len()
    }

    /// Where each of the sheet's vertices lands, in the plane.
    pub fn positions(&self) -> &[DVec2] {
        &self.positions
    }

    /// True when facet-of-triangle `t` lies face down.
    fn triangle_flipped(&self, t: u32) -> bool {
        self.geometry.flipped(self.geometry.facet_of[t as usize])
    }

    /// Whether the facet of triangle `i` lies above that of triangle `j`
    /// (towards the first facet's normal), `None` when they do not overlap.
    fn triangle_above(&self, i: u32, j: u32) -> Option<bool> {
        let (f, g) = (
            self.geometry.facet_of[i as usize],
            self.geometry.facet_of[j as usize],
        );
        let (var, sense) = self.problem.literal(f, g)?;
        Some(self.above[var] == sense)
    }

    /// Number of overlapping pairs whose order every valid order shares
    /// (the creases and conditions force it).
    pub fn forced_pairs(&self) -> usize {
        self.forced.iter().filter(|&&f| f).count()
    }

    /// The side each facet lies on of every facet it overlaps, for the
    /// pairs whose order is forced (the same in every valid order), for
    /// contacts that keep layers in order ([`FacetSides`]). Pairs the
    /// search chose are left out: paper may stack them either way.
    pub fn facet_sides(&self) -> FacetSides {
        let mut sides = Vec::with_capacity(2 * self.problem.pairs.len());
        let pairs = self.problem.pairs.iter().zip(&self.above).zip(&self.forced);
        for ((&[f, g], &f_above), _) in pairs.filter(|(_, &forced)| forced) {
            let side = |above: bool, below: u32| {
                if above != self.geometry.flipped(below) {
                    1
                } else {
                    -1
                }
            };
            sides.push(([f, g], side(f_above, g)));
            sides.push(([g, f], side(!f_above, f)));
        }
        sides.sort_unstable();
        FacetSides {
            facet_of: self.geometry.facet_of.clone(),
            sides,
        }
    }

    /// The order as FOLD's `faceOrders` over the sheet's triangles: every
    /// pair of overlapping triangles of different facets, `[f, g, s]`
    /// with `f < g`, `s = 1` when `f` lies on the side `g`'s normal points
    /// to and -1 when on the other.
    pub fn face_orders(&self) -> Vec<[i64; 3]> {
        self.problem
            .triangle_pairs
            .iter()
            .filter_map(|&[i, j]| {
                let above = self.triangle_above(i, j)?;
                let s = if above != self.triangle_flipped(j) {
                    1
                } else {
                    -1
                };
                Some([i.into(), j.into(), s])
            })
            .collect()
    }

    /// Checks a given order of stacked triangles, `(f, g, s)` as in
    /// [`FlatFolded::face_orders`] (the layers of a simulated fold, as
    /// [`crate::metrics::layer_order`] reads them), against the creases and
    /// the conditions. Pairs of triangles that do not overlap in the flat
    /// fold are left out.
    pub fn check(&self, orders: impl IntoIterator<Item = (u32, u32, i8)>) -> LayerCheck {
        let mut values: Vec<Option<bool>> = vec![None; self.problem.pairs.len()];
        let mut both = vec![false; self.problem.pairs.len()];
        for (f, g, s) in orders {
            let (a, b) = (
                self.geometry.facet_of[f as usize],
                self.geometry.facet_of[g as usize],
            );
            let Some((var, sense)) = self.problem.literal(a, b) else {
                continue;
            };
            let a_above = (s > 0) != self.geometry.flipped(b);
            let value = a_above == sense;
            match values[var] {
                None => values[var] = Some(value),
                Some(v) if v != value => both[var] = true,
                Some(_) => {}
            }
        }
        let mut check = LayerCheck {
            both_ways: both.iter().filter(|&&b| b).count(),
            ..LayerCheck::default()
        };
        for (var, value) in values.iter().enumerate() {
            if let Some(v) = value {
                check.pairs += 1;
                check.as_solved += usize::from(*v == self.above[var]);
            }
        }
        check.creases_broken = self
            .problem
            .fixed
            .iter()
            .filter(|&&(var, value)| values[var] == Some(!value))
            .count();
        for condition in &self.problem.conditions {
            if let Some(broken) = search::breaks(&self.problem, condition, &values) {
                check.conditions_checked += 1;
                check.conditions_broken += usize::from(broken);
            }
        }
        check.valid = check.is_valid();
        check
    }

    /// The folded state as a FOLD object (one frame of class
    /// `foldedForm`): the sheet's vertices where they land (2D), its
    /// triangles as faces, and `faceOrders`.
    pub fn to_fold_json(&self, sheet: &Sheet, title: &str) -> serde_json::Value {
        let coords: Vec<[f64; 2]> = self.positions.iter().map(|p| p.to_array()).collect();
        serde_json::json!({
            "file_spec": 1.1,
            "file_creator": "pleat",
            "file_classes": ["singleModel"],
            "frame_title": title,
            "frame_classes": ["foldedForm"],
            "frame_attributes": ["2D"],
            "vertices_coords": coords,
            "faces_vertices": sheet.triangles,
            "faceOrders": self.face_orders(),
        })
    }
}

/// The error for a search that found no order.
fn unsolved(geometry: &FoldedGeometry, why: Unsolved) -> PatternError {
    match why {
        Unsolved::Contradiction(facets) if !facets.is_empty() => {
            let at = facets
                .iter()
                .filter_map(|&f| geometry.facet_of.iter().position(|&x| x == f))
                .map(|t| {
                    let c = geometry.folded[t].iter().sum::<DVec2>() / 3.0;
                    format!("({:.3}, {:.3})", c.x, c.y)
                })
                .collect::<Vec<_>>()
                .join(", ");
            PatternError::new(
                "",
                format!("no layer order: its layers cannot be stacked where facets fold to {at} (in the folded state)"),
            )
        }
        Unsolved::Contradiction(_) => PatternError::new(
            "",
            "no layer order: every way of stacking its layers breaks a condition",
        ),
        Unsolved::TooHard => PatternError::new(
            "",
            "layer order not found: the search gave up after a million choices",
        ),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::origami::pattern::PatternBuilder;
    use crate::origami::{
        builtin, check_flat_foldability, Assignment, CreasePattern, SheetOptions,
    };

    fn sheet(pattern: &CreasePattern) -> Sheet {
        Sheet::from_pattern(pattern, &SheetOptions::default()).expect("a sheet")
    }

    /// A square sheet with one vertex at its centre and a crease from it to
    /// the edge at each of `creases` (degrees, assignment).
    fn single_vertex(creases: &[(f64, Assignment)]) -> CreasePattern {
        let mut b = PatternBuilder::default();
        let corners = [[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]].map(DVec2::from);
        for k in 0..4 {
            b.segment(corners[k], corners[(k + 1) % 4], Assignment::Boundary, None);
        }
        for &(degrees, assignment) in creases {
            let d = DVec2::from_angle(f64::to_radians(degrees));
            b.segment(DVec2::ZERO, d / d.abs().max_element(), assignment, None);
        }
        b.finish()
    }

    /// The facet of each triangle of `sheet` that holds `point` (flat).
    fn triangle_at(sheet: &Sheet, point: DVec2) -> u32 {
        let flat = |v: u32| {
            DVec2::new(
                sheet.positions[v as usize].x.into(),
                sheet.positions[v as usize].y.into(),
            )
        };
        sheet
            .triangles
            .iter()
            .position(|t| {
                let [a, b, c] = t.map(flat);
                let inside = |p: DVec2, q: DVec2| (q - p).perp_dot(point - p) > 0.0;
                inside(a, b) && inside(b, c) && inside(c, a)
            })
            .expect("a triangle there") as u32
    }

    #[test]
    fn a_valley_puts_each_half_on_the_side_the_other_faces_and_a_mountain_away() {
        for (assignment, s) in [(Assignment::Valley, 1), (Assignment::Mountain, -1)] {
            let mut b = PatternBuilder::default();
            let corners = [[0.0, 0.0], [2.0, 0.0], [2.0, 1.0], [0.0, 1.0]].map(DVec2::from);
            for k in 0..4 {
                b.segment(corners[k], corners[(k + 1) % 4], Assignment::Boundary, None);
            }
            b.segment(DVec2::new(1.0, 0.0), DVec2::new(1.0, 1.0), assignment, None);
            let sheet = sheet(&b.finish());
            let folded = FlatFolded::solve(&sheet).unwrap();
            assert_eq!(folded.facet_count(), 2);
            assert_eq!(folded.overlapping_pairs(), 1);
            let orders = folded.face_orders();
            assert!(!orders.is_empty());
            for [_, _, side] in &orders {
                assert_eq!(*side, s, "{assignment:?}: {orders:?}");
            }
            // The right half lands on the left one, mirrored.
            let right = sheet.positions.iter().position(|p| p.x > 0.4).unwrap();
            assert!(
                folded.positions()[right].x < 1e-6,
                "{:?}",
                folded.positions()[right]
            );
        }
    }

    #[test]
    fn the_order_found_passes_its_own_check_and_fails_it_reversed() {
        for name in [
            "waterbomb-base",
            "miura-ori",
            "kresling",
            "waterbomb-tessellation",
        ] {
            let sheet = sheet(&builtin(name).unwrap());
            let folded = FlatFolded::solve(&sheet).unwrap();
            let orders = folded.face_orders();
            let as_given = |flip: i64| {
                orders
                    .iter()
                    .map(move |&[f, g, s]| (f as u32, g as u32, (s * flip) as i8))
            };
            let check = folded.check(as_given(1));
            assert!(check.valid, "{name}: {check:?}");
            assert_eq!(check.pairs, folded.overlapping_pairs(), "{name}");
            assert_eq!(check.as_solved, check.pairs, "{name}");
            assert!(
                check.conditions_checked > 0 || name == "waterbomb-base",
                "{name}: {check:?}"
            );
            let reversed = folded.check(as_given(-1));
            assert!(
                !reversed.valid && reversed.creases_broken > 0,
                "{name}: {reversed:?}"
            );
        }
    }

    #[test]
    fn one_flap_turned_over_breaks_a_condition_not_only_its_crease() {
        // The waterbomb base's six facets: reverse the order of one facet
        // against every other, as a flap that went the wrong way would be.
        let sheet = sheet(&builtin("waterbomb-base").unwrap());
        let folded = FlatFolded::solve(&sheet).unwrap();
        let moved = folded.geometry.facet_of[0];
        let orders = folded.face_orders().into_iter().map(|[f, g, s]| {
            let flip = folded.geometry.facet_of[f as usize] == moved
                || folded.geometry.facet_of[g as usize] == moved;
            (f as u32, g as u32, if flip { -s } else { s } as i8)
        });
        let check = folded.check(orders);
        assert!(!check.valid, "{check:?}");
        assert!(check.as_solved < check.pairs);
    }

    #[test]
    fn a_vertex_that_breaks_big_little_big_has_no_layer_order_though_both_theorems_hold() {
        use Assignment::{Mountain as M, Valley as V};
        // Sectors of 100, 60, 80 and 120 degrees: Kawasaki holds (100 + 80 =
        // 60 + 120 = 180). The 60-degree sector is smaller than both its
        // neighbours, so its creases must differ; here they do not.
        let bad = single_vertex(&[(0.0, M), (100.0, M), (160.0, M), (240.0, V)]);
        assert!(check_flat_foldability(&bad).unwrap().is_flat_foldable());
        let e = FlatFolded::solve(&sheet(&bad)).unwrap_err();
        assert!(e.to_string().contains("no layer order"), "{e}");
        let good = single_vertex(&[(0.0, M), (100.0, M), (160.0, V), (240.0, M)]);
        let folded = FlatFolded::solve(&sheet(&good)).unwrap();
        assert_eq!(folded.facet_count(), 4);
        assert_eq!(folded.overlapping_pairs(), 6);
    }

    #[test]
    fn creases_that_do_not_close_are_refused_with_the_reason() {
        use Assignment::{Mountain as M, Valley as V};
        // Sectors of 90, 90, 80 and 100 degrees: every other one sums to
        // 170, not 180 (Kawasaki fails by 10 degrees).
        let pattern = single_vertex(&[(0.0, M), (90.0, M), (180.0, V), (260.0, M)]);
        let e = FlatFolded::solve(&sheet(&pattern)).unwrap_err();
        assert!(
            e.to_string().contains(
                "Kawasaki's theorem fails there (its alternate sector angles sum to 170.000 and 190.000 deg"
            ),
            "{e}"
        );
        // A crease to 90 degrees is no flat fold.
        let mut half = builtin("single-line").unwrap();
        for edge in &mut half.edges {
            if edge.assignment == V || edge.assignment == M {
                edge.fold_angle = Some(90.0);
            }
        }
        let e = FlatFolded::solve(&sheet(&half)).unwrap_err();
        assert!(e.to_string().contains("not flat"), "{e}");
    }

    /// A vertex a quarter of a degree off Kawasaki's theorem closes within
    /// the sheet's closure tolerance, but cannot fold flat: no layer order
    /// is given for it (`pleat check` refuses it, and contacts must not
    /// be steered by one). A twentieth of a degree is drawing round-off.
    #[test]
    fn a_vertex_slightly_off_kawasaki_has_no_flat_folded_state() {
        use Assignment::{Mountain as M, Valley as V};
        let off = single_vertex(&[(0.0, M), (90.0, M), (180.0, V), (270.25, M)]);
        let e = FlatFolded::solve(&sheet(&off)).unwrap_err();
        assert!(
            e.to_string().contains("sum to 179.750 and 180.250 deg"),
            "{e}"
        );
        let drawn = single_vertex(&[(0.0, M), (90.0, M), (180.0, V), (270.05, M)]);
        assert_eq!(FlatFolded::solve(&sheet(&drawn)).unwrap().facet_count(), 4);
    }

    #[test]
    fn flaps_folded_over_each_others_creases_interlock_unless_on_opposite_sides() {
        // A strip of length 3 with creases at 1 and 1.5: the left flap
        // lands on [1, 2], the right one on [0, 1.5]. Each flap lies across
        // the other's crease, so neither can lie between the middle and the
        // other (taco-tortilla): both on one side interlock, which no order
        // allows; on opposite sides each has its own.
        use Assignment::{Mountain as M, Valley as V};
        let strip = |right: Assignment| {
            let mut b = PatternBuilder::default();
            let corners = [[0.0, 0.0], [3.0, 0.0], [3.0, 1.0], [0.0, 1.0]].map(DVec2::from);
            for k in 0..4 {
                b.segment(corners[k], corners[(k + 1) % 4], Assignment::Boundary, None);
            }
            b.segment(DVec2::new(1.0, 0.0), DVec2::new(1.0, 1.0), V, None);
            b.segment(DVec2::new(1.5, 0.0), DVec2::new(1.5, 1.0), right, None);
            b.finish()
        };
        let e = FlatFolded::solve(&sheet(&strip(V))).unwrap_err();
        assert!(e.to_string().contains("no layer order"), "{e}");
        let sheet = sheet(&strip(M));
        let folded = FlatFolded::solve(&sheet).unwrap();
        assert_eq!(folded.overlapping_pairs(), 3);
        // On the sheet scaled to 1 m: x from -0.5 to 0.5.
        let (left, middle, right) = (
            triangle_at(&sheet, DVec2::new(-0.4, 0.011)),
            triangle_at(&sheet, DVec2::new(-0.1, 0.021)),
            triangle_at(&sheet, DVec2::new(0.3, 0.017)),
        );
        let above = |a: u32, b: u32| folded.triangle_above(a, b).unwrap();
        assert_ne!(above(left, middle), above(right, middle));
        assert_eq!(above(left, right), above(left, middle));
    }
}
