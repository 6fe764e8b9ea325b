//! Contact corrections, as XPBD contact constraints of compliance zero
//! (Macklin et al. 2014, "Unified particle physics"), each computed from the
//! current positions alone so that all contacts can be evaluated in parallel:
//!
//! - particle-particle: `C = |x_i - x_j| - thickness >= 0`;
//! - vertex-triangle: `C = s n . (p - q) - thickness >= 0`, with `q` the
//!   contact point on the triangle and `s` the side the vertex came from; a
//!   vertex that crossed the triangle's plane within the substep is caught by
//!   continuous collision detection ([`ccd::vertex_triangle`]) and pulled back;
//! - edge-edge: `C = |p_a - p_b| - thickness >= 0` between points of the two
//!   edges fixed when the contact is found (their closest points at the
//!   substep's end); edges that crossed during the substep
//!   ([`ccd::edge_edge`], checked once per substep when they may have) are
//!   held at the points where they met, along the separation they had at
//!   the substep's start: `C = n . (p_a - p_b) - thickness >= 0`.
//!
//! Each contact also removes relative tangential motion (Coulomb friction,
//! static then kinetic, as for colliders). Every correction is equal and
//! opposite, weighted by inverse mass, so each contact keeps linear momentum.

use super::SelfCollision;
use crate::collide::ccd::{self, Sweep};
use crate::collide::Friction;
use glam::Vec3;

/// An edge-edge contact: edge `a` is `v[0] v[1]`, edge `b` is `v[2] v[3]`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct EdgePair {
    pub v: [u32; 4],
    /// Parameters of the contact points along each edge.
    pub s: f32,
    pub u: f32,
    /// Whether the edges were close enough, given how far they moved, to
    /// have crossed during the substep.
    pub may_cross: bool,
    /// Once found to have crossed: the unit direction from `b` to `a` at the
    /// substep's start.
    pub crossed: Option<Vec3>,
    /// Where paper's layer order gives it: a triangle of a facet of `b`
    /// and the side of it (along its normal) that `a` belongs on
    /// ([`super::layer_sides`]); edges that cross towards it are let
    /// through.
    pub belongs: Option<([u32; 3], i8)>,
}

/// A candidate contact.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Contact {
    Pair([u32; 2]),
    /// Vertex, then the triangle's corners; the side of the triangle (of
    /// its normal) the vertex belongs on in paper's layer order, 0 where
    /// none is known ([`super::layer_sides`]).
    VertexTriangle([u32; 4], i8),
    EdgeEdge(EdgePair),
}

impl Contact {
    pub fn particles(&self) -> &[u32] {
        match self {
            Contact::Pair(v) => v,
            Contact::VertexTriangle(v, _) | Contact::EdgeEdge(EdgePair { v, .. }) => v,
        }
    }

    /// Readies a kept candidate for the substep from `x_prev` to `x`, as the
    /// broad phase finds a new one: an edge pair takes its closest points at
    /// `x`, forgets an earlier crossing and may have crossed if it is no
    /// further apart than its edges moved.
    pub fn refresh(&mut self, x: &[Vec3], x_prev: &[Vec3]) {
        if let Contact::EdgeEdge(e) = self {
            let [a0, a1, b0, b1] = e.v.map(|k| x[k as usize]);
            (e.s, e.u) = ccd::segment_closest_params(a0, a1, b0, b1);
            let motion = |k: &[u32]| {
                k.iter()
                    .map(|&k| x[k as usize].distance(x_prev[k as usize]))
                    .fold(0.0, f32::max)
            };
            let distance = a0.lerp(a1, e.s).distance(b0.lerp(b1, e.u));
            e.may_cross = distance <= motion(&e.v[..2]) + motion(&e.v[2..]);
            e.crossed = None;
        }
    }

    /// Finds, once per substep, whether an edge pair crossed.
    pub fn detect_crossing(&mut self, x: &[Vec3], x_prev: &[Vec3]) {
        if let Contact::EdgeEdge(e) = self {
            if e.may_cross {
                e.detect_crossing(x, x_prev);
            }
        }
    }

