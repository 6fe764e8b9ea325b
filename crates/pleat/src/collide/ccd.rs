//! Continuous collision detection of a vertex against a triangle and of an
//! edge against an edge (Provot 1997; Bridson et al. 2002): with every point
//! moving linearly over the substep, four points become coplanar when the
//! triple product `(b - a) x (c - a) . (p - a)`, a cubic in `t`, vanishes. The
//! cubic is split at the roots of its derivative into monotone pieces, each
//! bracketed and solved by safeguarded Newton iteration, earliest first; a
//! root counts when the vertex lies inside the triangle, or the two edges
//! meet, at that time.
//!
//! The arithmetic is `f64`: the triple product of small cloth edges is tiny.

use glam::{DVec3, Vec3};

/// Slack on barycentric coordinates when testing "inside the triangle".
pub(crate) const INSIDE_TOLERANCE: f64 = 1e-3;
/// Newton steps per monotone piece (bisection takes over when Newton strays).
const MAX_STEPS: usize = 40;

/// Positions of one point at the start and end of the substep.
#[derive(Clone, Copy, Debug)]
pub struct Sweep {
    /// Position at the start of the substep.
    pub start: Vec3,
    /// Position at the end of the substep.
    pub end: Vec3,
}

/// Where a vertex first hits a triangle: the time in `[0, 1]` and the
/// barycentric coordinates of the hit point on the triangle.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    /// Time of the hit as a fraction of the substep, in `[0, 1]`.
    pub t: f32,
    /// Barycentric coordinates of the hit point on the triangle `abc`.
    pub barycentric: [f32; 3],
}

/// The earliest time the vertex `p` crosses the triangle `abc`, if it does.
pub fn vertex_triangle(p: Sweep, a: Sweep, b: Sweep, c: Sweep) -> Option<Hit> {
    let at = |s: Sweep, t: f64| s.start.as_dvec3() + (s.end - s.start).as_dvec3() * t;
    let k = coplanarity_cubic(p, a, b, c);
    let mut found = None;
    for_each_root(k, |t| {
        let bary = barycentric(at(p, t), at(a, t), at(b, t), at(c, t))?;
        found = Some(Hit {
            t: t as f32,
            barycentric: bary.map(|x| x as f32),
        });
        Some(())
    });
    found
}

/// Where two edges first meet: the time in `[0, 1]` and the parameters of the
/// meeting point along each edge (`0` at its first end, `1` at its second).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EdgeHit {
    /// Time of the meeting as a fraction of the substep, in `[0, 1]`.
    pub t: f32,
    /// Parameter of the meeting point along the first edge.
    pub s: f32,
    /// Parameter of the meeting point along the second edge.
    pub u: f32,
}

/// The earliest time the edges `a0 a1` and `b0 b1` cross, if they do.
pub fn edge_edge(a0: Sweep, a1: Sweep, b0: Sweep, b1: Sweep) -> Option<EdgeHit> {
    let at = |s: Sweep, t: f32| s.start.lerp(s.end, t);
    let k = coplanarity_cubic(b1, a0, a1, b0);
    let mut found = None;
    for_each_root(k, |t| {
        let t = t as f32;
        let [p0, p1, q0, q1] = [a0, a1, b0, b1].map(|e| at(e, t));
        let (s, u) = segment_closest_params(p0, p1, q0, q1);
        let gap = p0.lerp(p1, s).distance(q0.lerp(q1, u));
        let scale = p0.distance(p1).max(q0.distance(q1));
        (gap <= INSIDE_TOLERANCE as f32 * scale).then_some(())?;
        found = Some(EdgeHit { t, s, u });
        Some(())
    });
    found
}

