//! The sheet: a crease pattern triangulated into a flat mesh whose interior
//! edges are hinges.
//!
//! The clean planar graph ([`planarize`]) is triangulated with constrained
//! Delaunay (spade), every pattern edge a constraint, optionally refined to a
//! target edge length. The paper is the region inside the boundary edges by
//! the even-odd rule (crossing a boundary edge goes from outside to inside or
//! back, so holes work); a pattern without boundary edges is the region its
//! lines enclose where that is all of their convex hull but for slivers,
//! else the convex hull. Cut edges, and boundary edges with paper on both
//! sides (slits), split the sheet: the vertices along them are duplicated
//! so the sides separate. Every other edge shared by two triangles is a
//! [`Hinge`].

use std::collections::{HashMap, HashSet};

use glam::{DVec2, Vec3};
use spade::handles::{FixedUndirectedEdgeHandle, FixedVertexHandle, OUTER_FACE};
use spade::{
    AngleLimit, ConstrainedDelaunayTriangulation, Point2, RefinementParameters, Triangulation,
};

use super::pattern::{Assignment, CreasePattern, PatternError};
use super::planar::planarize;

type Cdt = ConstrainedDelaunayTriangulation<Point2<f64>>;

/// Most vertices refinement may create; a smaller `max_edge` is refused.
const MAX_REFINED_VERTICES: f64 = 2.0e6;

/// How far (unit-box units) a constraint vertex may sit off the pattern edge
/// it splits.
const WALK_TOLERANCE: f64 = 1e-9;

/// Coordinates in the unit box are rounded to multiples of 1 / GRID.
const GRID: f64 = (1u64 << 40) as f64;

/// Share of its convex hull a pattern without boundary edges must enclose
/// for the enclosed region to be the paper ([`Region::without_boundary`]).
const ENCLOSED_FRACTION: f64 = 0.99;

/// Smallest angle refinement aims for, in degrees.
const REFINEMENT_ANGLE: f64 = 20.0;

/// Default [`SheetOptions::merge_tolerance`]: 0.3 % of the pattern's
/// diameter, the 3 px of Origami Simulator's import on its 600 to 1000 px
/// drawings. Isolated points that close are one vertex and a point that
/// close to an edge lies on it, so boundaries drawn as short segments with
/// tiny gaps close, and near-coincident vertices leave no sliver triangles
/// (a triangle a few ten-thousandths as high as it is long has a dihedral
/// gradient so steep that folding it blows up). Features finer than the
/// tolerance (a twist's central polygons) keep their points: only isolated
/// clusters merge, and a point is moved onto an edge by at most a quarter
/// of its distance to its other neighbours
/// ([`planarize`](super::planar::planarize)).
pub const MERGE_TOLERANCE: f64 = 3e-3;

/// Largest merge tolerance accepted: beyond a tenth of the diameter whole
/// features would collapse.
const MAX_MERGE_TOLERANCE: f64 = 0.1;

/// How the pattern becomes a sheet.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SheetOptions {
    /// Longest side of the sheet's bounding box, in metres.
    pub size: f64,
    /// Target edge length for refinement, in metres; `None` keeps only the
    /// pattern's own vertices.
    pub max_edge: Option<f64>,
    /// Points closer than this fraction of the pattern's diameter are
    /// merged, and points this close to an edge split it
    /// ([`MERGE_TOLERANCE`] by default). Where merging leaves edges that
    /// cross (features finer than the tolerance), the sheet is built again
    /// with half the tolerance, up to three times.
    pub merge_tolerance: f64,
}

impl Default for SheetOptions {
    fn default() -> Self {
        SheetOptions {
            size: 1.0,
            max_edge: None,
            merge_tolerance: MERGE_TOLERANCE,
        }
    }
}

/// An interior edge between two triangles, with what it should do.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hinge {
    /// `v[0]`, `v[1]`: the shared edge; `v[2]`: the opposite vertex of the
    /// triangle in which the edge runs `v[0] -> v[1]` counter-clockwise;
    /// `v[3]`: the opposite vertex of the other triangle.
    pub v: [u32; 4],
    /// Mountain, Valley, Unassigned, or Flat (facet lines, auxiliary lines
    /// and edges the triangulation added).
    pub assignment: Assignment,
    /// Target fold angle in radians, valley positive; `None` when the pattern
    /// gives none.
    pub fold_angle: Option<f32>,
}

/// A flat triangulated sheet in the z = 0 plane, centred on the origin.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Sheet {
    /// Vertex positions (m), with z = 0.
    pub positions: Vec<Vec3>,
    /// Counter-clockwise seen from +z.
    pub triangles: Vec<[u32; 3]>,
    /// Every interior edge as a hinge: the pattern's creases and the facet
    /// hinges.
    pub hinges: Vec<Hinge>,
}

