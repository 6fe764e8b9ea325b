//! Generated closed meshes for colliders: a tube around a (p, q) torus knot
//! and a subdivided icosphere.
//!
//! Both are closed and watertight (every edge is shared by exactly two
//! triangles, and the two use it in opposite directions) with
//! counter-clockwise triangles seen from outside, so a
//! [`crate::collide::MeshCollider`] built from them has a winding number of
//! one inside and zero outside.
//!
//! The torus knot follows the convention of three.js' `TorusKnotGeometry`:
//! its centre line winds `p` times around the knot's axis (here the y axis)
//! and `q` times around the core circle of a torus with radii `radius` and
//! `radius / 2`. A tube of radius `tube` around that line intersects itself
//! once `tube` reaches [`TorusKnot::max_tube`]: the smaller of the line's
//! least radius of curvature and half the shortest chord that is
//! perpendicular to the line at both ends (where two strands pass closest).
//! That limit is sharp for the smooth tube (within 1% in the tests); the
//! mesh is a polygon of it, and a coarse one (few segments) may cross itself
//! a little below the limit, so a caller that needs certainty counts the
//! mesh's self-intersections (as scenes do).

use super::Mesh;
use glam::{Quat, Vec3};
use std::collections::HashMap;
use std::f32::consts::TAU;

/// Largest `p` and `q` accepted.
pub const MAX_WINDINGS: u32 = 16;
/// Least segments along the knot per winding (of the larger of `p` and `q`).
pub const SEGMENTS_PER_WINDING: u32 = 8;
/// Most triangles a generated mesh may have.
pub const MAX_TRIANGLES: u64 = 1 << 22;
/// Most subdivisions of an icosphere (20 * 4^7 = 327,680 triangles).
pub const MAX_SUBDIVISIONS: u32 = 7;

/// A tube around a (p, q) torus knot, centred at `center`, its axis along
/// `rotation * y`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TorusKnot {
    /// Centre of the knot.
    pub center: Vec3,
    /// Turns the knot's axis from y to `rotation * y`.
    pub rotation: Quat,
    /// Major radius of the torus the centre line winds on (its minor radius is half this).
    pub radius: f32,
    /// Radius of the tube around the centre line.
    pub tube: f32,
    /// Turns around the axis.
    pub p: u32,
    /// Turns around the torus' core circle.
    pub q: u32,
    /// Rings of vertices along the knot.
    pub segments: u32,
    /// Vertices around each ring.
    pub sides: u32,
}

