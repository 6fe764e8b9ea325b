//! Triangle-mesh colliders: a bounding volume hierarchy over the triangles
//! (median split on the longest axis of the centroids, a flat node array),
//! the exact closest point on the mesh (Ericson, *Real-Time Collision
//! Detection*, 5.1.5) and the inside/outside sign.
//!
//! The sign depends on whether the mesh is closed, which is decided when the
//! collider is built: no degenerate triangle, every edge used by exactly two
//! triangles in opposite directions, the triangles around every vertex one
//! fan (no pinched vertex), and every connected surface facing outward (the
//! winding number just in front of its largest triangle is 0 and just behind
//! it 1; this refuses inside-out meshes and a surface nested in another's
//! volume, and accepts a cavity's inward surface).
//!
//! - Closed meshes take the sign from the closest point, by the
//!   angle-weighted pseudonormals of Baerentzen and Aanaes 2005: the face
//!   normal where the closest point is inside a triangle, the sum of the two
//!   face normals on an edge, the angle-weighted sum of the face normals at a
//!   vertex; `p` is inside if it is behind that pseudonormal. This is exact
//!   for a closed, manifold surface that does not cross itself (self
//!   crossings are not detected here; scenes refuse generated meshes that
//!   cross themselves), and costs nothing beyond the closest point.
//! - Open meshes, such as the Utah teapot, keep the generalized winding
//!   number (Jacobson et al. 2013), in the fast, first-order evaluation of
//!   Barill et al. 2018: a node seen from farther than `FAR_FIELD` times its
//!   radius adds the solid angle of its area-weighted normal (a dipole)
//!   instead of its triangles, so a query visits about `O(log n)` nodes plus
//!   the triangles near the point; [`winding_number_brute_force`] sums every
//!   triangle's exact solid angle (`O(n)`) for checks. Inside above one half.
//!
//! Points outside the mesh's bounding box are outside without either:
//! exact for closed meshes, and the convention for open ones.
//!
//! Contacts ask [`MeshCollider::signed_distance_within`]: the signed distance
//! only where it is below a `reach` (the cloth's thickness). Most particles
//! are farther than that, and the whole cost used to be their sign. The
//! query, in order:
//! 1. For a closed mesh, a grid over its box (`OutsideCells`, built with
//!    the collider) marks cells that are certainly outside (no triangle's box
//!    touches them and they join the box's border through such cells; the
//!    winding number of a closed mesh is constant off its surface, zero
//!    there), each with its clearance from the surface in cells: a point in
//!    a cell outside and clear by at least `reach` is answered at once.
//! 2. The closest point within `reach`, by a descent that prunes every box
//!    farther than `reach`: cheap for a point far from the surface. If there
//!    is one, it is signed (pseudonormal, or winding number for an open mesh).
//! 3. Nothing within reach: outside the bounding box, or in a cell certainly
//!    outside, the point is outside. Otherwise it may be deep inside, where
//!    the contact needs the whole distance to push it out, so a closed mesh
//!    finds the unbounded closest point and signs it (the point is outside
//!    if it is in front), and an open mesh evaluates the winding number
//!    first and searches only inside. A parity ray would be cheaper than the
//!    unbounded search but fragile at edges and vertices; the grid leaves the
//!    search to points in the thin band of cells the surface touches, inside,
//!    or in cavities.
//!
//! [`MeshCollider::signed_distance`] and [`MeshCollider::contains`] sign the
//! same way, so a baked [`crate::collide::SdfGrid`] does too.
//!
//! Swept queries keep fast particles from tunnelling through thin meshes:
//! [`MeshCollider::first_hit`] finds where the segment from a particle's
//! previous position to its new one first crosses a triangle (slab tests on
//! the boxes, nearer child first, boxes beyond the best hit skipped), and
//! [`MeshCollider::swept_signed_distance_within`] turns that crossing into
//! the distance and normal a contact pushes along, back to the side the
//! particle came from.

use crate::math::Aabb;
use crate::mesh::Mesh;
use glam::Vec3;
use std::collections::HashMap;
use std::f32::consts::PI;
use std::fmt;

/// Most triangles in a leaf.
const LEAF_SIZE: usize = 4;
/// A node farther than this many radii away is summed as one dipole.
const FAR_FIELD: f32 = 2.0;
/// Distances below this, relative to the coordinates, are rounding: on the surface.
const ON_SURFACE: f32 = 1e-6;
/// Deeper than any median-split hierarchy of `u32` triangles needs.
const STACK_DEPTH: usize = 64;
/// Cells of the outside grid of a closed mesh, per triangle and at most.
const CELLS_PER_TRIANGLE: usize = 64;
const MIN_CELLS: usize = 1 << 12;
const MAX_CELLS: usize = 1 << 18;

