//! The plain data the kernels read, laid out as their WGSL structs
//! (`shaders/structs.wgsl`; `crate::layout` tests the match), and its
//! construction from the core's world. Constraint arrays need no
//! conversion: the core's constraint types are already `#[repr(C)]` Pod.

use crate::GpuError;
use bytemuck::{Pod, Zeroable};
use glam::{Affine3A, Vec3};
use pleat::collide::{Collider, ColliderPose, SdfGrid, Shape};
use pleat::control::Control;
use pleat::solver::SolverSettings;
use pleat::World;

/// Per-substep parameters (`Params` in structs.wgsl).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct Params {
    pub gravity: [f32; 3],
    pub dt: f32,
    pub wind_velocity: [f32; 3],
    pub inv_dt2: f32,
    pub t: f32,
    pub keep: f32,
    pub progress: f32,
    pub substep: u32,
    pub particle_count: u32,
    pub triangle_count: u32,
    pub pin_count: u32,
    pub collider_count: u32,
    pub wind_on: u32,
    pub drag: f32,
    pub lift: f32,
    pub air_density: f32,
    pub turbulence: f32,
    pub turbulence_scale: f32,
    pub turbulence_frequency: f32,
    pub grab_particle: u32,
    pub grab_target: [f32; 3],
    pub grab_compliance: f32,
    pub relaxation: f32,
    pub contact_cell: f32,
    pub contact_thickness: f32,
    pub contact_buckets: u32,
    pub contact_static: f32,
    pub contact_kinetic: f32,
    /// 1 while the fold progress is held: driven creases stiffen.
    pub fold_held: u32,
    /// Always 0, unknown to the shader compiler: an exact sum's round-off
    /// masked with it is not simplified away (momentum.wgsl).
    pub opaque_zero: u32,
    pub contact_margin: f32,
    pub contact_exclusion: f32,
    pub contact_capacity: u32,
    /// Largest angle a crease is driven to (radians), `FoldDrive::max_angle`.
    pub max_fold_angle: f32,
}

/// What [`Params::at`] needs besides the world and the settings.
pub struct Counts {
    pub particles: u32,
    pub triangles: u32,
    pub pins: u32,
    pub colliders: u32,
    /// Self-contacts (zero when off): the hash grid's cell size and
    /// buckets, and the candidates' margin, exclusion radius and capacity.
    pub contact_cell: f32,
    pub contact_buckets: u32,
    pub contact_margin: f32,
    pub contact_exclusion: f32,
    pub contact_capacity: u32,
}

impl Params {
    /// The parameters of substep `substep`, from `t` to `t + dt`.
    pub fn at(
        world: &World,
        settings: &SolverSettings,
        counts: &Counts,
        control: &Control,
        (substep, t, dt): (u32, f32, f32),
    ) -> Self {
        let wind = world.wind.unwrap_or_default();
        let grab = control.grab;
        Params {
            gravity: world.gravity.to_array(),
            dt,
            wind_velocity: wind.velocity.to_array(),
            inv_dt2: 1.0 / (dt * dt),
            t,
            keep: (1.0 - settings.damping * dt).max(0.0),
            progress: control.fold.progress,
            substep,
            particle_count: counts.particles,
            triangle_count: counts.triangles,
            pin_count: counts.pins,
            collider_count: counts.colliders,
            wind_on: world.wind.is_some() as u32,
            drag: wind.drag,
            lift: wind.lift,
            air_density: wind.air_density,
            turbulence: wind.turbulence,
            turbulence_scale: wind.turbulence_scale,
            turbulence_frequency: wind.turbulence_frequency,
            grab_particle: grab.map_or(u32::MAX, |g| g.particle),
            grab_target: grab.map_or([0.0; 3], |g| g.target.to_array()),
            grab_compliance: grab.map_or(0.0, |g| g.compliance),
            relaxation: settings.relaxation,
            contact_cell: counts.contact_cell,
            contact_thickness: settings.self_collision.thickness,
            contact_buckets: counts.contact_buckets,
            contact_static: settings.self_collision.friction.static_coefficient,
            contact_kinetic: settings.self_collision.friction.kinetic_coefficient,
            fold_held: control.fold.held as u32,
            opaque_zero: 0,
            contact_margin: counts.contact_margin,
            contact_exclusion: counts.contact_exclusion,
            contact_capacity: counts.contact_capacity,
            max_fold_angle: control.fold.max_angle(),
        }
    }
}

/// A slice of a constraint array (`Range` in structs.wgsl).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct Range {
    pub first: u32,
    pub count: u32,
}

/// A soft attachment (`Attachment` in structs.wgsl).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct Attachment {
    pub particle: u32,
    pub compliance: f32,
    /// Index of its target among the pins' targets of a substep.
    pub slot: u32,
    pub pad: u32,
}

/// A collider shape (`Collider` in structs.wgsl).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct GpuCollider {
    pub kind: u32,
    pub sdf_offset: u32,
    pub static_friction: f32,
    pub kinetic_friction: f32,
    pub a: [f32; 4],
    pub b: [f32; 4],
    pub c: [f32; 4],
    pub dims: [u32; 4],
}

const PLANE: u32 = 0;
const SPHERE: u32 = 1;
const BOX: u32 = 2;
const CAPSULE: u32 = 3;
const SDF: u32 = 4;

