//! Dynamic rigid bodies, integrated the way Müller et al. 2020, "Detailed
//! Rigid Body Simulation with Extended Position Based Dynamics", do it: each
//! substep predicts the pose from the velocities and gravity (rotation by
//! `q += dt/2 [omega, 0] q`, then normalised), lets contacts correct the pose
//! with positional impulses, and derives the velocities from the change of pose.
//!
//! Mass properties come from the collider's shape and a density: analytic
//! for spheres, boxes and capsules, and for closed triangle meshes the
//! polyhedral volume integrals of Mirtich 1996 in the form of Eberly,
//! "Polyhedral Mass Properties (Revisited)". A body's shape stays in the
//! coordinates it was placed in at time zero; the pose maps those to the
//! world: `x -> position + orientation * (x - center_of_mass)`.

use super::mesh_collider::MeshCollider;
use super::shape::Shape;
use glam::{Affine3A, DVec3, Mat3, Quat, Vec3};
use std::collections::HashSet;
use std::f32::consts::PI;

/// Why a shape has no mass properties.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum MassError {
    /// The mesh's signed volume is (nearly) zero: it is open or flat.
    #[error("the mesh encloses no volume: a dynamic mesh must be closed")]
    NoVolume,
    /// A plane is unbounded.
    #[error("a plane cannot be dynamic: it has no finite mass")]
    Plane,
    /// A distance field keeps no solid to integrate; the mesh it was baked
    /// from must be weighed instead.
    #[error("a distance field needs its mesh to be weighed")]
    DistanceField,
}

/// Mass, centre of mass and inertia tensor of a solid.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MassProperties {
    /// kg.
    pub mass: f32,
    /// In the shape's time-zero coordinates (m).
    pub center_of_mass: Vec3,
    /// About the centre of mass, in the shape's axes (kg m^2).
    pub inertia: Mat3,
}

impl MassProperties {
    /// A solid sphere.
    pub fn sphere(center: Vec3, radius: f32, density: f32) -> Self {
        let mass = density * 4.0 / 3.0 * PI * radius.powi(3);
        MassProperties {
            mass,
            center_of_mass: center,
            inertia: Mat3::from_diagonal(Vec3::splat(0.4 * mass * radius * radius)),
        }
    }

    /// A solid box with `half_extents` along its own axes, turned by `rotation`.
    pub fn cuboid(center: Vec3, half_extents: Vec3, rotation: Quat, density: f32) -> Self {
        let h2 = half_extents * half_extents;
        let mass = density * 8.0 * half_extents.x * half_extents.y * half_extents.z;
        let local =
            Mat3::from_diagonal(Vec3::new(h2.y + h2.z, h2.x + h2.z, h2.x + h2.y) * mass / 3.0);
        let r = Mat3::from_quat(rotation);
        MassProperties {
            mass,
            center_of_mass: center,
            inertia: r * local * r.transpose(),
        }
    }

    /// A solid capsule: a cylinder of length `|b - a|` capped by two half spheres.
    pub fn capsule(a: Vec3, b: Vec3, radius: f32, density: f32) -> Self {
        let length = a.distance(b);
        let r2 = radius * radius;
        let cylinder = density * PI * r2 * length;
        let half_sphere = density * 2.0 / 3.0 * PI * radius.powi(3);
        let axial = cylinder * r2 / 2.0 + 2.0 * half_sphere * 0.4 * r2;
        let across = cylinder * (length * length / 12.0 + r2 / 4.0)
            + 2.0 * half_sphere * (0.4 * r2 + length * length / 4.0 + 3.0 * length * radius / 8.0);
        let u = if length > 0.0 {
            (b - a) / length
        } else {
            Vec3::Y
        };
        let uu = Mat3::from_cols(u * u.x, u * u.y, u * u.z);
        MassProperties {
            mass: cylinder + 2.0 * half_sphere,
            center_of_mass: (a + b) / 2.0,
            inertia: Mat3::IDENTITY * across + uu * (axial - across),
        }
    }

