//! Contacts of dynamic rigid bodies, solved as XPBD contact constraints
//! (compliance zero) with positional Coulomb friction, as in
//! Müller et al. 2020, sections 3.3 to 3.5:
//!
//! - cloth-body: `C = sdf_body(x) - thickness >= 0` between a particle of
//!   inverse mass `w_p` and a body of generalised inverse mass
//!   `w_b = 1/m + (r x n)^T I^-1 (r x n)`. The particle moves by
//!   `w_p / (w_p + w_b)` of the correction, the body takes the equal and
//!   opposite positional impulse. The contacts of one body are solved as
//!   Jacobi: all particles in parallel against the body's pose at the start
//!   of the pass, each seeing the body's mass split among the `N` contacts
//!   (mass splitting, Tonge et al. 2012, so that `N` simultaneous contacts do
//!   not overshoot); the impulses are then summed in particle order
//!   (independent of the thread count) and applied to the body. A particle
//!   that lies on a static or kinematic collider (within 1.5 thicknesses)
//!   counts as part of it, with infinite mass, so that a body resting on
//!   cloth that rests on a table is held up by the table through the cloth
//!   (shock propagation, Guendelman et al. 2003) instead of sinking through
//!   particles much lighter than itself.
//! - body-static: sample points of the body ([`super::rigid_body::SamplePoint`])
//!   against the distance of the static and kinematic colliders, the
//!   colliders having infinite mass; Jacobi with mass splitting as well.
//!
//! Friction acts on the relative tangential motion over the substep: static
//! when the tangential impulse is within `static * normal impulse`, else
//! reduced by `kinetic * normal impulse`, as in [`super::project_contacts`].

use super::contact::ColliderPose;
use super::rigid_body::RigidBody;
use super::{Collider, Friction};
use glam::{Affine3A, Mat3, Vec3};
use rayon::prelude::*;

/// One particle's contact with the body being solved.
#[derive(Clone, Copy, Debug, Default)]
pub struct ParticleHit {
    /// Unit outward normal of the body's surface at the contact (world).
    pub normal: Vec3,
    /// Penetration: the particle's thickness less its distance to the body's
    /// surface (m).
    pub depth: f32,
    /// Contact point on the body's surface, from its centre of mass.
    pub r: Vec3,
    /// How far the body's material point at the contact moved this substep.
    pub surface_motion: Vec3,
    /// Positional impulse the particle gave the body.
    pub impulse: Vec3,
    /// The particle lies on a static collider: it moves with it.
    pub supported: bool,
}

/// One sample point's contact with a static collider.
#[derive(Clone, Copy, Debug)]
struct StaticHit {
    normal: Vec3,
    depth: f32,
    r: Vec3,
    /// Motion of the body point relative to the collider's surface this substep.
    relative_motion: Vec3,
    friction: Friction,
}

/// Scratch space of the body contacts, kept between substeps.
#[derive(Clone, Debug, Default)]
pub struct BodyContacts {
    hits: Vec<Option<ParticleHit>>,
    static_hits: Vec<StaticHit>,
}

impl BodyContacts {
    /// Two-way contacts between the particles and `body` (the dynamic part
    /// of `colliders[own]`); returns the number of contacts.
    #[allow(clippy::too_many_arguments)]
    pub fn cloth_body(
        &mut self,
        x: &mut [Vec3],
        x_prev: &[Vec3],
        inv_mass: &[f32],
        thickness: &[f32],
        body: &mut RigidBody,
        own: usize,
        colliders: &[Collider],
        poses: &[ColliderPose],
    ) -> usize {
        let collider = &colliders[own];
        self.hits.resize(x.len(), None);
        let end = body.pose();
        let start = body.prev_pose();
        let end_inverse = end.inverse();
        let com = body.position;
        let reach = body.bound_radius;
        let found: usize = (&*x, &mut self.hits, x_prev, inv_mass, thickness)
            .into_par_iter()
            .with_min_len(1024)
            .map(|(xi, hit, _, &w, &h)| {
                *hit = None;
                if w == 0.0 || xi.distance_squared(com) > (reach + h) * (reach + h) {
                    return 0;
                }
                *hit = find_hit(*xi, h, collider, &start, &end, &end_inverse, com);
                if let Some(hit) = hit {
                    hit.supported = on_static(*xi, 1.5 * h, own, colliders, poses);
                }
                hit.is_some() as usize
            })
            .sum();
        if found == 0 {
            return 0;
        }
        let split = found as f32;
        let inv_inertia = body.inv_inertia_world();
        let friction = collider.friction;
        let b: &RigidBody = body;
        (x, &mut self.hits, x_prev, inv_mass)
            .into_par_iter()
            .with_min_len(1024)
            .for_each(|(xi, hit, &xp, &w)| {
                if let Some(hit) = hit {
                    resolve_particle(xi, xp, w, hit, b, inv_inertia, split, friction);
                }
            });
        let (mut linear, mut angular) = (Vec3::ZERO, Vec3::ZERO);
        for hit in self.hits.iter().flatten() {
            linear += hit.impulse;
            angular += hit.r.cross(hit.impulse);
        }
        body.apply_impulse(inv_inertia, linear, angular);
        found
    }