/// A node: a leaf holds `count > 0` triangles from `first` in leaf order; an
/// inner node (`count == 0`) has its children at `first` and `first + 1`.
/// The dipole (`centre`, `area_normal`, `radius`) stands for the node's
/// triangles in the far field of the winding number.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Node {
    bounds: Aabb,
    first: u32,
    count: u32,
    /// Area-weighted centroid of the triangles.
    centre: Vec3,
    /// Sum of the triangles' area vectors, `(b - a) x (c - a) / 2`.
    area_normal: Vec3,
    /// Largest distance from `centre` to the node's box.
    radius: f32,
}

/// Where a segment first crosses a mesh.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SegmentHit {
    /// Fraction of the way from the segment's start, in `[0, 1]`.
    pub t: f32,
    /// The crossing point.
    pub point: Vec3,
    /// Index into the collider's triangles.
    pub triangle: usize,
    /// The triangle's unit normal turned towards the segment's start: the
    /// side the segment came from.
    pub normal: Vec3,
    /// Whether the segment came from the triangle's front (outward) side.
    pub front: bool,
}

impl Node {
    fn is_leaf(&self) -> bool {
        self.count > 0
    }

    fn items(&self) -> std::ops::Range<usize> {
        self.first as usize..(self.first + self.count) as usize
    }

    fn children(&self) -> [u32; 2] {
        [self.first, self.first + 1]
    }
}

/// The point of the mesh nearest a query point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Closest {
    /// The nearest point on the mesh.
    pub point: Vec3,
    /// Index into the collider's triangles.
    pub triangle: usize,
    /// Squared distance from the query point to `point` (m^2).
    pub distance_squared: f32,
}

/// A static triangle mesh prepared for distance and inside/outside queries.
#[derive(Clone, PartialEq)]
pub struct MeshCollider {
    positions: Vec<Vec3>,
    /// In leaf order of the hierarchy.
    triangles: Vec<[u32; 3]>,
    nodes: Vec<Node>,
    /// For a closed mesh, the pseudonormals that sign its distances.
    pseudonormals: Option<Pseudonormals>,
    /// For a closed mesh, the cells of its box that are certainly outside.
    outside: Option<OutsideCells>,
}

/// A grid over a closed mesh's bounding box that marks the cells certainly
/// outside the mesh: those no triangle's box touches, joined through such
/// cells to the grid's border. The winding number of a closed mesh is an
/// integer, so it is constant on every connected region the surface does
/// not cross; on the flooded cells it is that of the space beyond the box,
/// zero. Cavities and the inside stay unmarked (unknown).
///
/// A marked cell also keeps its clearance: how many cells away, along the
/// axis where they are farthest apart (the Chebyshev distance of their
/// indices), the nearest touched cell is. Every point of the surface lies in
/// a touched cell, so no point of the surface is nearer a point of the cell
/// than `(clearance - 1) * cell`.
#[derive(Clone, PartialEq)]
struct OutsideCells {
    origin: Vec3,
    cell: f32,
    inverse_cell: f32,
    dims: [usize; 3],
    /// Per cell: 0 where it may be inside (or touched), else its clearance
    /// (at most 255).
    clearance: Vec<u8>,
}

