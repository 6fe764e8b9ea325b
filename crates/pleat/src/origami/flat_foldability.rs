//! Local flat-foldability of a crease pattern: Kawasaki's and Maekawa's
//! theorems at every interior vertex that folds flat.
//!
//! A vertex folds flat (all its creases to 180 degrees, without tearing or
//! stretching the paper) only if
//! - **Kawasaki's theorem** (Kawasaki–Justin): the alternating sum of the
//!   sector angles around it is zero, so the angles of every other sector
//!   sum to 180 degrees;
//! - **Maekawa's theorem** (Maekawa–Justin): its mountain and valley
//!   creases differ in number by two, |M − V| = 2.
//!
//! Both are necessary local conditions, not sufficient ones: a pattern that
//! meets them at every vertex may still not fold flat as a whole (the layer
//! order can fail, e.g. by the big-little-big lemma or across vertices;
//! deciding global flat-foldability is NP-hard, Bern and Hayes 1996). A
//! pattern that breaks them somewhere cannot fold flat as drawn, though a
//! partial fold of it is legitimate.
//!
//! Which vertices are checked: those inside the paper (no boundary or cut
//! edge meets them) whose creases are all mountain or valley folds with the
//! full flat-fold target of 180 degrees. Flat facet lines and auxiliary
//! lines do not fold and are ignored (the sectors on either side of one
//! are one sector). A vertex with an unassigned crease, or a crease whose
//! target is a partial angle, is skipped and counted as such.

use glam::DVec2;
use serde::Serialize;
use std::f64::consts::PI;

use super::planar::planarize;
use super::{Assignment, CreasePattern, PatternError, MERGE_TOLERANCE};

/// Largest Kawasaki defect (degrees) still taken as flat-foldable: drawing
/// round-off. Origami Simulator's library, drawn in Illustrator, is exact to
/// about 0.01 degree; a vertex moved by a visible amount breaks it by more.
pub const KAWASAKI_TOLERANCE_DEG: f64 = 0.1;

/// Which theorem a vertex breaks.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Theorem {
    /// Alternate sector angles do not each sum to 180 degrees (or the
    /// vertex has an odd number of creases).
    Kawasaki,
    /// |M − V| is not 2.
    Maekawa,
}

/// One vertex that breaks a theorem.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Violation {
    /// Index of the vertex in the cleaned pattern (the planar graph: crossings
    /// split, near points merged, unused points dropped).
    pub vertex: usize,
    /// Index of the same point among the file's own vertices (FOLD's
    /// `vertices_coords`, the order a .cp or .svg file's segment ends first
    /// appear), where the file has one there; messages name this one.
    pub pattern_vertex: Option<usize>,
    /// Where the vertex is, in the pattern's own units.
    pub position: [f64; 2],
    /// The theorem it breaks.
    pub theorem: Theorem,
    /// By how much: for Kawasaki, degrees between the sum of every other
    /// sector angle and 180 (the odd sectors' sum minus 180); for
    /// Maekawa, |M − V| − 2 (creases).
    pub by: f64,
    /// Mountain creases at the vertex.
    pub mountains: usize,
    /// Valley creases at the vertex.
    pub valleys: usize,
}

impl std::fmt::Display for Violation {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let [x, y] = self.position;
        match self.pattern_vertex {
            Some(v) => write!(f, "vertex {v} at ({x:.4}, {y:.4})")?,
            None => write!(
                f,
                "the crossing at ({x:.4}, {y:.4}) (vertex {} of the cleaned pattern)",
                self.vertex
            )?,
        }
        let creases = self.mountains + self.valleys;
        match self.theorem {
            Theorem::Kawasaki if creases % 2 == 1 => write!(
                f,
                ": Kawasaki's theorem fails: {creases} creases, an odd number"
            ),
            Theorem::Kawasaki => write!(
                f,
                ": Kawasaki's theorem fails: every other sector angle sums to {:.3} deg, not 180 (off by {:.3} deg)",
                180.0 + self.by,
                self.by.abs()
            ),
            Theorem::Maekawa => write!(
                f,
                ": Maekawa's theorem fails: {} mountains and {} valleys, |M - V| = {} (not 2)",
                self.mountains,
                self.valleys,
                self.mountains.abs_diff(self.valleys)
            ),
        }
    }
}

