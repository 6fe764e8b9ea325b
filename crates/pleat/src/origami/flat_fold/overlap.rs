//! Where folded triangles overlap: convex clipping (Sutherland–Hodgman) of
//! counter-clockwise triangles, each first shrunk by the tolerance so that
//! neighbours that only touch along an edge or at a corner do not overlap.

use glam::DVec2;

/// A convex polygon, counter-clockwise.
pub(super) type Polygon = Vec<DVec2>;

/// Twice the signed area of the triangle `a b c`: positive counter-clockwise.
pub(super) fn cross(a: DVec2, b: DVec2, c: DVec2) -> f64 {
    (b - a).perp_dot(c - a)
}

/// Area of a convex polygon given counter-clockwise.
pub(super) fn area(polygon: &[DVec2]) -> f64 {
    let n = polygon.len();
    (0..n)
        .map(|i| polygon[i].perp_dot(polygon[(i + 1) % n]))
        .sum::<f64>()
        * 0.5
}

/// `triangle` (counter-clockwise) with every edge moved inwards by `by`,
/// or `None` when that leaves nothing.
pub(super) fn shrunk(triangle: [DVec2; 3], by: f64) -> Option<[DVec2; 3]> {
    let [a, b, c] = triangle;
    let (la, lb, lc) = ((b - c).length(), (c - a).length(), (a - b).length());
    let perimeter = la + lb + lc;
    let double_area = cross(a, b, c);
    if perimeter <= 0.0 || double_area <= 0.0 {
        return None;
    }
    let inradius = double_area / perimeter;
    if inradius <= 2.0 * by {
        return None;
    }
    let incentre = (a * la + b * lb + c * lc) / perimeter;
    let scale = 1.0 - by / inradius;
    Some(triangle.map(|p| incentre + (p - incentre) * scale))
}

/// The part of `polygon` inside the counter-clockwise triangle `clip`.
pub(super) fn clip(polygon: &[DVec2], clip: &[DVec2; 3]) -> Polygon {
    let mut out: Polygon = polygon.to_vec();
    for k in 0..3 {
        let (a, b) = (clip[k], clip[(k + 1) % 3]);
        let input = std::mem::take(&mut out);
        let n = input.len();
        for i in 0..n {
            let (p, q) = (input[i], input[(i + 1) % n]);
            let (sp, sq) = (cross(a, b, p), cross(a, b, q));
            if sp >= 0.0 {
                out.push(p);
            }
            if (sp >= 0.0) != (sq >= 0.0) {
                out.push(p + (q - p) * (sp / (sp - sq)));
            }
        }
        if out.len() < 3 {
            return Vec::new();
        }
    }
    out
}

/// Every pair `(i, j)`, `i < j`, of boxes that overlap, by a sweep along x.
pub(super) fn box_pairs(boxes: &[(DVec2, DVec2)]) -> Vec<(u32, u32)> {
    let mut order: Vec<u32> = (0..boxes.len() as u32).collect();
    order.sort_by(|&a, &b| boxes[a as usize].0.x.total_cmp(&boxes[b as usize].0.x));
    let mut pairs = Vec::new();
    for (k, &i) in order.iter().enumerate() {
        let (lo, hi) = boxes[i as usize];
        for &j in &order[k + 1..] {
            let (lo_j, hi_j) = boxes[j as usize];
            if lo_j.x > hi.x {
                break;
            }
            if lo_j.y <= hi.y && lo.y <= hi_j.y {
                pairs.push((i.min(j), i.max(j)));
            }
        }
    }
    pairs
}

/// The bounding box of some points.
pub(super) fn bounds(points: &[DVec2]) -> (DVec2, DVec2) {
    points.iter().fold(
        (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY)),
        |(lo, hi), &p| (lo.min(p), hi.max(p)),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tri(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> [DVec2; 3] {
        [a, b, c].map(DVec2::from)
    }

    #[test]
    fn two_halves_of_a_square_overlap_in_a_quarter() {
        let a = tri([0.0, 0.0], [1.0, 0.0], [0.0, 1.0]);
        let b = tri([0.0, 0.0], [1.0, 0.0], [1.0, 1.0]);
        let overlap = clip(&a, &b);
        assert!((area(&overlap) - 0.25).abs() < 1e-12, "{overlap:?}");
    }

    #[test]
    fn neighbours_sharing_an_edge_do_not_overlap_once_shrunk() {
        let a = shrunk(tri([0.0, 0.0], [1.0, 0.0], [0.0, 1.0]), 1e-6).unwrap();
        let b = shrunk(tri([1.0, 0.0], [1.0, 1.0], [0.0, 1.0]), 1e-6).unwrap();
        assert!(clip(&a, &b).is_empty());
        assert!((area(&a) - 0.5).abs() < 1e-5);
    }

    #[test]
    fn the_sweep_finds_the_same_pairs_as_every_pair_tested() {
        let boxes: Vec<(DVec2, DVec2)> = (0..40)
            .map(|i| {
                let x = ((i * 37) % 17) as f64 * 0.3;
                let y = ((i * 11) % 13) as f64 * 0.3;
                (DVec2::new(x, y), DVec2::new(x + 0.5, y + 0.4))
            })
            .collect();
        let mut swept = box_pairs(&boxes);
        swept.sort();
        let mut every = Vec::new();
        for i in 0..boxes.len() {
            for j in i + 1..boxes.len() {
                let (a, b) = (boxes[i], boxes[j]);
                if a.0.x <= b.1.x && b.0.x <= a.1.x && a.0.y <= b.1.y && b.0.y <= a.1.y {
                    every.push((i as u32, j as u32));
                }
            }
        }
        assert_eq!(swept, every);
    }
}