impl Sheet {
    /// Triangulates `pattern` into a sheet scaled so its longest side is
    /// `options.size`.
    pub fn from_pattern(
        pattern: &CreasePattern,
        options: &SheetOptions,
    ) -> Result<Sheet, PatternError> {
        check_options(options)?;
        let max_edge = options.max_edge.map(|e| e / options.size);
        // Merging moves points, and a crossing snapped onto a nearby vertex
        // can leave pieces that cross other edges where the pattern has
        // features finer than the merge tolerance (dense curved creases
        // drawn as many short pieces): the cleanup is then repeated with a
        // tolerance halved, a few times, before the pattern is refused.
        let mut tolerance = options.merge_tolerance;
        let mut attempts = 1;
        let (graph, cdt) = loop {
            let graph = planarize(pattern, tolerance)?;
            if graph.edges.is_empty() {
                return Err(PatternError::new(
                    "",
                    "the pattern has no segment of non-zero length",
                ));
            }
            let frame = Frame::of(&graph);
            match triangulate(&graph, &frame, max_edge) {
                Ok(cdt) => break (graph, cdt),
                Err(Crossing(_)) if attempts < CLEANUP_ATTEMPTS => {
                    tolerance *= 0.5;
                    attempts += 1;
                }
                Err(Crossing(e) | Other(e)) => return Err(e),
            }
        };
        let labels = label_constraints(&cdt, &graph)?;
        let region = Region::find(&cdt, &graph, &labels);
        if region.inside.iter().all(|&inside| !inside) {
            return Err(PatternError::new(
                "",
                "no part of the pattern lies inside its boundary",
            ));
        }
        Ok(assemble(&cdt, &graph, &labels, &region, options.size))
    }

    /// Number of hinges that fold: mountain, valley and unassigned.
    pub fn crease_count(&self) -> usize {
        self.hinges
            .iter()
            .filter(|h| {
                matches!(
                    h.assignment,
                    Assignment::Mountain | Assignment::Valley | Assignment::Unassigned
                )
            })
            .count()
    }
}

fn check_options(options: &SheetOptions) -> Result<(), PatternError> {
    if !(options.size.is_finite() && options.size > 0.0) {
        return Err(PatternError::new(
            "size",
            format!(
                "must be a positive number of metres, found {}",
                options.size
            ),
        ));
    }
    if !(0.0..=MAX_MERGE_TOLERANCE).contains(&options.merge_tolerance) {
        return Err(PatternError::new(
            "merge_tolerance",
            format!(
                "must be between 0 and {MAX_MERGE_TOLERANCE} (a fraction of the pattern's size), found {}",
                options.merge_tolerance
            ),
        ));
    }
    match options.max_edge {
        Some(e) if !(e.is_finite() && e > 0.0) => Err(PatternError::new(
            "max_edge",
            format!("must be a positive number of metres, found {e}"),
        )),
        _ => Ok(()),
    }
}

/// Maps pattern units to a unit box centred on the origin.
struct Frame {
    centre: DVec2,
    extent: f64,
}

impl Frame {
    fn of(graph: &CreasePattern) -> Frame {
        let min = graph
            .vertices
            .iter()
            .copied()
            .fold(DVec2::INFINITY, DVec2::min);
        let max = graph
            .vertices
            .iter()
            .copied()
            .fold(DVec2::NEG_INFINITY, DVec2::max);
        Frame {
            centre: (min + max) * 0.5,
            extent: (max - min).max_element(),
        }
    }

    /// The point in the unit box, rounded to a multiple of 2^-40 (far below
    /// the merge tolerance) so that round-off such as 1e-33 becomes an exact
    /// zero: spade's refinement otherwise spirals into such points.
    fn normalise(&self, p: DVec2) -> Point2<f64> {
        let q = ((p - self.centre) / self.extent * GRID).round() / GRID;
        Point2::new(q.x, q.y)
    }
}

/// Merge tolerances tried (each half the last) before a pattern whose
/// edges still cross after cleanup is refused.
const CLEANUP_ATTEMPTS: usize = 4;

/// Why a graph did not triangulate.
enum TriangulationError {
    /// An edge crosses another: another cleanup pass may help.
    Crossing(PatternError),
    Other(PatternError),
}
use TriangulationError::{Crossing, Other};

