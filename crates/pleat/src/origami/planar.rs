//! Planar straight-line graph: turns the segments of an imported pattern,
//! which may cross, overlap, touch only approximately or repeat, into a
//! clean graph where edges meet only at shared vertices.
//!
//! Steps: merge points closer than the tolerance (relative to the pattern's
//! diameter), split every segment at the points of other segments that lie on
//! it (T-junctions, overlaps) and at proper crossings, drop zero-length
//! pieces, and keep one edge per vertex pair, choosing between overlapping
//! edges by [`Assignment::overlap_rank`](super::pattern::Assignment::overlap_rank).
//! Candidate pairs come from a sweep over x, so sparse patterns cost close to
//! O(n log n).

use std::collections::HashMap;

use glam::DVec2;

use super::pattern::{CreasePattern, PatternEdge, PatternError};

/// Merge tolerance for imported coordinates, relative to the pattern's
/// diameter: well above the 1e-14 round-off of ORIPA files, far below any
/// real feature.
pub const DEFAULT_TOLERANCE: f64 = 1e-9;

/// Builds the clean planar graph of `pattern`, merging points closer than
/// `relative_tolerance` times the diameter of its bounding box. Vertices no
/// edge uses are dropped. Fails on an edge naming a missing vertex, on a
/// coordinate that is not finite and on coordinates so large that the
/// diameter overflows.
pub fn planarize(
    pattern: &CreasePattern,
    relative_tolerance: f64,
) -> Result<CreasePattern, PatternError> {
    validate(pattern)?;
    let Some((min, max)) = bounds(pattern) else {
        return Ok(CreasePattern::default());
    };
    let diameter = (max - min).length();
    if !diameter.is_finite() {
        return Err(PatternError::new(
            "",
            "coordinates are too large: the pattern's size overflows",
        ));
    }
    let tolerance = relative_tolerance * diameter;
    if tolerance <= 0.0 {
        // All points coincide: every segment has zero length.
        return Ok(CreasePattern::default());
    }
    let mut snap = VertexSnap::new(min, tolerance);
    let segments = snapped_segments(pattern, &mut snap);
    let splits = find_splits(&segments, &mut snap);
    let pieces = split_segments(&segments, &splits, &snap.points);
    let kept = resolve_overlaps(pattern, pieces);
    Ok(compact(pattern, &snap.points, &kept))
}

fn validate(pattern: &CreasePattern) -> Result<(), PatternError> {
    if let Some(i) = pattern.vertices.iter().position(|p| !p.is_finite()) {
        return Err(PatternError::new(
            format!("vertex {i}"),
            "coordinate is not a finite number",
        ));
    }
    let count = pattern.vertices.len();
    match pattern
        .edges
        .iter()
        .position(|e| e.v.iter().any(|&v| v >= count))
    {
        Some(i) => Err(PatternError::new(
            format!("edge {i}"),
            format!("vertex index out of range (there are {count} vertices)"),
        )),
        None => Ok(()),
    }
}

/// Bounding box of the vertices that edges use; `None` without edges.
fn bounds(pattern: &CreasePattern) -> Option<(DVec2, DVec2)> {
    let mut used = pattern
        .edges
        .iter()
        .flat_map(|e| e.v)
        .map(|i| pattern.vertices[i])
        .peekable();
    used.peek()?;
    Some(
        used.fold((DVec2::INFINITY, DVec2::NEG_INFINITY), |(lo, hi), p| {
            (lo.min(p), hi.max(p))
        }),
    )
}

/// Greedy point merging on a hash grid whose cells are one tolerance wide,
/// so every point within the tolerance of `p` lies in the 3 x 3 cells
/// around `p`'s cell.
struct VertexSnap {
    origin: DVec2,
    tolerance: f64,
    cells: HashMap<(i64, i64), Vec<usize>>,
    points: Vec<DVec2>,
}

impl VertexSnap {
    fn new(origin: DVec2, tolerance: f64) -> Self {
        VertexSnap {
            origin,
            tolerance,
            cells: HashMap::new(),
            points: Vec::new(),
        }
    }

