//! What a layer order must satisfy: one unknown per pair of overlapping
//! facets (which lies above the other), fixed by the creases between
//! neighbours and bound by the conditions of Justin (1997) as ORIPA and
//! Rabbit Ear use them:
//!
//! - **crease**: the two facets of a fold lie one above the other, the
//!   valley's moving facet on the side its neighbour's normal points to;
//! - **taco-taco**: two folds that land on the same segment, on the same
//!   side, nest or stack but do not interleave;
//! - **taco-tortilla**: a facet that a fold lands across, inside it, does not
//!   lie between the fold's two facets;
//! - **transitivity**: three facets overlapping in one place are stacked in
//!   some order, never in a cycle.

use std::collections::{HashMap, HashSet};

use glam::DVec2;

use super::geometry::{FoldedCrease, FoldedGeometry};
use super::overlap::{area, bounds, box_pairs, clip, cross, shrunk, Polygon};

/// A condition on the order of a few facets.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub(super) enum Condition {
    /// `[a, b, c]` are not stacked in a cycle.
    Transitive([u32; 3]),
    /// `[a, b, c]`: `c` does not lie between the fold's facets `a` and `b`.
    TacoTortilla([u32; 3]),
    /// `[a, b, c, d]`: the fold `a b` and the fold `c d` do not interleave.
    TacoTaco([u32; 4]),
}

impl Condition {
    pub(super) fn facets(&self) -> &[u32] {
        match self {
            Condition::Transitive(f) | Condition::TacoTortilla(f) => f,
            Condition::TacoTaco(f) => f,
        }
    }

    /// Whether the order `above` (defined on every pair of this condition's
    /// facets) meets it.
    pub(super) fn holds(&self, above: impl Fn(u32, u32) -> bool) -> bool {
        match *self {
            Condition::Transitive([a, b, c]) => {
                !(above(a, b) == above(b, c) && above(b, c) == above(c, a))
            }
            Condition::TacoTortilla([a, b, c]) => above(a, c) == above(b, c),
            Condition::TacoTaco(f) => {
                // In a strict order the number of facets below each is a
                // permutation of 0..4; anything else has a cycle.
                let rank = f.map(|x| f.iter().filter(|&&y| y != x && above(x, y)).count());
                let mut seen = [false; 4];
                for &r in &rank {
                    if seen[r] {
                        return false;
                    }
                    seen[r] = true;
                }
                let (lo, hi) = (rank[0].min(rank[1]), rank[0].max(rank[1]));
                let between = |r: usize| lo < r && r < hi;
                between(rank[2]) == between(rank[3])
            }
        }
    }
}

/// The unknowns and what binds them.
#[derive(Clone, Debug, Default)]
pub(super) struct Problem {
    /// Every pair of overlapping facets, `[f, g]` with `f < g`; its unknown
    /// is true when `f` lies above `g` (towards the first facet's normal).
    pub(super) pairs: Vec<[u32; 2]>,
    /// Index of each pair in `pairs`.
    pub(super) index: HashMap<[u32; 2], usize>,
    /// Unknowns the creases fix.
    pub(super) fixed: Vec<(usize, bool)>,
    /// The conditions.
    pub(super) conditions: Vec<Condition>,
    /// Every pair of overlapping triangles of different facets, `i < j`.
    pub(super) triangle_pairs: Vec<[u32; 2]>,
}

impl Problem {
    /// The problem of the folded `geometry`.
    pub(super) fn of(geometry: &FoldedGeometry) -> Problem {
        let overlaps = triangle_overlaps(geometry);
        let mut problem = Problem::default();
        let mut triangle_pairs: Vec<[u32; 2]> = overlaps.keys().copied().collect();
        triangle_pairs.sort_unstable();
        for &[i, j] in &triangle_pairs {
            let (f, g) = (geometry.facet_of[i as usize], geometry.facet_of[j as usize]);
            let key = [f.min(g), f.max(g)];
            if !problem.index.contains_key(&key) {
                problem.index.insert(key, problem.pairs.len());
                problem.pairs.push(key);
            }
        }
        problem.triangle_pairs = triangle_pairs;
        problem.fix_creases(geometry);
        let mut conditions: HashSet<Condition> = HashSet::new();
        conditions.extend(taco_tacos(geometry));
        conditions.extend(taco_tortillas(geometry));
        conditions.extend(transitivity(geometry, &overlaps));
        problem.conditions = conditions
            .into_iter()
            .filter(|c| problem.has_every_pair(c.facets()))
            .collect();
        problem
            .conditions
            .sort_unstable_by_key(|c| c.facets().to_vec());
        problem
    }