/// A parameter that makes no mesh: its field name and the reason.
pub type ParameterError = (&'static str, String);

/// Errors of a shape's `center` (finite) and `radius` (positive).
fn placement_errors(center: Vec3, radius: f32) -> Vec<ParameterError> {
    let mut errors = Vec::new();
    if !center.is_finite() {
        errors.push(("center", "must be three finite numbers".to_string()));
    }
    if !(radius.is_finite() && radius > 0.0) {
        errors.push(("radius", format!("must be a positive number, got {radius}")));
    }
    errors
}

impl TorusKnot {
    /// The centre line at `phi` in `[0, 2 pi)`, about the origin and
    /// unrotated, with its first and second derivatives.
    fn centre_line(&self, phi: f32) -> [Vec3; 3] {
        let (p, q, big) = (self.p as f32, self.q as f32, self.radius);
        let (sq, cq) = (q * phi).sin_cos();
        let (sp, cp) = (p * phi).sin_cos();
        // Distance from the axis, and its derivatives.
        let r = big * (2.0 + cq) * 0.5;
        let r1 = -big * q * sq * 0.5;
        let r2 = -big * q * q * cq * 0.5;
        let point = Vec3::new(r * cp, big * sq * 0.5, r * sp);
        let first = Vec3::new(
            r1 * cp - r * p * sp,
            big * q * cq * 0.5,
            r1 * sp + r * p * cp,
        );
        let second = Vec3::new(
            r2 * cp - 2.0 * r1 * p * sp - r * p * p * cp,
            -big * q * q * sq * 0.5,
            r2 * sp + 2.0 * r1 * p * cp - r * p * p * sp,
        );
        [point, first, second]
    }

    /// The largest tube radius that does not intersect itself (the smooth
    /// tube touches itself there), measured on 256 samples of the centre
    /// line per winding.
    pub fn max_tube(&self) -> f32 {
        let n = (256 * self.p.max(self.q).max(1)) as usize;
        let samples: Vec<[Vec3; 3]> = (0..n)
            .map(|i| self.centre_line(TAU * i as f32 / n as f32))
            .collect();
        let curvature_radius = samples
            .iter()
            .map(|[_, d1, d2]| d1.length().powi(3) / d1.cross(*d2).length())
            .fold(f32::INFINITY, f32::min);
        // Doubly critical chords: local minima of the distance between
        // samples i and j over the (cyclic) grid of pairs. Near the diagonal
        // the distance grows with |i - j|, so none is found there.
        let d = |i: usize, j: usize| samples[i % n][0].distance(samples[j % n][0]);
        let mut chord = f32::INFINITY;
        for i in 0..n {
            for j in i + 2..n {
                if n - (j - i) < 2 {
                    continue;
                }
                let here = d(i, j);
                if here >= chord * 1.0001 {
                    continue;
                }
                let local_minimum = [(1, 0), (n - 1, 0), (0, 1), (0, n - 1)]
                    .iter()
                    .chain(&[(1, 1), (n - 1, n - 1), (1, n - 1), (n - 1, 1)])
                    .all(|&(di, dj)| d(i + di, j + dj) >= here);
                if local_minimum {
                    chord = here;
                }
            }
        }
        curvature_radius.min(chord * 0.5)
    }

    /// Checks the parameters: positive sizes, counts in range, coprime
    /// windings and a tube thinner than [`Self::max_tube`].
    pub fn check(&self) -> Result<(), Vec<ParameterError>> {
        let mut errors = placement_errors(self.center, self.radius);
        if !(self.tube.is_finite() && self.tube > 0.0) {
            errors.push((
                "tube",
                format!("must be a positive number, got {}", self.tube),
            ));
        }
        for (name, w) in [("p", self.p), ("q", self.q)] {
            if !(1..=MAX_WINDINGS).contains(&w) {
                errors.push((
                    name,
                    format!("must be between 1 and {MAX_WINDINGS}, got {w}"),
                ));
            }
        }
        let windings_ok = errors.iter().all(|(f, _)| *f != "p" && *f != "q");
        if windings_ok && gcd(self.p, self.q) != 1 {
            errors.push((
                "q",
                format!(
                    "p = {} and q = {} share the factor {}: the line would run over itself {} times; choose coprime p and q",
                    self.p,
                    self.q,
                    gcd(self.p, self.q),
                    gcd(self.p, self.q)
                ),
            ));
        }
        let least_segments = SEGMENTS_PER_WINDING * self.p.max(self.q);
        if windings_ok && self.segments < least_segments {
            errors.push((
                "segments",
                format!(
                    "must be at least {least_segments} ({SEGMENTS_PER_WINDING} per winding) for p = {} and q = {}, got {}",
                    self.p, self.q, self.segments
                ),
            ));
        }
        if !(3..=1024).contains(&self.sides) {
            errors.push((
                "sides",
                format!("must be between 3 and 1024, got {}", self.sides),
            ));
        }
        let triangles = 2 * u64::from(self.segments) * u64::from(self.sides);
        if triangles > MAX_TRIANGLES {
            errors.push((
                "segments",
                format!("segments x sides makes {triangles} triangles, more than {MAX_TRIANGLES}"),
            ));
        }
        if errors.is_empty() {
            let limit = self.max_tube();
            if self.tube >= limit {
                errors.push((
                    "tube",
                    format!(
                        "must be less than {limit:.4} for a ({}, {}) knot of radius {}: a thicker tube intersects itself",
                        self.p, self.q, self.radius
                    ),
                ));
            }
        }
        if errors.is_empty() {
            Ok(())
        } else {
            Err(errors)
        }
    }

    /// The tube: `segments` rings of `sides` vertices, each ring
    /// perpendicular to the centre line, in a frame (tangent, normal,
    /// binormal) whose binormal is the tangent crossed with the position
    /// from the centre: smooth and periodic, so the last ring joins the first.
    ///
    /// The parameters should pass [`Self::check`]; others give a degenerate
    /// or self-intersecting mesh, never a panic.
    pub fn mesh(&self) -> Mesh {
        let (n, s) = (self.segments as usize, self.sides as usize);
        let mut mesh = Mesh {
            positions: Vec::with_capacity(n * s),
            triangles: Vec::with_capacity(2 * n * s),
            grid: None,
        };
        for i in 0..n {
            let [point, first, _] = self.centre_line(TAU * i as f32 / n as f32);
            let tangent = first.normalize_or(Vec3::X);
            let binormal = tangent.cross(point).normalize_or(Vec3::Y);
            let normal = binormal.cross(tangent);
            for j in 0..s {
                let (st, ct) = (TAU * j as f32 / s as f32).sin_cos();
                let local = point + (normal * ct + binormal * st) * self.tube;
                mesh.positions.push(self.center + self.rotation * local);
            }
        }
        let index = |i: usize, j: usize| ((i % n) * s + j % s) as u32;
        for i in 0..n {
            for j in 0..s {
                // Around the ring, then along the line: outward (see the module tests).
                let (a, b) = (index(i, j), index(i, j + 1));
                let (c, d) = (index(i + 1, j), index(i + 1, j + 1));
                mesh.triangles.extend([[a, b, d], [a, d, c]]);
            }
        }
        mesh
    }
}

/// A sphere made by splitting each triangle of an icosahedron into four,
/// `subdivisions` times, and pushing the vertices onto the sphere.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Icosphere {
    /// Centre of the sphere.
    pub center: Vec3,
    /// Radius of the sphere (m).
    pub radius: f32,
    /// Times each triangle of the icosahedron is split in four.
    pub subdivisions: u32,
}