    fn cell(&self, p: DVec2) -> (i64, i64) {
        // `as` saturates, so far-away or odd points still land in a cell.
        let c = ((p - self.origin) / self.tolerance).floor();
        (c.x as i64, c.y as i64)
    }

    /// Index of the merged point for `p`, creating one when none is near.
    fn snap(&mut self, p: DVec2) -> usize {
        let (cx, cy) = self.cell(p);
        for dx in -1..=1 {
            for dy in -1..=1 {
                let key = (cx.saturating_add(dx), cy.saturating_add(dy));
                if let Some(found) = self.cells.get(&key).and_then(|list| {
                    list.iter()
                        .copied()
                        .find(|&i| self.points[i].distance(p) <= self.tolerance)
                }) {
                    return found;
                }
            }
        }
        self.points.push(p);
        let index = self.points.len() - 1;
        self.cells.entry((cx, cy)).or_default().push(index);
        index
    }
}

/// A segment after point merging: its end points and the edge it came from.
#[derive(Clone, Copy)]
struct Segment {
    v: [usize; 2],
    source: usize,
}

fn snapped_segments(pattern: &CreasePattern, snap: &mut VertexSnap) -> Vec<Segment> {
    let mut merged: HashMap<usize, usize> = HashMap::new();
    let mut segments = Vec::with_capacity(pattern.edges.len());
    for (source, edge) in pattern.edges.iter().enumerate() {
        let v = edge.v.map(|i| {
            *merged
                .entry(i)
                .or_insert_with(|| snap.snap(pattern.vertices[i]))
        });
        if v[0] != v[1] {
            segments.push(Segment { v, source });
        }
    }
    segments
}

/// For every segment, the merged points (other than its ends) that lie on it.
fn find_splits(segments: &[Segment], snap: &mut VertexSnap) -> Vec<Vec<usize>> {
    let mut order: Vec<usize> = (0..segments.len()).collect();
    let min_x = |s: &Segment, pts: &[DVec2]| pts[s.v[0]].x.min(pts[s.v[1]].x);
    order.sort_by(|&a, &b| {
        min_x(&segments[a], &snap.points).total_cmp(&min_x(&segments[b], &snap.points))
    });
    let mut splits = vec![Vec::new(); segments.len()];
    for (k, &i) in order.iter().enumerate() {
        let (lo_i, hi_i) = extent(&segments[i], &snap.points);
        for &j in &order[k + 1..] {
            let (lo_j, hi_j) = extent(&segments[j], &snap.points);
            if lo_j.x > hi_i.x + snap.tolerance {
                break;
            }
            if lo_j.y > hi_i.y + snap.tolerance || lo_i.y > hi_j.y + snap.tolerance {
                continue;
            }
            intersect_pair(segments, i, j, snap, &mut splits);
        }
    }
    splits
}

fn extent(s: &Segment, points: &[DVec2]) -> (DVec2, DVec2) {
    let (a, b) = (points[s.v[0]], points[s.v[1]]);
    (a.min(b), a.max(b))
}

/// Records where segments `i` and `j` touch: an end point of one on the
/// other, or a proper crossing.
fn intersect_pair(
    segments: &[Segment],
    i: usize,
    j: usize,
    snap: &mut VertexSnap,
    splits: &mut [Vec<usize>],
) {
    let mut touching = false;
    for (on, other) in [(i, j), (j, i)] {
        for end in segments[other].v {
            if segments[on].v.contains(&end) {
                touching = true;
            } else if distance_to_segment(&segments[on], snap.points[end], &snap.points)
                <= snap.tolerance
            {
                splits[on].push(end);
                touching = true;
            }
        }
    }
    if touching {
        return;
    }
    if let Some(p) = crossing(&segments[i], &segments[j], &snap.points, snap.tolerance) {
        let v = snap.snap(p);
        for s in [i, j] {
            if !segments[s].v.contains(&v) {
                splits[s].push(v);
            }
        }
    }
}

