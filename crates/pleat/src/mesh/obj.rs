//! Wavefront OBJ input (through `tobj`): every model of the file merged into one mesh.

use super::Mesh;
use glam::Vec3;
use std::path::Path;

/// Why an OBJ file could not become a mesh: the file, as the caller named
/// it, and what is wrong with it.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{file}: {reason}")]
pub struct ObjError {
    /// The file, as named by the caller.
    pub file: String,
    /// What is wrong with it.
    pub reason: ObjReason,
}

/// What is wrong with an OBJ file. Vertex and face numbers index the mesh
/// (from 0); messages count them from 1, as OBJ does.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum ObjReason {
    /// The file could not be opened.
    #[error("cannot open the file")]
    Open,
    /// The file could not be read through.
    #[error("cannot read the file")]
    Read,
    /// A `v` line does not hold three numbers.
    #[error("a vertex position (v) is not three numbers")]
    Position,
    /// An `f` line is malformed.
    #[error("a face (f) is malformed")]
    Face,
    /// A face names a vertex index past the file's vertices (found while
    /// reading, before faces are numbered).
    #[error("a face refers to a vertex that does not exist")]
    FaceVertexOutOfBounds,
    /// Any other fault the OBJ reader found, in its words.
    #[error("malformed OBJ ({detail})")]
    Malformed {
        /// The OBJ reader's description.
        detail: String,
    },
    /// The file has no faces (points and lines are left out).
    #[error("no faces: a cloth or collider mesh needs at least one triangle")]
    NoFaces,
    /// A vertex has an infinite or NaN coordinate.
    #[error("vertex {} has a non-finite coordinate", .vertex + 1)]
    NonFiniteVertex {
        /// Index into [`Mesh::positions`].
        vertex: usize,
    },
    /// A triangle names a vertex the mesh lacks.
    #[error("face {} refers to a vertex that does not exist", .face + 1)]
    MissingVertex {
        /// Index into [`Mesh::triangles`].
        face: usize,
    },
}

/// Polygons triangulated, one index per vertex, points and lines left out.
const OPTIONS: tobj::LoadOptions = tobj::LoadOptions {
    triangulate: true,
    single_index: true,
    ignore_points: true,
    ignore_lines: true,
};

/// Reads `path`, triangulating polygons and merging all of its models.
pub fn load_obj(path: &Path) -> Result<Mesh, ObjError> {
    let error = |reason: ObjReason| ObjError {
        file: path.display().to_string(),
        reason,
    };
    let (models, _) = tobj::load_obj(path, &OPTIONS).map_err(|e| error(describe(e)))?;
    let mesh = merge(&models);
    validate(&mesh).map_err(error)?;
    Ok(mesh)
}

/// Reads OBJ text held in memory (a dropped file, a file in a web page);
/// `file` names it in errors. Material libraries are not read.
pub fn parse_obj(text: &str, file: &str) -> Result<Mesh, ObjError> {
    let error = |reason: ObjReason| ObjError {
        file: file.to_string(),
        reason,
    };
    let mut reader = std::io::Cursor::new(text.as_bytes());
    let (models, _) = tobj::load_obj_buf(&mut reader, &OPTIONS, |_| {
        Err(tobj::LoadError::OpenFileFailed)
    })
    .map_err(|e| error(describe(e)))?;
    let mesh = merge(&models);
    validate(&mesh).map_err(error)?;
    Ok(mesh)
}

fn describe(e: tobj::LoadError) -> ObjReason {
    match e {
        tobj::LoadError::OpenFileFailed => ObjReason::Open,
        tobj::LoadError::ReadError => ObjReason::Read,
        tobj::LoadError::PositionParseError => ObjReason::Position,
        tobj::LoadError::FaceParseError => ObjReason::Face,
        tobj::LoadError::FaceVertexOutOfBounds => ObjReason::FaceVertexOutOfBounds,
        other => ObjReason::Malformed {
            detail: other.to_string(),
        },
    }
}

fn merge(models: &[tobj::Model]) -> Mesh {
    let mut mesh = Mesh::default();
    for model in models {
        let base = mesh.positions.len() as u32;
        let m = &model.mesh;
        mesh.positions.extend(
            m.positions
                .chunks_exact(3)
                .map(|p| Vec3::new(p[0], p[1], p[2])),
        );
        mesh.triangles.extend(
            m.indices
                .chunks_exact(3)
                .map(|t| [t[0] + base, t[1] + base, t[2] + base]),
        );
    }
    mesh
}

fn validate(mesh: &Mesh) -> Result<(), ObjReason> {
    if mesh.triangles.is_empty() {
        return Err(ObjReason::NoFaces);
    }
    if let Some(vertex) = mesh.positions.iter().position(|p| !p.is_finite()) {
        return Err(ObjReason::NonFiniteVertex { vertex });
    }
    let n = mesh.positions.len() as u32;
    if let Some(face) = mesh
        .triangles
        .iter()
        .position(|t| t.iter().any(|&i| i >= n))
    {
        return Err(ObjReason::MissingVertex { face });
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn write(name: &str, text: &str) -> std::path::PathBuf {
        let path = std::env::temp_dir().join(format!("pleat-obj-{}-{name}", std::process::id()));
        std::fs::write(&path, text).unwrap();
        path
    }

    #[test]
    fn quad_is_triangulated() {
        let path = write(
            "quad.obj",
            "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n",
        );
        let mesh = load_obj(&path).unwrap();
        assert_eq!(mesh.positions.len(), 4);
        assert_eq!(mesh.triangles.len(), 2);
    }

    #[test]
    fn text_in_memory_reads_as_the_file_would() {
        let mesh = parse_obj(
            "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n",
            "drop.obj",
        )
        .unwrap();
        assert_eq!((mesh.positions.len(), mesh.triangles.len()), (4, 2));
        let e = parse_obj("v 0 0 0\nf 1 2 7\n", "drop.obj")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("drop.obj") && e.contains("does not exist"),
            "{e}"
        );
    }

    #[test]
    fn errors_name_the_file_and_reason() {
        let path = write("bad.obj", "v 0 0 0\nv 1 0 0\nf 1 2 7\n");
        let e = load_obj(&path).unwrap_err().to_string();
        assert!(e.contains("bad.obj") && e.contains("does not exist"), "{e}");
        let path = write("empty.obj", "v 0 0 0\n");
        let e = load_obj(&path).unwrap_err();
        assert_eq!(e.reason, ObjReason::NoFaces);
        assert!(e.to_string().contains("no faces"), "{e}");
        let e = load_obj(Path::new("/nonexistent/x.obj"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("cannot open"), "{e}");
    }

    #[test]
    fn validation_names_the_vertex_and_face_from_one() {
        let mut mesh = Mesh {
            positions: vec![Vec3::ZERO, Vec3::X, Vec3::new(0.0, f32::NAN, 0.0)],
            triangles: vec![[0, 1, 2]],
            grid: None,
        };
        let e = validate(&mesh).unwrap_err();
        assert_eq!(e, ObjReason::NonFiniteVertex { vertex: 2 });
        assert_eq!(e.to_string(), "vertex 3 has a non-finite coordinate");
        mesh.positions[2] = Vec3::Y;
        mesh.triangles.push([0, 1, 3]);
        let e = validate(&mesh).unwrap_err();
        assert_eq!(e, ObjReason::MissingVertex { face: 1 });
        assert_eq!(
            e.to_string(),
            "face 2 refers to a vertex that does not exist"
        );
    }
}
