//! Triangle–triangle overlap test of Guigue and Devillers ("Fast and robust
//! triangle-triangle overlap test using orientation predicates", JGT 2003),
//! in `f64` on `f32` input.
//!
//! The test decides from signs of orientation determinants only; it never
//! divides. Plane-side signs within a relative tolerance ([`REL_EPS`] times
//! the triangles' size) count as "on the plane", so triangles that lie in one
//! plane up to rounding take the coplanar branch (a 2D separating-axis test)
//! instead of deciding from rounding noise. Otherwise the general case works
//! from the exact signs of the computed distances: its interval test reads
//! the real positions, and a vertex rounded onto the other plane by the
//! tolerance would invert its canonical form (two nearly coplanar triangles a
//! centimetre apart in their plane then "overlap"). Triangles that only touch
//! (within that tolerance) may be reported either way.

use glam::{DVec2, DVec3, Vec3};

/// Relative tolerance of the plane-side classification and of degeneracy.
const REL_EPS: f64 = 1e-12;

/// A non-degenerate triangle with finite corners, ready for overlap tests.
#[derive(Clone, Copy, Debug)]
pub(super) struct Triangle {
    v: [DVec3; 3],
    /// `(v1 - v0) x (v2 - v0)`, not normalised.
    normal: DVec3,
    normal_len: f64,
    /// Longest edge: the length scale of the tolerances.
    size: f64,
}

impl Triangle {
    /// `None` if a corner is not finite or the triangle has (numerically)
    /// zero area: the sine of its angle at `a` is below [`REL_EPS`].
    pub(super) fn new(a: Vec3, b: Vec3, c: Vec3) -> Option<Self> {
        let v = [a.as_dvec3(), b.as_dvec3(), c.as_dvec3()];
        if !v.iter().all(|p| p.is_finite()) {
            return None;
        }
        let (e1, e2) = (v[1] - v[0], v[2] - v[0]);
        let normal = e1.cross(e2);
        let normal_len = normal.length();
        if normal_len <= REL_EPS * e1.length() * e2.length() {
            return None;
        }
        let size = e1.length().max(e2.length()).max((v[2] - v[1]).length());
        Some(Self {
            v,
            normal,
            normal_len,
            size,
        })
    }
}

/// Whether the two (closed) triangles share at least one point.
pub(super) fn overlap(t1: &Triangle, t2: &Triangle) -> bool {
    let scale = t1.size + t2.size;
    let d1 = plane_distances(t2, &t1.v);
    let s1 = sides(d1, REL_EPS * t2.normal_len * scale);
    if strictly_one_side(s1) {
        return false;
    }
    let d2 = plane_distances(t1, &t2.v);
    let s2 = sides(d2, REL_EPS * t1.normal_len * scale);
    if strictly_one_side(s2) {
        return false;
    }
    if s1 == [0; 3] {
        return coplanar_overlap(t1, t2, t2.normal);
    }
    if s2 == [0; 3] {
        return coplanar_overlap(t1, t2, t1.normal);
    }
    let (s1, s2) = (sides(d1, 0.0), sides(d2, 0.0));
    if strictly_one_side(s1) || strictly_one_side(s2) {
        return false;
    }
    crossing_overlap(t1.v, s1, t2.v, s2)
}

/// Signed distances (times the normal's length) of `points` from the plane
/// of `plane`.
fn plane_distances(plane: &Triangle, points: &[DVec3; 3]) -> [f64; 3] {
    points.map(|p| (p - plane.v[0]).dot(plane.normal))
}

/// Sign (-1, 0, 1) of each distance, those within `tolerance` counting 0.
fn sides(d: [f64; 3], tolerance: f64) -> [i8; 3] {
    d.map(|d| {
        if d > tolerance {
            1
        } else if d < -tolerance {
            -1
        } else {
            0
        }
    })
}

fn strictly_one_side(s: [i8; 3]) -> bool {
    s[0] != 0 && s[0] == s[1] && s[0] == s[2]
}

/// The general case: each triangle meets the other's plane.
///
/// Both triangles are brought to the canonical form of the paper: `p1` alone
/// on the positive side of plane 2 and `p2` alone on the positive side of
/// plane 1 (rotating a triangle keeps its orientation, swapping `q` and `r`
/// flips the other's side signs). Then the triangles overlap if and only if
/// the two intervals they cut on the planes' common line overlap, which two
/// orientation determinants decide.
fn crossing_overlap(v1: [DVec3; 3], s1: [i8; 3], mut v2: [DVec3; 3], mut s2: [i8; 3]) -> bool {
    let Some((alone1, negative1)) = lone_vertex(s1) else {
        return false; // unreachable: s1 is not all zero
    };
    let [p1, mut q1, mut r1] = rotate(v1, alone1);
    if negative1 {
        v2.swap(1, 2);
        s2.swap(1, 2);
    }
    let Some((alone2, negative2)) = lone_vertex(s2) else {
        return false; // unreachable: s2 is not all zero
    };
    let [p2, q2, r2] = rotate(v2, alone2);
    if negative2 {
        std::mem::swap(&mut q1, &mut r1);
    }
    orient(q1, p2, p1, q2) <= 0.0 && orient(p1, p2, r1, r2) <= 0.0
}