fn distance_to_segment(s: &Segment, p: DVec2, points: &[DVec2]) -> f64 {
    let (a, b) = (points[s.v[0]], points[s.v[1]]);
    let ab = b - a;
    let t = ((p - a).dot(ab) / ab.length_squared()).clamp(0.0, 1.0);
    p.distance(a + ab * t)
}

/// Signed distance of `p` from the line through segment `s`.
fn side(s: &Segment, p: DVec2, points: &[DVec2]) -> f64 {
    let (a, b) = (points[s.v[0]], points[s.v[1]]);
    (b - a).perp_dot(p - a) / (b - a).length()
}

/// The crossing point of two segments whose ends lie clearly on opposite
/// sides of each other's lines.
fn crossing(s: &Segment, t: &Segment, points: &[DVec2], tolerance: f64) -> Option<DVec2> {
    let opposite =
        |x: f64, y: f64| (x > tolerance && y < -tolerance) || (x < -tolerance && y > tolerance);
    let (d0, d1) = (
        side(s, points[t.v[0]], points),
        side(s, points[t.v[1]], points),
    );
    let (e0, e1) = (
        side(t, points[s.v[0]], points),
        side(t, points[s.v[1]], points),
    );
    if !opposite(d0, d1) || !opposite(e0, e1) {
        return None;
    }
    let (p, q) = (points[t.v[0]], points[t.v[1]]);
    Some(p + (q - p) * (d0 / (d0 - d1)))
}

/// A piece of an input edge between two consecutive points along it.
struct Piece {
    v: [usize; 2],
    source: usize,
}

fn split_segments(segments: &[Segment], splits: &[Vec<usize>], points: &[DVec2]) -> Vec<Piece> {
    let mut pieces = Vec::new();
    for (segment, inner) in segments.iter().zip(splits) {
        let (a, b) = (points[segment.v[0]], points[segment.v[1]]);
        let along = |v: &usize| (points[*v] - a).dot(b - a);
        let mut chain = inner.clone();
        chain.sort_by(|x, y| along(x).total_cmp(&along(y)));
        chain.insert(0, segment.v[0]);
        chain.push(segment.v[1]);
        chain.dedup();
        for pair in chain.windows(2) {
            if pair[0] != pair[1] {
                pieces.push(Piece {
                    v: [pair[0], pair[1]],
                    source: segment.source,
                });
            }
        }
    }
    pieces
}

/// One piece per vertex pair: the highest
/// [`Assignment::overlap_rank`](super::pattern::Assignment::overlap_rank) of
/// the input edges wins, the earlier input edge on a tie.
fn resolve_overlaps(pattern: &CreasePattern, pieces: Vec<Piece>) -> Vec<Piece> {
    let rank = |p: &Piece| {
        (
            pattern.edges[p.source].assignment.overlap_rank(),
            std::cmp::Reverse(p.source),
        )
    };
    let mut slot: HashMap<[usize; 2], usize> = HashMap::new();
    let mut kept: Vec<Piece> = Vec::new();
    for piece in pieces {
        let key = [piece.v[0].min(piece.v[1]), piece.v[0].max(piece.v[1])];
        match slot.get(&key) {
            Some(&k) if rank(&piece) > rank(&kept[k]) => kept[k] = piece,
            Some(_) => {}
            None => {
                slot.insert(key, kept.len());
                kept.push(piece);
            }
        }
    }
    kept
}

/// The output pattern: only used points, renumbered in first-use order.
fn compact(pattern: &CreasePattern, points: &[DVec2], pieces: &[Piece]) -> CreasePattern {
    let mut index: HashMap<usize, usize> = HashMap::new();
    let mut out = CreasePattern::default();
    for piece in pieces {
        let v = piece.v.map(|p| {
            *index.entry(p).or_insert_with(|| {
                out.vertices.push(points[p]);
                out.vertices.len() - 1
            })
        });
        let source = &pattern.edges[piece.source];
        out.edges.push(PatternEdge {
            v,
            assignment: source.assignment,
            fold_angle: source.fold_angle,
        });
    }
    out
}

#[cfg(test)]
mod tests {
    use super::super::pattern::{Assignment, PatternBuilder};
    use super::*;