    /// The unknown of `a` above `b` and the value that means it.
    pub(super) fn literal(&self, a: u32, b: u32) -> Option<(usize, bool)> {
        self.index
            .get(&[a.min(b), a.max(b)])
            .map(|&var| (var, a < b))
    }

    fn has_every_pair(&self, facets: &[u32]) -> bool {
        facets.iter().enumerate().all(|(k, &a)| {
            facets[k + 1..]
                .iter()
                .all(|&b| a != b && self.literal(a, b).is_some())
        })
    }

    /// A valley's moving facet lies on the side its neighbour's normal
    /// points to, a mountain's on the other.
    fn fix_creases(&mut self, geometry: &FoldedGeometry) {
        for crease in &geometry.creases {
            let [a, b] = crease.facets;
            if let Some((var, sense)) = self.literal(b, a) {
                let b_above_a = crease.valley != geometry.flipped(a);
                self.fixed.push((var, b_above_a == sense));
            }
        }
    }
}

/// Every pair of triangles of different facets that overlap in an area,
/// with their overlap.
fn triangle_overlaps(geometry: &FoldedGeometry) -> HashMap<[u32; 2], Polygon> {
    let shrunk: Vec<Option<[DVec2; 3]>> = geometry
        .folded
        .iter()
        .map(|&t| shrunk(t, geometry.tolerance))
        .collect();
    let boxes: Vec<(DVec2, DVec2)> = shrunk
        .iter()
        .map(|t| t.map_or((DVec2::NAN, DVec2::NAN), |t| bounds(&t)))
        .collect();
    let least_area = geometry.tolerance * geometry.tolerance;
    box_pairs(&boxes)
        .into_iter()
        .filter(|&(i, j)| geometry.facet_of[i as usize] != geometry.facet_of[j as usize])
        .filter_map(|(i, j)| {
            let (a, b) = (shrunk[i as usize]?, shrunk[j as usize]?);
            let overlap = clip(&a, &b);
            (area(&overlap) > least_area).then_some(([i, j], overlap))
        })
        .collect()
}

/// Two folds on one segment, on one side of it.
fn taco_tacos(geometry: &FoldedGeometry) -> Vec<Condition> {
    let tol = geometry.tolerance;
    let boxes: Vec<(DVec2, DVec2)> = geometry
        .creases
        .iter()
        .map(|c| {
            let (lo, hi) = bounds(&c.ends);
            (lo - tol, hi + tol)
        })
        .collect();
    box_pairs(&boxes)
        .into_iter()
        .filter_map(|(i, j)| {
            let (c, d) = (&geometry.creases[i as usize], &geometry.creases[j as usize]);
            let shared = c.facets.iter().any(|f| d.facets.contains(f));
            let same_side = side(c, c.inside) == side(c, d.inside);
            (!shared && same_side && overlap_along(c, d.ends, tol).is_some_and(|l| l > tol))
                .then(|| Condition::TacoTaco([c.facets[0], c.facets[1], d.facets[0], d.facets[1]]))
        })
        .collect()
}

/// Which side of `crease`'s line `p` lies on.
fn side(crease: &FoldedCrease, p: DVec2) -> bool {
    cross(crease.ends[0], crease.ends[1], p) > 0.0
}

/// How long a stretch of `crease` the segment `ends` covers, when it lies
/// on its line (within `tol`); `None` when it does not.
fn overlap_along(crease: &FoldedCrease, ends: [DVec2; 2], tol: f64) -> Option<f64> {
    let [a, b] = crease.ends;
    let length = (b - a).length();
    if length <= tol {
        return None;
    }
    let dir = (b - a) / length;
    let off = |p: DVec2| dir.perp_dot(p - a).abs();
    if off(ends[0]) > tol || off(ends[1]) > tol {
        return None;
    }
    let (s, t) = (dir.dot(ends[0] - a), dir.dot(ends[1] - a));
    Some(s.max(t).min(length) - s.min(t).max(0.0))
}

/// A fold that lands across the inside of another facet.
fn taco_tortillas(geometry: &FoldedGeometry) -> Vec<Condition> {
    let tol = geometry.tolerance;
    let triangle_boxes: Vec<(DVec2, DVec2)> = geometry.folded.iter().map(|t| bounds(t)).collect();
    let mut found = Vec::new();
    for crease in &geometry.creases {
        let (lo, hi) = bounds(&crease.ends);
        for (t, &(t_lo, t_hi)) in triangle_boxes.iter().enumerate() {
            let facet = geometry.facet_of[t];
            if crease.facets.contains(&facet)
                || t_lo.x > hi.x + tol
                || lo.x > t_hi.x + tol
                || t_lo.y > hi.y + tol
                || lo.y > t_hi.y + tol
            {
                continue;
            }
            if crosses_inside(geometry, t, crease.ends) {
                found.push(Condition::TacoTortilla([
                    crease.facets[0],
                    crease.facets[1],
                    facet,
                ]));
            }
        }
    }
    found
}

