//! The layer order of a folded state: which of two stacked faces lies above
//! the other, as FOLD's `faceOrders` gives it.
//!
//! Two triangles are stacked when they are nearly parallel (within
//! [`PARALLEL_DEGREES`]), their projections onto the second one's plane
//! overlap in an area (not only along an edge or at a corner), and at the
//! overlap's centroid they lie closer along that plane's normal than
//! [`STACKED`] times the overlap's size: the layers of a flat fold, a
//! thickness apart, are stacked; the walls of a box are not. The first lies
//! above the second (`+1`) when it is on the side the second's normal
//! points to, below (`-1`) otherwise, as the FOLD specification has it.
//! A crossing pair, whose layers pass through each other, has no single
//! order: it is given by its overlap's centroid alone.

use super::intersections::tri_bvh::TriBvh;
use crate::math::Aabb;
use glam::{DVec2, DVec3, Vec3};

/// Most angle between two stacked faces' planes (degrees).
pub const PARALLEL_DEGREES: f64 = 15.0;
/// Most distance between two stacked faces along the normal, in square
/// roots of their overlap's area.
pub const STACKED: f64 = 0.25;
/// Least overlap, as a fraction of the smaller face's area, that counts
/// (neighbours that only touch overlap in nothing but round-off).
const LEAST_OVERLAP: f64 = 1e-4;

/// One entry of `faceOrders`: face `f` lies above (`s = 1`) or below
/// (`s = -1`) face `g`, relative to `g`'s normal.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct FaceOrder {
    /// The face placed.
    pub f: u32,
    /// The face it is placed against.
    pub g: u32,
    /// 1: `f` lies on the side `g`'s normal points to; -1: on the other.
    pub s: i8,
}

/// The order of every stacked pair of `triangles` at `positions`, each pair
/// once with `f < g`, sorted. Degenerate and non-finite triangles take no part.
pub fn face_orders(positions: &[Vec3], triangles: &[[u32; 3]]) -> Vec<FaceOrder> {
    let faces: Vec<Option<Face>> = triangles
        .iter()
        .map(|t| Face::new(t.map(|i| positions.get(i as usize).copied())))
        .collect();
    let boxes = faces
        .iter()
        .enumerate()
        .filter_map(|(k, f)| f.as_ref().map(|f| (k as u32, f.reach_box())))
        .collect();
    let mut orders = Vec::new();
    TriBvh::build(boxes).for_each_overlapping_pair(|a, b| {
        let (f, g) = (a.min(b), a.max(b));
        if let (Some(face_f), Some(face_g)) = (&faces[f as usize], &faces[g as usize]) {
            if let Some(s) = face_f.side_of(face_g) {
                orders.push(FaceOrder { f, g, s });
            }
        }
    });
    orders.sort_unstable_by_key(|o| (o.f, o.g));
    orders
}

/// A triangle prepared for the tests, in `f64`.
struct Face {
    corners: [DVec3; 3],
    normal: DVec3,
    area: f64,
}

impl Face {
    fn new(corners: [Option<Vec3>; 3]) -> Option<Face> {
        let corners = [corners[0]?, corners[1]?, corners[2]?].map(|c| c.as_dvec3());
        if !corners.iter().all(|c| c.is_finite()) {
            return None;
        }
        let cross = (corners[1] - corners[0]).cross(corners[2] - corners[0]);
        let area = 0.5 * cross.length();
        (area > 0.0).then(|| Face {
            corners,
            normal: cross.normalize(),
            area,
        })
    }

    /// The triangle's box grown by as far as a face stacked on it may lie.
    fn reach_box(&self) -> Aabb {
        let points = self.corners.map(|c| c.as_vec3());
        let reach = (STACKED * (2.0 * self.area).sqrt()) as f32;
        Aabb::of_points(points).expanded(reach)
    }

    /// Whether `self` lies above (+1) or below (-1) `other`, relative to
    /// `other`'s normal; `None` when they are not stacked.
    fn side_of(&self, other: &Face) -> Option<i8> {
        if self.normal.dot(other.normal).abs() < PARALLEL_DEGREES.to_radians().cos() {
            return None;
        }
        let plane = Plane::of(other);
        let mine = self.corners.map(|c| plane.project(c));
        let theirs = other.corners.map(|c| plane.project(c));
        let overlap = clip(&ccw(mine), &ccw(theirs));
        let (area, centroid) = area_and_centroid(&overlap);
        if area < LEAST_OVERLAP * self.area.min(other.area) {
            return None;
        }
        let height = interpolate(mine, self.corners.map(|c| plane.height(c)), centroid)
            - interpolate(theirs, other.corners.map(|c| plane.height(c)), centroid);
        (height.abs() <= STACKED * area.sqrt() && height != 0.0).then_some(if height > 0.0 {
            1
        } else {
            -1
        })
    }
}

/// A face's plane, with axes in it and its normal.
struct Plane {
    origin: DVec3,
    u: DVec3,
    v: DVec3,
    normal: DVec3,
}

impl Plane {
    fn of(face: &Face) -> Plane {
        let u = (face.corners[1] - face.corners[0]).normalize();
        Plane {
            origin: face.corners[0],
            u,
            v: face.normal.cross(u),
            normal: face.normal,
        }
    }

    fn project(&self, p: DVec3) -> DVec2 {
        let d = p - self.origin;
        DVec2::new(d.dot(self.u), d.dot(self.v))
    }