impl Icosphere {
    /// Checks a finite centre, a positive radius and at most [`MAX_SUBDIVISIONS`].
    pub fn check(&self) -> Result<(), Vec<ParameterError>> {
        let mut errors = placement_errors(self.center, self.radius);
        if self.subdivisions > MAX_SUBDIVISIONS {
            errors.push((
                "subdivisions",
                format!(
                    "must be at most {MAX_SUBDIVISIONS}, got {}",
                    self.subdivisions
                ),
            ));
        }
        if errors.is_empty() {
            Ok(())
        } else {
            Err(errors)
        }
    }

    /// `20 * 4^subdivisions` triangles; edges are split once each (shared midpoints).
    pub fn mesh(&self) -> Mesh {
        let t = (1.0 + 5f32.sqrt()) / 2.0;
        let mut positions: Vec<Vec3> = [
            [-1.0, t, 0.0],
            [1.0, t, 0.0],
            [-1.0, -t, 0.0],
            [1.0, -t, 0.0],
            [0.0, -1.0, t],
            [0.0, 1.0, t],
            [0.0, -1.0, -t],
            [0.0, 1.0, -t],
            [t, 0.0, -1.0],
            [t, 0.0, 1.0],
            [-t, 0.0, -1.0],
            [-t, 0.0, 1.0],
        ]
        .map(|v| Vec3::from_array(v).normalize())
        .to_vec();
        let mut triangles: Vec<[u32; 3]> = vec![
            [0, 11, 5],
            [0, 5, 1],
            [0, 1, 7],
            [0, 7, 10],
            [0, 10, 11],
            [1, 5, 9],
            [5, 11, 4],
            [11, 10, 2],
            [10, 7, 6],
            [7, 1, 8],
            [3, 9, 4],
            [3, 4, 2],
            [3, 2, 6],
            [3, 6, 8],
            [3, 8, 9],
            [4, 9, 5],
            [2, 4, 11],
            [6, 2, 10],
            [8, 6, 7],
            [9, 8, 1],
        ];
        for _ in 0..self.subdivisions.min(MAX_SUBDIVISIONS) {
            let mut midpoints = HashMap::new();
            let mut midpoint = |a: u32, b: u32| {
                *midpoints.entry((a.min(b), a.max(b))).or_insert_with(|| {
                    let m = (positions[a as usize] + positions[b as usize]).normalize();
                    positions.push(m);
                    positions.len() as u32 - 1
                })
            };
            triangles = triangles
                .iter()
                .flat_map(|&[a, b, c]| {
                    let (ab, bc, ca) = (midpoint(a, b), midpoint(b, c), midpoint(c, a));
                    [[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]
                })
                .collect();
        }
        for p in &mut positions {
            *p = self.center + *p * self.radius;
        }
        Mesh {
            positions,
            triangles,
            grid: None,
        }
    }
}

fn gcd(a: u32, b: u32) -> u32 {
    if b == 0 {
        a
    } else {
        gcd(b, a % b)
    }
}

/// Whether every edge of `mesh` is used by exactly two triangles, once in
/// each direction: a closed, consistently oriented surface.
pub fn is_closed_and_oriented(mesh: &Mesh) -> bool {
    let mut directed: HashMap<(u32, u32), u32> = HashMap::new();
    for &[a, b, c] in &mesh.triangles {
        for edge in [(a, b), (b, c), (c, a)] {
            *directed.entry(edge).or_default() += 1;
        }
    }
    directed
        .iter()
        .all(|(&(a, b), &count)| count == 1 && directed.get(&(b, a)) == Some(&1))
}

/// Volume enclosed by a closed mesh (divergence theorem): positive when its
/// triangles face outward.
pub fn signed_volume(mesh: &Mesh) -> f32 {
    mesh.triangles
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|i| mesh.positions[i as usize]);
            a.dot(b.cross(c)) / 6.0
        })
        .sum()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::collide::MeshCollider;
    use crate::metrics::intersections::count_self_intersections;
    use std::f32::consts::PI;

    fn trefoil(tube: f32) -> TorusKnot {
        TorusKnot {
            center: Vec3::new(0.5, 1.0, -0.2),
            rotation: Quat::IDENTITY,
            radius: 1.0,
            tube,
            p: 2,
            q: 3,
            segments: 128,
            sides: 12,
        }
    }

    #[test]
    fn torus_knot_is_closed_outward_and_watertight() {
        let knot = trefoil(0.2);
        let mesh = knot.mesh();
        assert_eq!(mesh.triangles.len(), 2 * 128 * 12);
        assert_eq!(mesh.positions.len(), 128 * 12);
        assert!(is_closed_and_oriented(&mesh));
        // Euler characteristic of a torus: V - E + F = 0.
        let (v, f) = (mesh.positions.len(), mesh.triangles.len());
        assert_eq!(v + f, 3 * f / 2);
        // A tube of length L and radius r holds about pi r^2 L.
        let length: f32 = (0..4096)
            .map(|i| {
                let phi = TAU * i as f32 / 4096.0;
                knot.centre_line(phi)[1].length() * TAU / 4096.0
            })
            .sum();
        let volume = signed_volume(&mesh);
        let expected = PI * 0.2 * 0.2 * length;
        assert!(
            volume > 0.9 * expected && volume < 1.02 * expected,
            "{volume} vs {expected}"
        );
        // Inside on the centre line, outside at the centre and far away.
        let collider = MeshCollider::new(&mesh);
        for i in 0..16 {
            let c = knot.center + knot.centre_line(TAU * i as f32 / 16.0)[0];
            let w = collider.winding_number(c);
            assert!((w - 1.0).abs() < 0.05, "winding number {w} at {c}");
            assert!(collider.signed_distance(c).0 < -0.18);
        }
        assert!(collider.winding_number(knot.center).abs() < 0.05);
        assert!(collider.signed_distance(knot.center + Vec3::Y * 5.0).0 > 4.0);
    }

    #[test]
    fn trefoil_tube_limit_and_no_self_intersection_below_it() {
        let limit = trefoil(0.1).max_tube();
        // Strands of the (2, 3) knot of radius 1 pass about 0.6 apart.
        assert!(limit > 0.2 && limit < 0.5, "{limit}");
        let mut knot = trefoil(0.95 * limit);
        knot.segments = SEGMENTS_PER_WINDING * 3 * 4;
        assert!(knot.check().is_ok());
        let mesh = knot.mesh();
        assert_eq!(
            count_self_intersections(&mesh.positions, &mesh.triangles),
            0
        );
        // Beyond the limit, strands cross.
        let thick = trefoil(1.1 * limit);
        assert!(thick.check().is_err());
        let mesh = thick.mesh();
        assert!(count_self_intersections(&mesh.positions, &mesh.triangles) > 0);
    }

    #[test]
    fn other_knots_are_closed_and_below_their_limit() {
        for (p, q) in [(3, 2), (1, 1), (3, 5), (5, 2)] {
            let mut knot = trefoil(0.0);
            (knot.p, knot.q) = (p, q);
            knot.segments = 64 * p.max(q);
            knot.rotation = Quat::from_rotation_x(0.7);
            knot.tube = 0.9 * knot.max_tube();
            knot.check().unwrap();
            let mesh = knot.mesh();
            assert!(is_closed_and_oriented(&mesh), "({p}, {q})");
            assert!(signed_volume(&mesh) > 0.0, "({p}, {q})");
            assert_eq!(
                count_self_intersections(&mesh.positions, &mesh.triangles),
                0,
                "({p}, {q}) with tube {}",
                knot.tube
            );
        }
    }

    #[test]
    fn bad_knot_parameters_name_their_field() {
        let fields = |k: TorusKnot| -> Vec<&'static str> {
            k.check().unwrap_err().into_iter().map(|(f, _)| f).collect()
        };
        let mut k = trefoil(0.2);
        k.q = 4;
        k.p = 2;
        assert_eq!(fields(k), ["q"]);
        let mut k = trefoil(-1.0);
        k.sides = 2;
        assert_eq!(fields(k), ["tube", "sides"]);
        let mut k = trefoil(0.2);
        k.segments = 10;
        assert_eq!(fields(k), ["segments"]);
        assert_eq!(fields(trefoil(0.9)), ["tube"]);
    }

    #[test]
    fn icosphere_is_closed_outward_and_round() {
        for subdivisions in 0..4 {
            let sphere = Icosphere {
                center: Vec3::new(1.0, 2.0, 3.0),
                radius: 0.5,
                subdivisions,
            };
            let mesh = sphere.mesh();
            assert_eq!(mesh.triangles.len(), 20 * 4usize.pow(subdivisions));
            assert_eq!(mesh.positions.len(), 10 * 4usize.pow(subdivisions) + 2);
            assert!(is_closed_and_oriented(&mesh));
            let volume = signed_volume(&mesh);
            let ball = 4.0 / 3.0 * PI * 0.125;
            assert!(volume > 0.6 * ball && volume <= ball, "{volume}");
            for p in &mesh.positions {
                assert!((p.distance(sphere.center) - 0.5).abs() < 1e-5);
            }
        }
    }
}
