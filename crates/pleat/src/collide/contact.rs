//! Cloth-collider contacts, solved as XPBD contact constraints with infinite
//! collider mass: `C = sdf(x) - thickness >= 0`, then position-based Coulomb
//! friction on the tangential motion relative to the collider's surface
//! (Macklin et al. 2014): static when it is within `static * depth`, else
//! reduced by `kinetic * depth`. Each particle's contacts are independent of
//! every other particle's, so all particles are solved in parallel.

use super::Collider;
use glam::{Affine3A, Vec3};
use rayon::prelude::*;

/// A collider's placement over one substep: where it starts and where it ends.
#[derive(Clone, Copy, Debug)]
pub struct ColliderPose {
    /// Placement at the start of the substep (time-zero coordinates to world).
    pub start: Affine3A,
    /// Placement at the end of the substep.
    pub end: Affine3A,
    /// Inverse of `end`: world to time-zero coordinates.
    pub end_inverse: Affine3A,
    /// Inverse of `start`.
    pub start_inverse: Affine3A,
}

impl ColliderPose {
    /// Where a static or kinematic collider is over `[t_start, t_end]`; a
    /// dynamic one over its current substep.
    pub fn over(collider: &Collider, t_start: f32, t_end: f32) -> Self {
        let (start, end) = match &collider.body {
            Some(body) => (body.prev_pose(), body.pose()),
            None => (
                collider.motion.pose_at(t_start),
                collider.motion.pose_at(t_end),
            ),
        };
        ColliderPose {
            start,
            end,
            end_inverse: end.inverse(),
            start_inverse: start.inverse(),
        }
    }
}

/// Pushes every particle out of every static or kinematic collider and
/// applies friction (dynamic colliders are left to [`super::body_contact`]).
/// Returns the number of contacts.
pub fn project_contacts(
    x: &mut [Vec3],
    x_prev: &[Vec3],
    inv_mass: &[f32],
    thickness: &[f32],
    colliders: &[Collider],
    poses: &[ColliderPose],
) -> usize {
    if colliders.is_empty() {
        return 0;
    }
    x.par_iter_mut()
        .enumerate()
        .with_min_len(1024)
        .map(|(i, xi)| {
            if inv_mass[i] == 0.0 {
                return 0;
            }
            colliders
                .iter()
                .zip(poses)
                .filter(|(c, pose)| contact(xi, x_prev[i], thickness[i], c, pose))
                .count()
        })
        .sum()
}

/// Resolves one particle against one collider; true if they touched.
fn contact(
    x: &mut Vec3,
    x_prev: Vec3,
    thickness: f32,
    collider: &Collider,
    pose: &ColliderPose,
) -> bool {
    if collider.body.is_some() {
        return false;
    }
    let local = pose.end_inverse.transform_point3(*x);
    let local_prev = pose.start_inverse.transform_point3(x_prev);
    let Some((distance, local_normal)) = collider
        .shape
        .swept_signed_distance_within(local_prev, local, thickness)
    else {
        return false;
    };
    let depth = thickness - distance;
    if depth.is_nan() || depth <= 0.0 {
        return false;
    }
    let normal = pose.end.transform_vector3(local_normal);
    let surface_motion = *x - pose.start.transform_point3(local);
    *x += normal * depth;
    let relative = (*x - x_prev) - surface_motion;
    let tangential = relative - normal * relative.dot(normal);
    let slide = tangential.length();
    let f = collider.friction;
    if slide < f.static_coefficient * depth {
        *x -= tangential;
    } else if slide > 0.0 {
        *x -= tangential * (f.kinetic_coefficient * depth / slide).min(1.0);
    }
    push_out(x, thickness, collider, pose);
    true
}

/// Pushes again, along the surface's normal, a particle that its contact
/// left within `thickness` of the collider: a sampled distance field's
/// gradient only approximates the normal, and friction moves a particle
/// along the tangent, inside a concave surface (bunny_sdf.json ended with
/// a particle 0.5 mm inside the bunny). At most [`PUSHES`] times.
fn push_out(x: &mut Vec3, thickness: f32, collider: &Collider, pose: &ColliderPose) {
    for _ in 0..PUSHES {
        let local = pose.end_inverse.transform_point3(*x);
        match collider.shape.signed_distance_within(local, thickness) {
            Some((distance, normal)) if distance < thickness => {
                *x += pose.end.transform_vector3(normal) * (thickness - distance);
            }
            _ => return,
        }
    }
}