    /// Contacts of `body` (the dynamic part of `colliders[own]`) with every
    /// static or kinematic collider; returns the number of contacts.
    pub fn body_static(
        &mut self,
        body: &mut RigidBody,
        own: usize,
        colliders: &[Collider],
        poses: &[ColliderPose],
    ) -> usize {
        self.static_hits.clear();
        let end = body.pose();
        let start = body.prev_pose();
        let own_friction = colliders[own].friction;
        for (k, (c, pose)) in colliders.iter().zip(poses).enumerate() {
            if k == own || c.body.is_some() {
                continue;
            }
            let friction = mix(own_friction, c.friction);
            for s in &body.samples {
                let p = end.transform_point3(s.local);
                let local = pose.end_inverse.transform_point3(p);
                let Some((distance, local_normal)) =
                    c.shape.signed_distance_within(local, s.radius)
                else {
                    continue;
                };
                let depth = s.radius - distance;
                if depth.is_nan() || depth <= 0.0 {
                    continue;
                }
                let normal = pose.end.transform_vector3(local_normal).normalize_or_zero();
                // The deepest point of the body, and where it and the surface were.
                let point = p - normal * s.radius;
                let body_local = end.inverse().transform_point3(point);
                let body_motion = point - start.transform_point3(body_local);
                let surface_local = pose.end_inverse.transform_point3(point);
                let surface_motion = point - pose.start.transform_point3(surface_local);
                self.static_hits.push(StaticHit {
                    normal,
                    depth,
                    r: point - body.position,
                    relative_motion: body_motion - surface_motion,
                    friction,
                });
            }
        }
        let found = self.static_hits.len();
        if found == 0 {
            return 0;
        }
        let split = found as f32;
        let inv_inertia = body.inv_inertia_world();
        let (mut linear, mut angular) = (Vec3::ZERO, Vec3::ZERO);
        for hit in &self.static_hits {
            let w = split * body.generalized_inv_mass(inv_inertia, hit.r, hit.normal);
            let lambda = hit.depth / w;
            let mut impulse = hit.normal * lambda;
            // The body point's tangential motion, opposed by friction.
            let tangential = hit.relative_motion - hit.normal * hit.relative_motion.dot(hit.normal);
            let slide = tangential.length();
            if slide > 0.0 {
                let t = tangential / slide;
                let wt = split * body.generalized_inv_mass(inv_inertia, hit.r, t);
                impulse -= t * friction_lambda(slide / wt, lambda, hit.friction);
            }
            linear += impulse;
            angular += hit.r.cross(impulse);
        }
        body.apply_impulse(inv_inertia, linear, angular);
        found
    }
}

/// Friction between a body and a static collider: the geometric mean of theirs.
fn mix(a: Friction, b: Friction) -> Friction {
    Friction {
        static_coefficient: (a.static_coefficient * b.static_coefficient).sqrt(),
        kinetic_coefficient: (a.kinetic_coefficient * b.kinetic_coefficient).sqrt(),
    }
}

/// The tangential impulse that friction applies, given the one that would
/// stop the sliding (`stop`) and the normal impulse.
fn friction_lambda(stop: f32, normal: f32, f: Friction) -> f32 {
    if stop < f.static_coefficient * normal {
        stop
    } else {
        stop.min(f.kinetic_coefficient * normal)
    }
}

/// Whether `x` is within `reach` of a static or kinematic collider's surface
/// (`colliders[own]`, whose body is out for solving, is neither).
fn on_static(
    x: Vec3,
    reach: f32,
    own: usize,
    colliders: &[Collider],
    poses: &[ColliderPose],
) -> bool {
    colliders
        .iter()
        .zip(poses)
        .enumerate()
        .any(|(k, (c, pose))| {
            k != own
                && c.body.is_none()
                && c.shape
                    .signed_distance_within(pose.end_inverse.transform_point3(x), reach)
                    .is_some()
        })
}

/// The contact of a particle at `x` with a body placed at `end` (at `start`
/// a substep ago), if it is within `thickness` of the body's surface.
fn find_hit(
    x: Vec3,
    thickness: f32,
    collider: &Collider,
    start: &Affine3A,
    end: &Affine3A,
    end_inverse: &Affine3A,
    com: Vec3,
) -> Option<ParticleHit> {
    let local = end_inverse.transform_point3(x);
    let (distance, local_normal) = collider.shape.signed_distance_within(local, thickness)?;
    let depth = thickness - distance;
    if depth.is_nan() || depth <= 0.0 {
        return None;
    }
    let normal = end.transform_vector3(local_normal).normalize_or_zero();
    let surface = x - normal * distance;
    Some(ParticleHit {
        normal,
        depth,
        r: surface - com,
        surface_motion: x - start.transform_point3(local),
        impulse: Vec3::ZERO,
        supported: false,
    })
}

/// Moves the particle by its share of the contact and friction corrections
/// and records the opposite impulse on the body in `hit`.
#[allow(clippy::too_many_arguments)]
fn resolve_particle(
    x: &mut Vec3,
    x_prev: Vec3,
    w: f32,
    hit: &mut ParticleHit,
    body: &RigidBody,
    inv_inertia: Mat3,
    split: f32,
    friction: Friction,
) {
    let w = if hit.supported { 0.0 } else { w };
    let n = hit.normal;
    let wb = split * body.generalized_inv_mass(inv_inertia, hit.r, n);
    let lambda = hit.depth / (w + wb);
    *x += n * (w * lambda);
    let mut impulse = -n * lambda;
    let relative = (*x - x_prev) - hit.surface_motion;
    let tangential = relative - n * relative.dot(n);
    let slide = tangential.length();
    if slide > 0.0 {
        let t = tangential / slide;
        let wbt = split * body.generalized_inv_mass(inv_inertia, hit.r, t);
        let lambda_t = friction_lambda(slide / (w + wbt), lambda, friction);
        *x -= t * (w * lambda_t);
        impulse += t * lambda_t;
    }
    hit.impulse = impulse;
}