/// What the check found over a whole pattern.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct FlatFoldability {
    /// Interior vertices whose creases all fold flat: the ones checked.
    pub vertices_checked: usize,
    /// Interior vertices skipped: an unassigned crease or a partial target
    /// angle meets them.
    pub vertices_skipped: usize,
    /// Largest Kawasaki defect over the checked vertices with an even
    /// number of creases (degrees, absolute): how far from flat-foldable
    /// the drawing is, 0 where none was checked.
    pub max_kawasaki_defect_deg: f64,
    /// Every broken theorem, by vertex.
    pub violations: Vec<Violation>,
}

impl FlatFoldability {
    /// True when every checked vertex meets both theorems (locally
    /// flat-foldable).
    pub fn is_flat_foldable(&self) -> bool {
        self.violations.is_empty()
    }

    /// One line: `flat-foldable: ...` or `not flat-foldable as drawn: ...`
    /// with the first few violations.
    pub fn summary(&self) -> String {
        if self.vertices_checked == 0 && self.vertices_skipped == 0 {
            return "flat-foldable: no crease meets another inside the paper".to_string();
        }
        if self.vertices_checked == 0 {
            return format!(
                "no interior vertex folds flat, none to check for flat-foldability{}",
                skipped(self.vertices_skipped)
            );
        }
        if self.is_flat_foldable() {
            return format!(
                "flat-foldable at every interior vertex (Kawasaki and Maekawa hold at {} vertices{})",
                self.vertices_checked,
                skipped(self.vertices_skipped)
            );
        }
        let shown: Vec<String> = self
            .violations
            .iter()
            .take(3)
            .map(|v| v.to_string())
            .collect();
        let more = self.violations.len().saturating_sub(shown.len());
        format!(
            "not flat-foldable as drawn: {} of {} vertices checked break a theorem{}: {}{}",
            self.vertices_with_violations(),
            self.vertices_checked,
            skipped(self.vertices_skipped),
            shown.join("; "),
            if more > 0 {
                format!("; and {more} more")
            } else {
                String::new()
            }
        )
    }

    /// Vertices that break at least one theorem.
    pub fn vertices_with_violations(&self) -> usize {
        let mut v: Vec<usize> = self.violations.iter().map(|v| v.vertex).collect();
        v.dedup();
        v.len()
    }
}

fn skipped(n: usize) -> String {
    if n == 0 {
        String::new()
    } else {
        format!(", {n} skipped for unassigned or partial creases")
    }
}

/// Checks Kawasaki's and Maekawa's theorems at every interior vertex of
/// `pattern` whose creases all fold flat (see the module's doc). The
/// pattern is cleaned first as the sheet is ([`planarize`] with
/// [`MERGE_TOLERANCE`]), so crossings are vertices too.
pub fn check_flat_foldability(pattern: &CreasePattern) -> Result<FlatFoldability, PatternError> {
    let graph = planarize(pattern, MERGE_TOLERANCE)?;
    let mut around: Vec<Vec<(f64, Assignment, Option<f64>)>> =
        vec![Vec::new(); graph.vertices.len()];
    for e in &graph.edges {
        let [a, b] = e.v;
        let (pa, pb) = (graph.vertices[a], graph.vertices[b]);
        let d = pb - pa;
        around[a].push((d.y.atan2(d.x), e.assignment, e.fold_angle));
        around[b].push(((-d.y).atan2(-d.x), e.assignment, e.fold_angle));
    }
    let diameter = bounds_diameter(&graph.vertices);
    let mut result = FlatFoldability::default();
    for (vertex, edges) in around.iter_mut().enumerate() {
        let on_rim = edges
            .iter()
            .any(|(_, a, _)| matches!(a, Assignment::Boundary | Assignment::Cut));
        if on_rim {
            continue;
        }
        edges.retain(|(_, a, _)| !matches!(a, Assignment::Flat | Assignment::Auxiliary));
        if edges.is_empty() {
            continue;
        }
        let flat_fold = edges.iter().all(|(_, a, angle)| {
            matches!(a, Assignment::Mountain | Assignment::Valley)
                && angle.is_none_or(|deg| (deg.abs() - 180.0).abs() < 1e-6)
        });
        if !flat_fold {
            result.vertices_skipped += 1;
            continue;
        }
        result.vertices_checked += 1;
        edges.sort_by(|a, b| a.0.total_cmp(&b.0));
        let mountains = edges
            .iter()
            .filter(|(_, a, _)| *a == Assignment::Mountain)
            .count();
        let valleys = edges.len() - mountains;
        let position = graph.vertices[vertex];
        let violation = |theorem, by| Violation {
            vertex,
            pattern_vertex: pattern_vertex(pattern, position, diameter),
            position: position.to_array(),
            theorem,
            by,
            mountains,
            valleys,
        };
        let defect = kawasaki_defect(edges.iter().map(|e| e.0));
        if let Some(by) = defect {
            result.max_kawasaki_defect_deg = result.max_kawasaki_defect_deg.max(by.abs());
        }
        match defect {
            Some(by) if by.abs() <= KAWASAKI_TOLERANCE_DEG => {}
            Some(by) => result.violations.push(violation(Theorem::Kawasaki, by)),
            None => result
                .violations
                .push(violation(Theorem::Kawasaki, f64::NAN)),
        }
        let m_minus_v = mountains.abs_diff(valleys);
        if m_minus_v != 2 {
            result
                .violations
                .push(violation(Theorem::Maekawa, m_minus_v as f64 - 2.0));
        }
    }
    Ok(result)
}