impl OutsideCells {
    /// Cells of about equal size, at most `CELLS_PER_TRIANGLE` per triangle
    /// (`MIN_CELLS` to `MAX_CELLS`): the flood is `O(cells)`, the marking
    /// about `O(triangles)` for triangles no larger than a cell.
    fn new(bounds: Aabb, triangles: impl Iterator<Item = [Vec3; 3]>, count: usize) -> Self {
        let size = bounds.max - bounds.min;
        let budget = (count * CELLS_PER_TRIANGLE).clamp(MIN_CELLS, MAX_CELLS) as f32;
        let thick = size.max(Vec3::splat(size.max_element() * 1e-3));
        let cell = (thick.x * thick.y * thick.z / budget).cbrt();
        let dims = (size / cell)
            .ceil()
            .max(Vec3::ONE)
            .to_array()
            .map(|n| n as usize);
        let mut grid = OutsideCells {
            origin: bounds.min,
            cell,
            inverse_cell: 1.0 / cell,
            dims,
            clearance: vec![0; dims.iter().product()],
        };
        // Padding beyond the rounding of coordinates and of cell indices.
        let pad =
            cell * 1e-3 + 8.0 * f32::EPSILON * bounds.min.abs().max(bounds.max.abs()).max_element();
        let mut surface = vec![false; grid.clearance.len()];
        for corners in triangles {
            let b = Aabb::of_points(corners);
            let [lo, hi] = [b.min - pad, b.max + pad].map(|q| grid.cell_of(q));
            for k in lo[2]..=hi[2] {
                for j in lo[1]..=hi[1] {
                    for i in lo[0]..=hi[0] {
                        surface[grid.index([i, j, k])] = true;
                    }
                }
            }
        }
        // Flood through faces from every free cell on the border.
        let [nx, ny, nz] = dims;
        let cells = (0..nz)
            .flat_map(|k| (0..ny).flat_map(move |j| (0..nx).map(move |i| [i, j, k])))
            .collect::<Vec<_>>();
        let border = |[i, j, k]: [usize; 3]| {
            i == 0 || j == 0 || k == 0 || i == nx - 1 || j == ny - 1 || k == nz - 1
        };
        let mut outside = vec![false; surface.len()];
        let mut stack = Vec::new();
        for &c in cells.iter().filter(|&&c| border(c)) {
            if !surface[grid.index(c)] {
                outside[grid.index(c)] = true;
                stack.push(c);
            }
        }
        while let Some(c) = stack.pop() {
            for axis in 0..3 {
                for next in [c[axis].wrapping_sub(1), c[axis] + 1] {
                    let mut n = c;
                    n[axis] = next;
                    if next < dims[axis] && !surface[grid.index(n)] && !outside[grid.index(n)] {
                        outside[grid.index(n)] = true;
                        stack.push(n);
                    }
                }
            }
        }
        // Clearances, breadth first from the touched cells over all 26 neighbours.
        let mut distance = vec![u8::MAX; surface.len()];
        let mut layer: Vec<_> = cells
            .into_iter()
            .filter(|&c| surface[grid.index(c)])
            .collect();
        layer.iter().for_each(|&c| distance[grid.index(c)] = 0);
        for d in 1..u8::MAX {
            let mut next_layer = Vec::new();
            for c in layer {
                let lo = c.map(|x| x.saturating_sub(1));
                let hi = [0, 1, 2].map(|axis| (c[axis] + 1).min(dims[axis] - 1));
                for k in lo[2]..=hi[2] {
                    for j in lo[1]..=hi[1] {
                        for i in lo[0]..=hi[0] {
                            let index = grid.index([i, j, k]);
                            if distance[index] == u8::MAX {
                                distance[index] = d;
                                next_layer.push([i, j, k]);
                            }
                        }
                    }
                }
            }
            if next_layer.is_empty() {
                break;
            }
            layer = next_layer;
        }
        for ((clearance, outside), distance) in grid.clearance.iter_mut().zip(outside).zip(distance)
        {
            if outside {
                *clearance = distance;
            }
        }
        grid
    }

    fn index(&self, [i, j, k]: [usize; 3]) -> usize {
        i + self.dims[0] * (j + self.dims[1] * k)
    }

    /// The cell holding `p`, clamped to the grid.
    fn cell_of(&self, p: Vec3) -> [usize; 3] {
        let g = ((p - self.origin) * self.inverse_cell)
            .floor()
            .max(Vec3::ZERO);
        [0, 1, 2].map(|axis| (g[axis] as usize).min(self.dims[axis] - 1))
    }

    /// Whether `p`, within the grid's box, is certainly outside the mesh.
    fn outside(&self, p: Vec3) -> bool {
        self.clearance[self.index(self.cell_of(p))] > 0
    }

    /// Whether `p`, within the grid's box, is certainly outside the mesh and
    /// at least `reach` from its surface.
    fn outside_beyond(&self, p: Vec3, reach: f32) -> bool {
        let clearance = self.clearance[self.index(self.cell_of(p))];
        clearance > 0 && f32::from(clearance - 1) * self.cell >= reach
    }
}

/// Angle-weighted pseudonormals of a closed surface (Baerentzen and Aanaes
/// 2005), unnormalised: only the sign of a dot product with them is used.
#[derive(Clone, PartialEq)]
struct Pseudonormals {
    /// Per triangle, in leaf order: its unit normal, then the pseudonormals
    /// of its edges 0, 1 and 2 (the sum of the unit normals of the two
    /// triangles on the edge).
    triangles: Vec<[Vec3; 4]>,
    /// Per vertex: the unit normals of its triangles, each weighted by the
    /// triangle's angle at the vertex.
    vertices: Vec<Vec3>,
}

