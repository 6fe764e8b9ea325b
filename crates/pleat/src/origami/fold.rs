//! FOLD importer and writer (<https://github.com/edemaine/fold>, file_spec
//! 1 to 1.2).
//!
//! Read: `vertices_coords` (2D, or 3D in one plane: z = 0, or any other
//! plane, as Origami Simulator saves its unfolded sheets in the x-z plane,
//! which is turned into the x-y plane keeping its sides; a folded state,
//! 3D or a flat `foldedForm`, is unfolded through its `faces_vertices` into
//! the crease pattern it folds from, each crease's target its fold angle
//! there: [`super::unfold`]), `edges_vertices`,
//! `edges_assignment` (B, M, V, F, U, C, and J, a join, read as an
//! auxiliary line that splits a face but never folds; absent means all U) and
//! `edges_foldAngle` (degrees; the sign is taken from the assignment for M
//! and V, `null` means none). When `edges_vertices` is absent the edges are
//! taken from `faces_vertices` (an edge used by one face is a boundary, the
//! others unassigned). A folded state's `faceOrders` give the direction of
//! its creases folded flat, which the faces' normals cannot. Every other key
//! is ignored. Errors name the JSON path.

use std::collections::{HashMap, HashSet};

use glam::{DVec2, DVec3};
use serde_json::{Map, Value};

use super::pattern::{Assignment, CreasePattern, PatternEdge, PatternError};
use super::unfold::{edge_key, face_edges, unfold, Dihedral, FaceOrders};

/// Largest distance of a vertex from the plane of the pattern, relative to
/// the pattern size (coordinates written from single precision are good
/// to about 1e-7).
const FLAT_TOLERANCE: f64 = 1e-6;

/// Parses the text of a FOLD file.
pub fn parse_fold(text: &str) -> Result<CreasePattern, PatternError> {
    parse_fold_with_warnings(text).map(|(pattern, _)| pattern)
}

/// Parses the text of a FOLD file, with warnings about what it reads but
/// cannot fold as the file means: creases a folded state folds flat with
/// neither a mountain or valley label nor `faceOrders` to say which way.
pub fn parse_fold_with_warnings(text: &str) -> Result<(CreasePattern, Vec<String>), PatternError> {
    let root: Value = serde_json::from_str(text).map_err(json_syntax_error)?;
    let Value::Object(root) = root else {
        return Err(PatternError::new(
            "top level",
            format!("expected a JSON object, found {}", kind(&root)),
        ));
    };
    let points = vertices_coords(&root)?;
    let flat = flatten(&points);
    let edges_vertices = root.get("edges_vertices");
    let labelled_folded = is_folded_form(&root);
    // Faces are read where they give the edges or unfold a folded state.
    let faces = if edges_vertices.is_none() || flat.is_err() || labelled_folded {
        faces_vertices(&root, points.len())?
    } else {
        None
    };
    let edges = match edges_vertices {
        Some(value) => edges_from_edges_vertices(&root, value, points.len())?,
        None => edges_from_faces(faces.as_deref())?,
    };
    // The layer order is checked wherever there are faces to order.
    let orders = match &faces {
        Some(faces) => face_orders(&root, faces.len())?,
        None => FaceOrders::new(),
    };
    match (flat, faces) {
        // A crease pattern labelled as a folded form (some editors write
        // one so) reads as it is; a flat-folded state is unfolded.
        (Ok(vertices), Some(faces)) if labelled_folded => {
            match folded_form(&points, &faces, edges.clone(), &orders) {
                Ok(form) if form.folded => Ok(form.with_warnings()),
                _ => Ok((CreasePattern { vertices, edges }, Vec::new())),
            }
        }
        (Ok(vertices), _) => Ok((CreasePattern { vertices, edges }, Vec::new())),
        (Err(_), Some(faces)) => {
            folded_form(&points, &faces, edges, &orders).map(FoldedForm::with_warnings)
        }
        (Err(off_plane), None) => Err(off_plane),
    }
}

/// A folded state unfolded ([`folded_form`]).
struct FoldedForm {
    pattern: CreasePattern,
    /// Whether any edge is folded.
    folded: bool,
    /// The edges folded flat whose direction neither a label nor the
    /// layer order gives: left unassigned, not driven.
    undirected: Vec<[usize; 2]>,
}

impl FoldedForm {
    /// The pattern, and a warning naming the undirected creases if any.
    fn with_warnings(self) -> (CreasePattern, Vec<String>) {
        let n = self.undirected.len();
        let warnings = self.undirected.first().map(|[a, b]| {
            let (creases, which) = match n {
                1 => ("1 crease is".to_string(), "one"),
                n => (format!("{n} creases are"), "first"),
            };
            format!(
                "{creases} folded flat with neither a mountain or valley label nor faceOrders \
                 to say which way (the {which} between vertices {a} and {b}): unassigned, not \
                 driven"
            )
        });
        (self.pattern, warnings.into_iter().collect())
    }
}

/// Whether the file calls its frame a folded form.
fn is_folded_form(root: &Map<String, Value>) -> bool {
    root.get("frame_classes")
        .and_then(Value::as_array)
        .is_some_and(|classes| classes.iter().any(|c| c == "foldedForm"))
}