/// Kawasaki's defect of a vertex whose creases leave it at `directions`
/// (radians, sorted): the sum of the odd sector angles minus 180 degrees,
/// in degrees (zero when the theorem holds). `None` for an odd number of
/// creases, where the alternate sectors are not defined.
pub fn kawasaki_defect(directions: impl IntoIterator<Item = f64>) -> Option<f64> {
    let d: Vec<f64> = directions.into_iter().collect();
    if d.is_empty() || d.len() % 2 == 1 {
        return None;
    }
    let mut odd = 0.0;
    for i in (0..d.len()).step_by(2) {
        let next = if i + 1 < d.len() {
            d[i + 1]
        } else {
            d[0] + 2.0 * PI
        };
        odd += next - d[i];
    }
    Some((odd - PI).to_degrees())
}

/// The file's vertex at `position`, if one lies within the merge tolerance.
fn pattern_vertex(pattern: &CreasePattern, position: DVec2, diameter: f64) -> Option<usize> {
    let tolerance = diameter * MERGE_TOLERANCE;
    pattern
        .vertices
        .iter()
        .enumerate()
        .map(|(i, p)| (i, p.distance(position)))
        .filter(|(_, d)| *d <= tolerance)
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .map(|(i, _)| i)
}

fn bounds_diameter(points: &[DVec2]) -> f64 {
    let (lo, hi) = points.iter().fold(
        (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY)),
        |(lo, hi), p| (lo.min(*p), hi.max(*p)),
    );
    if points.is_empty() {
        0.0
    } else {
        (hi - lo).length()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::origami::{builtin, PatternEdge};

    /// A unit square with creases from its centre to the given points on
    /// its rim, each with its assignment.
    fn single_vertex(creases: &[(DVec2, Assignment)]) -> CreasePattern {
        let mut vertices = vec![
            DVec2::new(-1.0, -1.0),
            DVec2::new(1.0, -1.0),
            DVec2::new(1.0, 1.0),
            DVec2::new(-1.0, 1.0),
            DVec2::ZERO,
        ];
        let mut edges: Vec<PatternEdge> = (0..4)
            .map(|i| PatternEdge {
                v: [i, (i + 1) % 4],
                assignment: Assignment::Boundary,
                fold_angle: None,
            })
            .collect();
        for (end, assignment) in creases {
            vertices.push(*end);
            edges.push(PatternEdge {
                v: [4, vertices.len() - 1],
                assignment: *assignment,
                fold_angle: None,
            });
        }
        CreasePattern { vertices, edges }
    }

    use Assignment::{Mountain as M, Valley as V};

    #[test]
    fn the_waterbomb_base_and_the_miura_ori_are_flat_foldable() {
        for name in [
            "waterbomb-base",
            "miura-ori",
            "square-twist",
            "parallel-lines",
        ] {
            let check = check_flat_foldability(&builtin(name).unwrap()).unwrap();
            assert!(check.is_flat_foldable(), "{name}: {}", check.summary());
            assert!(
                check.vertices_checked >= 1 || name == "parallel-lines",
                "{name}"
            );
        }
    }

    #[test]
    fn maekawa_counts_mountains_and_valleys_at_a_hand_made_vertex() {
        // A square's diagonals and midlines meet at the centre: 8 creases,
        // sector angles all 45 degrees, so Kawasaki holds whatever the
        // assignment.
        let rim = [
            (1.0, 0.0),
            (1.0, 1.0),
            (0.0, 1.0),
            (-1.0, 1.0),
            (-1.0, 0.0),
            (-1.0, -1.0),
            (0.0, -1.0),
            (1.0, -1.0),
        ];
        let with = |assign: [Assignment; 8]| {
            let creases: Vec<(DVec2, Assignment)> = rim
                .iter()
                .zip(assign)
                .map(|(&(x, y), a)| (DVec2::new(x, y), a))
                .collect();
            check_flat_foldability(&single_vertex(&creases)).unwrap()
        };
        // 5 mountains, 3 valleys: |M - V| = 2 (the waterbomb's centre, turned over).
        let ok = with([M, V, M, V, M, V, M, M]);
        assert_eq!(ok.vertices_checked, 1);
        assert!(ok.is_flat_foldable(), "{}", ok.summary());
        // 4 and 4: Maekawa fails by 2.
        let even = with([M, V, M, V, M, V, M, V]);
        let v = &even.violations[..];
        assert_eq!(v.len(), 1, "{}", even.summary());
        assert_eq!(v[0].theorem, Theorem::Maekawa);
        assert_eq!((v[0].mountains, v[0].valleys), (4, 4));
        assert_eq!(v[0].by, -2.0);
        assert_eq!(v[0].position, [0.0, 0.0]);
        assert!(
            even.summary().contains("4 mountains and 4 valleys"),
            "{}",
            even.summary()
        );
        // 8 mountains: |M - V| = 8, off by 6.
        let all = with([M; 8]);
        assert_eq!(all.violations[0].by, 6.0);
        // Partial fold angles: skipped, not checked.
        let mut partial = single_vertex(&[(DVec2::X, M), (DVec2::NEG_X, V)]);
        partial.edges[4].fold_angle = Some(-90.0);
        let skipped = check_flat_foldability(&partial).unwrap();
        assert_eq!((skipped.vertices_checked, skipped.vertices_skipped), (0, 1));
        assert!(skipped
            .summary()
            .starts_with("no interior vertex folds flat"));
    }

    #[test]
    fn kawasaki_fails_at_a_moved_vertex_and_names_it() {
        // Four creases through a point: straight lines are flat-foldable
        // (three mountains and a valley), a bent one is not.
        let straight = single_vertex(&[
            (DVec2::new(1.0, 0.0), M),
            (DVec2::new(0.0, 1.0), M),
            (DVec2::new(-1.0, 0.0), M),
            (DVec2::new(0.0, -1.0), V),
        ]);
        let ok = check_flat_foldability(&straight).unwrap();
        assert!(ok.is_flat_foldable(), "{}", ok.summary());
        let mut moved = straight.clone();
        // The centre moved: the sectors are no longer 90 degrees each.
        moved.vertices[4] = DVec2::new(0.2, 0.1);
        let bad = check_flat_foldability(&moved).unwrap();
        assert_eq!(bad.violations.len(), 1, "{}", bad.summary());
        let v = &bad.violations[0];
        assert_eq!(v.theorem, Theorem::Kawasaki);
        assert_eq!(v.pattern_vertex, Some(4));
        assert_eq!(v.position, [0.2, 0.1]);
        // Sectors towards +x and +y: atan2 differences; the odd ones sum to
        // 180 + by.
        let dirs: Vec<f64> = [(0.8, -0.1), (-0.2, 0.9), (-1.2, -0.1), (-0.2, -1.1)]
            .iter()
            .map(|&(x, y): &(f64, f64)| f64::atan2(y, x))
            .collect();
        let mut sorted = dirs.clone();
        sorted.sort_by(f64::total_cmp);
        let expected = kawasaki_defect(sorted).unwrap();
        assert!(
            (v.by - expected).abs() < 1e-9 && v.by.abs() > 1.0,
            "{}",
            v.by
        );
        assert!(
            bad.summary().contains("vertex 4 at (0.2000, 0.1000)"),
            "{}",
            bad.summary()
        );
        assert!(bad.summary().contains("Kawasaki"), "{}", bad.summary());
        // An odd number of creases breaks both.
        let three = single_vertex(&[(DVec2::X, M), (DVec2::Y, M), (DVec2::NEG_X, V)]);
        let odd = check_flat_foldability(&three).unwrap();
        let theorems: Vec<Theorem> = odd.violations.iter().map(|v| v.theorem).collect();
        assert_eq!(theorems, [Theorem::Kawasaki, Theorem::Maekawa]);
        assert!(odd.summary().contains("odd number"), "{}", odd.summary());
    }
}
