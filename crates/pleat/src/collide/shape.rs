//! Collider shapes and their signed distance functions: analytic ones, and
//! triangle meshes queried directly or through a baked distance field.

use super::mesh_collider::MeshCollider;
use super::sdf::SdfGrid;
use glam::{Quat, Vec3};
use std::sync::Arc;

/// A collider's shape in its time-zero placement, with a signed distance
/// (negative inside).
#[derive(Clone, Debug, PartialEq)]
pub enum Shape {
    /// Half-space below the plane through `point` with outward `normal`.
    Plane {
        /// A point on the plane.
        point: Vec3,
        /// Unit outward normal.
        normal: Vec3,
    },
    /// A solid sphere.
    Sphere {
        /// Centre.
        center: Vec3,
        /// Radius (m).
        radius: f32,
    },
    /// Oriented box.
    Box {
        /// Centre.
        center: Vec3,
        /// Half the box's size along its own axes (m).
        half_extents: Vec3,
        /// Rotation of the box's axes.
        rotation: Quat,
    },
    /// Segment `a`-`b` swept by a sphere of `radius`.
    Capsule {
        /// One end of the segment.
        a: Vec3,
        /// The other end of the segment.
        b: Vec3,
        /// Radius of the swept sphere (m).
        radius: f32,
    },
    /// A triangle mesh, queried through its hierarchy (shared, not copied).
    Mesh(Arc<MeshCollider>),
    /// A distance field baked from a mesh.
    Sdf(Arc<SdfGrid>),
}

impl Shape {
    /// Signed distance from `p` to the surface (negative inside) and the outward
    /// unit normal (the direction that increases the distance fastest).
    pub fn signed_distance(&self, p: Vec3) -> (f32, Vec3) {
        match self {
            Shape::Plane { point, normal } => ((p - *point).dot(*normal), *normal),
            Shape::Sphere { center, radius } => sphere(p - *center, *radius),
            Shape::Box {
                center,
                half_extents,
                rotation,
            } => {
                let (d, n) = oriented_box(rotation.inverse() * (p - *center), *half_extents);
                (d, rotation * n)
            }
            Shape::Capsule { a, b, radius } => {
                let ab = *b - *a;
                let t =
                    ((p - *a).dot(ab) / ab.length_squared().max(f32::MIN_POSITIVE)).clamp(0.0, 1.0);
                sphere(p - (*a + ab * t), *radius)
            }
            Shape::Mesh(mesh) => mesh.signed_distance(p),
            Shape::Sdf(grid) => grid.signed_distance(p),
        }
    }

    /// The signed distance and normal where the distance is below `reach`,
    /// `None` beyond it: what a contact needs. Mesh colliders stop their
    /// closest-point search at `reach`; the other shapes are cheap anyway.
    pub fn signed_distance_within(&self, p: Vec3, reach: f32) -> Option<(f32, Vec3)> {
        match self {
            Shape::Mesh(mesh) => mesh.signed_distance_within(p, reach),
            _ => Some(self.signed_distance(p)).filter(|&(d, _)| d < reach),
        }
    }

    /// [`Self::signed_distance_within`] at `to` for a particle that moved
    /// there from `from` (both in the shape's frame). Mesh colliders also
    /// catch a move that crossed their surface, however thin the mesh, and
    /// push back to the side it came from
    /// ([`MeshCollider::swept_signed_distance_within`]); the other shapes
    /// answer at `to` alone.
    pub fn swept_signed_distance_within(
        &self,
        from: Vec3,
        to: Vec3,
        reach: f32,
    ) -> Option<(f32, Vec3)> {
        match self {
            Shape::Mesh(mesh) => mesh.swept_signed_distance_within(from, to, reach),
            _ => self.signed_distance_within(to, reach),
        }
    }
}

fn sphere(d: Vec3, radius: f32) -> (f32, Vec3) {
    let len = d.length();
    let normal = if len > 0.0 { d / len } else { Vec3::Y };
    (len - radius, normal)
}

/// Distance to an axis-aligned box centred at the origin.
fn oriented_box(p: Vec3, half: Vec3) -> (f32, Vec3) {
    let q = p.abs() - half;
    if q.max_element() > 0.0 {
        let outside = q.max(Vec3::ZERO);
        let len = outside.length();
        (len, (outside * p.signum()) / len)
    } else {
        // Inside: the nearest face is the axis with the largest (least negative) q.
        let axis = if q.x >= q.y && q.x >= q.z {
            Vec3::X
        } else if q.y >= q.z {
            Vec3::Y
        } else {
            Vec3::Z
        };
        (q.max_element(), axis * p.signum())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The normal must be the gradient of the distance.
    fn check_gradient(shape: &Shape, p: Vec3) {
        let (d, n) = shape.signed_distance(p);
        let h = 1e-3;
        let fd = Vec3::new(
            shape.signed_distance(p + Vec3::X * h).0 - d,
            shape.signed_distance(p + Vec3::Y * h).0 - d,
            shape.signed_distance(p + Vec3::Z * h).0 - d,
        ) / h;
        assert!(fd.distance(n) < 1e-2, "{shape:?} at {p}: fd {fd} vs {n}");
    }

    #[test]
    fn distances_and_normals() {
        let sphere = Shape::Sphere {
            center: Vec3::ONE,
            radius: 0.5,
        };
        assert!((sphere.signed_distance(Vec3::new(1.0, 2.0, 1.0)).0 - 0.5).abs() < 1e-6);
        let boxed = Shape::Box {
            center: Vec3::ZERO,
            half_extents: Vec3::new(1.0, 0.5, 0.25),
            rotation: Quat::from_rotation_y(0.3),
        };
        assert!((boxed.signed_distance(Vec3::ZERO).0 + 0.25).abs() < 1e-6);
        let capsule = Shape::Capsule {
            a: Vec3::ZERO,
            b: Vec3::Y,
            radius: 0.2,
        };
        assert!((capsule.signed_distance(Vec3::new(0.5, 0.5, 0.0)).0 - 0.3).abs() < 1e-6);
        let plane = Shape::Plane {
            point: Vec3::ZERO,
            normal: Vec3::Y,
        };
        for shape in &[sphere, boxed, capsule, plane] {
            for p in [
                Vec3::new(0.3, 1.4, -0.2),
                Vec3::new(1.2, 0.1, 0.05),
                Vec3::new(-0.1, 0.2, 0.1),
            ] {
                check_gradient(shape, p);
            }
        }
    }
}