impl Pseudonormals {
    /// The pseudonormals of `triangles` if they make closed, oriented,
    /// manifold surfaces: no degenerate triangle, every edge used by exactly
    /// two triangles in opposite directions, and the triangles around every
    /// vertex a single fan. Also one triangle of each connected surface, the
    /// largest, to check which way the surface faces. `None` otherwise.
    fn of_closed(positions: &[Vec3], triangles: &[[u32; 3]]) -> Option<(Self, Vec<usize>)> {
        let corners = |t: &[u32; 3]| t.map(|i| positions[i as usize]);
        let mut faces = Vec::with_capacity(triangles.len());
        for t in triangles {
            let [a, b, c] = corners(t);
            faces.push((b - a).cross(c - a).try_normalize()?);
        }
        // Half-edge `3 t + k` runs from corner `k` of triangle `t` to corner `k + 1`.
        let half_edge_count = 3 * triangles.len();
        let mut half_edges = HashMap::with_capacity(half_edge_count);
        for (h, (t, k)) in (0..triangles.len())
            .flat_map(|t| (0..3).map(move |k| (t, k)))
            .enumerate()
        {
            let edge = (triangles[t][k], triangles[t][(k + 1) % 3]);
            if edge.0 == edge.1 || half_edges.insert(edge, h).is_some() {
                return None;
            }
        }
        let mut twin = vec![0; half_edge_count];
        for (&(from, to), &h) in &half_edges {
            twin[h] = *half_edges.get(&(to, from))?;
        }
        // Going round a vertex: the half-edge into it in the same triangle,
        // then that one's twin, out of it in the next triangle.
        let turn = |h: usize| twin[3 * (h / 3) + (h + 2) % 3];
        let mut fans = vec![false; positions.len()];
        let mut seen = vec![false; half_edge_count];
        for start in 0..half_edge_count {
            if seen[start] {
                continue;
            }
            let vertex = triangles[start / 3][start % 3] as usize;
            if std::mem::replace(&mut fans[vertex], true) {
                return None; // a second fan: the surface pinches at the vertex
            }
            let mut h = start;
            while !seen[h] {
                seen[h] = true;
                h = turn(h);
            }
        }
        let mut vertices = vec![Vec3::ZERO; positions.len()];
        for (t, face) in triangles.iter().zip(&faces) {
            let p = corners(t);
            for k in 0..3 {
                let (u, v) = (p[(k + 1) % 3] - p[k], p[(k + 2) % 3] - p[k]);
                let angle = u.cross(v).length().atan2(u.dot(v));
                vertices[t[k] as usize] += *face * angle;
            }
        }
        let normals = Pseudonormals {
            triangles: (0..triangles.len())
                .map(|t| {
                    let edge = |k: usize| faces[t] + faces[twin[3 * t + k] / 3];
                    [faces[t], edge(0), edge(1), edge(2)]
                })
                .collect(),
            vertices,
        };
        // Connected surfaces, by flooding across edges.
        let area = |t: usize| {
            let [a, b, c] = corners(&triangles[t]);
            (b - a).cross(c - a).length()
        };
        let mut flooded = vec![false; triangles.len()];
        let mut largest = Vec::new();
        for seed in 0..triangles.len() {
            if std::mem::replace(&mut flooded[seed], true) {
                continue;
            }
            let (mut stack, mut best) = (vec![seed], seed);
            while let Some(t) = stack.pop() {
                if area(t) > area(best) {
                    best = t;
                }
                for &h in &twin[3 * t..3 * t + 3] {
                    let next = h / 3;
                    if !std::mem::replace(&mut flooded[next], true) {
                        stack.push(next);
                    }
                }
            }
            largest.push(best);
        }
        Some((normals, largest))
    }

    /// The pseudonormal of `feature` of triangle `t` (corners `corners`).
    fn at(&self, t: usize, corners: &[u32; 3], feature: Feature) -> Vec3 {
        match feature {
            Feature::Face => self.triangles[t][0],
            Feature::Edge(k) => self.triangles[t][1 + k],
            Feature::Vertex(k) => self.vertices[corners[k] as usize],
        }
    }
}

impl fmt::Debug for MeshCollider {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("MeshCollider")
            .field("vertices", &self.positions.len())
            .field("triangles", &self.triangles.len())
            .field("bounds", &self.bounds())
            .field("closed", &self.is_closed())
            .finish()
    }
}

impl MeshCollider {
    /// Builds the hierarchy over `mesh`'s triangles.
    ///
    /// # Panics
    /// If a triangle refers to a vertex `mesh` lacks; meshes from
    /// [`crate::mesh::obj::load_obj`] are checked for that.
    pub fn new(mesh: &Mesh) -> Self {
        let mut collider = MeshCollider {
            positions: mesh.positions.clone(),
            triangles: mesh.triangles.clone(),
            nodes: Vec::with_capacity(2 * mesh.triangles.len() / LEAF_SIZE + 1),
            pseudonormals: None,
            outside: None,
        };
        if !collider.triangles.is_empty() {
            let mut triangles = std::mem::take(&mut collider.triangles);
            collider.nodes.push(collider.leaf(&triangles, 0));
            collider.split(0, &mut triangles, 0);
            collider.triangles = triangles;
        }
        if let Some((normals, largest)) =
            Pseudonormals::of_closed(&collider.positions, &collider.triangles)
        {
            if largest.into_iter().all(|t| collider.faces_outward(t)) {
                collider.pseudonormals = Some(normals);
                collider.outside = Some(OutsideCells::new(
                    collider.bounds(),
                    collider.triangles(),
                    collider.triangles.len(),
                ));
            }
        }
        collider
    }