/// The vertex alone on its side of the other plane, and whether that side is
/// negative. A vertex on the plane is alone when the other two are strictly
/// on one side (it then counts as being on the other side). `None` when all
/// three lie on the plane.
fn lone_vertex(s: [i8; 3]) -> Option<(usize, bool)> {
    (0..3).find_map(|i| {
        let (own, a, b) = (s[i], s[(i + 1) % 3], s[(i + 2) % 3]);
        if own != 0 && a != own && b != own {
            Some((i, own < 0))
        } else if own == 0 && a == b && a != 0 {
            Some((i, a > 0))
        } else {
            None
        }
    })
}

fn rotate(v: [DVec3; 3], first: usize) -> [DVec3; 3] {
    [v[first], v[(first + 1) % 3], v[(first + 2) % 3]]
}

/// `((b - a) x (c - a)) . (d - a)`: positive when `d` is on the side the
/// normal of triangle `a b c` points to.
fn orient(a: DVec3, b: DVec3, c: DVec3, d: DVec3) -> f64 {
    (b - a).cross(c - a).dot(d - a)
}

/// Both triangles lie in one plane with normal `normal`: drop the normal's
/// largest axis and test the 2D triangles.
fn coplanar_overlap(t1: &Triangle, t2: &Triangle, normal: DVec3) -> bool {
    let n = normal.abs();
    let project: fn(DVec3) -> DVec2 = if n.x >= n.y && n.x >= n.z {
        |p| DVec2::new(p.y, p.z)
    } else if n.y >= n.z {
        |p| DVec2::new(p.z, p.x)
    } else {
        |p| DVec2::new(p.x, p.y)
    };
    let a = t1.v.map(project);
    let b = t2.v.map(project);
    !separated_by_an_edge_of(&a, &b) && !separated_by_an_edge_of(&b, &a)
}

/// Separating-axis test in 2D: whether one edge line of `a` has all of `b`
/// strictly on its outer side. Two convex polygons are disjoint if and only
/// if one of their edges separates them in this way.
fn separated_by_an_edge_of(a: &[DVec2; 3], b: &[DVec2; 3]) -> bool {
    let winding = orient_2d(a[0], a[1], a[2]).signum();
    (0..3).any(|i| {
        let (from, to) = (a[i], a[(i + 1) % 3]);
        b.iter().all(|&p| orient_2d(from, to, p) * winding < 0.0)
    })
}