fn triangulate(
    graph: &CreasePattern,
    frame: &Frame,
    max_edge: Option<f64>,
) -> Result<Cdt, TriangulationError> {
    let mut cdt = Cdt::new();
    for (i, &p) in graph.vertices.iter().enumerate() {
        let handle = cdt.insert(frame.normalise(p)).map_err(|e| {
            Other(PatternError::new(
                format!("vertex {i}"),
                format!("cannot be triangulated: {e}"),
            ))
        })?;
        // Points closer than the unit box's rounding (1e-12 of the
        // pattern's size) land on one point, which the triangulation
        // keeps once: the constraints would then name vertices it lacks.
        if handle.index() != i {
            let j = handle.index();
            return Err(Other(PatternError::new(
                format!("point ({}, {})", p.x, p.y),
                format!(
                    "lands on the point ({}, {}) once the pattern is scaled to a unit box: \
                     its coordinates span too wide a range for its finest features",
                    graph.vertices[j].x, graph.vertices[j].y
                ),
            )));
        }
    }
    for (i, edge) in graph.edges.iter().enumerate() {
        let [a, b] = edge.v.map(FixedVertexHandle::from_index);
        if cdt.try_add_constraint(a, b).is_empty() {
            return Err(Crossing(PatternError::new(
                format!("edge {i}"),
                "crosses another edge after cleanup (the pattern is numerically degenerate)",
            )));
        }
    }
    if let Some(max_edge) = max_edge {
        refine(&mut cdt, max_edge).map_err(Other)?;
    }
    Ok(cdt)
}

/// Delaunay refinement until triangles are no larger than an equilateral
/// triangle of side `max_edge` (unit-box units).
fn refine(cdt: &mut Cdt, max_edge: f64) -> Result<(), PatternError> {
    let max_area = 3f64.sqrt() / 4.0 * max_edge * max_edge;
    // The unit box holds about 1 / max_area triangles, half as many vertices.
    let estimate = 1.0 / max_area;
    if estimate > MAX_REFINED_VERTICES {
        return Err(PatternError::new(
            "max_edge",
            format!("too small: refinement would need about {estimate:.0} vertices"),
        ));
    }
    let budget = 2 * estimate as usize + 10 * cdt.num_vertices();
    cdt.refine(
        RefinementParameters::new()
            .with_max_allowed_area(max_area)
            .with_angle_limit(AngleLimit::from_deg(REFINEMENT_ANGLE))
            .with_max_additional_vertices(budget),
    );
    Ok(())
}

/// For every undirected CDT edge, the pattern edge it lies on, if any.
///
/// A pattern edge may be split into several collinear constraint edges (by
/// refinement, or by a vertex on it), so each is walked from one end to the
/// other, always taking the constraint edge that moves towards the far end
/// and stays closest to the segment.
fn label_constraints(cdt: &Cdt, graph: &CreasePattern) -> Result<Vec<Option<usize>>, PatternError> {
    let mut labels = vec![None; cdt.num_undirected_edges()];
    for (i, edge) in graph.edges.iter().enumerate() {
        let [from, to] = edge.v.map(FixedVertexHandle::from_index);
        let path = constraint_path(cdt, from, to).ok_or_else(|| {
            PatternError::new(
                format!("edge {i}"),
                "lost in the triangulation (the pattern is numerically degenerate)",
            )
        })?;
        for e in path {
            labels[e.index()] = Some(i);
        }
    }
    Ok(labels)
}

fn constraint_path(
    cdt: &Cdt,
    from: FixedVertexHandle,
    to: FixedVertexHandle,
) -> Option<Vec<FixedUndirectedEdgeHandle>> {
    let start = position(cdt.vertex(from).position());
    let end = position(cdt.vertex(to).position());
    let axis = (end - start).normalize_or_zero();
    let along = |p: DVec2| (p - start).dot(axis);
    let off_line = |p: DVec2| axis.perp_dot(p - start).abs();
    let mut path = Vec::new();
    let mut at = from;
    while at != to {
        if path.len() > cdt.num_vertices() {
            return None;
        }
        let here = along(position(cdt.vertex(at).position()));
        let step = cdt
            .vertex(at)
            .out_edges()
            .filter(|e| e.is_constraint_edge())
            .map(|e| (position(e.to().position()), e))
            .filter(|(p, _)| along(*p) > here && off_line(*p) <= WALK_TOLERANCE)
            .min_by(|a, b| off_line(a.0).total_cmp(&off_line(b.0)))?;
        path.push(step.1.as_undirected().fix());
        at = step.1.to().fix();
    }
    Some(path)
}

fn position(p: Point2<f64>) -> DVec2 {
    DVec2::new(p.x, p.y)
}

/// Which faces of the CDT are paper (even-odd rule over boundary edges).
struct Region {
    /// Indexed by face index; the outer face is never inside.
    inside: Vec<bool>,
}