/// The crease pattern a folded state unfolds from, each crease's target
/// its fold angle in the folded state (where the file gives none; a flat
/// fold's direction from the file's `faceOrders`).
fn folded_form(
    points: &[DVec3],
    faces: &[Vec<usize>],
    mut edges: Vec<PatternEdge>,
    orders: &FaceOrders,
) -> Result<FoldedForm, PatternError> {
    let walls: HashSet<[usize; 2]> = edges
        .iter()
        .filter(|e| matches!(e.assignment, Assignment::Boundary | Assignment::Cut))
        .map(|e| edge_key(e.v))
        .collect();
    let mut unfolded = unfold(points, faces, |key| !walls.contains(&key), orders)?;
    if seen_from_the_back(&edges, &unfolded.dihedrals) {
        unfolded.turn_over();
    }
    for edge in &mut edges {
        if edge.fold_angle.is_none() {
            if let Some(&d) = unfolded.dihedrals.get(&edge_key(edge.v)) {
                take_fold_angle(edge, d);
            }
        }
    }
    let undirected = edges
        .iter()
        .filter(|e| e.assignment == Assignment::Unassigned)
        .map(|e| edge_key(e.v))
        .filter(|key| unfolded.dihedrals.get(key) == Some(&Dihedral::FlatFolded))
        .collect();
    Ok(FoldedForm {
        folded: !unfolded.is_flat(),
        pattern: CreasePattern {
            vertices: unfolded.vertices,
            edges,
        },
        undirected,
    })
}

/// The file's `faceOrders` (`[f, g, s]`: face `f` lies on the side of face
/// `g` that `g`'s normal points to for `s = 1`, the other for `s = -1`,
/// unknown for 0), the known ones; empty without the key.
fn face_orders(root: &Map<String, Value>, face_count: usize) -> Result<FaceOrders, PatternError> {
    let Some(value) = root.get("faceOrders") else {
        return Ok(FaceOrders::new());
    };
    let mut orders = FaceOrders::new();
    for (i, entry) in expect_array(value, "faceOrders")?.iter().enumerate() {
        let path = format!("faceOrders[{i}]");
        let triple = expect_array(entry, &path)?;
        let [f, g, s] = triple.as_slice() else {
            return Err(PatternError::new(
                path,
                format!("expected [f, g, s], found {} values", triple.len()),
            ));
        };
        let face = |value: &Value, k: usize| face_index(value, &format!("{path}[{k}]"), face_count);
        let (f, g) = (face(f, 0)?, face(g, 1)?);
        let side = match s.as_f64() {
            Some(side) if side == 1.0 || side == -1.0 => side,
            Some(0.0) => continue,
            _ => {
                return Err(PatternError::new(
                    format!("{path}[2]"),
                    format!("expected 1, -1 or 0, found {s}"),
                ))
            }
        };
        if f == g {
            return Err(PatternError::new(
                path,
                format!("face {f} ordered against itself"),
            ));
        }
        orders.insert([f, g], side);
    }
    Ok(orders)
}

fn face_index(value: &Value, path: &str, face_count: usize) -> Result<usize, PatternError> {
    value
        .as_u64()
        .and_then(|index| usize::try_from(index).ok())
        .filter(|&i| i < face_count)
        .ok_or_else(|| {
            PatternError::new(
                path,
                format!("expected a face index below {face_count} (the faces in faces_vertices), found {value}"),
            )
        })
}

/// Whether most mountains and valleys fold the other way in the folded
/// state: the file's front is the side the unfolding took for the back.
fn seen_from_the_back(edges: &[PatternEdge], dihedrals: &HashMap<[usize; 2], Dihedral>) -> bool {
    let (mut same, mut opposite) = (0, 0);
    for edge in edges {
        let sign = edge.assignment.fold_sign();
        if let (Some(sign), Some(Dihedral::Folded(angle))) =
            (sign, dihedrals.get(&edge_key(edge.v)))
        {
            if sign * angle > 0.0 {
                same += 1;
            } else {
                opposite += 1;
            }
        }
    }
    opposite > same
}

/// A crease's target from its fold angle in a folded state: mountains and
/// valleys keep their direction and take the angle; unassigned edges that
/// are folded become mountains or valleys, those it leaves flat facet lines
/// (`F`, kept flat as the state has them). Flat folds keep the full fold
/// (the folded state cannot tell their direction), flat lines and joins
/// stay flat.
fn take_fold_angle(edge: &mut PatternEdge, dihedral: Dihedral) {
    match (edge.assignment, dihedral) {
        (Assignment::Unassigned, Dihedral::Flat) => edge.assignment = Assignment::Flat,
        (Assignment::Mountain | Assignment::Valley, Dihedral::Folded(angle)) => {
            edge.fold_angle = edge.assignment.fold_sign().map(|s| s * angle.abs());
        }
        (Assignment::Mountain | Assignment::Valley, Dihedral::Flat) => {
            edge.fold_angle = Some(0.0);
        }
        (Assignment::Unassigned, Dihedral::Folded(angle)) => {
            edge.assignment = if angle > 0.0 {
                Assignment::Valley
            } else {
                Assignment::Mountain
            };
            edge.fold_angle = Some(angle);
        }
        _ => {}
    }
}

