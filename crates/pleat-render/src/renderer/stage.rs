//! What is drawn besides the cloth, and where from: the colliders as
//! meshes, the ground, the pins' markers, and the camera and light framing
//! them all, worked out once from the model and the world.

use super::resources::linear;
use crate::camera::{Bounds, Camera};
use crate::geometry::{collider_color, ground, ground_plane, ColliderMesh, MeshVertex, Surface};
use crate::settings::RenderSettings;
use glam::{Affine3A, Mat4, Vec3, Vec4};
use pleat::collide::Motion;
use pleat::{Model, World};

/// The scene around the cloth and its framing.
pub(super) struct Stage {
    /// Each collider drawn as a mesh, with its colour.
    pub(super) colliders: Vec<(ColliderMesh, Vec3)>,
    /// The ground under the scene.
    pub(super) ground: Vec<MeshVertex>,
    /// A ball drawn at each pin, and where the pins are at time zero and how they move.
    pub(super) pin_marker: ColliderMesh,
    pub(super) pins: Vec<(Vec3, Motion)>,
    /// Radius of the scene's bounding sphere: where the near and far planes go.
    pub(super) radius: f32,
    /// The box around the colliders and the cloth at rest.
    pub(super) bounds: Bounds,
    /// The light's world to clip, its box holding the scene and the ground under it.
    pub(super) light_view_proj: Mat4,
}

impl Stage {
    /// The stage of `model`'s cloths and `world`'s colliders as they are
    /// now, lit by `settings`' light.
    pub(super) fn new(model: &Model, world: &World, settings: &RenderSettings) -> Self {
        let colliders: Vec<(ColliderMesh, Vec3)> = world
            .colliders
            .iter()
            .enumerate()
            .filter_map(|(i, c)| ColliderMesh::of(&c.shape).map(|m| (m, collider_color(i))))
            .collect();
        let bounds = colliders
            .iter()
            .filter_map(|(m, _)| m.bounds())
            .chain(Bounds::of(model.rest.iter().copied()))
            .reduce(Bounds::union)
            .unwrap_or(Bounds {
                min: Vec3::splat(-0.5),
                max: Vec3::splat(0.5),
            });
        let (center, radius) = (bounds.center(), bounds.radius());
        let (plane_point, plane_normal) = ground_plane(&world.colliders, &bounds);
        // The light's box holds the scene and the ground under it.
        let foot = center - plane_normal * (center - plane_point).dot(plane_normal);
        let lit = bounds.union(Bounds {
            min: foot,
            max: foot,
        });
        Stage {
            ground: ground(plane_point, plane_normal, center, radius * 25.0),
            colliders,
            pin_marker: ColliderMesh::pin_marker(radius * 0.012),
            pins: model
                .pins
                .iter()
                .map(|p| (model.rest[p.particle as usize], p.motion))
                .collect(),
            radius,
            bounds,
            light_view_proj: settings.light.view_proj(lit.center(), lit.radius()),
        }
    }

    /// The settings' camera, else one framing the stage in pictures of
    /// `aspect` (width over height).
    pub(super) fn camera(&self, settings: &RenderSettings, aspect: f32) -> Camera {
        settings
            .camera
            .unwrap_or_else(|| Camera::framing(&self.bounds, aspect))
    }

    /// Vertices of the ground, the colliders and the pins' markers together.
    pub(super) fn mesh_vertex_count(&self) -> u32 {
        let colliders: usize = self.colliders.iter().map(|(m, _)| m.positions.len()).sum();
        (self.ground.len() + colliders + self.pins.len() * self.pin_marker.positions.len()) as u32
    }

    /// The ground, the colliders and the pins, placed at the world's time
    /// (`mirror`: colliders as mirrors), as the mesh pipeline draws them.
    pub(super) fn vertices(&self, world: &World, mirror: bool) -> Vec<MeshVertex> {
        let mut vertices = self.ground.clone();
        let surface = if mirror {
            Surface::Mirror
        } else {
            Surface::Patterned
        };
        let placed = world
            .colliders
            .iter()
            .filter(|c| !matches!(c.shape, pleat::collide::Shape::Plane { .. }));
        for ((mesh, color), collider) in self.colliders.iter().zip(placed) {
            let tint = if mirror { Vec3::splat(0.9) } else { *color };
            let linear_tint = Vec4::from_array(linear(tint)).truncate();
            vertices.extend(mesh.vertices(&collider.pose_at(world.time), linear_tint, surface));
        }
        let pin_color = Vec4::from_array(linear(Vec3::splat(0.15))).truncate();
        for (anchor, motion) in &self.pins {
            let at = motion.pose_at(world.time).transform_point3(*anchor);
            let pose = Affine3A::from_translation(at);
            vertices.extend(self.pin_marker.vertices(&pose, pin_color, Surface::Matte));
        }
        vertices.truncate(self.mesh_vertex_count() as usize);
        vertices
    }
}