/// Most further pushes out of a collider a contact makes (`PUSHES` in
/// collide.wgsl). Of 891 points within a thickness of the baked bunny, the
/// contact's one push left 320 short of the thickness; 2 more left 4, 4
/// more 1, 8 more none (most leave after one). Near the open teapot's rim,
/// where the field's sign flips, 2 of 228 stay short after 8.
const PUSHES: usize = 8;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::collide::{Friction, Motion, Shape};

    fn ground(friction: Friction) -> Collider {
        Collider {
            shape: Shape::Plane {
                point: Vec3::ZERO,
                normal: Vec3::Y,
            },
            motion: Motion::default(),
            friction,
            body: None,
        }
    }

    fn resolve(collider: &Collider, x_prev: Vec3, x: Vec3) -> Vec3 {
        let mut x = [x];
        let pose = ColliderPose::over(collider, 0.0, 0.01);
        project_contacts(
            &mut x,
            &[x_prev],
            &[1.0],
            &[0.01],
            std::slice::from_ref(collider),
            &[pose],
        );
        x[0]
    }

    #[test]
    fn fast_particle_stops_on_a_thin_mesh_plate() {
        use crate::collide::MeshCollider;
        use crate::mesh::Mesh;
        let plate = Mesh {
            positions: vec![
                Vec3::new(-1.0, 0.0, -1.0),
                Vec3::new(1.0, 0.0, -1.0),
                Vec3::new(1.0, 0.0, 1.0),
                Vec3::new(-1.0, 0.0, 1.0),
            ],
            triangles: vec![[0, 2, 1], [0, 3, 2]],
            grid: None,
        };
        let collider = Collider {
            shape: Shape::Mesh(std::sync::Arc::new(MeshCollider::new(&plate))),
            motion: Motion::default(),
            friction: Friction::default(),
            body: None,
        };
        // 100 m/s downwards over a substep of 1/600 s, from 1 cm above.
        let x = resolve(
            &collider,
            Vec3::new(0.1, 0.01, 0.2),
            Vec3::new(0.1, -0.157, 0.2),
        );
        assert!((x.y - 0.01).abs() < 1e-5, "stopped on top: {x}");
        // And from below, upwards.
        let x = resolve(
            &collider,
            Vec3::new(0.1, -0.01, 0.2),
            Vec3::new(0.1, 0.157, 0.2),
        );
        assert!((x.y + 0.01).abs() < 1e-5, "stopped underneath: {x}");
    }

    #[test]
    fn pushed_out_to_thickness() {
        let x = resolve(
            &ground(Friction::default()),
            Vec3::new(0.0, 0.05, 0.0),
            Vec3::new(0.0, -0.1, 0.0),
        );
        assert!((x.y - 0.01).abs() < 1e-6, "{x}");
    }

    #[test]
    fn static_friction_sticks_and_kinetic_slides() {
        let sticky = Friction {
            static_coefficient: 1.0,
            kinetic_coefficient: 0.5,
        };
        let x = resolve(
            &ground(sticky),
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(0.05, -0.1, 0.0),
        );
        assert!(x.x.abs() < 1e-6, "stuck: {x}");
        let slippery = Friction {
            static_coefficient: 0.1,
            kinetic_coefficient: 0.1,
        };
        let x = resolve(
            &ground(slippery),
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(0.5, -0.1, 0.0),
        );
        assert!(x.x > 0.0 && x.x < 0.5, "slides, slowed: {x}");
    }

    #[test]
    fn spinning_sphere_drags_resting_particle() {
        let collider = Collider {
            shape: Shape::Sphere {
                center: Vec3::ZERO,
                radius: 1.0,
            },
            motion: Motion {
                angular_velocity: Vec3::new(0.0, 10.0, 0.0),
                ..Motion::default()
            },
            friction: Friction {
                static_coefficient: 1.0,
                kinetic_coefficient: 1.0,
            },
            body: None,
        };
        // A particle resting on the equator, pressed in slightly: the surface moves along -z.
        let x = resolve(
            &collider,
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(0.999, 0.0, 0.0),
        );
        assert!(x.z < 0.0, "carried along by the surface: {x}");
    }
}