    /// Whether the mesh is closed (see the module documentation): its
    /// distances are then signed by pseudonormals rather than the winding number.
    pub fn is_closed(&self) -> bool {
        self.pseudonormals.is_some()
    }

    /// Whether triangle `t` faces out of the volume its surface bounds: the
    /// winding number is below one half just in front of its centroid and
    /// above one half just behind it. Not so for a surface turned inside
    /// out, or one inside another's volume.
    fn faces_outward(&self, t: usize) -> bool {
        let [a, b, c] = self.corners(&self.triangles[t]);
        let normal = (b - a).cross(c - a);
        let step = normal.normalize_or_zero() * 1e-3 * normal.length().sqrt();
        let centroid = (a + b + c) / 3.0;
        self.winding_number(centroid + step) < 0.5 && self.winding_number(centroid - step) > 0.5
    }

    /// The corners of every triangle, in the hierarchy's leaf order.
    pub fn triangles(&self) -> impl Iterator<Item = [Vec3; 3]> + '_ {
        self.triangles.iter().map(|t| self.corners(t))
    }

    /// The box around every triangle (empty, inverted, for no triangles).
    pub fn bounds(&self) -> Aabb {
        self.nodes.first().map_or(Aabb::EMPTY, |n| n.bounds)
    }

    fn corners(&self, t: &[u32; 3]) -> [Vec3; 3] {
        t.map(|i| self.positions[i as usize])
    }

    /// A leaf over `triangles`, which start at `first` in leaf order.
    fn leaf(&self, triangles: &[[u32; 3]], first: usize) -> Node {
        let corners = triangles.iter().map(|t| self.corners(t));
        let bounds = Aabb::of_points(corners.clone().flatten());
        let (mut weighted, mut area, mut area_normal) = (Vec3::ZERO, 0.0, Vec3::ZERO);
        for [a, b, c] in corners {
            let n = (b - a).cross(c - a) * 0.5;
            weighted += (a + b + c) / 3.0 * n.length();
            area += n.length();
            area_normal += n;
        }
        let box_centre = (bounds.min + bounds.max) * 0.5;
        let centre = if area > 0.0 {
            weighted / area
        } else {
            box_centre
        };
        Node {
            bounds,
            first: first as u32,
            count: triangles.len() as u32,
            centre,
            area_normal,
            radius: centre.distance(box_centre) + (bounds.max - box_centre).length(),
        }
    }

    /// Fills node `index` with `triangles`, starting at `first` in leaf order.
    /// Median splits halve the triangles, so the depth is about log2(n).
    fn split(&mut self, index: usize, triangles: &mut [[u32; 3]], first: usize) {
        self.nodes[index] = self.leaf(triangles, first);
        if triangles.len() <= LEAF_SIZE {
            return;
        }
        let centroid = |t: &[u32; 3]| self.corners(t).into_iter().sum::<Vec3>();
        let spread = Aabb::of_points(triangles.iter().map(centroid));
        let axis = (spread.max - spread.min).max_position();
        let mid = triangles.len() / 2;
        triangles
            .select_nth_unstable_by(mid, |a, b| centroid(a)[axis].total_cmp(&centroid(b)[axis]));
        let child = self.nodes.len();
        self.nodes.extend([self.nodes[index]; 2]);
        let (left, right) = triangles.split_at_mut(mid);
        self.split(child, left, first);
        self.split(child + 1, right, first + mid);
        self.nodes[index].first = child as u32;
        self.nodes[index].count = 0;
    }

    /// The nearest point of the mesh to `p`. `None` without triangles.
    pub fn closest_point(&self, p: Vec3) -> Option<Closest> {
        self.closest_point_within(p, f32::INFINITY)
    }

    /// The nearest point of the mesh to `p` if it is nearer than
    /// `sqrt(limit_squared)`: a best-first descent that skips every box
    /// farther than the limit or the best triangle so far, so a small limit
    /// makes a far query cheap.
    pub fn closest_point_within(&self, p: Vec3, limit_squared: f32) -> Option<Closest> {
        let mut best: Option<Closest> = None;
        let mut stack = Stack::with_root(!self.nodes.is_empty());
        while let Some(index) = stack.pop() {
            let node = &self.nodes[index as usize];
            let mut bound = best.map_or(limit_squared, |b| b.distance_squared);
            if node.bounds.distance_squared(p) >= bound {
                continue;
            }
            if node.is_leaf() {
                for triangle in node.items() {
                    let [a, b, c] = self.corners(&self.triangles[triangle]);
                    let point = closest_point_on_triangle(p, a, b, c);
                    let distance_squared = (p - point).length_squared();
                    if distance_squared < bound {
                        bound = distance_squared;
                        best = Some(Closest {
                            point,
                            triangle,
                            distance_squared,
                        });
                    }
                }
            } else {
                // The farther child goes in first, so the nearer one is searched first.
                let [l, r] = node.children();
                let dl = self.nodes[l as usize].bounds.distance_squared(p);
                let dr = self.nodes[r as usize].bounds.distance_squared(p);
                let (near, far) = if dl <= dr { (l, r) } else { (r, l) };
                stack.push(far);
                stack.push(near);
            }
        }
        best
    }

    /// The generalized winding number at `p`: about 1 inside a closed,
    /// outward-facing mesh, 0 outside, in between near the holes of an open one.
    /// Far nodes count as dipoles (Barill et al. 2018), near triangles exactly.
    pub fn winding_number(&self, p: Vec3) -> f32 {
        let mut solid_angle = 0.0;
        let mut stack = Stack::with_root(!self.nodes.is_empty());
        while let Some(index) = stack.pop() {
            let node = &self.nodes[index as usize];
            let r = node.centre - p;
            let distance = r.length();
            if distance > FAR_FIELD * node.radius {
                solid_angle += r.dot(node.area_normal) / (distance * distance * distance);
            } else if node.is_leaf() {
                solid_angle += node
                    .items()
                    .map(|i| {
                        let [a, b, c] = self.corners(&self.triangles[i]);
                        triangle_solid_angle(p, a, b, c)
                    })
                    .sum::<f32>();
            } else {
                let [l, r] = node.children();
                stack.push(l);
                stack.push(r);
            }
        }
        solid_angle / (4.0 * PI)
    }

    /// Whether `p` is inside: within the bounding box, and behind the surface
    /// at its closest point for a closed mesh, or with a winding number above
    /// one half for an open one.
    pub fn contains(&self, p: Vec3) -> bool {
        self.bounds().contains(p)
            && !self.outside.as_ref().is_some_and(|o| o.outside(p))
            && match &self.pseudonormals {
                Some(normals) => self
                    .closest_point(p)
                    .is_some_and(|closest| self.behind(normals, p, closest.triangle)),
                None => self.winding_number(p) > 0.5,
            }
    }

    /// Whether `p`, whose closest point of the mesh is `closest`, is inside.
    fn inside(&self, p: Vec3, closest: Closest) -> bool {
        match &self.pseudonormals {
            Some(normals) => self.behind(normals, p, closest.triangle),
            None => self.bounds().contains(p) && self.winding_number(p) > 0.5,
        }
    }

    /// Whether `p` is behind a closed surface at its closest point on
    /// `triangle`: the sign of the direction from that point to `p` against
    /// the pseudonormal of the face, edge or vertex the point lies on.
    fn behind(&self, normals: &Pseudonormals, p: Vec3, triangle: usize) -> bool {
        let t = &self.triangles[triangle];
        let [a, b, c] = self.corners(t);
        let (point, feature) = closest_feature_on_triangle(p, a, b, c);
        (p - point).dot(normals.at(triangle, t, feature)) < 0.0
    }

    /// Signed distance (negative inside) and the outward unit normal: the
    /// direction from the closest point to `p`, flipped inside, or the face
    /// normal on the surface (within rounding of it, where that direction is
    /// noise). Infinitely far, facing up, without triangles.
    pub fn signed_distance(&self, p: Vec3) -> (f32, Vec3) {
        match self.closest_point(p) {
            Some(closest) => self.signed(p, closest, self.inside(p, closest)),
            None => (f32::INFINITY, Vec3::Y),
        }
    }

    /// [`Self::signed_distance`] where it is below `reach`, `None` beyond:
    /// for contacts. The closest-point search stops at `reach`; only where
    /// it finds nothing and `p` is within the bounding box does the point
    /// need its sign on its own (deep inside, the whole distance is needed
    /// to push out). See the module documentation.
    pub fn signed_distance_within(&self, p: Vec3, reach: f32) -> Option<(f32, Vec3)> {
        let bounds = self.bounds();
        if let Some(outside) = &self.outside {
            if bounds.contains(p) && outside.outside_beyond(p, reach) {
                return None;
            }
        }
        if let Some(closest) = self.closest_point_within(p, reach * reach) {
            return Some(self.signed(p, closest, self.inside(p, closest)))
                .filter(|&(d, _)| d < reach);
        }
        if !bounds.contains(p) || self.outside.as_ref().is_some_and(|o| o.outside(p)) {
            return None;
        }
        let closest = match &self.pseudonormals {
            Some(normals) => self
                .closest_point(p)
                .filter(|closest| self.behind(normals, p, closest.triangle))?,
            None if self.winding_number(p) > 0.5 => self.closest_point(p)?,
            None => return None,
        };
        Some(self.signed(p, closest, true)).filter(|&(d, _)| d < reach)
    }

    /// The first triangle the segment `from`-`to` crosses, nearest `from`.
    /// A crossing goes from strictly one side of the triangle's plane to the
    /// other side or onto it; a segment that starts on a triangle's plane does
    /// not cross that triangle. Shared edges are hit from both triangles.
    pub fn first_hit(&self, from: Vec3, to: Vec3) -> Option<SegmentHit> {
        let delta = to - from;
        let mut best: Option<SegmentHit> = None;
        let mut stack = Stack::with_root(!self.nodes.is_empty());
        while let Some(index) = stack.pop() {
            let node = &self.nodes[index as usize];
            let limit = best.map_or(1.0, |b| b.t);
            if node.bounds.segment_entry(from, delta, limit).is_none() {
                continue;
            }
            if node.is_leaf() {
                for triangle in node.items() {
                    let [a, b, c] = self.corners(&self.triangles[triangle]);
                    if let Some(hit) = segment_triangle(from, to, a, b, c) {
                        if best.is_none_or(|b| hit.t < b.t) {
                            best = Some(SegmentHit { triangle, ..hit });
                        }
                    }
                }
            } else {
                let [l, r] = node.children();
                let entry = |i: u32| {
                    self.nodes[i as usize]
                        .bounds
                        .segment_entry(from, delta, limit)
                };
                match (entry(l), entry(r)) {
                    (Some(tl), Some(tr)) => {
                        let (near, far) = if tl <= tr { (l, r) } else { (r, l) };
                        stack.push(far);
                        stack.push(near);
                    }
                    (Some(_), None) => stack.push(l),
                    (None, Some(_)) => stack.push(r),
                    (None, None) => {}
                }
            }
        }
        best
    }

    /// [`Self::signed_distance_within`] at `to` for a particle that moved
    /// there from `from`, unless the move crossed the surface: then the
    /// distance of `to` from the crossed triangle's plane along its normal
    /// turned back towards `from` (negative: `to` is behind it), so that a
    /// contact pushes the particle back out on the side it came from, however
    /// thin the mesh. A crossing out of the back of a triangle from inside a
    /// closed mesh is the particle leaving, and is not a hit.
    pub fn swept_signed_distance_within(
        &self,
        from: Vec3,
        to: Vec3,
        reach: f32,
    ) -> Option<(f32, Vec3)> {
        match self.first_hit(from, to) {
            Some(hit) if hit.front || !self.contains(from) => {
                Some(((to - hit.point).dot(hit.normal), hit.normal))
            }
            _ => self.signed_distance_within(to, reach),
        }
    }

    /// The signed distance and normal at `p` from its closest point.
    fn signed(&self, p: Vec3, closest: Closest, inside: bool) -> (f32, Vec3) {
        let distance = closest.distance_squared.sqrt();
        if distance <= ON_SURFACE * (1.0 + p.abs().max_element()) {
            let [a, b, c] = self.corners(&self.triangles[closest.triangle]);
            return (0.0, (b - a).cross(c - a).normalize_or(Vec3::Y));
        }
        let away = (p - closest.point) / distance;
        if inside {
            (-distance, -away)
        } else {
            (distance, away)
        }
    }
}

