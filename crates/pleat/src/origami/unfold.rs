//! A folded state unfolded into its crease pattern (FOLD's `foldedForm`:
//! faces in 3D, or folded flat in the plane).
//!
//! Each face is laid in the plane by an isometry of its own shape, across
//! the face graph from the first face: a face shares an edge with a face
//! already laid and goes on the far side of that edge, as neighbours lie in
//! a crease pattern. Paper that cannot lie flat is an error: a vertex whose
//! faces' corners do not sum to 360 degrees (more than 360 on the rim), or
//! one laid in two places (layers of the folded form that share it). The angle
//! between each pair of neighbouring faces is the folded state's own fold
//! angle, so that the sheet can fold back into the file's shape. The first
//! face's normal (by its vertex order) is the sheet's front; where the
//! file's mountains and valleys say the other side is, the caller turns the
//! sheet over. A crease folded flat cannot tell a mountain from a valley by
//! its faces' normals; the file's `faceOrders` can: two faces folded flat
//! across a valley each lie on the side the other's front faces.

use std::collections::{HashMap, VecDeque};

use glam::{DMat2, DVec2, DVec3};

use super::pattern::PatternError;

/// Largest disagreement between two layouts of a vertex, relative to the
/// folded form's diameter, and largest distance of a face's vertex from
/// its plane, relative to the face's: paper that a simulator left
/// strained by a few percent unfolds (each vertex where its faces put it
/// on average), a cone or layers that share a vertex do not.
const MISFIT: f64 = 0.05;

/// Faces smaller than this, relative to the square of the folded form's
/// diameter, have no area.
const NO_AREA: f64 = 1e-12;

/// Fold angles below this (degrees) are no fold.
const FLAT_ANGLE: f64 = 0.5;

/// Fold angles beyond this (degrees) are folded flat: the faces' normals
/// then cannot tell a mountain from a valley.
const FLAT_FOLD_ANGLE: f64 = 179.5;

/// The fold angle between two neighbouring faces of a folded state.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Dihedral {
    /// Within [`FLAT_ANGLE`] of no fold.
    Flat,
    /// Folded by this many degrees, valley positive.
    Folded(f64),
    /// Folded flat, one face on the other: mountain or valley unknown.
    FlatFolded,
}

/// FOLD's `faceOrders` of a folded state: for a pair of faces `[f, g]`,
/// the side of face `g` that face `f` lies on, along `g`'s normal by its
/// vertex order (1 the side it points to, -1 the other).
pub(super) type FaceOrders = HashMap<[usize; 2], f64>;

/// A folded state laid flat.
#[derive(Debug)]
pub(super) struct Unfolded {
    /// Each vertex's place in the crease pattern.
    pub vertices: Vec<DVec2>,
    /// The fold angle of each edge between two faces, by its sorted vertex
    /// pair.
    pub dihedrals: HashMap<[usize; 2], Dihedral>,
}

impl Unfolded {
    /// Whether no edge is folded: the file was a crease pattern already.
    pub fn is_flat(&self) -> bool {
        self.dihedrals.values().all(|d| *d == Dihedral::Flat)
    }

    /// The same sheet seen from its back: the pattern mirrored, mountains
    /// and valleys swapped. It folds into the same shape.
    pub fn turn_over(&mut self) {
        for p in &mut self.vertices {
            p.x = -p.x;
        }
        for d in self.dihedrals.values_mut() {
            if let Dihedral::Folded(angle) = d {
                *angle = -*angle;
            }
        }
    }
}

/// An edge's key: its two vertices, smaller first.
pub(super) fn edge_key([a, b]: [usize; 2]) -> [usize; 2] {
    [a.min(b), a.max(b)]
}

/// The edges of a face's cycle of vertices, each from a vertex to the next.
pub(super) fn face_edges(face: &[usize]) -> impl Iterator<Item = (usize, usize)> + '_ {
    (0..face.len()).map(|k| (face[k], face[(k + 1) % face.len()]))
}

/// A face in its own plane: centroid, unit normal (by its vertex order)
/// and each vertex in an orthonormal frame of the plane.
struct FaceFrame {
    centroid: DVec3,
    normal: DVec3,
    local: Vec<DVec2>,
}

/// Where a face lies in the crease pattern: `plane = map * local + offset`
/// (`map` orthogonal; its determinant says whether the face's normal is
/// the sheet's front).
#[derive(Clone, Copy)]
struct Placement {
    map: DMat2,
    offset: DVec2,
}

impl Placement {
    fn place(&self, local: DVec2) -> DVec2 {
        self.map * local + self.offset
    }