    fn pattern(segments: &[(Assignment, [f64; 4])]) -> CreasePattern {
        let mut b = PatternBuilder::default();
        for &(a, [x1, y1, x2, y2]) in segments {
            b.segment(DVec2::new(x1, y1), DVec2::new(x2, y2), a, None);
        }
        b.finish()
    }

    fn clean(segments: &[(Assignment, [f64; 4])]) -> CreasePattern {
        planarize(&pattern(segments), DEFAULT_TOLERANCE).unwrap()
    }

    #[test]
    fn crossing_segments_are_split() {
        let g = clean(&[
            (Assignment::Mountain, [0.0, 0.0, 2.0, 2.0]),
            (Assignment::Valley, [0.0, 2.0, 2.0, 0.0]),
        ]);
        assert_eq!(g.vertices.len(), 5);
        assert_eq!(g.edges.len(), 4);
        let centre = g
            .vertices
            .iter()
            .position(|p| p.distance(DVec2::ONE) < 1e-12);
        let centre = centre.unwrap();
        assert!(g.edges.iter().all(|e| e.v.contains(&centre)));
    }

    #[test]
    fn round_off_is_merged_and_t_junctions_split() {
        let g = clean(&[
            (Assignment::Boundary, [0.0, 0.0, 4.0, 0.0]),
            (Assignment::Valley, [2.0 + 1e-14, -1e-14, 2.0, 4.0]),
            (Assignment::Boundary, [4.0, 1e-14, 4.0, 4.0]),
        ]);
        // (4, 0) and (4, 1e-14) merge; (2, 0) splits the bottom edge.
        assert_eq!(g.vertices.len(), 5);
        assert_eq!(g.edges.len(), 4);
    }

    #[test]
    fn overlaps_keep_the_higher_rank_and_zero_length_goes() {
        let g = clean(&[
            (Assignment::Auxiliary, [0.0, 0.0, 3.0, 0.0]),
            (Assignment::Mountain, [1.0, 0.0, 2.0, 0.0]),
            (Assignment::Boundary, [2.0, 0.0, 3.0, 0.0]),
            (Assignment::Valley, [5.0, 5.0, 5.0, 5.0]),
        ]);
        let mut kinds: Vec<_> = g
            .edges
            .iter()
            .map(|e| {
                (
                    g.vertices[e.v[0]].x.min(g.vertices[e.v[1]].x) as i32,
                    e.assignment,
                )
            })
            .collect();
        kinds.sort_by_key(|k| k.0);
        assert_eq!(
            kinds,
            [
                (0, Assignment::Auxiliary),
                (1, Assignment::Mountain),
                (2, Assignment::Boundary)
            ]
        );
        assert_eq!(g.vertices.len(), 4);
    }

    #[test]
    fn concurrent_lines_meet_in_one_vertex() {
        let g = clean(&[
            (Assignment::Mountain, [-1.0, 0.0, 1.0, 0.0]),
            (Assignment::Mountain, [0.0, -1.0, 0.0, 1.0]),
            (Assignment::Valley, [-1.0, -1.0, 1.0, 1.0]),
        ]);
        assert_eq!(g.vertices.len(), 7);
        assert_eq!(g.edges.len(), 6);
    }

    #[test]
    fn bad_indices_and_coordinates_are_errors() {
        let mut p = pattern(&[(Assignment::Valley, [0.0, 0.0, 1.0, 0.0])]);
        p.edges[0].v[1] = 9;
        assert!(planarize(&p, DEFAULT_TOLERANCE)
            .unwrap_err()
            .reason
            .contains("out of range"));
        p.edges[0].v[1] = 1;
        p.vertices[1].x = f64::NAN;
        assert!(planarize(&p, DEFAULT_TOLERANCE).is_err());
        p.vertices[1].x = f64::MAX;
        p.vertices[0].x = -f64::MAX;
        assert!(planarize(&p, DEFAULT_TOLERANCE)
            .unwrap_err()
            .reason
            .contains("too large"));
    }
}