/// Parameters `(s, u)` in `[0, 1]` of the closest points of the segments
/// `p0 p1` and `q0 q1` (Ericson, Real-Time Collision Detection 5.1.9).
pub fn segment_closest_params(p0: Vec3, p1: Vec3, q0: Vec3, q1: Vec3) -> (f32, f32) {
    let (d1, d2, r) = (p1 - p0, q1 - q0, p0 - q0);
    let (a, e, f) = (d1.length_squared(), d2.length_squared(), d2.dot(r));
    if a <= f32::EPSILON && e <= f32::EPSILON {
        return (0.0, 0.0);
    }
    if a <= f32::EPSILON {
        return (0.0, (f / e).clamp(0.0, 1.0));
    }
    let c = d1.dot(r);
    if e <= f32::EPSILON {
        return ((-c / a).clamp(0.0, 1.0), 0.0);
    }
    let b = d1.dot(d2);
    let denom = a * e - b * b;
    let mut s = if denom > 0.0 {
        ((b * f - c * e) / denom).clamp(0.0, 1.0)
    } else {
        0.0
    };
    let mut u = (b * s + f) / e;
    if u < 0.0 {
        u = 0.0;
        s = (-c / a).clamp(0.0, 1.0);
    } else if u > 1.0 {
        u = 1.0;
        s = ((b - c) / a).clamp(0.0, 1.0);
    }
    (s, u)
}

/// Distance between the segments `p0 p1` and `q0 q1`.
pub fn segment_distance(p0: Vec3, p1: Vec3, q0: Vec3, q1: Vec3) -> f32 {
    let (s, u) = segment_closest_params(p0, p1, q0, q1);
    p0.lerp(p1, s).distance(q0.lerp(q1, u))
}

/// Distance from `p` to the triangle `abc` (Ericson, Real-Time Collision Detection 5.1.5).
pub fn point_triangle_distance(p: Vec3, a: Vec3, b: Vec3, c: Vec3) -> f32 {
    let (ab, ac, ap) = (b - a, c - a, p - a);
    let (d1, d2) = (ab.dot(ap), ac.dot(ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return ap.length();
    }
    let bp = p - b;
    let (d3, d4) = (ab.dot(bp), ac.dot(bp));
    if d3 >= 0.0 && d4 <= d3 {
        return bp.length();
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return p.distance(a + ab * (d1 / (d1 - d3)));
    }
    let cp = p - c;
    let (d5, d6) = (ab.dot(cp), ac.dot(cp));
    if d6 >= 0.0 && d5 <= d6 {
        return cp.length();
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        return p.distance(a + ac * (d2 / (d2 - d6)));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        return p.distance(b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6))));
    }
    let denom = 1.0 / (va + vb + vc);
    p.distance(a + ab * (vb * denom) + ac * (vc * denom))
}

/// Coefficients `k[0] + k[1] t + k[2] t^2 + k[3] t^3` of the triple product.
fn coplanarity_cubic(p: Sweep, a: Sweep, b: Sweep, c: Sweep) -> [f64; 4] {
    let rel = |s: Sweep| {
        (
            (s.start - a.start).as_dvec3(),
            ((s.end - s.start) - (a.end - a.start)).as_dvec3(),
        )
    };
    let (e1, v1) = rel(b);
    let (e2, v2) = rel(c);
    let (q, vq) = rel(p);
    let n0 = e1.cross(e2);
    let n1 = e1.cross(v2) + v1.cross(e2);
    let n2 = v1.cross(v2);
    [
        n0.dot(q),
        n0.dot(vq) + n1.dot(q),
        n1.dot(vq) + n2.dot(q),
        n2.dot(vq),
    ]
}

fn eval(k: [f64; 4], t: f64) -> f64 {
    ((k[3] * t + k[2]) * t + k[1]) * t + k[0]
}

fn derivative(k: [f64; 4], t: f64) -> f64 {
    (3.0 * k[3] * t + 2.0 * k[2]) * t + k[1]
}

/// Calls `accept` on the roots of the cubic in `[0, 1]`, earliest first,
/// until it returns `Some`.
fn for_each_root(k: [f64; 4], mut accept: impl FnMut(f64) -> Option<()>) {
    let mut bounds = [0.0, 1.0, 1.0, 1.0];
    let mut len = 1;
    for t in critical_points(k) {
        if t > bounds[len - 1] && t < 1.0 {
            bounds[len] = t;
            len += 1;
        }
    }
    bounds[len] = 1.0;
    for w in bounds[..=len].windows(2) {
        if let Some(t) = monotone_root(k, w[0], w[1]) {
            if accept(t).is_some() {
                return;
            }
        }
    }
}