    /// The face's normal turned to the sheet's front side.
    fn front(&self, normal: DVec3) -> DVec3 {
        normal * self.map.determinant().signum()
    }
}

/// Unfolds the faces `faces` (indices into `points`, each a cycle) across
/// every edge between two faces that `crossable` allows (not a cut); a
/// crease folded flat takes its direction from `orders` where they stack
/// its two faces. Errors name the face (`faces_vertices[f]`) or vertex and
/// the reason.
pub(super) fn unfold(
    points: &[DVec3],
    faces: &[Vec<usize>],
    crossable: impl Fn([usize; 2]) -> bool,
    orders: &FaceOrders,
) -> Result<Unfolded, PatternError> {
    let (min, max) = points
        .iter()
        .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), p| {
            (lo.min(*p), hi.max(*p))
        });
    let diameter = (max - min).length();
    if !diameter.is_finite() {
        return Err(PatternError::new(
            "vertices_coords",
            "coordinates too large to unfold",
        ));
    }
    let frames = faces
        .iter()
        .enumerate()
        .map(|(f, face)| face_frame(points, face, diameter).map_err(|r| at_face(f, r)))
        .collect::<Result<Vec<_>, _>>()?;
    let neighbours = neighbours(faces, &crossable)?;
    check_paper_around_vertices(faces, &frames, &neighbours)?;
    let placements = lay_out(faces, &frames, &neighbours, MISFIT * diameter)?;
    let mut sums = vec![(DVec2::ZERO, 0.0); points.len()];
    for (f, face) in faces.iter().enumerate() {
        for (k, &v) in face.iter().enumerate() {
            sums[v].0 += placements[f].place(frames[f].local[k]);
            sums[v].1 += 1.0;
        }
    }
    let vertices = sums
        .into_iter()
        .enumerate()
        .map(|(v, (sum, count))| {
            (count > 0.0).then(|| sum / count).ok_or_else(|| {
                PatternError::new(
                    format!("vertices_coords[{v}]"),
                    "lies on no face, so the folded form cannot place it in the crease pattern",
                )
            })
        })
        .collect::<Result<Vec<_>, _>>()?;
    let dihedrals = neighbours
        .iter()
        .map(|(&key, &[f, g])| {
            let front = |h: usize| placements[h].front(frames[h].normal);
            let along = points[key[0]];
            let d = match dihedral(front(f), front(g), frames[g].centroid - along) {
                Dihedral::FlatFolded => {
                    let front_side = |h: usize| placements[h].map.determinant().signum();
                    flat_fold_by_order([f, g], orders, front_side)
                }
                d => d,
            };
            (key, d)
        })
        .collect();
    Ok(Unfolded {
        vertices,
        dihedrals,
    })
}

fn at_face(f: usize, reason: impl ToString) -> PatternError {
    PatternError::new(format!("faces_vertices[{f}]"), reason.to_string())
}

/// Why a face of a folded form has no frame; [`unfold`] puts it in a
/// [`PatternError`] at the face.
#[derive(Clone, Copy, Debug, PartialEq, thiserror::Error)]
enum FaceError {
    /// Fewer than three vertices.
    #[error("a face needs 3 vertices, found {found}")]
    TooFewVertices { found: usize },
    /// Its vertices are (nearly) on one line or one point.
    #[error("a face of no area")]
    NoArea,
    /// A vertex is off the plane of the others.
    #[error("not flat: vertex {vertex} lies {off} off the face's plane")]
    NotFlat {
        /// The vertex, by its index in the file.
        vertex: usize,
        /// Its distance from the face's plane.
        off: f64,
    },
}

/// A face's frame, or why it has none (too few vertices, no area, not
/// flat).
fn face_frame(points: &[DVec3], face: &[usize], diameter: f64) -> Result<FaceFrame, FaceError> {
    if face.len() < 3 {
        return Err(FaceError::TooFewVertices { found: face.len() });
    }
    let corners: Vec<DVec3> = face.iter().map(|&v| points[v]).collect();
    let centroid = corners.iter().sum::<DVec3>() / corners.len() as f64;
    // Newell's normal: twice the vector area of the polygon.
    let area_vector: DVec3 = (0..corners.len())
        .map(|k| (corners[k] - centroid).cross(corners[(k + 1) % corners.len()] - centroid))
        .sum();
    if area_vector.length() <= NO_AREA * diameter * diameter {
        return Err(FaceError::NoArea);
    }
    let normal = area_vector.normalize();
    let size = corners
        .iter()
        .map(|p| p.distance(centroid))
        .fold(0.0, f64::max);
    if let Some((k, off)) = corners
        .iter()
        .map(|p| (*p - centroid).dot(normal).abs())
        .enumerate()
        .find(|(_, off)| *off > MISFIT * size)
    {
        return Err(FaceError::NotFlat {
            vertex: face[k],
            off,
        });
    }
    let x = normal.any_orthonormal_vector();
    let y = normal.cross(x);
    let local = corners
        .iter()
        .map(|p| DVec2::new((*p - centroid).dot(x), (*p - centroid).dot(y)))
        .collect();
    Ok(FaceFrame {
        centroid,
        normal,
        local,
    })
}