/// The steps of a multi-frame FOLD file (`file_frames`) for `pattern`, the
/// crease pattern its key frame gives ([`parse_fold`]): per frame after the
/// key frame, in order, each edge's fold angle at the end of that step
/// (degrees, signed as [`PatternEdge::fold_angle`]: mountains and valleys
/// take the sign of their assignment; `null` is the full fold). A frame
/// takes its `edges_foldAngle`, or inherits it (`frame_inherit` true) from
/// its `frame_parent` (0 the key frame, `i` the frame `file_frames[i - 1]`);
/// the frames' other keys are ignored. Empty when the file has no
/// `file_frames`, or when no frame, the key frame included, has an
/// `edges_foldAngle` (its frames are then folded forms or other views of
/// the model, such as Rabbit Ear writes, not steps). Errors name the
/// frame's JSON path.
pub fn parse_fold_frames(
    text: &str,
    pattern: &CreasePattern,
) -> Result<Vec<Vec<Option<f64>>>, PatternError> {
    let root: Value = serde_json::from_str(text).map_err(json_syntax_error)?;
    let Some(root) = root.as_object() else {
        return Err(PatternError::new("top level", "expected a JSON object"));
    };
    let Some(frames) = root.get("file_frames") else {
        return Ok(Vec::new());
    };
    let frames = expect_array(frames, "file_frames")?;
    let mut objects = Vec::with_capacity(frames.len());
    for (i, frame) in frames.iter().enumerate() {
        objects.push(frame.as_object().ok_or_else(|| {
            PatternError::new(
                format!("file_frames[{i}]"),
                format!("expected an object, found {}", kind(frame)),
            )
        })?);
    }
    // Frames without a fold angle anywhere are other views of the model
    // (folded forms, layer orders, diagrams), not steps.
    let has_angles = |f: &Map<String, Value>| f.contains_key("edges_foldAngle");
    if !has_angles(root) && !objects.iter().any(|f| has_angles(f)) {
        return Ok(Vec::new());
    }
    (0..objects.len())
        .map(|i| {
            let (path, value, frame) = frame_fold_angles(root, &objects, i)?;
            let own = frame_assignments(frame, &path, pattern.edges.len())?;
            step_angles(value, &path, pattern, own.as_deref())
        })
        .collect()
}

/// The `edges_assignment` of the frame whose `edges_foldAngle` a step takes
/// (`angles_path` is that array's path), where that frame has its own: a
/// step may fold a crease the other way from the key frame (a petal fold
/// or a reverse fold turns creases over), and says so there.
fn frame_assignments(
    frame: &Map<String, Value>,
    angles_path: &str,
    edge_count: usize,
) -> Result<Option<Vec<Assignment>>, PatternError> {
    if angles_path == "edges_foldAngle" {
        // The key frame's own assignments are the pattern's.
        return Ok(None);
    }
    let prefix = angles_path.trim_end_matches("edges_foldAngle");
    let Some(list) = per_edge(frame, "edges_assignment", edge_count)
        .map_err(|e| PatternError::new(format!("{prefix}{}", e.location), e.reason))?
    else {
        return Ok(None);
    };
    list.iter()
        .enumerate()
        .map(|(e, value)| assignment(value, &format!("{prefix}edges_assignment[{e}]")))
        .collect::<Result<_, _>>()
        .map(Some)
}

/// The `edges_foldAngle` frame `file_frames[i]` has or inherits, and its
/// JSON path.
fn frame_fold_angles<'a>(
    root: &'a Map<String, Value>,
    frames: &[&'a Map<String, Value>],
    i: usize,
) -> Result<(String, &'a Value, &'a Map<String, Value>), PatternError> {
    let mut id = i + 1;
    // Each step up goes to another frame; more steps than frames is a cycle.
    for _ in 0..=frames.len() {
        let (frame, path) = if id == 0 {
            (root, String::new())
        } else {
            (frames[id - 1], format!("file_frames[{}].", id - 1))
        };
        if let Some(value) = frame.get("edges_foldAngle") {
            return Ok((format!("{path}edges_foldAngle"), value, frame));
        }
        let here = match id {
            0 => "the key frame".to_string(),
            _ => format!("file_frames[{}]", id - 1),
        };
        if id == 0 || frame.get("frame_inherit") != Some(&Value::Bool(true)) {
            return Err(PatternError::new(
                format!("file_frames[{i}]"),
                if id == i + 1 {
                    "a step needs edges_foldAngle, or frame_inherit from a frame that has it"
                        .to_string()
                } else {
                    format!("inherits no edges_foldAngle: {here} has none and inherits none")
                },
            ));
        }
        let parent = match frame.get("frame_parent") {
            None => 0,
            Some(value) => value
                .as_u64()
                .filter(|&p| (p as usize) <= frames.len())
                .ok_or_else(|| {
                    PatternError::new(
                        format!("{here}.frame_parent"),
                        format!(
                            "expected a frame index from 0 (the key frame) to {}, found {value}",
                            frames.len()
                        ),
                    )
                })? as usize,
        };
        id = parent;
    }
    Err(PatternError::new(
        format!("file_frames[{i}].frame_parent"),
        "the frames inherit from one another in a cycle",
    ))
}

/// One step's edge angles from an `edges_foldAngle` at `path`.
fn step_angles(
    value: &Value,
    path: &str,
    pattern: &CreasePattern,
    assignments: Option<&[Assignment]>,
) -> Result<Vec<Option<f64>>, PatternError> {
    let list = expect_array(value, path)?;
    if list.len() != pattern.edges.len() {
        return Err(PatternError::new(
            path,
            format!(
                "has {} entries, but edges_vertices has {}",
                list.len(),
                pattern.edges.len()
            ),
        ));
    }
    list.iter()
        .zip(&pattern.edges)
        .enumerate()
        .map(|(e, (value, edge))| {
            let path = format!("{path}[{e}]");
            let assignment = assignments.map_or(edge.assignment, |a| a[e]);
            let angle = fold_angle(value, &path, assignment)?;
            if angle.is_some_and(|a| !(-180.0..=180.0).contains(&a)) {
                return Err(PatternError::new(
                    path,
                    "must be between -180 and 180 degrees",
                ));
            }
            Ok(angle)
        })
        .collect()
}