/// True when a stretch longer than the tolerance of the segment `ends` lies
/// inside triangle `t`'s facet: inside the triangle, or along one of its
/// edges that is not the facet's edge (the facet goes on across it; the
/// whole segment then lies on that edge's line). The stretch's middle must
/// lie more than the tolerance inside every other edge, so a segment that
/// only grazes a corner does not count.
pub(super) fn crosses_inside(geometry: &FoldedGeometry, t: usize, ends: [DVec2; 2]) -> bool {
    let tri = geometry.folded[t];
    let tol = geometry.tolerance;
    let Some((s0, s1)) = clip_segment(ends, &tri, tol) else {
        return false;
    };
    let (p, q) = (
        ends[0] + (ends[1] - ends[0]) * s0,
        ends[0] + (ends[1] - ends[0]) * s1,
    );
    if (q - p).length() <= tol {
        return false;
    }
    let middle = (p + q) * 0.5;
    // The folded triangle is the sheet's reversed where the facet is
    // flipped: its edge k is the sheet's edge 2 - k.
    let flipped = geometry.flipped(geometry.facet_of[t]);
    (0..3).all(|k| {
        let (a, b) = (tri[k], tri[(k + 1) % 3]);
        let dir = (b - a).normalize_or_zero();
        let along = ends.iter().all(|&e| dir.perp_dot(e - a).abs() <= tol);
        let sheet_edge = if flipped { 2 - k } else { k };
        if along {
            !geometry.facet_edge[t][sheet_edge]
        } else {
            dir.perp_dot(middle - a) > tol
        }
    })
}

/// The parameters `[s0, s1]` of the part of segment `ends` inside the
/// counter-clockwise triangle `tri` grown by `tol` (Cyrus–Beck).
fn clip_segment(ends: [DVec2; 2], tri: &[DVec2; 3], tol: f64) -> Option<(f64, f64)> {
    let (mut s0, mut s1) = (0.0_f64, 1.0_f64);
    let d = ends[1] - ends[0];
    for k in 0..3 {
        let (a, b) = (tri[k], tri[(k + 1) % 3]);
        let edge = b - a;
        let len = edge.length();
        if len == 0.0 {
            return None;
        }
        // Signed distance inside the edge, grown by tol.
        let at = edge.perp_dot(ends[0] - a) / len + tol;
        let rate = edge.perp_dot(d) / len;
        if rate.abs() < 1e-300 {
            if at < 0.0 {
                return None;
            }
            continue;
        }
        let s = -at / rate;
        if rate > 0.0 {
            s0 = s0.max(s);
        } else {
            s1 = s1.min(s);
        }
    }
    (s0 < s1).then_some((s0, s1))
}

/// Triples of facets with a common overlap.
fn transitivity(
    geometry: &FoldedGeometry,
    overlaps: &HashMap<[u32; 2], Polygon>,
) -> Vec<Condition> {
    let mut neighbours: Vec<Vec<u32>> = vec![Vec::new(); geometry.folded.len()];
    for &[i, j] in overlaps.keys() {
        neighbours[i as usize].push(j);
        neighbours[j as usize].push(i);
    }
    for n in &mut neighbours {
        n.sort_unstable();
    }
    let least_area = geometry.tolerance * geometry.tolerance;
    let mut found = HashSet::new();
    for (&[i, j], polygon) in overlaps {
        let facets = [i, j].map(|t| geometry.facet_of[t as usize]);
        for &k in common(&neighbours[i as usize], &neighbours[j as usize]) {
            let f = geometry.facet_of[k as usize];
            if k < j || facets.contains(&f) {
                continue;
            }
            let Some(tri) = shrunk(geometry.folded[k as usize], geometry.tolerance) else {
                continue;
            };
            if area(&clip(polygon, &tri)) > least_area {
                let mut triple = [facets[0], facets[1], f];
                triple.sort_unstable();
                found.insert(Condition::Transitive(triple));
            }
        }
    }
    found.into_iter().collect()
}

/// The items of two sorted lists that are in both.
fn common<'a>(a: &'a [u32], b: &'a [u32]) -> impl Iterator<Item = &'a u32> {
    a.iter().filter(move |x| b.binary_search(x).is_ok())
}
