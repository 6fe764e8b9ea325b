//! Writing one mesh, the format chosen by the file's extension: OBJ and
//! PLY with vertex normals as `pleat run --format obj|ply` writes each
//! frame, or a binary glTF of this one frame.

use crate::errors::value_error;
use pleat::export::{gltf::GlbAnimation, obj::write_obj, ply::write_ply, vertex_normals};
use pleat::glam::Vec3;
use pyo3::exceptions::PyOSError;
use pyo3::prelude::*;
use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::Path;

/// Writes the mesh of `positions` and `triangles` to `path` (`.obj`,
/// `.ply` or `.glb`); a glb's frame lasts `frame_dt` seconds.
pub fn write_mesh(
    path: &Path,
    positions: &[Vec3],
    triangles: &[[u32; 3]],
    frame_dt: f32,
) -> PyResult<()> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .unwrap_or("")
        .to_ascii_lowercase();
    if !matches!(ext.as_str(), "obj" | "ply" | "glb") {
        return Err(value_error(format!(
            "{}: unknown mesh format '.{ext}': use .obj, .ply or .glb",
            path.display()
        )));
    }
    let os_error = |e: std::io::Error| PyOSError::new_err(format!("{}: {e}", path.display()));
    let mut w = BufWriter::new(File::create(path).map_err(os_error)?);
    match ext.as_str() {
        "glb" => GlbAnimation::new(triangles, positions, frame_dt).write(&mut w),
        "ply" => write_ply(
            &mut w,
            positions,
            triangles,
            Some(&vertex_normals(positions, triangles)),
        ),
        _ => write_obj(
            &mut w,
            positions,
            triangles,
            Some(&vertex_normals(positions, triangles)),
            None,
        ),
    }
    .and_then(|()| w.flush())
    .map_err(os_error)
}