    /// The solid a closed triangle mesh bounds (either winding; the sign of
    /// the volume tells). Errors on a mesh that encloses no volume.
    pub fn mesh(
        triangles: impl Iterator<Item = [Vec3; 3]>,
        density: f32,
    ) -> Result<Self, MassError> {
        let triangles: Vec<[Vec3; 3]> = triangles.collect();
        // Integrate about a point near the mesh, for precision.
        let origin = triangles.first().map_or(Vec3::ZERO, |t| t[0]).as_dvec3();
        let mut integral = [0.0f64; 10];
        for t in &triangles {
            let [p0, p1, p2] = t.map(|p| p.as_dvec3() - origin);
            let d = (p1 - p0).cross(p2 - p0);
            let (f1x, f2x, f3x, g0x, g1x, g2x) = subexpressions(p0.x, p1.x, p2.x);
            let (_, f2y, f3y, g0y, g1y, g2y) = subexpressions(p0.y, p1.y, p2.y);
            let (_, f2z, f3z, g0z, g1z, g2z) = subexpressions(p0.z, p1.z, p2.z);
            integral[0] += d.x * f1x;
            integral[1] += d.x * f2x;
            integral[2] += d.y * f2y;
            integral[3] += d.z * f2z;
            integral[4] += d.x * f3x;
            integral[5] += d.y * f3y;
            integral[6] += d.z * f3z;
            integral[7] += d.x * (p0.y * g0x + p1.y * g1x + p2.y * g2x);
            integral[8] += d.y * (p0.z * g0y + p1.z * g1y + p2.z * g2y);
            integral[9] += d.z * (p0.x * g0z + p1.x * g1z + p2.x * g2z);
        }
        let scale = [
            1.0 / 6.0,
            1.0 / 24.0,
            1.0 / 24.0,
            1.0 / 24.0,
            1.0 / 60.0,
            1.0 / 60.0,
            1.0 / 60.0,
            1.0 / 120.0,
            1.0 / 120.0,
            1.0 / 120.0,
        ];
        for (i, s) in integral.iter_mut().zip(scale) {
            *i *= s;
        }
        let volume = integral[0];
        let (lo, hi) = triangles.iter().flatten().fold(
            (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
            |(lo, hi), p| (lo.min(*p), hi.max(*p)),
        );
        let extent = (hi - lo).as_dvec3();
        if !volume.is_finite() || volume.abs() <= 1e-6 * extent.x * extent.y * extent.z {
            return Err(MassError::NoVolume);
        }
        if volume < 0.0 {
            for i in &mut integral {
                *i = -*i;
            }
        }
        let density = density as f64;
        let mass = integral[0] * density;
        let c = DVec3::new(integral[1], integral[2], integral[3]) / integral[0];
        let m = integral[0];
        let xx = integral[5] + integral[6] - m * (c.y * c.y + c.z * c.z);
        let yy = integral[4] + integral[6] - m * (c.z * c.z + c.x * c.x);
        let zz = integral[4] + integral[5] - m * (c.x * c.x + c.y * c.y);
        let xy = -(integral[7] - m * c.x * c.y);
        let yz = -(integral[8] - m * c.y * c.z);
        let zx = -(integral[9] - m * c.z * c.x);
        let inertia = Mat3::from_cols(
            Vec3::new(xx as f32, xy as f32, zx as f32),
            Vec3::new(xy as f32, yy as f32, yz as f32),
            Vec3::new(zx as f32, yz as f32, zz as f32),
        ) * density as f32;
        Ok(MassProperties {
            mass: mass as f32,
            center_of_mass: (c + origin).as_vec3(),
            inertia,
        })
    }

    /// The mass properties of `shape` at `density` (kg/m^3). Planes have
    /// none; distance fields are measured from the mesh they were baked
    /// from ([`MassProperties::mesh`]).
    pub fn of_shape(shape: &Shape, density: f32) -> Result<Self, MassError> {
        match shape {
            Shape::Plane { .. } => Err(MassError::Plane),
            Shape::Sphere { center, radius } => Ok(Self::sphere(*center, *radius, density)),
            Shape::Box {
                center,
                half_extents,
                rotation,
            } => Ok(Self::cuboid(*center, *half_extents, *rotation, density)),
            Shape::Capsule { a, b, radius } => Ok(Self::capsule(*a, *b, *radius, density)),
            Shape::Mesh(mesh) => Self::mesh(mesh.triangles(), density),
            Shape::Sdf(_) => Err(MassError::DistanceField),
        }
    }

    /// The same solid scaled to weigh `mass`.
    pub fn with_mass(self, mass: f32) -> Self {
        let k = mass / self.mass;
        MassProperties {
            mass,
            center_of_mass: self.center_of_mass,
            inertia: self.inertia * k,
        }
    }
}

/// Eberly's subexpressions of the integrals over one triangle along one axis.
fn subexpressions(w0: f64, w1: f64, w2: f64) -> (f64, f64, f64, f64, f64, f64) {
    let temp0 = w0 + w1;
    let f1 = temp0 + w2;
    let temp1 = w0 * w0;
    let temp2 = temp1 + w1 * temp0;
    let f2 = temp2 + w2 * f1;
    let f3 = w0 * temp1 + w1 * temp2 + w2 * f2;
    let g0 = f2 + w0 * (f1 + w0);
    let g1 = f2 + w1 * (f1 + w1);
    let g2 = f2 + w2 * (f1 + w2);
    (f1, f2, f3, g0, g1, g2)
}

/// A point of a body's surface, swept by `radius`, that is tested against
/// static colliders (Müller 2020, section 3.5): the centre of a sphere, points
/// along a capsule's axis, a box's corners, edge midpoints and face centres,
/// a mesh's vertices. In the shape's time-zero coordinates.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SamplePoint {
    /// The point, in the shape's time-zero coordinates.
    pub local: Vec3,
    /// Radius swept around the point (m): the sphere's or capsule's radius; 0 for a box corner or a mesh vertex.
    pub radius: f32,
}