impl Region {
    fn find(cdt: &Cdt, graph: &CreasePattern, labels: &[Option<usize>]) -> Region {
        let is_boundary = |e: FixedUndirectedEdgeHandle| {
            labels[e.index()].is_some_and(|i| graph.edges[i].assignment == Assignment::Boundary)
        };
        let faces = cdt.num_all_faces();
        let has_boundary = cdt.fixed_undirected_edges().any(is_boundary);
        if !has_boundary {
            return Region::without_boundary(cdt, labels);
        }
        let (mut sets, walls) = components(cdt, is_boundary);
        // Breadth-first over components, toggling at each boundary.
        let mut neighbours: HashMap<usize, Vec<usize>> = HashMap::new();
        for (a, b) in walls {
            let (a, b) = (sets.find(a), sets.find(b));
            neighbours.entry(a).or_default().push(b);
            neighbours.entry(b).or_default().push(a);
        }
        let mut parity: HashMap<usize, bool> = HashMap::new();
        let start = sets.find(OUTER_FACE.index());
        parity.insert(start, false);
        let mut queue = std::collections::VecDeque::from([start]);
        while let Some(c) = queue.pop_front() {
            let next = !parity[&c];
            for &n in neighbours.get(&c).into_iter().flatten() {
                if let std::collections::hash_map::Entry::Vacant(slot) = parity.entry(n) {
                    slot.insert(next);
                    queue.push_back(n);
                }
            }
        }
        let inside = (0..faces)
            .map(|f| parity.get(&sets.find(f)).copied().unwrap_or(false))
            .collect();
        Region { inside }
    }

    /// The paper of a pattern drawn without boundary edges: the region its
    /// lines enclose (faces reached from outside only across a pattern
    /// edge), as Origami Simulator's import takes it, where that is all of
    /// the convex hull but for slivers (at least [`ENCLOSED_FRACTION`] of
    /// its area: an outline whose points waver by a merge tolerance leaves
    /// hair-thin triangles between it and the hull, and these would make
    /// the outline creases hinges of paper a hair wide); else the convex
    /// hull, as where the lines enclose nothing.
    fn without_boundary(cdt: &Cdt, labels: &[Option<usize>]) -> Region {
        let (mut sets, _) = components(cdt, |e| labels[e.index()].is_some());
        let outside = sets.find(OUTER_FACE.index());
        let enclosed: Vec<bool> = (0..cdt.num_all_faces())
            .map(|f| sets.find(f) != outside)
            .collect();
        let area = |keep: &dyn Fn(usize) -> bool| -> f64 {
            cdt.inner_faces()
                .filter(|f| keep(f.fix().index()))
                .map(|f| f.area())
                .sum()
        };
        if area(&|f| enclosed[f]) >= ENCLOSED_FRACTION * area(&|_| true) {
            return Region { inside: enclosed };
        }
        let mut inside = vec![true; enclosed.len()];
        inside[OUTER_FACE.index()] = false;
        Region { inside }
    }
}

/// The faces of `cdt` joined into components across every edge that is not
/// a wall, and the pairs of faces on either side of each wall.
fn components(
    cdt: &Cdt,
    is_wall: impl Fn(FixedUndirectedEdgeHandle) -> bool,
) -> (DisjointSets, Vec<(usize, usize)>) {
    let mut sets = DisjointSets::new(cdt.num_all_faces());
    let mut walls = Vec::new();
    for edge in cdt.undirected_edges() {
        let d = edge.as_directed();
        let (left, right) = (d.face().fix().index(), d.rev().face().fix().index());
        if is_wall(edge.fix()) {
            walls.push((left, right));
        } else {
            sets.union(left, right);
        }
    }
    (sets, walls)
}

/// Union-find with path halving.
struct DisjointSets {
    parent: Vec<usize>,
}

impl DisjointSets {
    fn new(n: usize) -> Self {
        DisjointSets {
            parent: (0..n).collect(),
        }
    }

    fn find(&mut self, mut x: usize) -> usize {
        while self.parent[x] != x {
            self.parent[x] = self.parent[self.parent[x]];
            x = self.parent[x];
        }
        x
    }

    fn union(&mut self, a: usize, b: usize) {
        let (a, b) = (self.find(a), self.find(b));
        self.parent[a] = b;
    }
}

