//! From a validated scene to a model, a world and a simulation: meshes are
//! built or loaded, pins resolved to vertices, colliders placed.

use super::{
    ClothSpec, ColliderSpec, Corner, MeshSpec, MotionSpec, PinSpec, Scene, SceneError, SceneErrors,
    ShapeSpec, Side,
};
use crate::collide::{Collider, Motion, Shape};
use crate::mesh::{obj::load_obj, GridSpec, Mesh};
use crate::model::{Model, Pin};
use crate::simulation::Simulation;
use crate::world::World;
use glam::{EulerRot, Quat, Vec3};
use std::path::Path;

impl Scene {
    /// The simulation this scene describes; OBJ paths are relative to `base_dir`,
    /// and `file` names the scene in errors.
    pub fn build(&self, base_dir: &Path, file: &str) -> Result<Simulation, SceneErrors> {
        let (model, world) = self.model(base_dir, file)?;
        Ok(Simulation::new(model, world, self.solver))
    }

    /// The model and world of this scene, without building a solver.
    pub fn model(&self, base_dir: &Path, file: &str) -> Result<(Model, World), SceneErrors> {
        let mut model = Model::default();
        let mut errors = Vec::new();
        for (i, cloth) in self.cloths.iter().enumerate() {
            let path = format!("cloths[{i}]");
            match cloth_mesh(cloth, base_dir)
                .and_then(|(mesh, grid)| Ok((pins(cloth, &mesh, grid.as_ref())?, mesh)))
            {
                Ok((pins, mesh)) => {
                    let name = if cloth.name.is_empty() {
                        format!("cloth{i}")
                    } else {
                        cloth.name.clone()
                    };
                    model.add_cloth(&name, mesh, cloth.material, &pins, cloth.tethers);
                    if let Err(reason) = apply_stiffness_weights(&mut model, cloth) {
                        errors.push(SceneError {
                            file: file.into(),
                            path: format!("{path}.stiffness_weights"),
                            reason,
                        });
                    }
                }
                Err((sub, reason)) => errors.push(SceneError {
                    file: file.into(),
                    path: format!("{path}.{sub}"),
                    reason,
                }),
            }
        }
        if !errors.is_empty() {
            return Err(SceneErrors(errors));
        }
        let world = World {
            gravity: self.gravity,
            wind: self.wind,
            colliders: self.colliders.iter().map(collider).collect(),
            time: 0.0,
        };
        Ok((model, world))
    }
}

/// Multiplies the scene's per-vertex weights into the cloth just added.
fn apply_stiffness_weights(model: &mut Model, cloth: &ClothSpec) -> Result<(), String> {
    let part = model.cloths.last_mut().expect("a cloth was just added");
    match cloth.stiffness_weights.len() {
        0 => Ok(()),
        n if n == part.stiffness_weights.len() => {
            for (w, s) in part
                .stiffness_weights
                .iter_mut()
                .zip(&cloth.stiffness_weights)
            {
                *w *= s;
            }
            Ok(())
        }
        n => Err(format!(
            "has {n} weights, the mesh has {} vertices",
            part.stiffness_weights.len()
        )),
    }
}

/// An error inside a cloth: the path below `cloths[i]` and the reason.
type ClothError = (String, String);

fn cloth_mesh(cloth: &ClothSpec, base_dir: &Path) -> Result<(Mesh, Option<GridSpec>), ClothError> {
    match &cloth.mesh {
        MeshSpec::Grid(g) => {
            let spec = GridSpec {
                cols: g.resolution[0] as usize,
                rows: g.resolution[1] as usize,
                size: g.size,
                orientation: g.orientation,
                center: g.center,
                alternate_diagonals: g.alternate_diagonals,
            };
            Ok((spec.build(), Some(spec)))
        }
        MeshSpec::Obj(o) => {
            let mut mesh = load_obj(&base_dir.join(&o.path))
                .map_err(|e| ("mesh.obj.path".to_string(), e.to_string()))?;
            for p in &mut mesh.positions {
                *p = *p * o.scale + o.translate;
            }
            Ok((mesh, None))
        }
    }
}

/// Resolves pin groups to cloth-local vertices (each vertex pinned once, first group wins).
fn pins(cloth: &ClothSpec, mesh: &Mesh, grid: Option<&GridSpec>) -> Result<Vec<Pin>, ClothError> {
    let n = mesh.positions.len();
    let mut pinned = vec![false; n];
    let mut out = Vec::new();
    for (g, group) in cloth.pins.iter().enumerate() {
        for v in group_vertices(group, grid, n)
            .map_err(|(sub, reason)| (format!("pins[{g}].{sub}"), reason))?
        {
            if !std::mem::replace(&mut pinned[v as usize], true) {
                out.push(Pin {
                    particle: v,
                    compliance: group.compliance,
                    motion: motion(&group.motion, Vec3::ZERO),
                });
            }
        }
    }
    Ok(out)
}

fn group_vertices(
    group: &PinSpec,
    grid: Option<&GridSpec>,
    n: usize,
) -> Result<Vec<u32>, ClothError> {
    let mut out = Vec::new();
    if !group.corners.is_empty() || !group.edges.is_empty() {
        let field = if group.corners.is_empty() {
            "edges"
        } else {
            "corners"
        };
        let grid = grid.ok_or((
            field.to_string(),
            "named corners and edges need a grid mesh; use indices".to_string(),
        ))?;
        out.extend(
            group
                .corners
                .iter()
                .map(|c| grid.corner(corner_name(*c)).expect("every corner is named")),
        );
        for side in &group.edges {
            out.extend(grid.edge(side_name(*side)).expect("every side is named"));
        }
    }
    for (k, &i) in group.indices.iter().enumerate() {
        if i as usize >= n {
            return Err((
                format!("indices[{k}]"),
                format!("vertex {i} does not exist: the mesh has {n} vertices"),
            ));
        }
        out.push(i);
    }
    Ok(out)
}

fn corner_name(c: Corner) -> &'static str {
    match c {
        Corner::TopLeft => "top_left",
        Corner::TopRight => "top_right",
        Corner::BottomLeft => "bottom_left",
        Corner::BottomRight => "bottom_right",
    }
}

fn side_name(s: Side) -> &'static str {
    match s {
        Side::Top => "top",
        Side::Bottom => "bottom",
        Side::Left => "left",
        Side::Right => "right",
    }
}

fn motion(spec: &MotionSpec, default_pivot: Vec3) -> Motion {
    Motion {
        linear_velocity: spec.linear_velocity,
        angular_velocity: spec.angular_velocity,
        pivot: spec.pivot.unwrap_or(default_pivot),
    }
}

fn collider(spec: &ColliderSpec) -> Collider {
    let (shape, centre) = match spec.shape {
        ShapeSpec::Plane { point, normal } => (
            Shape::Plane {
                point,
                normal: normal.normalize(),
            },
            point,
        ),
        ShapeSpec::Sphere { center, radius } => (Shape::Sphere { center, radius }, center),
        ShapeSpec::Box {
            center,
            half_extents,
            rotation_degrees: r,
        } => {
            let rotation = Quat::from_euler(
                EulerRot::XYZ,
                r.x.to_radians(),
                r.y.to_radians(),
                r.z.to_radians(),
            );
            (
                Shape::Box {
                    center,
                    half_extents,
                    rotation,
                },
                center,
            )
        }
        ShapeSpec::Capsule { a, b, radius } => (Shape::Capsule { a, b, radius }, (a + b) / 2.0),
    };
    Collider {
        shape,
        motion: motion(&spec.motion, centre),
        friction: spec.friction,
    }
}