/// The points of `shape` that touch static colliders; distance fields use
/// the vertices of their mesh ([`mesh_samples`]).
pub fn sample_points(shape: &Shape) -> Vec<SamplePoint> {
    match shape {
        Shape::Plane { .. } | Shape::Sdf(_) => Vec::new(),
        Shape::Sphere { center, radius } => vec![SamplePoint {
            local: *center,
            radius: *radius,
        }],
        Shape::Box {
            center,
            half_extents,
            rotation,
        } => {
            let mut out = Vec::with_capacity(26);
            for i in -1..=1 {
                for j in -1..=1 {
                    for k in -1..=1 {
                        if (i, j, k) != (0, 0, 0) {
                            let s = Vec3::new(i as f32, j as f32, k as f32);
                            out.push(SamplePoint {
                                local: *center + *rotation * (s * *half_extents),
                                radius: 0.0,
                            });
                        }
                    }
                }
            }
            out
        }
        Shape::Capsule { a, b, radius } => {
            let n = ((a.distance(*b) / radius).ceil() as usize + 1).clamp(2, 16);
            (0..n)
                .map(|i| SamplePoint {
                    local: a.lerp(*b, i as f32 / (n - 1) as f32),
                    radius: *radius,
                })
                .collect()
        }
        Shape::Mesh(mesh) => mesh_samples(mesh),
    }
}

/// Every distinct vertex of `mesh`, in first-seen order.
pub fn mesh_samples(mesh: &MeshCollider) -> Vec<SamplePoint> {
    let mut seen = HashSet::new();
    mesh.triangles()
        .flatten()
        .filter(|p| seen.insert(p.to_array().map(f32::to_bits)))
        .map(|local| SamplePoint { local, radius: 0.0 })
        .collect()
}