/// The sheet from the inside faces: compact vertices, orient triangles,
/// split along cuts, find hinges, scale.
fn assemble(
    cdt: &Cdt,
    graph: &CreasePattern,
    labels: &[Option<usize>],
    region: &Region,
    size: f64,
) -> Sheet {
    let mut index: HashMap<usize, u32> = HashMap::new();
    let mut points: Vec<DVec2> = Vec::new();
    let mut triangles = Vec::new();
    for face in cdt.inner_faces().filter(|f| region.inside[f.fix().index()]) {
        let mut tri = face.vertices().map(|v| {
            *index.entry(v.fix().index()).or_insert_with(|| {
                points.push(position(v.position()));
                (points.len() - 1) as u32
            })
        });
        if signed_area(&points, tri) < 0.0 {
            tri.swap(1, 2);
        }
        triangles.push(tri);
    }
    // Pattern edge of each sheet edge, by (sorted) sheet vertex pair.
    let mut edge_source: HashMap<[u32; 2], usize> = HashMap::new();
    let mut cuts: HashSet<[u32; 2]> = HashSet::new();
    for edge in cdt.undirected_edges() {
        let Some(source) = labels[edge.fix().index()] else {
            continue;
        };
        let ends = edge
            .vertices()
            .map(|v| index.get(&v.fix().index()).copied());
        let [Some(a), Some(b)] = ends else {
            continue;
        };
        let key = [a.min(b), a.max(b)];
        edge_source.insert(key, source);
        let d = edge.as_directed();
        let both_inside =
            region.inside[d.face().fix().index()] && region.inside[d.rev().face().fix().index()];
        let splits = matches!(
            graph.edges[source].assignment,
            Assignment::Cut | Assignment::Boundary
        );
        if splits && both_inside {
            cuts.insert(key);
        }
    }
    let origin = split_along_cuts(&mut triangles, &mut points, &cuts);
    let hinges = find_hinges(&triangles, &origin, &cuts, |key| {
        edge_source.get(&key).map(|&i| &graph.edges[i])
    });
    Sheet {
        positions: scale_to_size(&points, size),
        triangles,
        hinges,
    }
}

fn signed_area(points: &[DVec2], t: [u32; 3]) -> f64 {
    let [a, b, c] = t.map(|i| points[i as usize]);
    0.5 * (b - a).perp_dot(c - a)
}

/// Duplicates the vertices on cut edges so that triangles on the two sides
/// of a cut share none. Returns, for each final vertex, the vertex it was
/// copied from (itself for originals).
fn split_along_cuts(
    triangles: &mut [[u32; 3]],
    points: &mut Vec<DVec2>,
    cuts: &HashSet<[u32; 2]>,
) -> Vec<u32> {
    let mut origin: Vec<u32> = (0..points.len() as u32).collect();
    let on_cut: HashSet<u32> = cuts.iter().flatten().copied().collect();
    let mut fans: HashMap<u32, Vec<usize>> = HashMap::new();
    for (t, tri) in triangles.iter().enumerate() {
        for &v in tri.iter().filter(|v| on_cut.contains(v)) {
            fans.entry(v).or_default().push(t);
        }
    }
    let mut vertices: Vec<u32> = fans.keys().copied().collect();
    vertices.sort_unstable();
    for v in vertices {
        let fan = &fans[&v];
        for group in fan_groups(triangles, fan, v, cuts).into_iter().skip(1) {
            points.push(points[v as usize]);
            origin.push(v);
            let copy = (points.len() - 1) as u32;
            for t in group {
                for corner in triangles[t].iter_mut().filter(|c| **c == v) {
                    *corner = copy;
                }
            }
        }
    }
    origin
}

/// The triangles around `v` grouped by connection across non-cut edges.
fn fan_groups(
    triangles: &[[u32; 3]],
    fan: &[usize],
    v: u32,
    cuts: &HashSet<[u32; 2]>,
) -> Vec<Vec<usize>> {
    let mut sets = DisjointSets::new(fan.len());
    let mut first_with: HashMap<u32, usize> = HashMap::new();
    for (k, &t) in fan.iter().enumerate() {
        for &w in triangles[t].iter().filter(|&&w| w != v) {
            if cuts.contains(&[v.min(w), v.max(w)]) {
                continue;
            }
            match first_with.get(&w) {
                Some(&other) => sets.union(k, other),
                None => {
                    first_with.insert(w, k);
                }
            }
        }
    }
    let mut groups: Vec<Vec<usize>> = Vec::new();
    let mut group_of: HashMap<usize, usize> = HashMap::new();
    for (k, &t) in fan.iter().enumerate() {
        let root = sets.find(k);
        let g = *group_of.entry(root).or_insert_with(|| {
            groups.push(Vec::new());
            groups.len() - 1
        });
        groups[g].push(t);
    }
    groups
}