    /// The corrections of the contact's particles, if it acts.
    pub fn correction(
        &self,
        x: &[Vec3],
        x_prev: &[Vec3],
        masses: ContactMasses<'_>,
        s: &SelfCollision,
    ) -> Option<[Vec3; 4]> {
        match self {
            Contact::Pair(v) => pair_correction(*v, x, x_prev, masses, s),
            Contact::VertexTriangle(v, side) => {
                vertex_triangle_correction(*v, *side, x, x_prev, masses, s)
            }
            Contact::EdgeEdge(e) => e.correction(x, x_prev, masses, s),
        }
    }
}

impl EdgePair {
    /// Sets `crossed` (and the meeting points) if the edges crossed.
    fn detect_crossing(&mut self, x: &[Vec3], x_prev: &[Vec3]) {
        let v = self.v;
        let sweep = |k: u32| Sweep {
            start: x_prev[k as usize],
            end: x[k as usize],
        };
        let Some(hit) = ccd::edge_edge(sweep(v[0]), sweep(v[1]), sweep(v[2]), sweep(v[3])) else {
            return;
        };
        let [a0, a1, b0, b1] = v.map(|k| x_prev[k as usize]);
        let before = a0.lerp(a1, hit.s) - b0.lerp(b1, hit.u);
        if let Some((t, side)) = self.belongs {
            let [p, q, r] = t.map(|k| x_prev[k as usize]);
            if before.dot((q - p).cross(r - p)) * f32::from(side) < 0.0 {
                // From the side `a` does not belong on: let it through.
                return;
            }
        }
        if let Some(normal) = before
            .try_normalize()
            .or_else(|| (a1 - a0).cross(b1 - b0).try_normalize())
        {
            (self.s, self.u, self.crossed) = (hit.s, hit.u, Some(normal));
        }
    }

    /// Corrections of two edges closer than the thickness at their contact
    /// points, or that crossed during the substep.
    fn correction(
        &self,
        x: &[Vec3],
        x_prev: &[Vec3],
        masses: ContactMasses<'_>,
        s: &SelfCollision,
    ) -> Option<[Vec3; 4]> {
        let [a0, a1, b0, b1] = self.v.map(|k| x[k as usize]);
        let diff = a0.lerp(a1, self.s) - b0.lerp(b1, self.u);
        let (normal, height) = match self.crossed {
            Some(n) => (n, n.dot(diff)),
            None => {
                let dist = diff.length();
                (diff.try_normalize()?, dist)
            }
        };
        if height >= s.thickness {
            return None;
        }
        let weights = [1.0 - self.s, self.s, self.u - 1.0, -self.u];
        separate(self.v, weights, normal, height, x, x_prev, masses, s)
    }
}

/// The particles' inverse masses in the self-contacts, and which ones a
/// collider held in the last substep (`crate::solver::collider_held`).
#[derive(Clone, Copy, Debug)]
pub struct ContactMasses<'a> {
    /// Per particle.
    pub inv_mass: &'a [f32],
    /// Empty where none is held.
    pub held: &'a [bool],
}

impl<'a> ContactMasses<'a> {
    /// The masses `inv_mass`, none held.
    pub fn free(inv_mass: &'a [f32]) -> Self {
        ContactMasses {
            inv_mass,
            held: &[],
        }
    }

    fn held(&self, k: u32) -> bool {
        self.held.get(k as usize).copied().unwrap_or(false)
    }

    /// The inverse masses of a contact's particles `v`, whose shares of the
    /// contact point are `weights` (positive on one side, negative on the
    /// other): none on a side whose every particle that shares in the
    /// point a collider held, where the other side can move. The collider
    /// stands behind them, so the other side gives way: a cloth lying on
    /// the floor is not pushed into it by one landing on it (for the
    /// floor to lift it back up through the cloth above). A side only
    /// partly held keeps its masses: moving its free particles alone, far
    /// to move the point a little (a lever), is worse.
    pub fn of<const N: usize>(&self, v: [u32; N], weights: [f32; N]) -> [f32; N] {
        let w = v.map(|k| self.inv_mass[k as usize]);
        let mut held = w;
        for side in [1.0, -1.0] {
            let sharing = (0..N).filter(|&k| weights[k] * side > 0.0);
            if sharing.clone().all(|k| self.held(v[k])) {
                sharing.for_each(|k| held[k] = 0.0);
            }
        }
        let moves = (0..N).any(|k| held[k] * weights[k] != 0.0);
        if moves {
            held
        } else {
            w
        }
    }
}