/// Roots of the derivative in `(0, 1)`, sorted (NaN where there is none).
fn critical_points(k: [f64; 4]) -> [f64; 2] {
    let (qa, qb, qc) = (3.0 * k[3], 2.0 * k[2], k[1]);
    let scale = qa.abs().max(qb.abs()).max(qc.abs());
    if scale == 0.0 {
        return [f64::NAN; 2];
    }
    if qa.abs() <= 1e-12 * scale {
        return [if qb != 0.0 { -qc / qb } else { f64::NAN }, f64::NAN];
    }
    let disc = qb * qb - 4.0 * qa * qc;
    if disc < 0.0 {
        return [f64::NAN; 2];
    }
    // Numerically stable quadratic roots.
    let q = -0.5 * (qb + qb.signum() * disc.sqrt());
    let (r1, r2) = (q / qa, if q != 0.0 { qc / q } else { f64::NAN });
    [r1.min(r2), r1.max(r2)]
}

/// The root of a cubic that is monotone on `[lo, hi]`, if it changes sign there.
fn monotone_root(k: [f64; 4], mut lo: f64, mut hi: f64) -> Option<f64> {
    let (mut f_lo, f_hi) = (eval(k, lo), eval(k, hi));
    if f_lo == 0.0 {
        return Some(lo);
    }
    if f_lo.signum() == f_hi.signum() {
        return None;
    }
    let mut t = 0.5 * (lo + hi);
    for _ in 0..MAX_STEPS {
        let f = eval(k, t);
        if f == 0.0 {
            return Some(t);
        }
        if f.signum() == f_lo.signum() {
            lo = t;
            f_lo = f;
        } else {
            hi = t;
        }
        let d = derivative(k, t);
        let newton = t - f / d;
        t = if d != 0.0 && newton > lo && newton < hi {
            newton
        } else {
            0.5 * (lo + hi)
        };
        if hi - lo < 1e-9 {
            break;
        }
    }
    Some(t)
}

/// Barycentric coordinates of `p` projected onto the triangle's plane, if the
/// projection lies inside the triangle (within [`INSIDE_TOLERANCE`]).
fn barycentric(p: DVec3, a: DVec3, b: DVec3, c: DVec3) -> Option<[f64; 3]> {
    let (ab, ac, ap) = (b - a, c - a, p - a);
    let (d00, d01, d11) = (ab.dot(ab), ab.dot(ac), ac.dot(ac));
    let (d20, d21) = (ap.dot(ab), ap.dot(ac));
    let denom = d00 * d11 - d01 * d01;
    if denom <= 0.0 {
        return None;
    }
    let v = (d11 * d20 - d01 * d21) / denom;
    let w = (d00 * d21 - d01 * d20) / denom;
    let u = 1.0 - v - w;
    [u, v, w]
        .iter()
        .all(|&x| x >= -INSIDE_TOLERANCE)
        .then_some([u, v, w])
}