/// A rigid body's mass properties and state.
#[derive(Clone, Debug, PartialEq)]
pub struct RigidBody {
    /// Mass (kg).
    pub mass: f32,
    /// Centre of mass in the shape's time-zero coordinates.
    pub center_of_mass: Vec3,
    /// Inertia about the centre of mass in the time-zero axes, and its inverse.
    pub inertia: Mat3,
    /// Inverse of `inertia`.
    pub inv_inertia: Mat3,
    /// Points of the surface tested against the static colliders.
    pub samples: Vec<SamplePoint>,
    /// Farthest a sample point reaches from the centre of mass (m).
    pub bound_radius: f32,
    /// World position of the centre of mass.
    pub position: Vec3,
    /// Rotation from the time-zero placement.
    pub orientation: Quat,
    /// Velocity of the centre of mass (m/s).
    pub linear_velocity: Vec3,
    /// rad/s, axis times rate.
    pub angular_velocity: Vec3,
    /// Pose at the start of the current substep.
    pub prev_position: Vec3,
    /// Orientation at the start of the current substep.
    pub prev_orientation: Quat,
    /// Sum of the contacts' translations this substep.
    correction: Vec3,
}

impl RigidBody {
    /// A body at rest where its shape was placed.
    pub fn new(props: MassProperties, samples: Vec<SamplePoint>) -> Self {
        let com = props.center_of_mass;
        let bound_radius = samples
            .iter()
            .map(|s| s.local.distance(com) + s.radius)
            .fold(0.0, f32::max);
        RigidBody {
            mass: props.mass,
            center_of_mass: com,
            inertia: props.inertia,
            inv_inertia: props.inertia.inverse(),
            samples,
            bound_radius,
            position: com,
            orientation: Quat::IDENTITY,
            linear_velocity: Vec3::ZERO,
            angular_velocity: Vec3::ZERO,
            prev_position: com,
            prev_orientation: Quat::IDENTITY,
            correction: Vec3::ZERO,
        }
    }

    /// Inverse mass (1/kg).
    pub fn inv_mass(&self) -> f32 {
        1.0 / self.mass
    }

    /// The map from time-zero coordinates to the world now.
    pub fn pose(&self) -> Affine3A {
        pose(self.position, self.orientation, self.center_of_mass)
    }

    /// The pose at the start of the current substep.
    pub fn prev_pose(&self) -> Affine3A {
        pose(
            self.prev_position,
            self.prev_orientation,
            self.center_of_mass,
        )
    }

    /// Inverse inertia in world axes at the current orientation.
    pub fn inv_inertia_world(&self) -> Mat3 {
        let r = Mat3::from_quat(self.orientation);
        r * self.inv_inertia * r.transpose()
    }

    /// Generalised inverse mass for a positional correction along the unit
    /// `n` at `r` from the centre of mass: `1/m + (r x n)^T I^-1 (r x n)`.
    pub fn generalized_inv_mass(&self, inv_inertia_world: Mat3, r: Vec3, n: Vec3) -> f32 {
        let rn = r.cross(n);
        self.inv_mass() + rn.dot(inv_inertia_world * rn)
    }

    /// Start of a substep: keeps the pose, then integrates gravity and the
    /// gyroscopic torque into the velocities and the velocities into the pose.
    pub fn predict(&mut self, gravity: Vec3, dt: f32) {
        self.prev_position = self.position;
        self.prev_orientation = self.orientation;
        self.correction = Vec3::ZERO;
        self.linear_velocity += gravity * dt;
        self.position += self.linear_velocity * dt;
        let r = Mat3::from_quat(self.orientation);
        let inertia = r * self.inertia * r.transpose();
        let w = self.angular_velocity;
        self.angular_velocity += self.inv_inertia_world() * (-w.cross(inertia * w)) * dt;
        self.orientation = rotate(self.orientation, self.angular_velocity * dt);
    }

    /// Applies the positional impulse `linear` (kg m) whose moment about the
    /// centre of mass is `angular`: `x += p / m`, `q += 1/2 [I^-1 L, 0] q`.
    pub fn apply_impulse(&mut self, inv_inertia_world: Mat3, linear: Vec3, angular: Vec3) {
        let translation = linear * self.inv_mass();
        self.position += translation;
        self.correction += translation;
        self.orientation = rotate(self.orientation, inv_inertia_world * angular);
    }