/// Cells along the longest side of a mesh collider's box when it is baked
/// into a distance field for the GPU.
pub const MESH_SDF_CELLS: f32 = 96.0;

/// The colliders as the kernels read them.
pub struct Colliders {
    pub shapes: Vec<GpuCollider>,
    /// Every distance field's node values, one field after another.
    pub sdf_values: Vec<f32>,
    /// For the user: each mesh baked into a distance field.
    pub notes: Vec<String>,
}

/// The world's colliders for the kernels; mesh colliders are baked into
/// distance fields. Dynamic bodies are refused.
pub fn colliders(world: &World) -> Result<Colliders, GpuError> {
    let mut shapes = Vec::with_capacity(world.colliders.len());
    let mut values = Vec::new();
    let mut notes = Vec::new();
    for (i, c) in world.colliders.iter().enumerate() {
        if c.is_dynamic() {
            return Err(GpuError::Unsupported {
                field: format!("colliders[{i}].body"),
                reason: "dynamic rigid bodies run on the CPU backend only".into(),
            });
        }
        shapes.push(collider(i, c, &mut values, &mut notes)?);
    }
    Ok(Colliders {
        shapes,
        sdf_values: values,
        notes,
    })
}

/// Copies the world's collider friction into `shapes`, since it is live
/// (the app and sweeps change it between frames); whether any changed.
pub fn refresh_friction(shapes: &mut [GpuCollider], world: &World) -> bool {
    let mut changed = false;
    for (g, c) in shapes.iter_mut().zip(&world.colliders) {
        let f = [
            c.friction.static_coefficient,
            c.friction.kinetic_coefficient,
        ];
        changed |= [g.static_friction, g.kinetic_friction] != f;
        [g.static_friction, g.kinetic_friction] = f;
    }
    changed
}

fn collider(
    i: usize,
    c: &Collider,
    values: &mut Vec<f32>,
    notes: &mut Vec<String>,
) -> Result<GpuCollider, GpuError> {
    let mut g = GpuCollider {
        static_friction: c.friction.static_coefficient,
        kinetic_friction: c.friction.kinetic_coefficient,
        ..GpuCollider::default()
    };
    let v4 = |v: Vec3, w: f32| [v.x, v.y, v.z, w];
    match &c.shape {
        Shape::Plane { point, normal } => {
            (g.kind, g.a, g.b) = (PLANE, v4(*point, 0.0), v4(*normal, 0.0));
        }
        Shape::Sphere { center, radius } => (g.kind, g.a) = (SPHERE, v4(*center, *radius)),
        Shape::Box {
            center,
            half_extents,
            rotation,
        } => {
            (g.kind, g.a, g.b, g.c) = (
                BOX,
                v4(*center, 0.0),
                v4(*half_extents, 0.0),
                rotation.to_array(),
            );
        }
        Shape::Capsule { a, b, radius } => {
            (g.kind, g.a, g.b) = (CAPSULE, v4(*a, *radius), v4(*b, 0.0));
        }
        Shape::Sdf(grid) => grid_collider(&mut g, grid, values),
        Shape::Mesh(mesh) => {
            let bounds = mesh.bounds();
            let cell = (bounds.max - bounds.min).max_element() / MESH_SDF_CELLS;
            let grid = SdfGrid::bake(mesh, cell).map_err(|reason| GpuError::Unsupported {
                field: format!("colliders[{i}].shape"),
                reason: format!("cannot bake the mesh into a distance field: {reason}"),
            })?;
            let [nx, ny, nz] = grid.dims();
            notes.push(format!(
                "colliders[{i}]: mesh baked into a {nx} x {ny} x {nz} distance field (cell {cell:.4} m) for the GPU"
            ));
            grid_collider(&mut g, &grid, values);
        }
    }
    Ok(g)
}

fn grid_collider(g: &mut GpuCollider, grid: &SdfGrid, values: &mut Vec<f32>) {
    let [nx, ny, nz] = grid.dims();
    let o = grid.origin();
    g.kind = SDF;
    g.sdf_offset = values.len() as u32;
    g.a = [o.x, o.y, o.z, grid.cell_size()];
    g.dims = [nx as u32, ny as u32, nz as u32, 0];
    values.extend_from_slice(grid.values());
}

/// An affine map as the three rows of its 3 x 4 matrix (`Affine` in structs.wgsl).
fn rows(m: Affine3A) -> [[f32; 4]; 3] {
    let (x, y, z, t) = (
        m.matrix3.x_axis,
        m.matrix3.y_axis,
        m.matrix3.z_axis,
        m.translation,
    );
    [0, 1, 2].map(|i| [x[i], y[i], z[i], t[i]])
}

/// A collider's placement over a substep (`Pose` in structs.wgsl).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct GpuPose {
    pub start: [[f32; 4]; 3],
    pub end: [[f32; 4]; 3],
    pub start_inverse: [[f32; 4]; 3],
    pub end_inverse: [[f32; 4]; 3],
}

impl From<ColliderPose> for GpuPose {
    fn from(p: ColliderPose) -> Self {
        GpuPose {
            start: rows(p.start),
            end: rows(p.end),
            start_inverse: rows(p.start_inverse),
            end_inverse: rows(p.end_inverse),
        }
    }
}
