//! Planar straight-line graph: turns the segments of an imported pattern,
//! which may cross, overlap, touch only approximately or repeat, into a
//! clean graph where edges meet only at shared vertices.
//!
//! Steps: merge points closer than the tolerance (relative to the pattern's
//! diameter) where they form an isolated cluster, and chains of points
//! finer than [`RESOLUTION`] greedily, split every segment at the
//! points of other segments that lie on it (T-junctions, overlaps) and at
//! proper crossings, drop zero-length pieces, and keep one edge per vertex
//! pair, choosing between overlapping edges by
//! [`Assignment::overlap_rank`](super::pattern::Assignment::overlap_rank).
//! Merging joins only points closer to each other than to any other point,
//! and no point moves onto an edge or a crossing by more than a quarter of
//! its local feature size ([`LOCAL_FRACTION`]), so a pattern's finest
//! features survive a tolerance chosen for its sloppiest corner: the narrow
//! tip of Origami Simulator's whirlpool keeps its creases, and its FTpoly7
//! (a twist whose central polygons shrink to 0.1 % of the sheet) every
//! point its own import keeps.
//! Candidate pairs come from a sweep over x, so sparse patterns cost close to
//! O(n log n).

use std::collections::HashMap;

use glam::DVec2;

use super::pattern::{CreasePattern, PatternEdge, PatternError};

/// Merge tolerance for imported coordinates, relative to the pattern's
/// diameter: well above the 1e-14 round-off of ORIPA files, far below any
/// real feature.
pub const DEFAULT_TOLERANCE: f64 = 1e-9;

/// Finest feature kept, relative to the pattern's diameter: 0.05 %, the
/// thickness of paper (0.1 mm) on a sheet 20 cm across. Points of a chain
/// finer than that (the innermost turns of a spiral drawn as Bezier curves,
/// each flattened into 8 pieces) are merged greedily: kept, they made
/// triangles a hundredth of a millimetre across that no strain limit holds.
pub const RESOLUTION: f64 = 5e-4;

/// Largest merge tolerance in the pattern's own units: the 3 units of
/// Origami Simulator's import. A drawing is as precise as its units, so a
/// pattern drawn on a fine grid keeps features finer than a tolerance
/// relative to its size (FTpoly7, 10000 units across, has central polygons
/// 12 units wide and points 1 unit apart that are meant as one).
pub const DRAWING_TOLERANCE: f64 = 3.0;

/// Builds the clean planar graph of `pattern`, merging isolated clusters of
/// points closer than `relative_tolerance` times the diameter of its
/// bounding box, or [`DRAWING_TOLERANCE`] units where that is less (see
/// [`VertexSnap`]). Vertices no
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
    let tolerance = (relative_tolerance * diameter).min(DRAWING_TOLERANCE);
    if tolerance <= 0.0 {
        // All points coincide: every segment has zero length.
        return Ok(CreasePattern::default());
    }
    let floor = (RESOLUTION * diameter).min(tolerance);
    let (mut snap, segments) = snapped_segments(pattern, tolerance, floor);
    let splits = find_splits(&segments, &mut snap);
    let pieces = split_segments(&segments, &splits, &snap.points);
    let kept = resolve_overlaps(pattern, pieces);
    let kept = trim_stubs(kept, &snap.points, relative_tolerance * diameter);
    Ok(compact(pattern, &snap.points, &kept))
}