/// The two faces on each edge that may be crossed. An edge on three faces
/// or more is an error.
fn neighbours(
    faces: &[Vec<usize>],
    crossable: &impl Fn([usize; 2]) -> bool,
) -> Result<HashMap<[usize; 2], [usize; 2]>, PatternError> {
    let mut on_edge: HashMap<[usize; 2], Vec<usize>> = HashMap::new();
    for (f, face) in faces.iter().enumerate() {
        for (a, b) in face_edges(face) {
            let users = on_edge.entry(edge_key([a, b])).or_default();
            users.push(f);
            if users.len() > 2 {
                return Err(at_face(
                    f,
                    format!("its edge from vertex {a} to {b} is on three faces or more"),
                ));
            }
        }
    }
    Ok(on_edge
        .into_iter()
        .filter(|(key, users)| users.len() == 2 && crossable(*key))
        .map(|(key, users)| (key, [users[0], users[1]]))
        .collect())
}

/// Refuses a vertex inside the paper (every edge at it between two faces)
/// whose faces' corners there do not sum to 360 degrees, or one on its
/// rim where they sum to more, within [`MISFIT`]: the paper cannot lie flat
/// around it (a cone, a ruffle).
fn check_paper_around_vertices(
    faces: &[Vec<usize>],
    frames: &[FaceFrame],
    neighbours: &HashMap<[usize; 2], [usize; 2]>,
) -> Result<(), PatternError> {
    let mut corners: HashMap<usize, (f64, bool)> = HashMap::new();
    for (face, frame) in faces.iter().zip(frames) {
        let n = face.len();
        for k in 0..n {
            let (previous, next) = (face[(k + n - 1) % n], face[(k + 1) % n]);
            let to_next = frame.local[(k + 1) % n] - frame.local[k];
            let to_previous = frame.local[(k + n - 1) % n] - frame.local[k];
            // Counter-clockwise in the face's frame: its interior angle.
            let angle = to_next
                .angle_to(to_previous)
                .rem_euclid(std::f64::consts::TAU);
            let inside = [previous, next]
                .iter()
                .all(|&w| neighbours.contains_key(&edge_key([w, face[k]])));
            let entry = corners.entry(face[k]).or_insert((0.0, true));
            entry.0 += angle;
            entry.1 &= inside;
        }
    }
    let mut sums: Vec<(usize, f64, bool)> = corners
        .into_iter()
        .map(|(v, (sum, inside))| (v, sum.to_degrees(), inside))
        .collect();
    sums.sort_unstable_by_key(|(v, _, _)| *v);
    let slack = 360.0 * MISFIT;
    match sums
        .into_iter()
        .find(|&(_, sum, inside)| sum > 360.0 + slack || (inside && sum < 360.0 - slack))
    {
        Some((v, sum, inside)) => Err(PatternError::new(
            format!("vertices_coords[{v}]"),
            format!(
                "the faces around it hold {sum:.1} degrees of paper, {}: the folded form \
                 does not lie flat there, so it cannot be unfolded",
                if inside { "not 360" } else { "more than 360" }
            ),
        )),
        None => Ok(()),
    }
}