fn json_syntax_error(e: serde_json::Error) -> PatternError {
    let message = e.to_string();
    let suffix = format!(" at line {} column {}", e.line(), e.column());
    let reason = message.strip_suffix(&suffix).unwrap_or(&message);
    PatternError::new(
        format!("line {}, column {}", e.line(), e.column()),
        format!("bad JSON: {reason}"),
    )
}

fn kind(value: &Value) -> &'static str {
    match value {
        Value::Null => "null",
        Value::Bool(_) => "a boolean",
        Value::Number(_) => "a number",
        Value::String(_) => "a string",
        Value::Array(_) => "an array",
        Value::Object(_) => "an object",
    }
}

fn expect_array<'a>(value: &'a Value, path: &str) -> Result<&'a Vec<Value>, PatternError> {
    value
        .as_array()
        .ok_or_else(|| PatternError::new(path, format!("expected an array, found {}", kind(value))))
}

fn required<'a>(root: &'a Map<String, Value>, key: &str) -> Result<&'a Value, PatternError> {
    root.get(key)
        .ok_or_else(|| PatternError::new(key, "missing"))
}

fn vertices_coords(root: &Map<String, Value>) -> Result<Vec<DVec3>, PatternError> {
    let list = expect_array(required(root, "vertices_coords")?, "vertices_coords")?;
    let mut points = Vec::with_capacity(list.len());
    for (i, entry) in list.iter().enumerate() {
        let path = format!("vertices_coords[{i}]");
        let coords = expect_array(entry, &path)?;
        if !(2..=3).contains(&coords.len()) {
            return Err(PatternError::new(
                path,
                format!(
                    "expected [x, y] or [x, y, z], found {} numbers",
                    coords.len()
                ),
            ));
        }
        let x = number(&coords[0], &format!("{path}[0]"))?;
        let y = number(&coords[1], &format!("{path}[1]"))?;
        let z = match coords.get(2) {
            Some(z) => number(z, &format!("{path}[2]"))?,
            None => 0.0,
        };
        points.push(DVec3::new(x, y, z));
    }
    Ok(points)
}

/// The vertices as 2D points: `(x, y)` when every z is 0 up to round-off,
/// else their coordinates in the plane they all lie in (axes chosen so that
/// the plane's normal, its largest component made positive, plays the part
/// of +z); a folded state, whose vertices lie in no one plane, is refused
/// with the vertex furthest from the plane.
fn flatten(points: &[DVec3]) -> Result<Vec<DVec2>, PatternError> {
    let min = points.iter().copied().fold(DVec3::INFINITY, DVec3::min);
    let max = points.iter().copied().fold(DVec3::NEG_INFINITY, DVec3::max);
    let tolerance = FLAT_TOLERANCE * (max - min).length();
    if points.iter().all(|p| p.z.abs() <= tolerance) {
        return Ok(points.iter().map(|p| p.truncate()).collect());
    }
    let Some(&origin) = points.first() else {
        return Ok(Vec::new());
    };
    let far = |from: &dyn Fn(DVec3) -> f64| {
        points
            .iter()
            .copied()
            .max_by(|a, b| from(*a).total_cmp(&from(*b)))
            .unwrap_or(origin)
    };
    let a = far(&|p| p.distance_squared(origin)) - origin;
    let b = far(&|p| a.cross(p - origin).length_squared()) - origin;
    let mut normal = a.cross(b).normalize_or_zero();
    // Collinear points lie in every plane: any normal will do.
    if normal == DVec3::ZERO {
        normal = a.any_orthonormal_vector();
    }
    let axis = normal.abs().max_position();
    if normal[axis] < 0.0 {
        normal = -normal;
    }
    let (worst, distance) = points
        .iter()
        .map(|p| (p - origin).dot(normal).abs())
        .enumerate()
        .max_by(|x, y| x.1.total_cmp(&y.1))
        .unwrap_or((0, 0.0));
    if distance > tolerance {
        return Err(PatternError::new(
            format!("vertices_coords[{worst}]"),
            format!(
                "{distance} off the plane of the others: a folded state (3D vertices_coords) \
                 with no faces_vertices to unfold it by"
            ),
        ));
    }
    let next = DVec3::AXES[(axis + 1) % 3];
    let u = (next - normal * normal.dot(next)).normalize();
    let w = normal.cross(u);
    Ok(points
        .iter()
        .map(|p| DVec2::new((p - origin).dot(u), (p - origin).dot(w)))
        .collect())
}

fn number(value: &Value, path: &str) -> Result<f64, PatternError> {
    value
        .as_f64()
        .filter(|v| v.is_finite())
        .ok_or_else(|| PatternError::new(path, format!("expected a number, found {}", kind(value))))
}

fn vertex_index(value: &Value, path: &str, vertex_count: usize) -> Result<usize, PatternError> {
    let Some(index) = value.as_u64() else {
        return Err(PatternError::new(
            path,
            format!("expected a vertex index (a non-negative integer), found {value}"),
        ));
    };
    usize::try_from(index)
        .ok()
        .filter(|&i| i < vertex_count)
        .ok_or_else(|| {
            PatternError::new(
                path,
                format!("vertex index {index} out of range (there are {vertex_count} vertices)"),
            )
        })
}