/// Drops the pieces that end in a point no other piece touches and are
/// shorter than `limit` (the relative tolerance, not capped in drawing
/// units), until none is left: a line drawn a little past the line it
/// meets (housePopup's valley 4.9 units past a junction, closer than the
/// 0.3 % tolerance but further than 3 units) would otherwise be a crease
/// ending inside a facet, which folds only by crumpling it.
fn trim_stubs(mut pieces: Vec<Piece>, points: &[DVec2], limit: f64) -> Vec<Piece> {
    loop {
        let mut degree: HashMap<usize, usize> = HashMap::new();
        for piece in &pieces {
            for v in piece.v {
                *degree.entry(v).or_default() += 1;
            }
        }
        let before = pieces.len();
        pieces.retain(|piece| {
            let dangling = piece.v.iter().any(|v| degree[v] == 1);
            !(dangling && points[piece.v[0]].distance(points[piece.v[1]]) < limit)
        });
        if pieces.len() == before {
            return pieces;
        }
    }
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

/// How far a point may be moved onto an edge or a crossing, relative to its
/// local feature size (the distance to its nearest other merged point, or
/// the length of the edge): a quarter, so that a pattern's finest features
/// (the narrow tip of a curved tessellation) survive the tolerance that
/// closes a sloppy drawing's gaps.
const LOCAL_FRACTION: f64 = 0.25;

/// Merged points and the tolerance each may be moved by.
///
/// Input points merge in clusters: the groups that single linkage at the
/// tolerance joins, each collapsed onto its first point when it lies within
/// the tolerance of that point and closer together than to any other
/// point. A group that is not (a chain of features finer than the
/// tolerance, not one sloppy corner) is clustered again at half the
/// tolerance, down to [`RESOLUTION`], where it is merged greedily. After
/// merging, a point lies on an edge, or a crossing snaps onto it, only
/// within [`LOCAL_FRACTION`] of its local feature size (and of the edge's
/// length), capped at the tolerance.
struct VertexSnap {
    tolerance: f64,
    points: Vec<DVec2>,
    /// Per merged point: how far another point may be moved onto it.
    reach: Vec<f64>,
    /// Hash grid of cells `tolerance / LOCAL_FRACTION` wide over `points`.
    grid: Grid,
}

impl VertexSnap {
    /// Merges `inputs` (in first-use order); returns the snap and, for each
    /// input, the index of its merged point.
    fn merge(inputs: &[DVec2], tolerance: f64, floor: f64) -> (Self, Vec<usize>) {
        let mut all = Grid::new(tolerance);
        for (i, &p) in inputs.iter().enumerate() {
            all.insert(p, i);
        }
        let mut clusters = Vec::new();
        let clustering = Clustering {
            points: inputs,
            all: &all,
            floor,
        };
        clustering.split((0..inputs.len()).collect(), tolerance, &mut clusters);
        clusters.sort_by_key(|c| c[0]);
        let mut merged = vec![0; inputs.len()];
        let mut points = Vec::with_capacity(clusters.len());
        for (k, members) in clusters.iter().enumerate() {
            points.push(inputs[members[0]]);
            for &i in members {
                merged[i] = k;
            }
        }
        let mut grid = Grid::new(tolerance / LOCAL_FRACTION);
        for (k, &p) in points.iter().enumerate() {
            grid.insert(p, k);
        }
        let mut snap = VertexSnap {
            tolerance,
            reach: Vec::with_capacity(points.len()),
            points,
            grid,
        };
        snap.reach = (0..snap.points.len())
            .map(|k| snap.reach_at(snap.points[k], Some(k)))
            .collect();
        (snap, merged)
    }

    /// The tolerance, or a quarter of the distance from `p` to the nearest
    /// merged point other than `own` where that is less.
    fn reach_at(&self, p: DVec2, own: Option<usize>) -> f64 {
        let nearest = self
            .grid
            .near(p)
            .filter(|&k| Some(k) != own)
            .map(|k| self.points[k].distance(p))
            .fold(f64::INFINITY, f64::min);
        self.tolerance.min(LOCAL_FRACTION * nearest)
    }

    /// How far point `end` may be from segment `s` to lie on it.
    fn on_segment_limit(&self, end: usize, s: &Segment) -> f64 {
        self.reach[end].min(LOCAL_FRACTION * length(s, &self.points))
    }

    /// The merged point for a crossing at `p`: an existing point within its
    /// reach, or a new one.
    fn snap_crossing(&mut self, p: DVec2) -> usize {
        if let Some(k) = self
            .grid
            .near(p)
            .find(|&k| self.points[k].distance(p) <= self.reach[k])
        {
            return k;
        }
        let reach = self.reach_at(p, None);
        let k = self.points.len();
        self.points.push(p);
        self.reach.push(reach);
        self.grid.insert(p, k);
        k
    }
}

/// Input points and a grid over all of them, for [`Clustering::split`].
struct Clustering<'a> {
    points: &'a [DVec2],
    /// Cells one tolerance wide.
    all: &'a Grid,
    floor: f64,
}

