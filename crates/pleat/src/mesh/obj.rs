//! Wavefront OBJ input (through `tobj`): every model of the file merged into one mesh.

use super::Mesh;
use glam::Vec3;
use std::path::Path;

/// Why an OBJ file could not become a mesh.
#[derive(Debug, thiserror::Error)]
#[error("{file}: {reason}")]
pub struct ObjError {
    pub file: String,
    pub reason: String,
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
    let error = |reason: String| ObjError {
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
    let error = |reason: String| ObjError {
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

fn describe(e: tobj::LoadError) -> String {
    match e {
        tobj::LoadError::OpenFileFailed => "cannot open the file".into(),
        tobj::LoadError::ReadError => "cannot read the file".into(),
        tobj::LoadError::PositionParseError => "a vertex position (v) is not three numbers".into(),
        tobj::LoadError::FaceParseError => "a face (f) is malformed".into(),
        tobj::LoadError::FaceVertexOutOfBounds => {
            "a face refers to a vertex that does not exist".into()
        }
        other => format!("malformed OBJ ({other})"),
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

fn validate(mesh: &Mesh) -> Result<(), String> {
    if mesh.triangles.is_empty() {
        return Err("no faces: a cloth or collider mesh needs at least one triangle".into());
    }
    if let Some(i) = mesh.positions.iter().position(|p| !p.is_finite()) {
        return Err(format!("vertex {} has a non-finite coordinate", i + 1));
    }
    let n = mesh.positions.len() as u32;
    if let Some(t) = mesh
        .triangles
        .iter()
        .position(|t| t.iter().any(|&i| i >= n))
    {
        return Err(format!(
            "face {} refers to a vertex that does not exist",
            t + 1
        ));
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
        assert!(load_obj(&path)
            .unwrap_err()
            .to_string()
            .contains("no faces"));
        let e = load_obj(Path::new("/nonexistent/x.obj"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("cannot open"), "{e}");
    }
}