fn orient_2d(a: DVec2, b: DVec2, c: DVec2) -> f64 {
    (b - a).perp_dot(c - a)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_rng::Rng;

    fn tri(a: [f32; 3], b: [f32; 3], c: [f32; 3]) -> Triangle {
        Triangle::new(a.into(), b.into(), c.into()).expect("non-degenerate")
    }

    /// Independent reference for triangles in general position: they meet if
    /// and only if an edge of one crosses the other (Möller–Trumbore style,
    /// with divisions, which the predicate above avoids).
    fn edge_crosses(from: DVec3, to: DVec3, t: &Triangle) -> bool {
        let dir = to - from;
        let (e1, e2) = (t.v[1] - t.v[0], t.v[2] - t.v[0]);
        let h = dir.cross(e2);
        let det = e1.dot(h);
        if det.abs() < 1e-15 {
            return false;
        }
        let s = from - t.v[0];
        let u = s.dot(h) / det;
        let q = s.cross(e1);
        let v = dir.dot(q) / det;
        let t_hit = e2.dot(q) / det;
        u >= 0.0 && v >= 0.0 && u + v <= 1.0 && (0.0..=1.0).contains(&t_hit)
    }

    fn reference(a: &Triangle, b: &Triangle) -> bool {
        let crosses =
            |x: &Triangle, y: &Triangle| (0..3).any(|i| edge_crosses(x.v[i], x.v[(i + 1) % 3], y));
        crosses(a, b) || crosses(b, a)
    }

    #[test]
    fn agrees_with_edge_crossing_reference_on_random_pairs() {
        let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
        let (mut hits, mut tested) = (0, 0);
        while tested < 20_000 {
            let (Some(a), Some(b)) = (
                Triangle::new(rng.point().into(), rng.point().into(), rng.point().into()),
                Triangle::new(rng.point().into(), rng.point().into(), rng.point().into()),
            ) else {
                continue;
            };
            tested += 1;
            let expected = reference(&a, &b);
            assert_eq!(overlap(&a, &b), expected, "{a:?} {b:?}");
            assert_eq!(overlap(&b, &a), expected, "swapped {a:?} {b:?}");
            hits += usize::from(expected);
        }
        // Both outcomes are well represented.
        assert!(hits > 2_000 && hits < 18_000, "{hits} hits");
    }

    #[test]
    fn vertex_orders_do_not_matter() {
        let a = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
        let b = [[0.2, 0.2, -0.5], [0.3, 0.2, 0.5], [0.2, 0.3, 0.5]];
        let c = [[2.0, 0.2, -0.5], [2.1, 0.2, 0.5], [2.0, 0.3, 0.5]];
        let orders = [
            [0, 1, 2],
            [1, 2, 0],
            [2, 0, 1],
            [0, 2, 1],
            [2, 1, 0],
            [1, 0, 2],
        ];
        for o in orders {
            for p in orders {
                let t = |v: [[f32; 3]; 3], o: [usize; 3]| tri(v[o[0]], v[o[1]], v[o[2]]);
                assert!(overlap(&t(a, o), &t(b, p)));
                assert!(!overlap(&t(a, o), &t(c, p)));
            }
        }
    }

    #[test]
    fn a_vertex_resting_on_the_other_plane_meets_it_only_inside() {
        let base = tri([0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]);
        // Apex on the plane z = 0, the other corners above it.
        let resting = |x: f32, y: f32| tri([x, y, 0.0], [x + 1.0, y, 1.0], [x, y + 1.0, 1.0]);
        let hanging = |x: f32, y: f32| tri([x, y, 0.0], [x + 1.0, y, -1.0], [x, y + 1.0, -1.0]);
        for make in [resting, hanging] {
            assert!(overlap(&base, &make(0.25, 0.25)));
            assert!(overlap(&make(0.25, 0.25), &base));
            assert!(!overlap(&base, &make(0.75, 0.75)));
            assert!(!overlap(&make(0.75, 0.75), &base));
        }
    }

    #[test]
    fn coplanar_cases() {
        let a = tri([0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]);
        let overlapping = tri([0.2, 0.2, 0.0], [2.0, 0.2, 0.0], [0.2, 2.0, 0.0]);
        let inside = tri([0.1, 0.1, 0.0], [0.2, 0.1, 0.0], [0.1, 0.2, 0.0]);
        let apart = tri([0.6, 0.6, 0.0], [2.0, 0.6, 0.0], [0.6, 2.0, 0.0]);
        assert!(overlap(&a, &overlapping) && overlap(&overlapping, &a));
        assert!(overlap(&a, &inside) && overlap(&inside, &a));
        assert!(!overlap(&a, &apart) && !overlap(&apart, &a));
        // The same in a tilted plane x = y, where rounding makes the
        // plane-side signs noisy.
        let tilt = |t: &Triangle| {
            let [p, q, r] =
                t.v.map(|p| [p.x as f32 * 0.3, p.x as f32 * 0.3, p.y as f32]);
            tri(p, q, r)
        };
        assert!(overlap(&tilt(&a), &tilt(&overlapping)));
        assert!(!overlap(&tilt(&a), &tilt(&apart)));
    }

    /// Two triangles of a flat cloth a cell apart in its plane, which the
    /// simulation leaves tilted by a few nanometres (positions from a run of
    /// `fold_onto_itself`): they never overlap, though a vertex of each may
    /// lie on the other's plane within the tolerance.
    #[test]
    fn nearly_coplanar_triangles_apart_in_their_plane_do_not_overlap() {
        let a = tri(
            [0.38888788, 1.1377577, 0.0076801754],
            [0.37301493, 1.1218845, 0.0076801726],
            [0.3888879, 1.1218845, 0.0076801726],
        );
        let b = tri(
            [0.4047609, 1.1218846, 0.0076801726],
            [0.3888879, 1.1060114, 0.00768017],
            [0.40476093, 1.1060116, 0.00768017],
        );
        assert!(!overlap(&a, &b) && !overlap(&b, &a));
    }

    #[test]
    fn degenerate_and_non_finite_triangles_are_rejected() {
        let z = Vec3::ZERO;
        assert!(Triangle::new(z, Vec3::X, Vec3::X * 2.0).is_none());
        assert!(Triangle::new(z, z, Vec3::Y).is_none());
        assert!(Triangle::new(z, Vec3::X, Vec3::new(f32::NAN, 0.0, 0.0)).is_none());
        assert!(Triangle::new(z, Vec3::X, Vec3::INFINITY).is_none());
        assert!(Triangle::new(z, Vec3::X, Vec3::Y).is_some());
    }
}
