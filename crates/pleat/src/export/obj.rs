//! Wavefront OBJ writer: one static triangle mesh per file (a simulation is
//! exported as a sequence `frame_00000.obj`, `frame_00001.obj`, ...).
//!
//! Coordinates are written with Rust's shortest round-trip formatting, so
//! reading the file back gives the exact `f32` values. Indices are 1-based;
//! faces take the form `f v`, `f v/vt`, `f v//vn` or `f v/vt/vn` depending
//! on which attributes are given (each attribute shares the vertex's index).

use super::{check_attribute, check_triangles};
use glam::{Vec2, Vec3};
use std::io::{self, BufWriter, Write};

/// Writes a triangle mesh as OBJ text to `w`.
///
/// `normals` and `uvs`, when given, must have one entry per position.
/// Returns an `InvalidInput` error (and writes nothing) if an index is out of
/// range or an attribute has the wrong length.
pub fn write_obj(
    w: &mut impl Write,
    positions: &[Vec3],
    triangles: &[[u32; 3]],
    normals: Option<&[Vec3]>,
    uvs: Option<&[Vec2]>,
) -> io::Result<()> {
    check_triangles(positions.len(), triangles)?;
    check_attribute("normals", normals, positions.len())?;
    check_attribute("uvs", uvs, positions.len())?;

    let mut out = BufWriter::new(w);
    writeln!(
        out,
        "# pleat: {} vertices, {} triangles",
        positions.len(),
        triangles.len()
    )?;
    for p in positions {
        writeln!(out, "v {} {} {}", p.x, p.y, p.z)?;
    }
    for t in uvs.unwrap_or_default() {
        writeln!(out, "vt {} {}", t.x, t.y)?;
    }
    for n in normals.unwrap_or_default() {
        writeln!(out, "vn {} {} {}", n.x, n.y, n.z)?;
    }
    let form = FaceForm::new(uvs.is_some(), normals.is_some());
    for tri in triangles {
        write!(out, "f")?;
        for &i in tri {
            write!(out, " ")?;
            form.write_corner(&mut out, i as u64 + 1)?;
        }
        writeln!(out)?;
    }
    out.flush()
}

/// Which attributes a face corner refers to.
#[derive(Clone, Copy)]
enum FaceForm {
    Position,
    PositionUv,
    PositionNormal,
    PositionUvNormal,
}

impl FaceForm {
    fn new(has_uvs: bool, has_normals: bool) -> Self {
        match (has_uvs, has_normals) {
            (false, false) => Self::Position,
            (true, false) => Self::PositionUv,
            (false, true) => Self::PositionNormal,
            (true, true) => Self::PositionUvNormal,
        }
    }