    /// End of a substep: velocities from the change of pose. The linear one
    /// is `(x - x_prev) / dt`, computed as the predicted velocity plus the
    /// contacts' translations over `dt`: the same in exact arithmetic, without
    /// the cancellation of subtracting two nearby positions far from the origin.
    pub fn update_velocities(&mut self, dt: f32) {
        self.linear_velocity += self.correction / dt;
        let dq = self.orientation * self.prev_orientation.inverse();
        let w = Vec3::new(dq.x, dq.y, dq.z) * (2.0 / dt);
        self.angular_velocity = if dq.w >= 0.0 { w } else { -w };
    }

    /// Linear momentum (kg m/s).
    pub fn momentum(&self) -> Vec3 {
        self.linear_velocity * self.mass
    }

    /// Kinetic energy, translational plus rotational (J).
    pub fn kinetic_energy(&self) -> f32 {
        let r = Mat3::from_quat(self.orientation);
        let inertia = r * self.inertia * r.transpose();
        let w = self.angular_velocity;
        0.5 * self.mass * self.linear_velocity.length_squared() + 0.5 * w.dot(inertia * w)
    }

    /// Whether the state holds NaN or infinity.
    pub fn is_finite(&self) -> bool {
        self.position.is_finite()
            && self.orientation.is_finite()
            && self.linear_velocity.is_finite()
            && self.angular_velocity.is_finite()
    }
}

fn pose(position: Vec3, orientation: Quat, com: Vec3) -> Affine3A {
    Affine3A::from_rotation_translation(orientation, position - orientation * com)
}

/// `q + 1/2 [theta, 0] q`, normalised: `q` turned by the small rotation vector `theta`.
fn rotate(q: Quat, theta: Vec3) -> Quat {
    let dq = Quat::from_xyzw(theta.x, theta.y, theta.z, 0.0) * q;
    (q + dq * 0.5).normalize()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pose_keeps_the_centre_of_mass() {
        let mut body = RigidBody::new(
            MassProperties::sphere(Vec3::new(1.0, 2.0, 3.0), 0.5, 1000.0),
            Vec::new(),
        );
        body.orientation = Quat::from_rotation_z(0.7);
        body.position = Vec3::new(0.0, 1.0, 0.0);
        let p = body.pose().transform_point3(Vec3::new(1.0, 2.0, 3.0));
        assert!(p.distance(Vec3::Y) < 1e-6, "{p}");
    }

    #[test]
    fn spin_is_recovered_from_the_change_of_orientation() {
        let mut body = RigidBody::new(MassProperties::sphere(Vec3::ZERO, 0.5, 1000.0), Vec::new());
        body.angular_velocity = Vec3::new(0.0, 0.0, 3.0);
        // One second in substeps of 1/600 s; each loses about (w dt)^2 / 8 of the spin.
        for _ in 0..600 {
            body.predict(Vec3::ZERO, 1.0 / 600.0);
            body.update_velocities(1.0 / 600.0);
        }
        assert!(
            (body.angular_velocity.z - 3.0).abs() < 1e-2,
            "{}",
            body.angular_velocity
        );
        let (axis, angle) = body.orientation.to_axis_angle();
        assert!(
            (angle - 3.0).abs() < 2e-2 && axis.z > 0.99,
            "{axis} {angle}"
        );
    }

    #[test]
    fn capsule_of_no_length_is_a_sphere() {
        let c = MassProperties::capsule(Vec3::ZERO, Vec3::ZERO, 0.3, 700.0);
        let s = MassProperties::sphere(Vec3::ZERO, 0.3, 700.0);
        assert!((c.mass - s.mass).abs() < 1e-4);
        assert!(c.inertia.abs_diff_eq(s.inertia, 1e-5));
    }
}
