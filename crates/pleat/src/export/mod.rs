//! Writers for simulated meshes: OBJ sequences, PLY and animated binary glTF.
//!
//! Every writer takes the mesh as plain slices (`positions: &[Vec3]`,
//! `triangles: &[[u32; 3]]`), checks it (indices in range, attribute arrays
//! as long as `positions`) and returns an [`std::io::Error`] of kind
//! `InvalidInput` instead of panicking on a bad mesh. Shading normals for the
//! writers come from [`vertex_normals`].

pub mod gltf;
pub mod obj;
pub mod ply;

pub use gltf::GlbAnimation;
pub use obj::write_obj;
pub use ply::write_ply;

use glam::Vec3;
use std::io;

/// Area-weighted vertex normals: each vertex gets the normalised sum of the
/// (unnormalised) face normals of its triangles, so a large triangle counts
/// more than a small one.
///
/// Triangles with an index out of range are ignored. A vertex with no
/// triangle of non-zero area, or whose sum is not finite (NaN positions),
/// gets `Vec3::Z`, so the result is always a unit vector (glTF requires
/// unit normals).
pub fn vertex_normals(positions: &[Vec3], triangles: &[[u32; 3]]) -> Vec<Vec3> {
    let mut sums = vec![Vec3::ZERO; positions.len()];
    for tri in triangles {
        let Some([a, b, c]) = corners(positions, tri) else {
            continue;
        };
        // |cross| is twice the area: the weighting by area comes for free.
        let face = (b - a).cross(c - a);
        for &i in tri {
            sums[i as usize] += face;
        }
    }
    sums.into_iter().map(|n| n.normalize_or(Vec3::Z)).collect()
}

/// The three corner positions of `tri`, or `None` if an index is out of range.
fn corners(positions: &[Vec3], tri: &[u32; 3]) -> Option<[Vec3; 3]> {
    let get = |i: u32| positions.get(i as usize).copied();
    Some([get(tri[0])?, get(tri[1])?, get(tri[2])?])
}

/// An `InvalidInput` error with `message`.
pub(crate) fn invalid_input(message: impl Into<String>) -> io::Error {
    io::Error::new(io::ErrorKind::InvalidInput, message.into())
}

/// Checks that every triangle index is below `vertex_count`.
pub(crate) fn check_triangles(vertex_count: usize, triangles: &[[u32; 3]]) -> io::Result<()> {
    for (t, tri) in triangles.iter().enumerate() {
        if let Some(&i) = tri.iter().find(|&&i| i as usize >= vertex_count) {
            return Err(invalid_input(format!(
                "triangle {t} uses vertex {i}, but the mesh has {vertex_count} vertices"
            )));
        }
    }
    Ok(())
}

/// Checks that an optional per-vertex attribute has one entry per vertex.
pub(crate) fn check_attribute<T>(
    name: &str,
    values: Option<&[T]>,
    vertex_count: usize,
) -> io::Result<()> {
    match values {
        Some(v) if v.len() != vertex_count => Err(invalid_input(format!(
            "{name} has {} entries, but the mesh has {vertex_count} vertices",
            v.len()
        ))),
        _ => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn normals_of_a_flat_square_point_up() {
        let positions = [Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0), Vec3::Y];
        let triangles = [[0, 1, 2], [0, 2, 3]];
        for n in vertex_normals(&positions, &triangles) {
            assert!((n - Vec3::Z).length() < 1e-6, "{n}");
        }
    }

    #[test]
    fn normals_are_weighted_by_area() {
        // A big triangle in the xy plane and a small one in the xz plane share vertex 0.
        let positions = [
            Vec3::ZERO,
            Vec3::new(10.0, 0.0, 0.0),
            Vec3::new(0.0, 10.0, 0.0),
            Vec3::new(0.0, 0.0, -1.0),
        ];
        let triangles = [[0, 1, 2], [0, 3, 1]];
        let n = vertex_normals(&positions, &triangles)[0];
        let expected = Vec3::new(0.0, -10.0, 100.0).normalize();
        assert!((n - expected).length() < 1e-6, "{n} vs {expected}");
    }

    #[test]
    fn isolated_degenerate_and_bad_input_give_unit_normals() {
        let positions = [Vec3::ZERO, Vec3::X, Vec3::X * 2.0, Vec3::NAN, Vec3::Y];
        let triangles = [[0, 1, 2], [0, 3, 4], [0, 1, 99]];
        let normals = vertex_normals(&positions, &triangles);
        assert_eq!(normals.len(), positions.len());
        for n in normals {
            assert!((n.length() - 1.0).abs() < 1e-6, "{n}");
        }
    }

    #[test]
    fn checks_report_bad_indices_and_lengths() {
        assert!(check_triangles(3, &[[0, 1, 2]]).is_ok());
        let err = check_triangles(3, &[[0, 1, 3]]).unwrap_err();
        assert_eq!(err.kind(), io::ErrorKind::InvalidInput);
        assert!(err.to_string().contains("vertex 3"), "{err}");
        assert!(check_attribute("normals", Some(&[Vec3::Z; 2]), 3).is_err());
        assert!(check_attribute::<Vec3>("normals", None, 3).is_ok());
    }
}