/// Share of a tangential slide `slide` that friction removes, given the
/// normal correction `depth` (Macklin et al. 2014, static then kinetic).
fn friction_share(slide: f32, depth: f32, f: &Friction) -> f32 {
    if slide < f.static_coefficient * depth {
        1.0
    } else if slide > 0.0 {
        (f.kinetic_coefficient * depth / slide).min(1.0)
    } else {
        0.0
    }
}

/// The tangential part of `u` removed by friction.
fn friction_removal(u: Vec3, normal: Vec3, depth: f32, f: &Friction) -> Vec3 {
    let tangential = u - normal * u.dot(normal);
    tangential * friction_share(tangential.length(), depth, f)
}

/// Corrections of a particle pair closer than the thickness.
fn pair_correction(
    v: [u32; 2],
    x: &[Vec3],
    x_prev: &[Vec3],
    masses: ContactMasses<'_>,
    s: &SelfCollision,
) -> Option<[Vec3; 4]> {
    let [i, j] = v.map(|k| k as usize);
    let diff = x[i] - x[j];
    let dist = diff.length();
    let [wi, wj] = masses.of(v, [1.0, -1.0]);
    let w = wi + wj;
    if dist >= s.thickness || dist == 0.0 || w == 0.0 {
        return None;
    }
    let normal = diff / dist;
    let depth = s.thickness - dist;
    let slip = friction_removal(
        (x[i] - x_prev[i]) - (x[j] - x_prev[j]),
        normal,
        depth,
        &s.friction,
    );
    let g = (normal * depth - slip) / w;
    Some([g * wi, -g * wj, Vec3::ZERO, Vec3::ZERO])
}

/// Corrections of a vertex closer to a triangle than the thickness, or that
/// crossed it during the substep (kept on the side it came from). Where
/// the layer order gives the side it belongs on (`belongs`, 1 or -1 along
/// the triangle's normal), that side is kept instead, and a vertex that
/// came from the other side is let through.
fn vertex_triangle_correction(
    v: [u32; 4],
    belongs: i8,
    x: &[Vec3],
    x_prev: &[Vec3],
    masses: ContactMasses<'_>,
    s: &SelfCollision,
) -> Option<[Vec3; 4]> {
    let [p, a, b, c] = v.map(|k| x[k as usize]);
    let [p0, a0, b0, c0] = v.map(|k| x_prev[k as usize]);
    let normal = (b - a).cross(c - a).try_normalize()?;
    let start_height = (b0 - a0).cross(c0 - a0).dot(p0 - a0);
    let came_from = if start_height != 0.0 {
        start_height.signum()
    } else {
        normal.dot(p - a).signum()
    };
    let side = if belongs == 0 {
        came_from
    } else {
        f32::from(belongs)
    };
    let height = side * normal.dot(p - a);
    if height >= s.thickness {
        return None;
    }
    let beta = if height < 0.0 {
        if side != came_from {
            return None;
        }
        let sweep = |k: u32| Sweep {
            start: x_prev[k as usize],
            end: x[k as usize],
        };
        ccd::vertex_triangle(sweep(v[0]), sweep(v[1]), sweep(v[2]), sweep(v[3]))?.barycentric
    } else {
        ccd::projection_inside(p, a, b, c)?
    };
    // Weights of the vertex (+) and of the triangle's contact point (-).
    let weights = [1.0, -beta[0], -beta[1], -beta[2]];
    separate(v, weights, side * normal, height, x, x_prev, masses, s)
}