/// Lays every face in the plane, breadth first from face 0: each on the far
/// side of the edge it shares with the face that reached it. A vertex laid
/// in two places further apart than `tolerance`, or a face that no path of
/// crossable edges reaches, is an error.
fn lay_out(
    faces: &[Vec<usize>],
    frames: &[FaceFrame],
    neighbours: &HashMap<[usize; 2], [usize; 2]>,
    tolerance: f64,
) -> Result<Vec<Placement>, PatternError> {
    let mut across: Vec<Vec<([usize; 2], usize)>> = vec![Vec::new(); faces.len()];
    for (&key, &[f, g]) in neighbours {
        across[f].push((key, g));
        across[g].push((key, f));
    }
    // Visit neighbours in the file's order, so the layout does not depend
    // on the hash map's.
    for list in &mut across {
        list.sort_unstable();
    }
    let mut placements: Vec<Option<Placement>> = vec![None; faces.len()];
    let mut laid: HashMap<usize, DVec2> = HashMap::new();
    let mut queue = VecDeque::new();
    if !faces.is_empty() {
        placements[0] = Some(Placement {
            map: DMat2::IDENTITY,
            offset: DVec2::ZERO,
        });
        queue.push_back(0);
    }
    while let Some(f) = queue.pop_front() {
        let here = placements[f].expect("queued faces are placed");
        for (k, &v) in faces[f].iter().enumerate() {
            let p = here.place(frames[f].local[k]);
            if let Some(q) = laid.insert(v, p) {
                if q.distance(p) > tolerance {
                    return Err(at_face(
                        f,
                        format!(
                            "vertex {v} unfolds to two places {} apart (more than {} % of \
                             the folded form's size): its faces close on themselves around a \
                             hole or a tube, which paper with no cut cannot unroll, or layers \
                             of the folded form share it",
                            q.distance(p),
                            MISFIT * 100.0
                        ),
                    ));
                }
            }
        }
        for &(key, g) in &across[f] {
            if placements[g].is_none() {
                let local = |v: usize| {
                    let k = faces[g].iter().position(|&u| u == v);
                    frames[g].local[k.expect("the edge's vertices are the face's")]
                };
                placements[g] = Some(beyond(here, local, key, &laid));
                queue.push_back(g);
            }
        }
    }
    placements
        .into_iter()
        .enumerate()
        .map(|(f, p)| {
            p.ok_or_else(|| {
                at_face(
                    f,
                    "no edge between two faces joins it to faces_vertices[0]: the folded \
                     form is in pieces",
                )
            })
        })
        .collect()
}

/// The placement of a face whose vertices lie at `local` in its own frame
/// and which shares edge `key` with the face laid at `from`: the isometry
/// that lays the edge where it is and the face on the far side of it.
fn beyond(
    from: Placement,
    local: impl Fn(usize) -> DVec2,
    key: [usize; 2],
    laid: &HashMap<usize, DVec2>,
) -> Placement {
    let (la, lb) = (local(key[0]), local(key[1]));
    let (pa, pb) = (laid[&key[0]], laid[&key[1]]);
    let u = (lb - la).normalize_or_zero();
    let w = (pb - pa).normalize_or_zero();
    let (cos, sin) = (u.dot(w), u.perp_dot(w));
    // The rotation that turns u onto w, and the reflection across u.
    let rotation = DMat2::from_cols(DVec2::new(cos, sin), DVec2::new(-sin, cos));
    let mirror = DMat2::from_cols(
        DVec2::new(2.0 * u.x * u.x - 1.0, 2.0 * u.x * u.y),
        DVec2::new(2.0 * u.x * u.y, 2.0 * u.y * u.y - 1.0),
    );
    let candidate = |map: DMat2| Placement {
        map,
        offset: pa - map * la,
    };
    // Faces' centroids are their frames' origins.
    let side = |p: Placement| (pb - pa).perp_dot(p.place(DVec2::ZERO) - pa);
    let turned = candidate(rotation);
    if side(turned) * side(from) < 0.0 {
        turned
    } else {
        candidate(rotation * mirror)
    }
}

/// The fold of two neighbouring faces `[f, g]` folded flat, from `orders`:
/// a valley where `f` lies on the side of `g` that `g`'s front faces
/// (`front_side(h)`: 1 where face `h`'s normal is the sheet's front, -1
/// where its back), or `g` on `f`'s; folded flat, direction unknown, where
/// `orders` do not stack them.
fn flat_fold_by_order(
    [f, g]: [usize; 2],
    orders: &FaceOrders,
    front_side: impl Fn(usize) -> f64,
) -> Dihedral {
    let on_front = orders
        .get(&[f, g])
        .map(|&side| side * front_side(g))
        .or_else(|| orders.get(&[g, f]).map(|&side| side * front_side(f)));
    match on_front {
        Some(side) if side > 0.0 => Dihedral::Folded(180.0),
        Some(side) if side < 0.0 => Dihedral::Folded(-180.0),
        _ => Dihedral::FlatFolded,
    }
}

/// The fold angle from face `f` (front normal `nf`) to face `g` (front
/// normal `ng`, centroid at `toward_g` from a point of their edge): valley
/// where `g` turned toward `f`'s front.
fn dihedral(nf: DVec3, ng: DVec3, toward_g: DVec3) -> Dihedral {
    let angle = nf.dot(ng).clamp(-1.0, 1.0).acos().to_degrees();
    if angle < FLAT_ANGLE {
        Dihedral::Flat
    } else if angle > FLAT_FOLD_ANGLE {
        Dihedral::FlatFolded
    } else if toward_g.dot(nf) > 0.0 {
        Dihedral::Folded(angle)
    } else {
        Dihedral::Folded(-angle)
    }
}