/// Every edge shared by exactly two consistently oriented triangles, except
/// cuts, as a hinge; in order of first appearance.
fn find_hinges<'a>(
    triangles: &[[u32; 3]],
    origin: &[u32],
    cuts: &HashSet<[u32; 2]>,
    source: impl Fn([u32; 2]) -> Option<&'a super::pattern::PatternEdge>,
) -> Vec<Hinge> {
    // Per undirected edge: the (from, to, opposite) of each triangle side.
    let mut sides: Vec<Vec<[u32; 3]>> = Vec::new();
    let mut slot: HashMap<[u32; 2], usize> = HashMap::new();
    for tri in triangles {
        for k in 0..3 {
            let (a, b, c) = (tri[k], tri[(k + 1) % 3], tri[(k + 2) % 3]);
            let s = *slot.entry([a.min(b), a.max(b)]).or_insert_with(|| {
                sides.push(Vec::new());
                sides.len() - 1
            });
            sides[s].push([a, b, c]);
        }
    }
    let original = |a: u32, b: u32| {
        let (a, b) = (origin[a as usize], origin[b as usize]);
        [a.min(b), a.max(b)]
    };
    sides
        .iter()
        .filter_map(|pair| {
            let [[a, b, c], [p, q, d]] = pair.as_slice() else {
                return None;
            };
            let key = original(*a, *b);
            if (*p, *q) != (*b, *a) || cuts.contains(&key) {
                return None;
            }
            let (assignment, fold_angle) = match source(key) {
                Some(edge) => (hinge_assignment(edge.assignment), edge.fold_angle),
                None => (Assignment::Flat, None),
            };
            Some(Hinge {
                v: [*a, *b, *c, *d],
                assignment,
                fold_angle: fold_angle.map(|deg| deg.to_radians() as f32),
            })
        })
        .collect()
}

/// What a pattern edge between two paper triangles does as a hinge.
fn hinge_assignment(assignment: Assignment) -> Assignment {
    match assignment {
        Assignment::Mountain | Assignment::Valley | Assignment::Unassigned => assignment,
        Assignment::Flat | Assignment::Auxiliary | Assignment::Boundary | Assignment::Cut => {
            Assignment::Flat
        }
    }
}