fn edges_from_edges_vertices(
    root: &Map<String, Value>,
    value: &Value,
    vertex_count: usize,
) -> Result<Vec<PatternEdge>, PatternError> {
    let list = expect_array(value, "edges_vertices")?;
    let assignments = per_edge(root, "edges_assignment", list.len())?;
    let angles = per_edge(root, "edges_foldAngle", list.len())?;
    let mut edges = Vec::with_capacity(list.len());
    for (i, entry) in list.iter().enumerate() {
        let path = format!("edges_vertices[{i}]");
        let pair = expect_array(entry, &path)?;
        if pair.len() != 2 {
            return Err(PatternError::new(
                path,
                format!("expected 2 vertex indices, found {}", pair.len()),
            ));
        }
        let v = [
            vertex_index(&pair[0], &format!("{path}[0]"), vertex_count)?,
            vertex_index(&pair[1], &format!("{path}[1]"), vertex_count)?,
        ];
        let assignment = match assignments.map(|a| &a[i]) {
            Some(value) => assignment(value, &format!("edges_assignment[{i}]"))?,
            None => Assignment::Unassigned,
        };
        let fold_angle = match angles.map(|a| &a[i]) {
            Some(value) => fold_angle(value, &format!("edges_foldAngle[{i}]"), assignment)?,
            None => None,
        };
        edges.push(PatternEdge {
            v,
            assignment,
            fold_angle,
        });
    }
    Ok(edges)
}

/// An optional per-edge array, which must have one entry per edge.
fn per_edge<'a>(
    root: &'a Map<String, Value>,
    key: &str,
    edge_count: usize,
) -> Result<Option<&'a Vec<Value>>, PatternError> {
    let Some(value) = root.get(key) else {
        return Ok(None);
    };
    let list = expect_array(value, key)?;
    if list.len() != edge_count {
        return Err(PatternError::new(
            key,
            format!(
                "has {} entries, but edges_vertices has {edge_count}",
                list.len()
            ),
        ));
    }
    Ok(Some(list))
}

fn assignment(value: &Value, path: &str) -> Result<Assignment, PatternError> {
    let Some(letter) = value.as_str() else {
        return Err(PatternError::new(
            path,
            format!("expected an assignment letter, found {}", kind(value)),
        ));
    };
    match letter {
        "B" | "b" => Ok(Assignment::Boundary),
        "M" | "m" => Ok(Assignment::Mountain),
        "V" | "v" => Ok(Assignment::Valley),
        "F" | "f" => Ok(Assignment::Flat),
        "U" | "u" => Ok(Assignment::Unassigned),
        "C" | "c" => Ok(Assignment::Cut),
        // FOLD 1.2's join: the faces on both sides are one face.
        "J" | "j" => Ok(Assignment::Auxiliary),
        other => Err(PatternError::new(
            path,
            format!("unknown assignment '{other}' (expected B, M, V, F, U, C or J)"),
        )),
    }
}

fn fold_angle(
    value: &Value,
    path: &str,
    assignment: Assignment,
) -> Result<Option<f64>, PatternError> {
    if value.is_null() {
        return Ok(None);
    }
    let angle = number(value, path)?;
    Ok(Some(match assignment.fold_sign() {
        Some(sign) => sign * angle.abs(),
        None => angle,
    }))
}

/// `faces_vertices`, if the file has it: each face's cycle of vertex
/// indices.
fn faces_vertices(
    root: &Map<String, Value>,
    vertex_count: usize,
) -> Result<Option<Vec<Vec<usize>>>, PatternError> {
    let Some(value) = root.get("faces_vertices") else {
        return Ok(None);
    };
    let faces = expect_array(value, "faces_vertices")?;
    faces
        .iter()
        .enumerate()
        .map(|(f, face)| {
            let path = format!("faces_vertices[{f}]");
            expect_array(face, &path)?
                .iter()
                .enumerate()
                .map(|(k, v)| vertex_index(v, &format!("{path}[{k}]"), vertex_count))
                .collect()
        })
        .collect::<Result<Vec<_>, _>>()
        .map(Some)
}

/// Edges of the face cycles: shared edges unassigned, the others boundary.
fn edges_from_faces(faces: Option<&[Vec<usize>]>) -> Result<Vec<PatternEdge>, PatternError> {
    let Some(faces) = faces else {
        return Err(PatternError::new(
            "edges_vertices",
            "missing (and no faces_vertices to take the edges from)",
        ));
    };
    let mut uses: HashMap<[usize; 2], usize> = HashMap::new();
    let mut order = Vec::new();
    for face in faces {
        for (a, b) in face_edges(face) {
            let key = edge_key([a, b]);
            let count = uses.entry(key).or_insert(0);
            if *count == 0 {
                order.push(key);
            }
            *count += 1;
        }
    }
    Ok(order
        .into_iter()
        .map(|v| PatternEdge {
            v,
            assignment: if uses[&v] == 1 {
                Assignment::Boundary
            } else {
                Assignment::Unassigned
            },
            fold_angle: None,
        })
        .collect())
}

/// Writes a pattern as a FOLD (file_spec 1.1) crease pattern. Auxiliary
/// lines, which FOLD has no letter for, are written as flat (`F`); missing
/// fold angles as `null`.
pub fn to_fold_json(pattern: &CreasePattern) -> String {
    let coords: Vec<Value> = pattern
        .vertices
        .iter()
        .map(|p| serde_json::json!([p.x, p.y]))
        .collect();
    let edges: Vec<Value> = pattern
        .edges
        .iter()
        .map(|e| serde_json::json!(e.v))
        .collect();
    let letters: Vec<&str> = pattern
        .edges
        .iter()
        .map(|e| assignment_letter(e.assignment))
        .collect();
    let angles: Vec<Option<f64>> = pattern.edges.iter().map(|e| e.fold_angle).collect();
    let fold = serde_json::json!({
        "file_spec": 1.1,
        "file_creator": "pleat",
        "file_classes": ["singleModel"],
        "frame_classes": ["creasePattern"],
        "vertices_coords": coords,
        "edges_vertices": edges,
        "edges_assignment": letters,
        "edges_foldAngle": angles,
    });
    // Serialising a `Value` built from finite numbers and strings cannot
    // fail; fall back to an empty object rather than panic.
    serde_json::to_string_pretty(&fold).unwrap_or_else(|_| String::from("{}"))
}

