//! Collisions: collider shapes (analytic, triangle meshes with a BVH and
//! signed distance fields baked from them), their scripted motion and the cloth-collider
//! contact projection with Coulomb friction; self-collision and cloth-cloth
//! contact over a spatial hash grid, with continuous collision detection.

pub mod ccd;
mod contact;
pub mod hash_grid;
pub mod mesh_collider;
mod motion;
pub mod sdf;
pub mod self_contact;
mod shape;

pub use contact::{project_contacts, ColliderPose};
pub use mesh_collider::MeshCollider;
pub use motion::Motion;
pub use sdf::SdfGrid;
pub use self_contact::{SelfCollision, SelfContactStats, SelfContacts};
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

/// A rigid obstacle: a shape placed at time zero, moved by its motion.
#[derive(Clone, Debug, PartialEq)]
pub struct Collider {
    pub shape: Shape,
    pub motion: Motion,
    pub friction: Friction,
}

impl Collider {
    /// Signed distance of the world point `p` at time `t` (negative inside).
    pub fn signed_distance_at(&self, p: glam::Vec3, t: f32) -> f32 {
        let local = self.motion.pose_at(t).inverse().transform_point3(p);
        self.shape.signed_distance(local).0
    }
}
