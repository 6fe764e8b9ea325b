//! Counting pairs of non-adjacent triangles that intersect: the
//! `self_intersections` figure of `report.json`.
//!
//! A bounding volume hierarchy over the triangles' boxes (`tri_bvh`) finds
//! candidate pairs; pairs that share a vertex index (adjacent triangles, which
//! always touch) are skipped; the rest go through an orientation-predicate
//! triangle–triangle test in `f64` (`tri_tri`). Coplanar overlapping pairs
//! count; pairs that only touch (within a relative 1e-12 of their size) may
//! or may not count.
//!
//! Triangles with a non-finite corner (NaN, infinity), zero area, or an index
//! out of range take no part: they intersect nothing. Two triangles sharing a
//! position but not a vertex index (a seam with duplicated vertices) touch,
//! and may count.
//!
//! The work is single-threaded and allocation is O(triangles).

pub(super) mod tri_bvh;
mod tri_tri;

use crate::math::Aabb;
use glam::Vec3;
use tri_bvh::TriBvh;
use tri_tri::Triangle;

/// Number of pairs of triangles that share no vertex and intersect.
pub fn count_self_intersections(positions: &[Vec3], triangles: &[[u32; 3]]) -> usize {
    let mut count = 0;
    for_each_intersecting_pair(positions, triangles, |_, _| count += 1);
    count
}

/// The pairs counted by [`count_self_intersections`], as triangle indices
/// `(i, j)` with `i < j`, sorted: for finding where a mesh intersects itself.
pub fn intersecting_pairs(positions: &[Vec3], triangles: &[[u32; 3]]) -> Vec<(u32, u32)> {
    let mut pairs = Vec::new();
    for_each_intersecting_pair(positions, triangles, |a, b| {
        pairs.push((a.min(b), a.max(b)))
    });
    pairs.sort_unstable();
    pairs
}

fn for_each_intersecting_pair(
    positions: &[Vec3],
    triangles: &[[u32; 3]],
    mut f: impl FnMut(u32, u32),
) {
    let candidates: Vec<Option<Triangle>> = triangles
        .iter()
        .map(|&corners| candidate(positions, corners))
        .collect();
    let boxes = candidates
        .iter()
        .zip(triangles)
        .enumerate()
        .filter(|(_, (c, _))| c.is_some())
        .map(|(i, (_, tri))| {
            (
                i as u32,
                Aabb::of_points(tri.map(|v| positions[v as usize])),
            )
        })
        .collect();
    TriBvh::build(boxes).for_each_overlapping_pair(|a, b| {
        // Most candidate pairs are neighbours: reject them from the compact
        // index array before touching the prepared triangles.
        if share_a_vertex(triangles[a as usize], triangles[b as usize]) {
            return;
        }
        if let (Some(ta), Some(tb)) = (&candidates[a as usize], &candidates[b as usize]) {
            if tri_tri::overlap(ta, tb) {
                f(a, b);
            }
        }
    });
}

/// `None` for a triangle that takes no part (see the module documentation).
fn candidate(positions: &[Vec3], corners: [u32; 3]) -> Option<Triangle> {
    let [a, b, c] = corners.map(|i| positions.get(i as usize).copied());
    Triangle::new(a?, b?, c?)
}