/// The FOLD letter of an assignment (`B`, `M`, `V`, `F`, `U`, `C`).
pub(crate) fn assignment_letter(assignment: Assignment) -> &'static str {
    match assignment {
        Assignment::Boundary => "B",
        Assignment::Mountain => "M",
        Assignment::Valley => "V",
        Assignment::Flat | Assignment::Auxiliary => "F",
        Assignment::Unassigned => "U",
        Assignment::Cut => "C",
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const SQUARE: &str = r#"{
        "file_spec": 1.1, "frame_classes": ["creasePattern"], "cpedit:page": {"xMin": 0},
        "vertices_coords": [[0,0],[1,0],[1,1,0],[0,1]],
        "edges_vertices": [[0,1],[1,2],[2,3],[3,0],[0,2]],
        "edges_assignment": ["B","B","B","B","M"],
        "edges_foldAngle": [0,0,0,0,90]
    }"#;

    #[test]
    fn reads_square_with_signed_angle_and_ignores_unknown_keys() {
        let p = parse_fold(SQUARE).unwrap();
        assert_eq!(p.vertices.len(), 4);
        assert_eq!(p.edges.len(), 5);
        assert_eq!(p.edges[4].assignment, Assignment::Mountain);
        assert_eq!(p.edges[4].fold_angle, Some(-90.0));
        assert_eq!(p.edges[0].fold_angle, Some(0.0));
    }

    #[test]
    fn a_join_is_an_auxiliary_line() {
        let p = parse_fold(&SQUARE.replace(r#""B","M"]"#, r#""B","J"]"#)).unwrap();
        assert_eq!(p.edges[4].assignment, Assignment::Auxiliary);
        assert_eq!(p.edges[4].fold_angle, Some(90.0));
    }

    #[test]
    fn absent_assignment_means_unassigned() {
        let p =
            parse_fold(r#"{"vertices_coords":[[0,0],[1,0]],"edges_vertices":[[0,1]]}"#).unwrap();
        assert_eq!(p.edges[0].assignment, Assignment::Unassigned);
    }

    #[test]
    fn faces_give_edges_when_edges_are_absent() {
        let p = parse_fold(
            r#"{"vertices_coords":[[0,0],[1,0],[1,1],[0,1]],"faces_vertices":[[0,1,2],[0,2,3]]}"#,
        )
        .unwrap();
        assert_eq!(p.edges.len(), 5);
        let shared = p.edges.iter().find(|e| e.v == [0, 2]).unwrap();
        assert_eq!(shared.assignment, Assignment::Unassigned);
        assert_eq!(
            p.edges
                .iter()
                .filter(|e| e.assignment == Assignment::Boundary)
                .count(),
            4
        );
    }

    fn error(text: &str) -> String {
        parse_fold(text).unwrap_err().to_string()
    }

    #[test]
    fn errors_name_json_path_and_reason() {
        assert!(error("{\"vertices_coords\": [").starts_with("line 1, column 21: bad JSON: "));
        assert_eq!(
            error("[1]"),
            "top level: expected a JSON object, found an array"
        );
        assert_eq!(error("{}"), "vertices_coords: missing");
        assert_eq!(
            error(r#"{"vertices_coords":[[0,0],[1,"a"]],"edges_vertices":[]}"#),
            "vertices_coords[1][1]: expected a number, found a string"
        );
        assert_eq!(
            error(r#"{"vertices_coords":[[0,0],[1,0]],"edges_vertices":[[0,1],[1,2]]}"#),
            "edges_vertices[1][1]: vertex index 2 out of range (there are 2 vertices)"
        );
        assert_eq!(
            error(
                r#"{"vertices_coords":[[0,0],[1,0]],"edges_vertices":[[0,1]],"edges_assignment":["X"]}"#
            ),
            "edges_assignment[0]: unknown assignment 'X' (expected B, M, V, F, U, C or J)"
        );
        assert_eq!(
            error(
                r#"{"vertices_coords":[[0,0],[1,0]],"edges_vertices":[[0,1]],"edges_assignment":[]}"#
            ),
            "edges_assignment: has 0 entries, but edges_vertices has 1"
        );
        assert_eq!(
            error(
                r#"{"vertices_coords":[[0,0,0],[1,0,0],[0,1,0],[0,0,0.5]],"edges_vertices":[[0,1]]}"#
            ),
            "vertices_coords[3]: 0.5 off the plane of the others: a folded state \
             (3D vertices_coords) with no faces_vertices to unfold it by"
        );
        assert_eq!(
            error(r#"{"vertices_coords":{},"edges_vertices":[]}"#),
            "vertices_coords: expected an array, found an object"
        );
    }

    /// A unit square folded along its diagonal from vertex 1 to vertex 3 by
    /// `degrees` toward the front of face [0, 1, 3] (+z, counter-clockwise
    /// from there), as a FOLD folded form with `extra` keys.
    fn folded_square(degrees: f64, extra: &str) -> String {
        let (s, c) = degrees.to_radians().sin_cos();
        let h = std::f64::consts::FRAC_1_SQRT_2;
        let lifted = [0.5 + 0.5 * c, 0.5 + 0.5 * c, h * s];
        format!(
            r#"{{"frame_classes":["foldedForm"],
            "vertices_coords":[[0,0,0],[1,0,0],{lifted:?},[0,1,0]],
            "faces_vertices":[[0,1,3],[1,2,3]]{extra}}}"#
        )
    }

    fn crease(p: &CreasePattern) -> &PatternEdge {
        p.edges
            .iter()
            .find(|e| edge_key(e.v) == [1, 3])
            .expect("the diagonal")
    }

    #[test]
    fn a_folded_state_unfolds_into_its_crease_pattern_and_angles() {
        // Folded toward the front of the first face: a valley of its angle.
        let p = parse_fold(&folded_square(90.0, "")).unwrap();
        for (v, at) in [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]
            .into_iter()
            .enumerate()
        {
            let d = p.vertices[v] - p.vertices[0];
            assert!(
                (d.length() - DVec2::from(at).length()).abs() < 1e-9,
                "{v}: {d}"
            );
        }
        assert!((p.vertices[2].distance(p.vertices[0]) - 2f64.sqrt()).abs() < 1e-9);
        assert_eq!(crease(&p).assignment, Assignment::Valley);
        assert!((crease(&p).fold_angle.unwrap() - 90.0).abs() < 1e-9);
        // Toward the back: a mountain.
        let p = parse_fold(&folded_square(-60.0, "")).unwrap();
        assert_eq!(crease(&p).assignment, Assignment::Mountain);
        assert!((crease(&p).fold_angle.unwrap() + 60.0).abs() < 1e-9);
        // Labelled a mountain, the sheet is seen from the other side.
        let labels = r#","edges_vertices":[[0,1],[1,2],[2,3],[3,0],[1,3]],
            "edges_assignment":["B","B","B","B","M"]"#;
        let p = parse_fold(&folded_square(90.0, labels)).unwrap();
        assert_eq!(crease(&p).assignment, Assignment::Mountain);
        assert!((crease(&p).fold_angle.unwrap() + 90.0).abs() < 1e-9);
        // The file's own angle wins; folded flat, the label says which way.
        let angles = format!(r#"{labels},"edges_foldAngle":[0,0,0,0,45]"#);
        assert_eq!(
            crease(&parse_fold(&folded_square(90.0, &angles)).unwrap()).fold_angle,
            Some(-45.0)
        );
        let flat = parse_fold(&folded_square(180.0, labels)).unwrap();
        assert_eq!(crease(&flat).fold_angle, None);
        assert_eq!(crease(&flat).assignment, Assignment::Mountain);
    }

    #[test]
    fn face_orders_give_the_direction_of_a_flat_fold() {
        let with_orders = |orders: &str| {
            let p = parse_fold(&folded_square(180.0, &format!(r#","faceOrders":{orders}"#)));
            crease(&p.unwrap()).clone()
        };
        // Folded flat onto the front of face 0: face 1 lies above face 0
        // (along face 0's normal, +z), and face 0 along face 1's normal
        // (-z once folded): a valley, whichever pair the file lists.
        for orders in ["[[1,0,1]]", "[[0,1,1]]", "[[0,1,0],[1,0,1]]"] {
            let edge = with_orders(orders);
            assert_eq!(edge.assignment, Assignment::Valley, "{orders}");
            assert_eq!(edge.fold_angle, Some(180.0), "{orders}");
        }
        // Folded onto the back: a mountain.
        for orders in ["[[1,0,-1]]", "[[0,1,-1]]"] {
            let edge = with_orders(orders);
            assert_eq!(edge.assignment, Assignment::Mountain, "{orders}");
            assert_eq!(edge.fold_angle, Some(-180.0), "{orders}");
        }
        // Unknown order (0), or none: folded flat, direction unknown.
        for orders in ["[[1,0,0]]", "[]"] {
            let edge = with_orders(orders);
            assert_eq!(edge.assignment, Assignment::Unassigned, "{orders}");
            assert_eq!(edge.fold_angle, None, "{orders}");
        }
        // Undirected, it is said: a flat fold that silently stayed flat
        // would be a wrong simulation.
        let (_, warnings) = parse_fold_with_warnings(&folded_square(180.0, "")).unwrap();
        assert_eq!(
            warnings,
            [
                "1 crease is folded flat with neither a mountain or valley label nor faceOrders \
              to say which way (the one between vertices 1 and 3): unassigned, not driven"
            ]
        );
        let directed = folded_square(180.0, r#","faceOrders":[[1,0,1]]"#);
        assert_eq!(
            parse_fold_with_warnings(&directed).unwrap().1,
            Vec::<String>::new()
        );
        // A label wins over the order.
        let labelled = r#","edges_vertices":[[0,1],[1,2],[2,3],[3,0],[1,3]],
            "edges_assignment":["B","B","B","B","M"],"faceOrders":[[1,0,1]]"#;
        let p = parse_fold(&folded_square(180.0, labelled)).unwrap();
        assert_eq!(crease(&p).assignment, Assignment::Mountain);
    }

    #[test]
    fn bad_face_orders_are_errors_that_name_the_entry() {
        let error_with =
            |orders: &str| error(&folded_square(180.0, &format!(r#","faceOrders":{orders}"#)));
        assert_eq!(
            error_with("{}"),
            "faceOrders: expected an array, found an object"
        );
        assert_eq!(
            error_with("[[1,0,1],[0,1]]"),
            "faceOrders[1]: expected [f, g, s], found 2 values"
        );
        assert_eq!(
            error_with("[[0,5,1]]"),
            "faceOrders[0][1]: expected a face index below 2 (the faces in faces_vertices), found 5"
        );
        assert_eq!(
            error_with("[[-1,0,1]]"),
            "faceOrders[0][0]: expected a face index below 2 (the faces in faces_vertices), found -1"
        );
        assert_eq!(
            error_with("[[0,1,2]]"),
            "faceOrders[0][2]: expected 1, -1 or 0, found 2"
        );
        assert_eq!(
            error_with(r#"[[0,1,"up"]]"#),
            r#"faceOrders[0][2]: expected 1, -1 or 0, found "up""#
        );
        assert_eq!(
            error_with("[[1,1,1]]"),
            "faceOrders[0]: face 1 ordered against itself"
        );
    }

    #[test]
    fn a_crease_pattern_labelled_a_folded_form_reads_as_it_is() {
        let p = parse_fold(&folded_square(0.0, "")).unwrap();
        assert_eq!(p.vertices[2], DVec2::new(1.0, 1.0));
        assert_eq!(crease(&p).fold_angle, None);
        assert_eq!(crease(&p).assignment, Assignment::Unassigned);
    }

    #[test]
    fn folded_states_that_do_not_unfold_are_errors() {
        // A pyramid's four sides: 282 degrees of paper around its apex.
        let pyramid = r#"{"vertices_coords":[[0,0,1],[1,1,0],[-1,1,0],[-1,-1,0],[1,-1,0]],
            "faces_vertices":[[0,1,2],[0,2,3],[0,3,4],[0,4,1]]}"#;
        assert_eq!(
            error(pyramid),
            "vertices_coords[0]: the faces around it hold 282.1 degrees of paper, not 360: \
             the folded form does not lie flat there, so it cannot be unfolded"
        );
        // Five quarter turns of a spiral ramp about its centre: 390 degrees
        // of paper there (its corners a little under 90 degrees, lifted).
        let ramp: Vec<String> = (0..6)
            .map(|k| {
                let (s, c) = (k as f64 * std::f64::consts::FRAC_PI_2).sin_cos();
                format!("[{c},{s},{}]", 0.2 * k as f64)
            })
            .collect();
        let spiral = format!(
            r#"{{"vertices_coords":[[0,0,0],{}],
            "faces_vertices":[[0,1,2],[0,2,3],[0,3,4],[0,4,5],[0,5,6]]}}"#,
            ramp.join(",")
        );
        assert!(
            error(&spiral).starts_with(
                "vertices_coords[0]: the faces around it hold 389.8 degrees of paper, more than 360"
            ),
            "{}",
            error(&spiral)
        );
        let bent = r#"{"vertices_coords":[[0,0,0],[1,0,0],[1,1,0.5],[0,1,0]],
            "faces_vertices":[[0,1,2,3]]}"#;
        assert!(error(bent).starts_with("faces_vertices[0]: not flat: vertex "));
        let fan = r#"{"vertices_coords":[[0,0,0],[1,0,0],[0,1,0],[0,0,1],[0,-1,1]],
            "faces_vertices":[[0,1,2],[0,1,3],[0,1,4]]}"#;
        assert_eq!(
            error(fan),
            "faces_vertices[2]: its edge from vertex 0 to 1 is on three faces or more"
        );
        let apart = r#"{"vertices_coords":[[0,0,0],[1,0,0],[0,1,0],[0,0,1],[1,0,1],[0,1,2]],
            "faces_vertices":[[0,1,2],[3,4,5]]}"#;
        assert!(error(apart).starts_with("faces_vertices[1]: no edge between two faces"));
        let stray = r#"{"vertices_coords":[[0,0,0],[1,0,0],[0,1,0],[5,5,5]],
            "faces_vertices":[[0,1,2]]}"#;
        assert!(error(stray).starts_with("vertices_coords[3]: lies on no face"));
        let needle = r#"{"vertices_coords":[[0,0,0],[1,0,0],[2,0,0],[0,1,0],[0,0,1]],
            "faces_vertices":[[0,1,2],[0,3,4]]}"#;
        assert!(error(needle).starts_with("faces_vertices[0]: a face of no area"));
    }

    #[test]
    fn a_sheet_in_another_plane_is_turned_into_the_xy_plane() {
        // Origami Simulator saves its sheets in the x-z plane (y up).
        let text = r#"{"vertices_coords":[[0,0,0],[2,0,0],[2,0,-1],[0,-0.0,-1]],
            "edges_vertices":[[0,1],[1,2],[2,3],[3,0],[0,2]],
            "edges_assignment":["B","B","B","B","V"]}"#;
        let p = parse_fold(text).unwrap();
        let lengths: Vec<f64> = p
            .edges
            .iter()
            .map(|e| p.vertices[e.v[0]].distance(p.vertices[e.v[1]]))
            .collect();
        for (l, expected) in lengths.iter().zip([2.0, 1.0, 2.0, 1.0, 5f64.sqrt()]) {
            assert!((l - expected).abs() < 1e-12, "{lengths:?}");
        }
        // Seen from +y, as from +z in the x-y plane: the sides are kept.
        let [o, a, b] = [0, 1, 2].map(|i| p.vertices[i]);
        assert!((a - o).perp_dot(b - o) > 0.0, "{:?}", p.vertices);
        // A tilted plane, too.
        let tilted =
            r#"{"vertices_coords":[[0,0,0],[1,1,1],[1,-1,0]],"edges_vertices":[[0,1],[1,2]]}"#;
        assert_eq!(parse_fold(tilted).unwrap().vertices.len(), 3);
    }

    #[test]
    fn writer_round_trips() {
        let p = parse_fold(SQUARE).unwrap();
        let again = parse_fold(&to_fold_json(&p)).unwrap();
        assert_eq!(p, again);
    }
}