/// A fixed-size stack of node indices: no allocation per query.
struct Stack {
    items: [u32; STACK_DEPTH],
    len: usize,
}

impl Stack {
    fn with_root(has_root: bool) -> Self {
        Stack {
            items: [0; STACK_DEPTH],
            len: usize::from(has_root),
        }
    }

    fn push(&mut self, node: u32) {
        self.items[self.len] = node;
        self.len += 1;
    }

    fn pop(&mut self) -> Option<u32> {
        self.len = self.len.checked_sub(1)?;
        Some(self.items[self.len])
    }
}

/// Where the segment `from`-`to` crosses triangle `abc`, or `None`: signed
/// distances of the ends from the triangle's plane, then the crossing point's
/// barycentric coordinates (inclusive, so a segment through a shared edge
/// hits both triangles). The hit's `triangle` is 0. `O(1)`; the brute-force
/// reference for [`MeshCollider::first_hit`].
pub fn segment_triangle(from: Vec3, to: Vec3, a: Vec3, b: Vec3, c: Vec3) -> Option<SegmentHit> {
    let normal = (b - a).cross(c - a);
    let (d0, d1) = ((from - a).dot(normal), (to - a).dot(normal));
    let crosses = (d0 > 0.0 && d1 <= 0.0) || (d0 < 0.0 && d1 >= 0.0);
    if !crosses {
        return None;
    }
    let t = d0 / (d0 - d1);
    let point = from + (to - from) * t;
    // Barycentric coordinates of the crossing from the sub-triangle areas.
    let area = normal.length_squared();
    let u = (c - b).cross(point - b).dot(normal) / area;
    let v = (a - c).cross(point - c).dot(normal) / area;
    let w = 1.0 - u - v;
    const EDGE: f32 = -1e-6;
    if u < EDGE || v < EDGE || w < EDGE || !t.is_finite() {
        return None;
    }
    let unit = normal.normalize();
    Some(SegmentHit {
        t: t.clamp(0.0, 1.0),
        point,
        triangle: 0,
        normal: if d0 > 0.0 { unit } else { -unit },
        front: d0 > 0.0,
    })
}