impl Clustering<'_> {
    /// Splits `members` into the clusters described at [`VertexSnap`]: a
    /// group is one point when it lies within `tolerance` of its first
    /// point and closer to it than any other point is (the ends of sloppily
    /// drawn curves at a junction, not two points of a fine pleat).
    fn split(&self, members: Vec<usize>, tolerance: f64, out: &mut Vec<Vec<usize>>) {
        for group in linked_groups(self.points, &members, tolerance) {
            let first = self.points[group[0]];
            let extent = group
                .iter()
                .map(|&i| self.points[i].distance(first))
                .fold(0.0, f64::max);
            let tight = extent <= tolerance && extent <= self.separation(&group);
            if tight {
                out.push(group);
            } else if tolerance <= self.floor {
                out.extend(greedy_clusters(self.points, group, self.floor));
            } else {
                self.split(group, 0.5 * tolerance, out);
            }
        }
    }

    /// Distance from `group` (ascending) to the nearest input point outside
    /// it, infinite beyond the grid's reach (one cell, at least the
    /// tolerance).
    fn separation(&self, group: &[usize]) -> f64 {
        group
            .iter()
            .flat_map(|&i| {
                self.all
                    .near(self.points[i])
                    .filter(|j| group.binary_search(j).is_err())
                    .map(move |j| self.points[j].distance(self.points[i]))
            })
            .fold(f64::INFINITY, f64::min)
    }
}

/// `group` (ascending) in clusters no wider than `radius`: each point joins
/// the first cluster whose first point is within `radius`, else starts one
/// (first points found through a grid, so a long chain costs O(n)).
fn greedy_clusters(points: &[DVec2], group: Vec<usize>, radius: f64) -> Vec<Vec<usize>> {
    let mut firsts = Grid::new(radius);
    let mut clusters: Vec<Vec<usize>> = Vec::new();
    for i in group {
        let p = points[i];
        let joined = firsts
            .near(p)
            .filter(|&k| points[clusters[k][0]].distance(p) <= radius)
            .min();
        match joined {
            Some(k) => clusters[k].push(i),
            None => {
                firsts.insert(p, clusters.len());
                clusters.push(vec![i]);
            }
        }
    }
    clusters
}

/// The groups of `members` that chains of points closer than `tolerance`
/// join, each in ascending order.
fn linked_groups(points: &[DVec2], members: &[usize], tolerance: f64) -> Vec<Vec<usize>> {
    let mut grid = Grid::new(tolerance);
    let mut parent: Vec<usize> = (0..members.len()).collect();
    fn root(parent: &mut [usize], mut i: usize) -> usize {
        while parent[i] != i {
            parent[i] = parent[parent[i]];
            i = parent[i];
        }
        i
    }
    for (a, &i) in members.iter().enumerate() {
        let near: Vec<usize> = grid
            .near(points[i])
            .filter(|&b| points[members[b]].distance(points[i]) <= tolerance)
            .collect();
        for b in near {
            let (ra, rb) = (root(&mut parent, a), root(&mut parent, b));
            parent[ra.max(rb)] = ra.min(rb);
        }
        grid.insert(points[i], a);
    }
    let mut groups: HashMap<usize, Vec<usize>> = HashMap::new();
    for (a, &i) in members.iter().enumerate() {
        groups.entry(root(&mut parent, a)).or_default().push(i);
    }
    let mut groups: Vec<Vec<usize>> = groups.into_values().collect();
    for g in &mut groups {
        g.sort_unstable();
    }
    groups
}

/// Hash grid of points; every point within one cell width of `p` lies in
/// the 3 x 3 cells around `p`'s cell.
struct Grid {
    width: f64,
    cells: HashMap<(i64, i64), Vec<usize>>,
}

impl Grid {
    fn new(width: f64) -> Self {
        Grid {
            width,
            cells: HashMap::new(),
        }
    }

    fn cell(&self, p: DVec2) -> (i64, i64) {
        // `as` saturates, so far-away or odd points still land in a cell.
        let c = (p / self.width).floor();
        (c.x as i64, c.y as i64)
    }

