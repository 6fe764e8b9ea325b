//! Stanford PLY writer, binary little-endian: compact and exact (raw `f32`).
//!
//! Layout: `element vertex N` with `float x, y, z` and, when normals are
//! given, `float nx, ny, nz`; then `element face M` with
//! `property list uchar int vertex_indices` (always 3 indices, 0-based).

use super::{check_attribute, check_triangles, invalid_input};
use glam::Vec3;
use std::io::{self, BufWriter, Write};

/// Writes a triangle mesh as binary little-endian PLY to `w`.
///
/// `normals`, when given, must have one entry per position. Returns an
/// `InvalidInput` error (and writes nothing) if an index is out of range, the
/// normals have the wrong length, or there are more vertices than a PLY
/// `int` index can address.
pub fn write_ply(
    w: &mut impl Write,
    positions: &[Vec3],
    triangles: &[[u32; 3]],
    normals: Option<&[Vec3]>,
) -> io::Result<()> {
    check_triangles(positions.len(), triangles)?;
    check_attribute("normals", normals, positions.len())?;
    if positions.len() > i32::MAX as usize {
        return Err(invalid_input(
            "PLY face indices are 32-bit signed: too many vertices",
        ));
    }

    let mut out = BufWriter::new(w);
    write_header(
        &mut out,
        positions.len(),
        triangles.len(),
        normals.is_some(),
    )?;
    for (i, p) in positions.iter().enumerate() {
        write_vec3(&mut out, *p)?;
        if let Some(n) = normals {
            write_vec3(&mut out, n[i])?;
        }
    }
    for tri in triangles {
        out.write_all(&[3u8])?;
        for &i in tri {
            // In range and below i32::MAX: checked above.
            out.write_all(&(i as i32).to_le_bytes())?;
        }
    }
    out.flush()
}

fn write_header(
    out: &mut impl Write,
    vertex_count: usize,
    face_count: usize,
    with_normals: bool,
) -> io::Result<()> {
    writeln!(out, "ply")?;
    writeln!(out, "format binary_little_endian 1.0")?;
    writeln!(out, "comment written by pleat")?;
    writeln!(out, "element vertex {vertex_count}")?;
    let mut names = vec!["x", "y", "z"];
    if with_normals {
        names.extend(["nx", "ny", "nz"]);
    }
    for name in names {
        writeln!(out, "property float {name}")?;
    }
    writeln!(out, "element face {face_count}")?;
    writeln!(out, "property list uchar int vertex_indices")?;
    writeln!(out, "end_header")
}

fn write_vec3(out: &mut impl Write, v: Vec3) -> io::Result<()> {
    for c in v.to_array() {
        out.write_all(&c.to_le_bytes())?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::export::vertex_normals;

    /// What the tiny reader below understands of a PLY file.
    #[derive(Debug, PartialEq)]
    struct Ply {
        properties: Vec<String>,
        vertices: Vec<Vec<f32>>,
        faces: Vec<Vec<i32>>,
    }

    /// A minimal reader for exactly the layout `write_ply` produces.
    fn read_ply(bytes: &[u8]) -> Ply {
        let end = b"end_header\n";
        let header_len = bytes.windows(end.len()).position(|w| w == end).unwrap() + end.len();
        let header = std::str::from_utf8(&bytes[..header_len]).unwrap();
        let mut lines = header.lines();
        assert_eq!(lines.next(), Some("ply"));
        assert_eq!(lines.next(), Some("format binary_little_endian 1.0"));
        let (mut vertex_count, mut face_count, mut properties) = (0, 0, Vec::new());
        for line in lines {
            let words: Vec<&str> = line.split(' ').collect();
            match words.as_slice() {
                ["element", "vertex", n] => vertex_count = n.parse().unwrap(),
                ["element", "face", n] => face_count = n.parse().unwrap(),
                ["property", "float", name] => properties.push(name.to_string()),
                ["property", "list", "uchar", "int", "vertex_indices"] => {}
                ["comment", ..] | ["end_header"] => {}
                other => panic!("unexpected header line {other:?}"),
            }
        }
        let mut body = &bytes[header_len..];
        let mut take4 = || {
            let (word, rest) = body.split_at(4);
            body = rest;
            [word[0], word[1], word[2], word[3]]
        };
        let vertices: Vec<Vec<f32>> = (0..vertex_count)
            .map(|_| {
                properties
                    .iter()
                    .map(|_| f32::from_le_bytes(take4()))
                    .collect()
            })
            .collect();
        let mut faces = Vec::new();
        for _ in 0..face_count {
            let (count, rest) = body.split_first().unwrap();
            body = rest;
            let mut take4 = || {
                let (word, rest) = body.split_at(4);
                body = rest;
                i32::from_le_bytes([word[0], word[1], word[2], word[3]])
            };
            faces.push((0..*count).map(|_| take4()).collect());
        }
        assert!(body.is_empty(), "{} trailing bytes", body.len());
        Ply {
            properties,
            vertices,
            faces,
        }
    }

    fn mesh() -> (Vec<Vec3>, Vec<[u32; 3]>) {
        let positions = vec![
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(1.5, 0.0, -0.25),
            Vec3::new(1.0, 1.0, 0.125),
            Vec3::new(-1e-7, 1.0, 3.0e5),
        ];
        (positions, vec![[0, 1, 2], [0, 2, 3]])
    }

    #[test]
    fn round_trips_with_normals() {
        let (positions, triangles) = mesh();
        let normals = vertex_normals(&positions, &triangles);
        let mut bytes = Vec::new();
        write_ply(&mut bytes, &positions, &triangles, Some(&normals)).unwrap();
        let ply = read_ply(&bytes);
        assert_eq!(ply.properties, ["x", "y", "z", "nx", "ny", "nz"]);
        for (i, v) in ply.vertices.iter().enumerate() {
            assert_eq!(v[..3], positions[i].to_array());
            assert_eq!(v[3..], normals[i].to_array());
        }
        assert_eq!(ply.faces, [[0, 1, 2], [0, 2, 3]]);
    }

    #[test]
    fn round_trips_without_normals() {
        let (positions, triangles) = mesh();
        let mut bytes = Vec::new();
        write_ply(&mut bytes, &positions, &triangles, None).unwrap();
        let ply = read_ply(&bytes);
        assert_eq!(ply.properties, ["x", "y", "z"]);
        let read: Vec<Vec<f32>> = positions.iter().map(|p| p.to_array().to_vec()).collect();
        assert_eq!(ply.vertices, read);
        assert_eq!(ply.faces.len(), 2);
    }

    #[test]
    fn bad_meshes_are_refused_without_output() {
        let (positions, _) = mesh();
        let mut bytes = Vec::new();
        let err = write_ply(&mut bytes, &positions, &[[4, 0, 1]], None).unwrap_err();
        assert_eq!(err.kind(), io::ErrorKind::InvalidInput);
        let err = write_ply(&mut bytes, &positions, &[], Some(&[Vec3::Z])).unwrap_err();
        assert!(err.to_string().contains("normals"), "{err}");
        assert!(bytes.is_empty());
    }
}