/// Barycentric coordinates of the projection of `p` onto the triangle `abc`,
/// if it falls inside; for discrete (proximity) contacts.
pub fn projection_inside(p: Vec3, a: Vec3, b: Vec3, c: Vec3) -> Option<[f32; 3]> {
    barycentric(p.as_dvec3(), a.as_dvec3(), b.as_dvec3(), c.as_dvec3()).map(|b| b.map(|x| x as f32))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn still(p: Vec3) -> Sweep {
        Sweep { start: p, end: p }
    }

    fn unit_triangle() -> [Sweep; 3] {
        [
            still(Vec3::new(0.0, 0.0, 0.0)),
            still(Vec3::new(1.0, 0.0, 0.0)),
            still(Vec3::new(0.0, 0.0, 1.0)),
        ]
    }

    #[test]
    fn vertex_through_a_still_triangle() {
        let [a, b, c] = unit_triangle();
        let p = Sweep {
            start: Vec3::new(0.25, 1.0, 0.25),
            end: Vec3::new(0.25, -3.0, 0.25),
        };
        let hit = vertex_triangle(p, a, b, c).expect("crosses");
        assert!((hit.t - 0.25).abs() < 1e-6, "{hit:?}");
        assert!((hit.barycentric[1] - 0.25).abs() < 1e-5);
    }

    #[test]
    fn vertex_passing_beside_the_triangle_is_no_hit() {
        let [a, b, c] = unit_triangle();
        let p = Sweep {
            start: Vec3::new(0.8, 1.0, 0.8),
            end: Vec3::new(0.8, -1.0, 0.8),
        };
        assert_eq!(vertex_triangle(p, a, b, c), None);
    }

    #[test]
    fn crossing_edges_are_found_where_they_meet() {
        // A still edge along x; another, along z, drops through it at t = 0.4.
        let a0 = still(Vec3::new(-1.0, 0.0, 0.0));
        let a1 = still(Vec3::new(1.0, 0.0, 0.0));
        let b0 = Sweep {
            start: Vec3::new(0.5, 0.4, -1.0),
            end: Vec3::new(0.5, -0.6, -1.0),
        };
        let b1 = Sweep {
            start: Vec3::new(0.5, 0.4, 3.0),
            end: Vec3::new(0.5, -0.6, 3.0),
        };
        let hit = edge_edge(a0, a1, b0, b1).expect("crosses");
        assert!((hit.t - 0.4).abs() < 1e-5, "{hit:?}");
        assert!(
            (hit.s - 0.75).abs() < 1e-4 && (hit.u - 0.25).abs() < 1e-4,
            "{hit:?}"
        );
        // Shifted past the end of the still edge, it passes by.
        let shift = |s: Sweep| Sweep {
            start: s.start + Vec3::X * 0.6,
            end: s.end + Vec3::X * 0.6,
        };
        assert_eq!(edge_edge(a0, a1, shift(b0), shift(b1)), None);
    }

    #[test]
    fn point_triangle_distance_matches_a_fine_search() {
        let mut rng = crate::test_rng::Rng(11);
        for _ in 0..200 {
            let [p, a, b, c] = [(); 4].map(|_| rng.vec3() * 2.0 - 1.0);
            let d = point_triangle_distance(p, a, b, c);
            let steps = 100;
            let brute = (0..=steps)
                .flat_map(|i| (0..=steps - i).map(move |j| (i, j)))
                .map(|(i, j)| {
                    let (u, v) = (i as f32 / steps as f32, j as f32 / steps as f32);
                    p.distance(a + (b - a) * u + (c - a) * v)
                })
                .fold(f32::MAX, f32::min);
            assert!(d <= brute + 1e-5 && d >= brute - 0.05, "{d} vs {brute}");
        }
    }

    #[test]
    fn closest_params_match_a_fine_search() {
        let mut rng = crate::test_rng::Rng(9);
        for _ in 0..200 {
            let [p0, p1, q0, q1] = [(); 4].map(|_| rng.vec3() * 2.0 - 1.0);
            let (s, u) = segment_closest_params(p0, p1, q0, q1);
            let best = p0.lerp(p1, s).distance(q0.lerp(q1, u));
            let steps = 100;
            let brute = (0..=steps)
                .flat_map(|i| (0..=steps).map(move |j| (i, j)))
                .map(|(i, j)| {
                    let (a, b) = (i as f32 / steps as f32, j as f32 / steps as f32);
                    p0.lerp(p1, a).distance(q0.lerp(q1, b))
                })
                .fold(f32::MAX, f32::min);
            assert!(best <= brute + 1e-5, "{best} > {brute}");
        }
    }

    #[test]
    fn rotating_triangle_sweeps_over_a_still_vertex() {
        // The triangle flips from above the vertex to below it, crossing it
        // only through a nonlinear (cubic) path.
        let a = still(Vec3::ZERO);
        let b = Sweep {
            start: Vec3::new(1.0, 0.5, 0.0),
            end: Vec3::new(1.0, -0.5, 0.0),
        };
        let c = Sweep {
            start: Vec3::new(0.0, 0.5, 1.0),
            end: Vec3::new(0.0, -0.5, 1.0),
        };
        let p = still(Vec3::new(0.3, 0.0, 0.3));
        let hit = vertex_triangle(p, a, b, c).expect("swept over");
        assert!((hit.t - 0.5).abs() < 1e-5, "{hit:?}");
    }
}