    fn insert(&mut self, p: DVec2, k: usize) {
        self.cells.entry(self.cell(p)).or_default().push(k);
    }

    fn near(&self, p: DVec2) -> impl Iterator<Item = usize> + '_ {
        let (cx, cy) = self.cell(p);
        (-1..=1)
            .flat_map(move |dx| {
                (-1..=1).map(move |dy| (cx.saturating_add(dx), cy.saturating_add(dy)))
            })
            .filter_map(|key| self.cells.get(&key))
            .flatten()
            .copied()
    }
}

/// A segment after point merging: its end points and the edge it came from.
#[derive(Clone, Copy)]
struct Segment {
    v: [usize; 2],
    source: usize,
}

fn snapped_segments(
    pattern: &CreasePattern,
    tolerance: f64,
    floor: f64,
) -> (VertexSnap, Vec<Segment>) {
    let mut input_of: HashMap<usize, usize> = HashMap::new();
    let mut inputs = Vec::new();
    for i in pattern.edges.iter().flat_map(|e| e.v) {
        input_of.entry(i).or_insert_with(|| {
            inputs.push(pattern.vertices[i]);
            inputs.len() - 1
        });
    }
    let (snap, merged) = VertexSnap::merge(&inputs, tolerance, floor);
    let segments = pattern
        .edges
        .iter()
        .enumerate()
        .map(|(source, edge)| Segment {
            v: edge.v.map(|i| merged[input_of[&i]]),
            source,
        })
        .filter(|s| s.v[0] != s.v[1])
        .collect();
    (snap, segments)
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
                <= snap.on_segment_limit(end, &segments[on])
            {
                splits[on].push(end);
                touching = true;
            }
        }
    }
    if touching {
        return;
    }
    if let Some(p) = crossing(&segments[i], &segments[j], snap) {
        let v = snap.snap_crossing(p);
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

fn length(s: &Segment, points: &[DVec2]) -> f64 {
    points[s.v[0]].distance(points[s.v[1]])
}

/// The crossing point of two segments whose ends lie clearly on opposite
/// sides of each other's lines: further than they may be moved onto them.
fn crossing(s: &Segment, t: &Segment, snap: &VertexSnap) -> Option<DVec2> {
    let points = &snap.points;
    let clear_sides = |a: &Segment, b: &Segment| {
        let [d0, d1] = b.v.map(|end| {
            let d = side(a, points[end], points);
            (d, snap.on_segment_limit(end, a))
        });
        let opposite = (d0.0 > d0.1 && d1.0 < -d1.1) || (d0.0 < -d0.1 && d1.0 > d1.1);
        opposite.then_some((d0.0, d1.0))
    };
    let (d0, d1) = clear_sides(s, t)?;
    clear_sides(t, s)?;
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

    /// `creases` inside a 1000 x 1000 square's boundary, cleaned with the
    /// default merge tolerance: 0.3 % of the diameter is 4.2, so the 3
    /// drawing units of [`DRAWING_TOLERANCE`] apply.
    fn in_square(creases: impl IntoIterator<Item = (Assignment, [f64; 4])>) -> CreasePattern {
        let c = [[0.0, 0.0], [1000.0, 0.0], [1000.0, 1000.0], [0.0, 1000.0]];
        let boundary = (0..4).map(|i| {
            let (a, b) = (c[i], c[(i + 1) % 4]);
            (Assignment::Boundary, [a[0], a[1], b[0], b[1]])
        });
        let segments: Vec<_> = boundary.chain(creases).collect();
        planarize(&pattern(&segments), 3e-3).unwrap()
    }

    #[test]
    fn a_sloppy_corner_and_a_near_miss_of_an_edge_close() {
        // Two creases that miss each other's end by 2, one that stops 3
        // short of the boundary.
        let g = in_square([
            (Assignment::Mountain, [300.0, 300.0, 500.0, 500.0]),
            (Assignment::Valley, [501.5, 501.0, 700.0, 300.0]),
            (Assignment::Valley, [500.0, 500.0, 500.0, 997.0]),
        ]);
        // Corners, (300, 300), (700, 300), one point at (500, 500) and one
        // where the valley meets the top edge, splitting it.
        assert_eq!(g.vertices.len(), 8);
        assert_eq!(g.edges.len(), 8);
    }

    #[test]
    fn a_ring_finer_than_the_tolerance_keeps_its_points() {
        // 24 points 2.6 apart on a circle of radius 10 (a twist's central
        // polygon): single linkage at 4.2 joins them all, but the ring is
        // no sloppy corner.
        let at = |k: usize| {
            let a = k as f64 * std::f64::consts::TAU / 24.0;
            [500.0 + 10.0 * a.cos(), 500.0 + 10.0 * a.sin()]
        };
        let g = in_square((0..24).map(|k| {
            let (a, b) = (at(k), at(k + 1));
            (Assignment::Mountain, [a[0], a[1], b[0], b[1]])
        }));
        assert_eq!(g.vertices.len(), 4 + 24);
        assert_eq!(g.edges.len(), 4 + 24);
    }

    #[test]
    fn a_pleat_finer_than_the_tolerance_keeps_its_lines() {
        // Twenty creases 2 apart, finer than the tolerance of 3: every
        // point is as close to one neighbour as to the other, so none is a
        // sloppy corner (merging greedily kept every other line).
        let g = in_square((0..20).map(|k| {
            let x = 400.0 + 2.0 * k as f64;
            let a = if k % 2 == 0 {
                Assignment::Valley
            } else {
                Assignment::Mountain
            };
            (a, [x, 100.0, x, 500.0])
        }));
        assert_eq!(g.vertices.len(), 4 + 40);
        assert_eq!(g.edges.len(), 4 + 20);
    }

    #[test]
    fn a_chain_finer_than_the_resolution_is_thinned() {
        // A spiral's inner end: a crease drawn as pieces 0.05 apart over
        // its first unit (finer than the 0.71 units of 0.05 % of the
        // diameter), then pieces 1 to 8 long out to x = 530 and one long
        // piece. The chain is not one sloppy corner, so no isolated
        // cluster takes it; at the resolution it is merged greedily into
        // 2 points, the rest kept (all 29 were kept before). A valley
        // from the boundary meets the chain's start, so no end dangles.
        let fine = (0..=20).map(|k| [500.0 + 0.05 * k as f64, 500.0 + 0.02 * (k % 2) as f64]);
        let coarse = [502.0, 504.0, 507.0, 511.0, 516.0, 522.0, 530.0, 900.0].map(|x| [x, 500.0]);
        let points: Vec<[f64; 2]> = fine.chain(coarse).collect();
        let chain = points
            .windows(2)
            .map(|w| (Assignment::Mountain, [w[0][0], w[0][1], w[1][0], w[1][1]]));
        // A valley from the boundary ends where the chain starts.
        let g = in_square(chain.chain([(Assignment::Valley, [500.0, 0.0, 500.0, 500.0])]));
        assert_eq!(g.vertices.len(), 5 + 10);
        assert_eq!(g.edges.len(), 5 + 1 + 9);
    }

    #[test]
    fn a_point_near_a_short_edge_is_not_moved_onto_it() {
        // A crease of length 8 with a point 3 from it: within the
        // tolerance, but snapping would move the point by more than a
        // quarter of the edge.
        let g = in_square([
            (Assignment::Mountain, [500.0, 500.0, 508.0, 500.0]),
            (Assignment::Valley, [504.0, 503.0, 504.0, 900.0]),
        ]);
        assert_eq!(g.vertices.len(), 4 + 4);
        assert_eq!(g.edges.len(), 4 + 2);
    }

    #[test]
    fn a_line_drawn_a_little_past_a_junction_is_trimmed() {
        // A valley that runs 4 past the mountain it ends on: its stub is
        // longer than the tolerance of 3, shorter than 0.3 % of the size.
        let g = in_square([
            (Assignment::Mountain, [0.0, 500.0, 1000.0, 500.0]),
            (Assignment::Valley, [500.0, 0.0, 500.0, 504.0]),
        ]);
        assert_eq!(g.vertices.len(), 4 + 4);
        let stub_end = DVec2::new(500.0, 504.0);
        assert!(g.vertices.iter().all(|p| p.distance(stub_end) > 1.0));
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