    /// Writes one corner (`v`, `v/vt`, `v//vn` or `v/vt/vn`) with 1-based index `i`.
    fn write_corner(self, out: &mut impl Write, i: u64) -> io::Result<()> {
        match self {
            Self::Position => write!(out, "{i}"),
            Self::PositionUv => write!(out, "{i}/{i}"),
            Self::PositionNormal => write!(out, "{i}//{i}"),
            Self::PositionUvNormal => write!(out, "{i}/{i}/{i}"),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::export::vertex_normals;

    /// A 3 x 2 vertex grid, slightly bent so no coordinate is trivial.
    fn small_mesh() -> (Vec<Vec3>, Vec<[u32; 3]>, Vec<Vec2>) {
        let mut positions = Vec::new();
        let mut uvs = Vec::new();
        for j in 0..2 {
            for i in 0..3 {
                let (u, v) = (i as f32 / 2.0, j as f32);
                positions.push(Vec3::new(u * 0.3, v * 0.7, 0.1 * (u * 3.1).sin() + 1e-3));
                uvs.push(Vec2::new(u, v));
            }
        }
        let triangles = vec![[0, 1, 4], [0, 4, 3], [1, 2, 5], [1, 5, 4]];
        (positions, triangles, uvs)
    }

    fn load(text: &[u8]) -> tobj::Mesh {
        let mut reader = io::BufReader::new(text);
        let options = tobj::LoadOptions {
            single_index: true,
            triangulate: false,
            ..Default::default()
        };
        let (models, _) = tobj::load_obj_buf(&mut reader, &options, |_| {
            Err(tobj::LoadError::GenericFailure)
        })
        .expect("tobj parses our OBJ");
        assert_eq!(models.len(), 1);
        models.into_iter().next().unwrap().mesh
    }

    /// The attribute of corner `k` as tobj sees it (tobj renumbers vertices
    /// in the order faces first use them, so compare corner by corner).
    fn corner<const N: usize>(values: &[f32], mesh: &tobj::Mesh, k: usize) -> [f32; N] {
        let i = mesh.indices[k] as usize;
        std::array::from_fn(|c| values[N * i + c])
    }

    #[test]
    fn positions_uvs_and_normals_round_trip_through_tobj() {
        let (positions, triangles, uvs) = small_mesh();
        let normals = vertex_normals(&positions, &triangles);
        let mut bytes = Vec::new();
        write_obj(
            &mut bytes,
            &positions,
            &triangles,
            Some(&normals),
            Some(&uvs),
        )
        .unwrap();
        let text = String::from_utf8(bytes.clone()).unwrap();
        assert!(text.contains("\nf 1/1/1 2/2/2 5/5/5\n"), "{text}");

        let mesh = load(&bytes);
        assert_eq!(mesh.positions.len(), 3 * positions.len());
        assert_eq!(mesh.indices.len(), 3 * triangles.len());
        for (k, &v) in triangles.iter().flatten().enumerate() {
            let v = v as usize;
            // Shortest round-trip formatting: the values come back exactly.
            assert_eq!(corner(&mesh.positions, &mesh, k), positions[v].to_array());
            assert_eq!(corner(&mesh.normals, &mesh, k), normals[v].to_array());
            assert_eq!(corner(&mesh.texcoords, &mesh, k), uvs[v].to_array());
        }
    }

    #[test]
    fn face_forms_follow_the_attributes_given() {
        let (positions, triangles, uvs) = small_mesh();
        let normals = vertex_normals(&positions, &triangles);
        let first_face = |n: Option<&[Vec3]>, t: Option<&[Vec2]>| {
            let mut bytes = Vec::new();
            write_obj(&mut bytes, &positions, &triangles, n, t).unwrap();
            let text = String::from_utf8(bytes).unwrap();
            text.lines()
                .find(|l| l.starts_with("f "))
                .unwrap()
                .to_owned()
        };
        assert_eq!(first_face(None, None), "f 1 2 5");
        assert_eq!(first_face(None, Some(&uvs)), "f 1/1 2/2 5/5");
        assert_eq!(first_face(Some(&normals), None), "f 1//1 2//2 5//5");

        let mut bytes = Vec::new();
        write_obj(&mut bytes, &positions, &triangles, None, None).unwrap();
        let mesh = load(&bytes);
        for (k, &v) in triangles.iter().flatten().enumerate() {
            assert_eq!(
                corner(&mesh.positions, &mesh, k),
                positions[v as usize].to_array()
            );
        }
        assert!(mesh.normals.is_empty() && mesh.texcoords.is_empty());
    }

    #[test]
    fn bad_meshes_are_refused_without_output() {
        let (positions, _, uvs) = small_mesh();
        let mut bytes = Vec::new();
        let err = write_obj(&mut bytes, &positions, &[[0, 1, 6]], None, None).unwrap_err();
        assert_eq!(err.kind(), io::ErrorKind::InvalidInput);
        let err = write_obj(&mut bytes, &positions, &[], None, Some(&uvs[..2])).unwrap_err();
        assert!(err.to_string().contains("uvs"), "{err}");
        assert!(bytes.is_empty());
    }
}