/// The winding number at `p` summed over every triangle: `O(n)`, for checks.
pub fn winding_number_brute_force(triangles: impl Iterator<Item = [Vec3; 3]>, p: Vec3) -> f32 {
    triangles
        .map(|[a, b, c]| triangle_solid_angle(p, a, b, c))
        .sum::<f32>()
        / (4.0 * PI)
}

/// Signed solid angle of triangle `abc` seen from `p` (Van Oosterom and
/// Strackee 1983): positive from behind a counter-clockwise triangle, that
/// is, from inside an outward-facing mesh.
pub fn triangle_solid_angle(p: Vec3, a: Vec3, b: Vec3, c: Vec3) -> f32 {
    let (a, b, c) = (a - p, b - p, c - p);
    let (la, lb, lc) = (a.length(), b.length(), c.length());
    let det = a.dot(b.cross(c));
    let denominator = la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb;
    2.0 * det.atan2(denominator)
}

/// The point of triangle `abc` nearest `p`, by its Voronoi regions (Ericson
/// 2005, 5.1.5). A degenerate triangle falls back to its nearest edge.
pub fn closest_point_on_triangle(p: Vec3, a: Vec3, b: Vec3, c: Vec3) -> Vec3 {
    closest_feature_on_triangle(p, a, b, c).0
}

