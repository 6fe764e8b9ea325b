//! Strain per facet: how much a triangle's edges have changed length, for
//! colour maps and reports (origami paper should stay near zero).

use glam::Vec3;

/// For each triangle, the mean relative change of its three edge lengths,
/// `mean |l / l_rest - 1|`, between `rest` and `x`; zero-length rest edges
/// are left out.
pub fn facet_strain(rest: &[Vec3], x: &[Vec3], triangles: &[[u32; 3]]) -> Vec<f32> {
    triangles
        .iter()
        .map(|&[a, b, c]| {
            let (sum, count) = [[a, b], [b, c], [c, a]]
                .into_iter()
                .filter_map(|e| edge_strain(rest, x, e))
                .fold((0.0, 0), |(s, n), strain| (s + strain, n + 1));
            if count > 0 {
                sum / count as f32
            } else {
                0.0
            }
        })
        .collect()
}

/// Largest facet strain (zero for no triangles).
pub fn max_facet_strain(rest: &[Vec3], x: &[Vec3], triangles: &[[u32; 3]]) -> f32 {
    facet_strain(rest, x, triangles)
        .into_iter()
        .fold(0.0, f32::max)
}

fn edge_strain(rest: &[Vec3], x: &[Vec3], [a, b]: [u32; 2]) -> Option<f32> {
    let rest_length = rest[a as usize].distance(rest[b as usize]);
    (rest_length > 0.0).then(|| (x[a as usize].distance(x[b as usize]) / rest_length - 1.0).abs())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn strain_is_the_mean_relative_edge_change() {
        let rest = [Vec3::ZERO, Vec3::X, Vec3::Y];
        let triangles = [[0, 1, 2]];
        assert_eq!(facet_strain(&rest, &rest, &triangles), [0.0]);
        // One leg 30 % longer, the other 30 % shorter: the hypotenuse
        // changes too, and shrinking counts as much as stretching.
        let x = [Vec3::ZERO, Vec3::X * 1.3, Vec3::Y * 0.7];
        let hypotenuse = (1.3f32.hypot(0.7) / 2f32.sqrt() - 1.0).abs();
        let expected = (0.3 + 0.3 + hypotenuse) / 3.0;
        let strain = facet_strain(&rest, &x, &triangles)[0];
        assert!((strain - expected).abs() < 1e-6, "{strain} vs {expected}");
        assert_eq!(max_facet_strain(&rest, &x, &triangles), strain);
        // Moving rigidly strains nothing.
        let moved = rest.map(|p| p + Vec3::splat(5.0));
        assert!(facet_strain(&rest, &moved, &triangles)[0] < 1e-6);
    }
}