    fn height(&self, p: DVec3) -> f64 {
        (p - self.origin).dot(self.normal)
    }
}

/// The triangle's corners counter-clockwise.
fn ccw(t: [DVec2; 3]) -> [DVec2; 3] {
    if (t[1] - t[0]).perp_dot(t[2] - t[0]) < 0.0 {
        [t[0], t[2], t[1]]
    } else {
        t
    }
}

/// The convex polygon `subject` clipped by the counter-clockwise triangle
/// `clipper` (Sutherland-Hodgman).
fn clip(subject: &[DVec2], clipper: &[DVec2; 3]) -> Vec<DVec2> {
    let mut polygon = subject.to_vec();
    for k in 0..3 {
        let (a, b) = (clipper[k], clipper[(k + 1) % 3]);
        let inside = |p: DVec2| (b - a).perp_dot(p - a);
        let input = std::mem::take(&mut polygon);
        for (i, &p) in input.iter().enumerate() {
            let q = input[(i + 1) % input.len()];
            let (dp, dq) = (inside(p), inside(q));
            if dp >= 0.0 {
                polygon.push(p);
            }
            if (dp >= 0.0) != (dq >= 0.0) {
                polygon.push(p + (q - p) * (dp / (dp - dq)));
            }
        }
        if polygon.is_empty() {
            break;
        }
    }
    polygon
}

/// A polygon's area and centroid (zero area for fewer than three corners).
fn area_and_centroid(polygon: &[DVec2]) -> (f64, DVec2) {
    let (mut twice_area, mut weighted) = (0.0, DVec2::ZERO);
    for (i, &p) in polygon.iter().enumerate() {
        let q = polygon[(i + 1) % polygon.len()];
        let cross = p.perp_dot(q);
        twice_area += cross;
        weighted += (p + q) * cross;
    }
    if twice_area <= 0.0 {
        return (0.0, DVec2::ZERO);
    }
    (0.5 * twice_area, weighted / (3.0 * twice_area))
}

/// The value at `p` of the linear function that is `values` at the corners
/// of the triangle `t`.
fn interpolate(t: [DVec2; 3], values: [f64; 3], p: DVec2) -> f64 {
    let det = (t[1] - t[0]).perp_dot(t[2] - t[0]);
    let b1 = (p - t[0]).perp_dot(t[2] - t[0]) / det;
    let b2 = (t[1] - t[0]).perp_dot(p - t[0]) / det;
    values[0] * (1.0 - b1 - b2) + values[1] * b1 + values[2] * b2
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A unit right triangle at height `y`, facing up (+y) or down.
    fn triangle(y: f32, up: bool) -> [Vec3; 3] {
        let [a, b, c] = [
            Vec3::new(0.0, y, 0.0),
            Vec3::new(0.0, y, 1.0),
            Vec3::new(1.0, y, 0.0),
        ];
        if up {
            [a, b, c]
        } else {
            [a, c, b]
        }
    }

    fn orders(lower: [Vec3; 3], upper: [Vec3; 3]) -> Vec<FaceOrder> {
        let positions = [lower, upper].concat();
        face_orders(&positions, &[[0, 1, 2], [3, 4, 5]])
    }

    #[test]
    fn a_face_above_another_is_on_the_side_its_normal_points_to() {
        let up = orders(triangle(0.0, true), triangle(0.001, true));
        assert_eq!(up, [FaceOrder { f: 0, g: 1, s: -1 }], "0 lies below 1");
        // Face 1 turned over: face 0 now lies on the side its normal points to.
        let over = orders(triangle(0.0, true), triangle(0.001, false));
        assert_eq!(over, [FaceOrder { f: 0, g: 1, s: 1 }]);
        // The layers swapped: the order turns round.
        let swapped = orders(triangle(0.001, true), triangle(0.0, true));
        assert_eq!(swapped, [FaceOrder { f: 0, g: 1, s: 1 }]);
    }

    #[test]
    fn faces_that_only_touch_or_lie_far_apart_or_across_have_no_order() {
        let beside = triangle(0.0, true).map(|p| p + Vec3::new(1.0, 0.0, 0.0));
        assert!(orders(triangle(0.0, true), beside).is_empty(), "touching");
        assert!(orders(triangle(0.0, true), triangle(0.5, true)).is_empty());
        let wall = [
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
            Vec3::new(1.0, 0.0, 0.0),
        ];
        assert!(orders(triangle(0.0, true), wall).is_empty(), "across");
    }

    #[test]
    fn heights_are_interpolated_linearly_over_a_face() {
        let t = [DVec2::ZERO, DVec2::new(2.0, 0.0), DVec2::new(0.0, 4.0)];
        let at = |p: DVec2| interpolate(t, [1.0, 3.0, 9.0], p);
        assert!((at(DVec2::new(1.0, 1.0)) - (1.0 + 1.0 + 2.0)).abs() < 1e-12);
        assert!((at(DVec2::new(0.0, 4.0)) - 9.0).abs() < 1e-12);
    }

    #[test]
    fn a_partial_overlap_is_ordered_at_its_centroid() {
        let shifted = triangle(0.002, true).map(|p| p + Vec3::new(0.5, 0.0, 0.0));
        assert_eq!(
            orders(triangle(0.0, true), shifted),
            [FaceOrder { f: 0, g: 1, s: -1 }]
        );
    }
}