fn share_a_vertex(a: [u32; 3], b: [u32; 3]) -> bool {
    a.iter().any(|v| b.contains(v))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_rng::Rng;
    use std::f32::consts::PI;

    /// Positions and triangles of an n x n vertex grid over [0, 1]^2 in the
    /// plane z = 0, split along alternating diagonals.
    fn grid(n: usize) -> (Vec<Vec3>, Vec<[u32; 3]>) {
        let positions = (0..n * n)
            .map(|v| {
                let (i, j) = (v % n, v / n);
                Vec3::new(i as f32, j as f32, 0.0) / (n - 1) as f32
            })
            .collect();
        let mut triangles = Vec::new();
        for j in 0..n - 1 {
            for i in 0..n - 1 {
                let a = (j * n + i) as u32;
                let (b, c, d) = (a + 1, a + n as u32, a + n as u32 + 1);
                if (i + j) % 2 == 0 {
                    triangles.extend([[a, b, d], [a, d, c]]);
                } else {
                    triangles.extend([[a, b, c], [b, d, c]]);
                }
            }
        }
        (positions, triangles)
    }

    /// The grid folded about the line x = 0.5 by `angle` (PI folds it flat
    /// onto itself); past PI the folded half passes through the other half.
    fn folded_grid(n: usize, angle: f32) -> (Vec<Vec3>, Vec<[u32; 3]>) {
        let (mut positions, triangles) = grid(n);
        for p in &mut positions {
            if p.x > 0.5 {
                let r = p.x - 0.5;
                p.x = 0.5 + r * angle.cos();
                p.z = r * angle.sin();
            }
        }
        (positions, triangles)
    }

    /// The reference the BVH must agree with: every pair, no broad phase.
    fn brute_force_pairs(positions: &[Vec3], triangles: &[[u32; 3]]) -> Vec<(u32, u32)> {
        let candidates: Vec<_> = triangles.iter().map(|&t| candidate(positions, t)).collect();
        let mut pairs = Vec::new();
        for (i, a) in candidates.iter().enumerate() {
            for (j, b) in candidates.iter().enumerate().skip(i + 1) {
                if let (Some(a), Some(b)) = (a, b) {
                    if !share_a_vertex(triangles[i], triangles[j]) && tri_tri::overlap(a, b) {
                        pairs.push((i as u32, j as u32));
                    }
                }
            }
        }
        pairs
    }

    #[test]
    fn two_crossing_triangles_count_once() {
        let positions = [
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
            Vec3::new(0.2, 0.2, -0.5),
            Vec3::new(0.3, 0.2, 0.5),
            Vec3::new(0.2, 0.3, 0.5),
        ];
        let triangles = [[0, 1, 2], [3, 4, 5]];
        assert_eq!(count_self_intersections(&positions, &triangles), 1);
        assert_eq!(intersecting_pairs(&positions, &triangles), [(0, 1)]);
    }

    #[test]
    fn parallel_separated_triangles_do_not_count() {
        let positions = [
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
            Vec3::new(0.0, 0.0, 0.01),
            Vec3::new(1.0, 0.0, 0.01),
            Vec3::new(0.0, 1.0, 0.01),
        ];
        assert_eq!(
            count_self_intersections(&positions, &[[0, 1, 2], [3, 4, 5]]),
            0
        );
    }

    #[test]
    fn triangles_sharing_a_vertex_do_not_count_even_folded_through() {
        // The second triangle shares vertex 0 and pierces the first.
        let positions = [
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
            Vec3::new(1.0, 1.0, 1.0),
            Vec3::new(1.0, 1.0, -1.0),
        ];
        let triangles = [[0, 1, 2], [0, 3, 4]];
        assert_eq!(count_self_intersections(&positions, &triangles), 0);
        // Without the shared index the same geometry counts.
        let mut split = positions.to_vec();
        split.push(Vec3::ZERO);
        assert_eq!(count_self_intersections(&split, &[[0, 1, 2], [5, 3, 4]]), 1);
    }

    #[test]
    fn flat_and_gently_folded_grids_have_none() {
        let (positions, triangles) = grid(40);
        assert_eq!(count_self_intersections(&positions, &triangles), 0);
        // The same sheet in a tilted plane, where coordinates round.
        let tilted: Vec<Vec3> = positions
            .iter()
            .map(|p| Vec3::new(p.x * 0.6, p.x * 0.8 + 0.3, p.y * 0.7 - 1.1))
            .collect();
        assert_eq!(count_self_intersections(&tilted, &triangles), 0);
        for angle in [0.5 * PI, 0.9 * PI] {
            let (folded, triangles) = folded_grid(40, angle);
            assert_eq!(count_self_intersections(&folded, &triangles), 0, "{angle}");
        }
    }

    #[test]
    fn a_grid_folded_through_itself_has_some() {
        // Folded about x = 0.5 past flat, so the flap slopes down under the
        // other half, then lifted: it now cuts through that half.
        let (mut positions, triangles) = folded_grid(20, 1.1 * PI);
        for p in &mut positions {
            if p.z != 0.0 {
                p.z += 0.05;
            }
        }
        let count = count_self_intersections(&positions, &triangles);
        assert!(count > 0);
        assert_eq!(count, brute_force_pairs(&positions, &triangles).len());
    }

    #[test]
    fn bvh_agrees_with_brute_force_on_random_soups() {
        let mut rng = Rng(0x2545_f491_4f6c_dd1d);
        for soup in 0..8 {
            // Small triangles around random centres, plus shared vertices:
            // each triangle reuses a vertex of the previous one half the time.
            let (mut positions, mut triangles) = (Vec::new(), Vec::new());
            let size = 0.05 + 0.05 * soup as f32;
            for t in 0..300u32 {
                let centre = rng.vec3();
                let mut corner = || centre + (rng.vec3() - 0.5) * size;
                let base = positions.len() as u32;
                positions.extend([corner(), corner(), corner()]);
                let first = if t > 0 && t % 2 == 0 { base - 1 } else { base };
                triangles.push([first, base + 1, base + 2]);
            }
            let expected = brute_force_pairs(&positions, &triangles);
            assert!(
                !expected.is_empty(),
                "soup {soup} too sparse to test anything"
            );
            assert_eq!(
                intersecting_pairs(&positions, &triangles),
                expected,
                "soup {soup}"
            );
            assert_eq!(
                count_self_intersections(&positions, &triangles),
                expected.len()
            );
        }
    }

    #[test]
    fn bad_input_does_not_panic_and_takes_no_part() {
        let (mut positions, mut triangles) = folded_grid(10, 1.1 * PI);
        let before = count_self_intersections(&positions, &triangles);
        let last = positions.len() as u32;
        positions.extend([
            Vec3::ZERO,
            Vec3::X,
            Vec3::X * 2.0,
            Vec3::NAN,
            Vec3::INFINITY,
        ]);
        triangles.extend([
            [last, last + 1, last + 2], // zero area
            [last, last, last + 1],     // repeated vertex
            [0, 1, last + 3],           // NaN corner
            [last + 4, last, last + 1], // infinite corner
            [0, 1, 1_000_000],          // index out of range
        ]);
        assert_eq!(count_self_intersections(&positions, &triangles), before);
        assert_eq!(count_self_intersections(&[], &[]), 0);
        assert_eq!(
            count_self_intersections(&[Vec3::NAN; 3], &[[0, 1, 2]; 4]),
            0
        );
    }

    #[test]
    fn coplanar_overlapping_pairs_count() {
        let positions = [
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
            Vec3::new(0.2, 0.2, 0.0),
            Vec3::new(1.2, 0.2, 0.0),
            Vec3::new(0.2, 1.2, 0.0),
        ];
        assert_eq!(
            count_self_intersections(&positions, &[[0, 1, 2], [3, 4, 5]]),
            1
        );
    }
}