/// Centres the points on the origin and scales the longest side to `size`.
fn scale_to_size(points: &[DVec2], size: f64) -> Vec<Vec3> {
    let min = points.iter().copied().fold(DVec2::INFINITY, DVec2::min);
    let max = points.iter().copied().fold(DVec2::NEG_INFINITY, DVec2::max);
    let centre = (min + max) * 0.5;
    let scale = size / (max - min).max_element();
    points
        .iter()
        .map(|&p| {
            let q = (p - centre) * scale;
            Vec3::new(q.x as f32, q.y as f32, 0.0)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::super::pattern::PatternBuilder;
    use super::*;

    type Segment = (Assignment, [f64; 4], Option<f64>);

    fn square(side: f64) -> Vec<Segment> {
        let s = side;
        [
            [0.0, 0.0, s, 0.0],
            [s, 0.0, s, s],
            [s, s, 0.0, s],
            [0.0, s, 0.0, 0.0],
        ]
        .map(|c| (Assignment::Boundary, c, None))
        .to_vec()
    }

    fn sheet(segments: &[Segment]) -> Result<Sheet, PatternError> {
        let mut b = PatternBuilder::default();
        for &(a, [x1, y1, x2, y2], angle) in segments {
            b.segment(DVec2::new(x1, y1), DVec2::new(x2, y2), a, angle);
        }
        Sheet::from_pattern(&b.finish(), &SheetOptions::default())
    }

    fn euler(sheet: &Sheet) -> i64 {
        let edges: HashSet<[u32; 2]> = sheet
            .triangles
            .iter()
            .flat_map(|&[a, b, c]| [[a, b], [b, c], [c, a]])
            .map(|[a, b]| [a.min(b), a.max(b)])
            .collect();
        sheet.positions.len() as i64 - edges.len() as i64 + sheet.triangles.len() as i64
    }

    #[test]
    fn square_with_a_valley_diagonal() {
        let mut segments = square(4.0);
        segments.push((Assignment::Valley, [0.0, 0.0, 4.0, 4.0], Some(90.0)));
        let s = sheet(&segments).unwrap();
        assert_eq!(s.triangles.len(), 2);
        assert_eq!(s.hinges.len(), 1);
        let h = s.hinges[0];
        assert_eq!(h.assignment, Assignment::Valley);
        assert_eq!(h.fold_angle, Some(std::f32::consts::FRAC_PI_2));
        // v2 lies left of v0 -> v1 (counter-clockwise), v3 right of it.
        let p = h.v.map(|i| s.positions[i as usize].truncate());
        assert!((p[1] - p[0]).perp_dot(p[2] - p[0]) > 0.0);
        assert!((p[1] - p[0]).perp_dot(p[3] - p[0]) < 0.0);
        let xs: Vec<f32> = s.positions.iter().map(|p| p.x.abs()).collect();
        assert!(xs.iter().all(|&x| (x - 0.5).abs() < 1e-6), "{xs:?}");
        assert_eq!(s.crease_count(), 1);
    }

    #[test]
    fn mountain_angle_is_negative_and_added_edges_are_flat() {
        let mut segments = square(4.0);
        segments.push((Assignment::Mountain, [2.0, 0.0, 2.0, 4.0], Some(-45.0)));
        let s = sheet(&segments).unwrap();
        let mountains: Vec<_> = s
            .hinges
            .iter()
            .filter(|h| h.assignment == Assignment::Mountain)
            .collect();
        assert_eq!(mountains.len(), 1);
        assert!((mountains[0].fold_angle.unwrap() + std::f32::consts::FRAC_PI_4).abs() < 1e-6);
        assert!(s
            .hinges
            .iter()
            .all(|h| matches!(h.assignment, Assignment::Mountain | Assignment::Flat)));
        assert_eq!(s.hinges.len(), 3);
    }

    #[test]
    fn boundary_holes_are_left_out() {
        let mut segments = square(6.0);
        let hole = square(2.0)
            .into_iter()
            .map(|(a, [x1, y1, x2, y2], f)| (a, [x1 + 2.0, y1 + 2.0, x2 + 2.0, y2 + 2.0], f));
        segments.extend(hole);
        let s = sheet(&segments).unwrap();
        for t in &s.triangles {
            let c = t.iter().map(|&i| s.positions[i as usize]).sum::<Vec3>() / 3.0;
            assert!(
                c.x.abs() > 1.0 / 6.0 || c.y.abs() > 1.0 / 6.0,
                "triangle in the hole"
            );
        }
        assert_eq!(euler(&s), 0);
    }

    #[test]
    fn cuts_separate_the_sides() {
        let mut segments = square(4.0);
        // A slit from the rim to the middle, and a boundary-coloured slit
        // inside the paper.
        segments.push((Assignment::Cut, [0.0, 2.0, 2.0, 2.0], None));
        segments.push((Assignment::Boundary, [2.0, 3.0, 3.0, 3.0], None));
        segments.push((Assignment::Boundary, [3.0, 3.0, 3.5, 3.0], None));
        segments.push((Assignment::Valley, [2.0, 0.0, 2.0, 2.0], None));
        let s = sheet(&segments).unwrap();
        let at = |x: f32, y: f32| {
            s.positions
                .iter()
                .filter(|p| {
                    (p.x - (x / 4.0 - 0.5)).abs() < 1e-6 && (p.y - (y / 4.0 - 0.5)).abs() < 1e-6
                })
                .count()
        };
        assert_eq!(at(0.0, 2.0), 2, "rim end of the cut is split");
        assert_eq!(at(2.0, 2.0), 1, "tip of the cut is not");
        assert_eq!(at(3.0, 3.0), 2, "middle of the slit is split");
        for h in &s.hinges {
            let [a, b] = [h.v[0], h.v[1]].map(|i| s.positions[i as usize]);
            let horizontal = (a.y - b.y).abs() < 1e-6;
            let on_rim_cut = a.y.abs() < 1e-6 && a.x.max(b.x) <= 1e-6;
            let on_slit =
                (a.y - 0.25).abs() < 1e-6 && a.x.min(b.x) >= -1e-6 && a.x.max(b.x) <= 0.375;
            let on_cut = horizontal && (on_rim_cut || on_slit);
            assert!(!on_cut, "hinge along a cut: {h:?}");
        }
        assert_eq!(s.crease_count(), 1);
    }

    #[test]
    fn without_boundary_the_convex_hull_is_the_sheet() {
        let s = sheet(&[
            (Assignment::Mountain, [0.0, 0.0, 2.0, 2.0], None),
            (Assignment::Valley, [0.0, 2.0, 2.0, 0.0], None),
        ])
        .unwrap();
        assert_eq!(s.triangles.len(), 4);
        assert_eq!(s.crease_count(), 4);
        assert_eq!(euler(&s), 1);
    }

    #[test]
    fn without_boundary_an_outline_in_crease_colours_is_the_sheet() {
        // A square drawn in mountain lines (no boundary colour), its right
        // side bent a hair inward at its middle, with a valley diagonal.
        // The convex hull would add a sliver triangle 1e-5 wide there and
        // make the two right-hand mountains hinges of it (4 triangles, 3
        // creases): the paper is what the lines enclose.
        let m = Assignment::Mountain;
        let s = sheet(&[
            (m, [0.0, 0.0, 2.0, 0.0], None),
            (m, [2.0, 0.0, 2.0 - 1e-5, 1.0], None),
            (m, [2.0 - 1e-5, 1.0, 2.0, 2.0], None),
            (m, [2.0, 2.0, 0.0, 2.0], None),
            (m, [0.0, 2.0, 0.0, 0.0], None),
            (Assignment::Valley, [0.0, 0.0, 2.0, 2.0], None),
        ])
        .unwrap();
        assert_eq!(s.triangles.len(), 3);
        assert_eq!(s.crease_count(), 1);
        assert_eq!(euler(&s), 1);
    }

    #[test]
    fn without_boundary_lines_that_enclose_only_part_take_the_hull() {
        // Two diagonals of a square and a small closed triangle of
        // mountains at its centre: the lines enclose 1.5 % of the hull, so
        // the paper is the hull (the whole square, area 1 once scaled).
        let m = Assignment::Mountain;
        let s = sheet(&[
            (Assignment::Valley, [0.0, 0.0, 2.0, 2.0], None),
            (Assignment::Valley, [0.0, 2.0, 2.0, 0.0], None),
            (m, [0.8, 0.9, 1.2, 0.9], None),
            (m, [1.2, 0.9, 1.0, 1.2], None),
            (m, [1.0, 1.2, 0.8, 0.9], None),
        ])
        .unwrap();
        let area: f32 = s
            .triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| s.positions[i as usize]);
                0.5 * (b - a).cross(c - a).length()
            })
            .sum();
        assert!((area - 1.0).abs() < 1e-5, "area {area}");
        assert_eq!(euler(&s), 1);
    }

    #[test]
    fn features_finer_than_the_rounding_of_a_huge_pattern_are_an_error() {
        // A 100-unit square and a crease 1e16 units long: the square's
        // corners land on one point of the unit box (this panicked inside
        // the triangulation, found by fuzzing).
        let mut segments = square(100.0);
        segments.push((Assignment::Mountain, [50.0, 50.0, 1e16, 50.0], None));
        let error = sheet(&segments).unwrap_err().to_string();
        assert!(error.contains("lands on the point (0, 0)"), "{error}");
    }

    #[test]
    fn refinement_splits_creases_into_hinges() {
        let mut segments = square(1.0);
        segments.push((Assignment::Valley, [0.5, 0.0, 0.5, 1.0], None));
        let mut b = PatternBuilder::default();
        for &(a, [x1, y1, x2, y2], angle) in &segments {
            b.segment(DVec2::new(x1, y1), DVec2::new(x2, y2), a, angle);
        }
        let options = SheetOptions {
            size: 1.0,
            max_edge: Some(0.1),
            ..SheetOptions::default()
        };
        let s = Sheet::from_pattern(&b.finish(), &options).unwrap();
        assert!(s.triangles.len() > 100, "{}", s.triangles.len());
        assert!(s.crease_count() >= 10);
        assert!(s
            .hinges
            .iter()
            .filter(|h| h.assignment == Assignment::Valley)
            .all(|h| h.v[..2]
                .iter()
                .all(|&i| s.positions[i as usize].x.abs() < 1e-6)));
        assert_eq!(euler(&s), 1);
    }

    #[test]
    fn bad_input_is_an_error() {
        let line = [(Assignment::Boundary, [0.0, 0.0, 1.0, 0.0], None)];
        assert!(sheet(&line)
            .unwrap_err()
            .reason
            .contains("inside its boundary"));
        assert!(sheet(&[]).unwrap_err().reason.contains("no segment"));
        let pattern = CreasePattern::default();
        let size = SheetOptions {
            size: 0.0,
            ..SheetOptions::default()
        };
        assert_eq!(
            Sheet::from_pattern(&pattern, &size).unwrap_err().location,
            "size"
        );
        let edge = SheetOptions {
            max_edge: Some(f64::NAN),
            ..SheetOptions::default()
        };
        assert_eq!(
            Sheet::from_pattern(&pattern, &edge).unwrap_err().location,
            "max_edge"
        );
        let tiny = SheetOptions {
            max_edge: Some(1e-6),
            ..SheetOptions::default()
        };
        let mut segments = square(1.0);
        segments.push((Assignment::Valley, [0.5, 0.0, 0.5, 1.0], None));
        let mut b = PatternBuilder::default();
        for &(a, [x1, y1, x2, y2], angle) in &segments {
            b.segment(DVec2::new(x1, y1), DVec2::new(x2, y2), a, angle);
        }
        assert!(Sheet::from_pattern(&b.finish(), &tiny)
            .unwrap_err()
            .reason
            .contains("too small"));
    }
}