/// Moves the contact points `sum_k weights[k] x[v[k]]` apart along `normal`
/// until their separation `height` reaches the thickness, with friction on
/// their relative motion; each particle moves in proportion to its inverse
/// mass and weight, so the total momentum is kept.
#[allow(clippy::too_many_arguments)]
fn separate(
    v: [u32; 4],
    weights: [f32; 4],
    normal: Vec3,
    height: f32,
    x: &[Vec3],
    x_prev: &[Vec3],
    masses: ContactMasses<'_>,
    s: &SelfCollision,
) -> Option<[Vec3; 4]> {
    let w = masses.of(v, weights);
    let generalized: f32 = (0..4).map(|k| weights[k] * weights[k] * w[k]).sum();
    if generalized == 0.0 {
        return None;
    }
    let depth = s.thickness - height;
    let relative: Vec3 = (0..4)
        .map(|k| (x[v[k] as usize] - x_prev[v[k] as usize]) * weights[k])
        .sum();
    let g = (normal * depth - friction_removal(relative, normal, depth, &s.friction)) / generalized;
    Some([0, 1, 2, 3].map(|k| g * (weights[k] * w[k])))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `sum m_k dx_k` of a contact's corrections.
    fn momentum_change(v: &[u32], delta: [Vec3; 4], inv_mass: &[f32]) -> Vec3 {
        v.iter()
            .zip(delta)
            .map(|(&k, d)| d / inv_mass[k as usize])
            .sum()
    }

    #[test]
    fn pair_contact_keeps_momentum_and_separates() {
        let x = [Vec3::ZERO, Vec3::new(0.002, 0.001, 0.0)];
        let x_prev = [Vec3::new(0.0, 0.01, 0.0), Vec3::new(0.005, 0.0, 0.0)];
        let inv_mass = [1.0, 3.0];
        let s = SelfCollision::default();
        let d = pair_correction([0, 1], &x, &x_prev, ContactMasses::free(&inv_mass), &s)
            .expect("touching");
        assert!(momentum_change(&[0, 1], d, &inv_mass).length() < 1e-6);
        let gap = (x[0] + d[0]).distance(x[1] + d[1]);
        assert!(gap >= s.thickness - 1e-3, "gap {gap}");
    }

    #[test]
    fn vertex_triangle_contact_keeps_momentum_and_the_side() {
        let tri = [
            Vec3::ZERO,
            Vec3::new(0.1, 0.0, 0.0),
            Vec3::new(0.0, 0.0, 0.1),
        ];
        // The vertex came from above and ended below the triangle.
        let x = [
            Vec3::new(0.02, -0.01, 0.03),
            tri[0],
            tri[1],
            tri[2] + Vec3::Y * 0.001,
        ];
        let x_prev = [Vec3::new(0.02, 0.01, 0.03), tri[0], tri[1], tri[2]];
        let inv_mass = [1.0, 2.0, 0.5, 1.0];
        let s = SelfCollision::default();
        let v = [0, 1, 2, 3];
        let d = vertex_triangle_correction(v, 0, &x, &x_prev, ContactMasses::free(&inv_mass), &s)
            .expect("crossed");
        assert!(momentum_change(&v, d, &inv_mass).length() < 1e-6);
        let moved: Vec<Vec3> = x.iter().zip(d).map(|(x, d)| *x + d).collect();
        let normal = (moved[2] - moved[1]).cross(moved[3] - moved[1]).normalize();
        let side = normal.dot(moved[0] - moved[1]) * normal.dot(x_prev[0] - x_prev[1]).signum();
        assert!(side > 0.9 * s.thickness, "height {side}");
    }

    #[test]
    fn a_vertex_is_let_through_towards_the_side_it_belongs_on_and_held_there() {
        // A triangle in z = 0 (normal +z); the vertex rose through it.
        let tri = [Vec3::ZERO, Vec3::X * 0.1, Vec3::Y * 0.1];
        let x_prev = [Vec3::new(0.02, 0.02, -0.002), tri[0], tri[1], tri[2]];
        let inv_mass = [1.0; 4];
        let s = SelfCollision::default();
        let v = [0, 1, 2, 3];
        let lift = |end_z: f32, belongs: i8| {
            let x = [Vec3::new(0.02, 0.02, end_z), tri[0], tri[1], tri[2]];
            vertex_triangle_correction(v, belongs, &x, &x_prev, ContactMasses::free(&inv_mass), &s)
                .map(|d| d[0].z)
        };
        // Above by more than the thickness: let through where it belongs
        // above, pulled back below where it belongs below or nothing is
        // known (it came from below).
        let far = 2.0 * s.thickness;
        assert_eq!(lift(far, 1), None);
        assert!(lift(far, -1).expect("crossed back") < 0.0);
        assert!(lift(far, 0).expect("crossed back") < 0.0);
        // Just above: held at the thickness above where it belongs above.
        assert!(lift(0.2 * s.thickness, 1).expect("held above") > 0.0);
        assert!(lift(0.2 * s.thickness, -1).expect("crossed back") < 0.0);
        // Still below, where it belongs above: left alone (no crossing yet).
        assert_eq!(lift(-0.5 * s.thickness, 1), None);
    }

    #[test]
    fn crossing_edges_are_let_through_towards_the_side_they_belong_on() {
        // Edge a drops through edge b, as in the test below. The triangle
        // [2, 3, 4] holds edge b; its normal points to +y, where a came
        // from.
        let x_prev = [
            Vec3::new(-0.1, 0.01, 0.0),
            Vec3::new(0.1, 0.01, 0.0),
            Vec3::new(0.02, 0.0, -0.1),
            Vec3::new(0.02, 0.0, 0.1),
            Vec3::new(0.2, 0.0, 0.0),
        ];
        let mut x = x_prev;
        x[0].y = -0.01;
        x[1].y = -0.01;
        let normal = (x_prev[3] - x_prev[2]).cross(x_prev[4] - x_prev[2]);
        assert!(normal.y > 0.0);
        for (belongs, let_through) in [(-1, true), (1, false)] {
            let mut contact = edge_pair([0, 1, 2, 3], &x, true);
            if let Contact::EdgeEdge(e) = &mut contact {
                e.belongs = Some(([2, 3, 4], belongs));
            }
            contact.detect_crossing(&x, &x_prev);
            let Contact::EdgeEdge(e) = contact else {
                unreachable!()
            };
            assert_eq!(e.crossed.is_none(), let_through, "belongs {belongs}");
        }
    }

    /// The edge pair `v` as found at the end positions `x`.
    fn edge_pair(v: [u32; 4], x: &[Vec3], may_cross: bool) -> Contact {
        let [a0, a1, b0, b1] = v.map(|k| x[k as usize]);
        let (s, u) = ccd::segment_closest_params(a0, a1, b0, b1);
        Contact::EdgeEdge(EdgePair {
            v,
            s,
            u,
            may_cross,
            crossed: None,
            belongs: None,
        })
    }

    #[test]
    fn crossed_edges_are_pulled_back_to_their_side_keeping_momentum() {
        // Edge a along x at y = 0.01 drops through edge b along z at y = 0.
        let x_prev = [
            Vec3::new(-0.1, 0.01, 0.0),
            Vec3::new(0.1, 0.01, 0.0),
            Vec3::new(0.02, 0.0, -0.1),
            Vec3::new(0.02, 0.0, 0.1),
        ];
        let mut x = x_prev;
        x[0].y = -0.01;
        x[1].y = -0.01;
        let inv_mass = [1.0, 2.0, 0.5, 1.0];
        let s = SelfCollision::default();
        let v = [0, 1, 2, 3];
        let mut contact = edge_pair(v, &x, true);
        contact.detect_crossing(&x, &x_prev);
        let d = contact
            .correction(&x, &x_prev, ContactMasses::free(&inv_mass), &s)
            .expect("crossed");
        assert!(momentum_change(&v, d, &inv_mass).length() < 1e-6);
        let moved: Vec<Vec3> = x.iter().zip(d).map(|(x, d)| *x + d).collect();
        let (sa, sb) = ccd::segment_closest_params(moved[0], moved[1], moved[2], moved[3]);
        let gap = moved[0].lerp(moved[1], sa) - moved[2].lerp(moved[3], sb);
        assert!(gap.y > 0.9 * s.thickness, "gap {gap}");
    }

    #[test]
    fn near_edges_are_pushed_to_the_thickness() {
        let x = [
            Vec3::new(-0.1, 0.002, 0.0),
            Vec3::new(0.1, 0.002, 0.0),
            Vec3::new(0.0, 0.0, -0.1),
            Vec3::new(0.0, 0.0, 0.1),
        ];
        let inv_mass = [1.0; 4];
        let s = SelfCollision::default();
        let mut contact = edge_pair([0, 1, 2, 3], &x, false);
        contact.detect_crossing(&x, &x);
        let d = contact
            .correction(&x, &x, ContactMasses::free(&inv_mass), &s)
            .expect("near");
        let gap = (x[0] + d[0]).y - (x[2] + d[2]).y;
        assert!((gap - s.thickness).abs() < 1e-5, "gap {gap}");
        let far = [x[0] + Vec3::Y * 0.01, x[1] + Vec3::Y * 0.01, x[2], x[3]];
        assert_eq!(
            contact.correction(&far, &far, ContactMasses::free(&inv_mass), &s),
            None
        );
    }
}
