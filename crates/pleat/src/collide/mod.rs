//! Collisions: collider shapes (analytic, triangle meshes with a BVH and
//! signed distance fields baked from them), their scripted motion and the cloth-collider
//! contact projection with Coulomb friction; dynamic rigid bodies and their
//! two-way contacts with the cloth and with the static colliders;
//! self-collision and cloth-cloth contact over a spatial hash grid, with
//! continuous collision detection.

pub mod body_contact;
pub mod ccd;
mod contact;
pub mod hash_grid;
pub mod mesh_collider;
pub mod rigid_body;
pub mod sdf;
pub mod self_contact;
mod shape;

pub use crate::motion::Motion;
pub use contact::{project_contacts, ColliderPose};
pub use mesh_collider::MeshCollider;
pub use rigid_body::{MassError, MassProperties, RigidBody};
pub use sdf::{SdfError, SdfGrid};
pub use self_contact::{ContactMasses, SelfCollision, SelfContactStats, SelfContacts};
pub use shape::Shape;

use serde::{Deserialize, Serialize};

/// Coulomb friction coefficients of a surface.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Friction {
    /// Below `static * normal correction` a sliding contact sticks.
    #[serde(rename = "static")]
    pub static_coefficient: f32,
    /// Sliding contacts lose `kinetic * normal correction` of tangential motion.
    #[serde(rename = "kinetic")]
    pub kinetic_coefficient: f32,
}

impl Default for Friction {
    fn default() -> Self {
        Friction {
            static_coefficient: 0.4,
            kinetic_coefficient: 0.3,
        }
    }
}

/// A rigid obstacle: a shape placed at time zero, moved by its scripted
/// motion (static or kinematic) or, when it has a body, by gravity and its
/// contacts (dynamic).
#[derive(Clone, Debug, PartialEq)]
pub struct Collider {
    /// The shape, in its time-zero placement.
    pub shape: Shape,
    /// Scripted motion of a static or kinematic collider.
    pub motion: Motion,
    /// Coulomb friction against the cloth.
    pub friction: Friction,
    /// Mass properties and state of a dynamic collider; `motion` is then unused.
    pub body: Option<RigidBody>,
}

impl Collider {
    /// A static or kinematic collider.
    pub fn scripted(shape: Shape, motion: Motion, friction: Friction) -> Self {
        Collider {
            shape,
            motion,
            friction,
            body: None,
        }
    }

    /// Whether the collider is a dynamic rigid body.
    pub fn is_dynamic(&self) -> bool {
        self.body.is_some()
    }

    /// The map from the time-zero placement to the world at time `t`; a
    /// dynamic collider's current pose, whatever `t`.
    pub fn pose_at(&self, t: f32) -> glam::Affine3A {
        match &self.body {
            Some(body) => body.pose(),
            None => self.motion.pose_at(t),
        }
    }

    /// Signed distance of the world point `p` at time `t` (negative inside).
    pub fn signed_distance_at(&self, p: glam::Vec3, t: f32) -> f32 {
        let local = self.pose_at(t).inverse().transform_point3(p);
        self.shape.signed_distance(local).0
    }
}