/// Which part of a triangle a closest point lies on: a corner, an edge
/// (edge `k` runs from corner `k` to corner `k + 1`, modulo 3) or the inside.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Feature {
    Vertex(usize),
    Edge(usize),
    Face,
}

/// [`closest_point_on_triangle`] and the feature the point lies on.
fn closest_feature_on_triangle(p: Vec3, a: Vec3, b: Vec3, c: Vec3) -> (Vec3, Feature) {
    let (ab, ac, ap) = (b - a, c - a, p - a);
    let (d1, d2) = (ab.dot(ap), ac.dot(ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return (a, Feature::Vertex(0));
    }
    let bp = p - b;
    let (d3, d4) = (ab.dot(bp), ac.dot(bp));
    if d3 >= 0.0 && d4 <= d3 {
        return (b, Feature::Vertex(1));
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return (a + ab * (d1 / (d1 - d3)), Feature::Edge(0));
    }
    let cp = p - c;
    let (d5, d6) = (ab.dot(cp), ac.dot(cp));
    if d6 >= 0.0 && d5 <= d6 {
        return (c, Feature::Vertex(2));
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        return (a + ac * (d2 / (d2 - d6)), Feature::Edge(2));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0 {
        return (
            b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6))),
            Feature::Edge(1),
        );
    }
    let sum = va + vb + vc;
    if sum <= 0.0 || !sum.is_finite() {
        return nearest_edge_point(p, [a, b, c]);
    }
    (a + ab * (vb / sum) + ac * (vc / sum), Feature::Face)
}

/// The point nearest `p` on the three edges of a (degenerate) triangle, and
/// that edge, or its corner where the point is one.
fn nearest_edge_point(p: Vec3, corners: [Vec3; 3]) -> (Vec3, Feature) {
    (0..3)
        .map(|k| {
            let (s, e) = (corners[k], corners[(k + 1) % 3]);
            let d = e - s;
            let t = ((p - s).dot(d) / d.length_squared().max(f32::MIN_POSITIVE)).clamp(0.0, 1.0);
            let feature = if t == 0.0 {
                Feature::Vertex(k)
            } else if t == 1.0 {
                Feature::Vertex((k + 1) % 3)
            } else {
                Feature::Edge(k)
            };
            (s + d * t, feature)
        })
        .min_by(|x, y| x.0.distance_squared(p).total_cmp(&y.0.distance_squared(p)))
        .unwrap_or((corners[0], Feature::Vertex(0)))
}
