//! The scene file schema (serde): every field, its default and its meaning.

use crate::collide::Friction;
use crate::force::Wind;
use crate::material::Material;
use crate::mesh::generate::{Icosphere, TorusKnot};
use crate::mesh::GridOrientation;
use crate::paper::{FoldRamp, PaperStiffness};
use crate::solver::SolverSettings;
use glam::{EulerRot, Quat, Vec3};
use serde::{Deserialize, Serialize};

/// A whole scene.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scene {
    /// Name used in reports; defaults to the file name.
    #[serde(default)]
    pub name: String,
    /// Frames to simulate; default 300.
    #[serde(default = "default_frames")]
    pub frames: u32,
    /// Frames per second of the output.
    #[serde(default = "default_fps")]
    pub fps: f32,
    /// Gravitational acceleration (m/s^2); default `[0, -9.81, 0]`.
    #[serde(default = "default_gravity")]
    pub gravity: Vec3,
    /// The solver and its settings (kind, substeps, iterations, damping,
    /// self-collision); defaults apply when absent.
    #[serde(default)]
    pub solver: SolverSettings,
    /// The cloths and sheets of paper, each with its mesh, material and pins.
    pub cloths: Vec<ClothSpec>,
    /// The rigid obstacles; default none.
    #[serde(default)]
    pub colliders: Vec<ColliderSpec>,
    /// Wind blowing on every cloth; absent for still air.
    #[serde(default)]
    pub wind: Option<Wind>,
    /// How pattern cloths fold; defaults apply when absent.
    #[serde(default)]
    pub fold: Option<FoldSpec>,
    /// How `pleat render` draws the scene; defaults apply when absent.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub render: Option<RenderSpec>,
}

/// How the scene is drawn (`pleat render`): camera, light and the cloth's
/// look. Every field is optional; colours are sRGB in `[0, 1]`.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct RenderSpec {
    /// Where the camera stands; absent frames the scene.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub camera: Option<CameraSpec>,
    /// The directional light; absent uses the renderer's default.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub light: Option<LightSpec>,
    /// The cloth's texture: `"fabric"`, `"checker"`, `"plain"`, or a PNG
    /// file relative to the scene file's folder. Default: fabric for
    /// cloth, plain for paper.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub texture: Option<String>,
    /// A grey PNG height map (relative to the scene file's folder) for bump
    /// and displacement mapping; default: the fabric weave's.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub height_map: Option<String>,
    /// Bump mapping: the height (m) of the height map's full range, white
    /// over black (0 turns it off; default 1.5 mm for cloth, 0 for paper).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub bump: Option<f32>,
    /// Displacement of the surface along its normal by the height map (m,
    /// white over black; default 0).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub displacement: Option<f32>,
    /// Colour of the cloth's front (the side its triangles face).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub front_color: Option<[f32; 3]>,
    /// Colour of the cloth's back.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub back_color: Option<[f32; 3]>,
    /// Draw the colliders as mirrors reflecting the sky.
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub mirror_colliders: bool,
}

/// A camera at `position` looking at `target`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CameraSpec {
    /// Where the camera stands (m).
    pub position: Vec3,
    /// The point the camera looks at (m).
    pub target: Vec3,
    /// Vertical field of view in degrees.
    #[serde(default = "default_fov")]
    pub fov_degrees: f32,
}

fn default_fov() -> f32 {
    40.0
}

/// A directional light.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LightSpec {
    /// The direction the light travels, e.g. `[0, -1, 0]` from straight above.
    pub direction: Vec3,
    /// Linear colour times intensity.
    #[serde(default = "default_light_color")]
    pub color: [f32; 3],
}

fn default_light_color() -> [f32; 3] {
    [0.9, 0.9, 0.9]
}

/// The fold progress of a scene's pattern cloths: ramped linearly from 0
/// to `progress` over the first `frames_to_fold` frames, then held; or,
/// with `steps` (or a pattern file with steps of its own, a multi-frame
/// FOLD file), folded step after step ([`crate::fold_steps`]).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct FoldSpec {
    /// Fold progress in `[0, 1]`: each crease folds to this fraction of its
    /// full angle (a fold in one go; not read with steps).
    pub progress: f32,
    /// Frames over which the progress rises from 0; 0 sets it at once.
    /// With steps: the frames of each step that gives none.
    pub frames_to_fold: u32,
    /// A fold in steps, one after another: each moves some creases to a
    /// fraction of their full angle, the others holding where the step
    /// before left them (flat before the first).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub steps: Vec<FoldStepSpec>,
}

impl Default for FoldSpec {
    fn default() -> Self {
        FoldSpec {
            progress: 1.0,
            frames_to_fold: 120,
            steps: Vec::new(),
        }
    }
}

/// One step of a scene's fold in steps.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FoldStepSpec {
    /// Which creases the step moves: `"all"`, `"M"` (the mountains), `"V"`
    /// (the valleys), or a list of the pattern's edge indices (the order
    /// of a FOLD file's `edges_vertices`, of a .cp file's lines).
    pub creases: CreaseSelection,
    /// The fraction of their full angle the creases reach at the step's
    /// end, in `[0, 1]`; default 1.
    #[serde(default = "unit_fraction")]
    pub fraction: f32,
    /// Frames of the step (at least 1); default `frames_to_fold`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub frames: Option<u32>,
}

fn unit_fraction() -> f32 {
    1.0
}

/// The creases a step moves: by kind (`"all"`, `"M"`, `"V"`) or by edge
/// index.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum CreaseSelection {
    /// `"all"`, `"M"` or `"V"`.
    Kind(String),
    /// The pattern's edge indices.
    Edges(Vec<usize>),
}

impl FoldSpec {
    /// The fold ramp of the scene's paper: `progress` reached over
    /// `frames_to_fold` frames.
    pub fn ramp(&self) -> FoldRamp {
        FoldRamp {
            progress: self.progress,
            frames: self.frames_to_fold,
        }
    }

    /// The frames of each of `steps` (the pattern's own steps where
    /// `steps` is empty: `frames_to_fold` each).
    pub fn step_frames(&self) -> Vec<u32> {
        if self.steps.is_empty() {
            return vec![self.frames_to_fold];
        }
        self.steps
            .iter()
            .map(|s| s.frames.unwrap_or(self.frames_to_fold))
            .collect()
    }
}

fn default_frames() -> u32 {
    300
}
fn default_fps() -> f32 {
    60.0
}
fn default_gravity() -> Vec3 {
    Vec3::new(0.0, -9.81, 0.0)
}

/// One cloth: its mesh, material, pins and tethers.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ClothSpec {
    /// Name used in reports and errors; defaults to `cloth<i>`, `i` its
    /// index in `cloths`.
    #[serde(default)]
    pub name: String,
    /// Where the mesh comes from: a grid, an OBJ file or a crease pattern.
    pub mesh: MeshSpec,
    /// Density, compliances and thickness of the cloth; defaults apply when
    /// absent.
    #[serde(default)]
    pub material: Material,
    /// Groups of pinned vertices; default none.
    #[serde(default)]
    pub pins: Vec<PinSpec>,
    /// Long-range attachments from the pins (limits stretch far from them).
    #[serde(default)]
    pub tethers: bool,
    /// One weight per vertex on the classic solvers' stiffness (a spring gets
    /// the mean of its two vertices' weights); empty for uniform stiffness.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub stiffness_weights: Vec<f32>,
}

/// The keys that name a [`MeshSpec`] in a scene file.
pub const MESH_KEYS: &[&str] = &["grid", "obj", "pattern"];

/// The keys that name a [`ShapeSpec`] in a scene file.
pub const SHAPE_KEYS: &[&str] = &[
    "plane",
    "sphere",
    "box",
    "capsule",
    "mesh",
    "sdf",
    "torus_knot",
    "icosphere",
];

/// Where a cloth's mesh comes from.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum MeshSpec {
    /// A rectangular grid generated from its resolution and size.
    Grid(GridMeshSpec),
    /// A triangle mesh read from an OBJ file.
    Obj(ObjMeshSpec),
    /// A crease pattern, folded as paper.
    Pattern(PatternMeshSpec),
}

/// A rectangular grid cloth (see [`crate::mesh::grid`]): row 0 is the top edge,
/// column 0 the left one.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GridMeshSpec {
    /// Vertices along x and along the other side.
    pub resolution: [u32; 2],
    /// Metres.
    #[serde(default = "unit_size")]
    pub size: [f32; 2],
    /// The plane the sheet lies in: `horizontal` (x-z, facing +y; the default)
    /// or `vertical` (x-y, facing +z).
    #[serde(default)]
    pub orientation: GridOrientation,
    /// Centre of the sheet (m); default the origin.
    #[serde(default)]
    pub center: Vec3,
    /// Alternate the diagonal direction from quad to quad (a less biased mesh);
    /// default true.
    #[serde(default = "yes")]
    pub alternate_diagonals: bool,
}

fn unit_size() -> [f32; 2] {
    [1.0, 1.0]
}
fn yes() -> bool {
    true
}

/// A cloth mesh read from an OBJ file, each vertex placed at
/// `position * scale + translate`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ObjMeshSpec {
    /// Relative to the scene file's folder.
    pub path: String,
    /// Uniform scale of the file's positions; default 1.
    #[serde(default = "unit_scale")]
    pub scale: f32,
    /// Offset added after scaling (m); default zero.
    #[serde(default)]
    pub translate: Vec3,
}

fn unit_scale() -> f32 {
    1.0
}

/// A crease pattern from a file or a built-in, triangulated into a sheet in
/// the x-y plane whose creases are hinges. Give `path` or `builtin`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PatternMeshSpec {
    /// A `.cp`, `.fold` or `.svg` file, relative to the scene file's folder.
    #[serde(default)]
    pub path: Option<String>,
    /// The name of a built-in pattern, such as `miura-ori`.
    #[serde(default)]
    pub builtin: Option<String>,
    /// Longest side of the sheet (m).
    #[serde(default = "unit_scale")]
    pub size: f32,
    /// Target edge length of the triangulation (m); absent keeps only the
    /// pattern's own vertices.
    #[serde(default)]
    pub max_edge: Option<f32>,
    /// Where the sheet's centre is placed (m); default the origin.
    #[serde(default)]
    pub center: Vec3,
    /// Compliance of the creases and of the facet hinges; 1 each when absent.
    #[serde(default)]
    pub stiffness: PaperStiffness,
}

/// A group of pinned vertices, chosen by grid corner, grid edge or index.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PinSpec {
    /// Grid corners to pin, e.g. `top_left` (grid meshes only).
    #[serde(default)]
    pub corners: Vec<Corner>,
    /// Whole grid edges to pin, e.g. `left` (grid meshes only).
    #[serde(default)]
    pub edges: Vec<Side>,
    /// Vertex indices to pin, for any mesh; each must exist.
    #[serde(default)]
    pub indices: Vec<u32>,
    /// 0 holds exactly; more lets the cloth pull away (m/N).
    #[serde(default)]
    pub compliance: f32,
    /// Scripted motion of the pinned vertices (pivot default: the origin);
    /// default at rest.
    #[serde(default)]
    pub motion: MotionSpec,
}

/// A corner of a grid cloth: row 0 is the top edge, column 0 the left one.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Corner {
    /// Row 0, column 0.
    TopLeft,
    /// Row 0, last column.
    TopRight,
    /// Last row, column 0.
    BottomLeft,
    /// Last row, last column.
    BottomRight,
}

/// An edge of a grid cloth: row 0 is the top edge, column 0 the left one.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Side {
    /// Row 0: the highest edge of a vertical sheet, the farthest along -z of a
    /// horizontal one.
    Top,
    /// The last row.
    Bottom,
    /// Column 0 (-x).
    Left,
    /// The last column (+x).
    Right,
}

/// Scripted motion: constant linear and angular velocity.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct MotionSpec {
    /// Constant velocity (m/s).
    pub linear_velocity: Vec3,
    /// Axis times rate (rad/s).
    pub angular_velocity: Vec3,
    /// Centre of rotation at time zero; defaults to the collider's centre (or the origin for pins).
    pub pivot: Option<Vec3>,
}

/// A collider: shape, friction, and either scripted motion (static or
/// kinematic) or a dynamic body.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ColliderSpec {
    /// The collider's shape, placed at time zero.
    pub shape: ShapeSpec,
    /// Coulomb friction against the cloth, `{"static": .., "kinetic": ..}`;
    /// default 0.4 and 0.3.
    #[serde(default)]
    pub friction: Friction,
    /// Scripted motion of a static or kinematic collider (pivot default: the
    /// shape's centre); default at rest, unused with `body`.
    #[serde(default)]
    pub motion: MotionSpec,
    /// Makes the collider a dynamic rigid body, moved by gravity, the cloth
    /// and the static colliders.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub body: Option<BodySpec>,
}

/// A dynamic rigid body: give its `density` (kg/m^3) or its `mass` (kg);
/// the inertia follows from the shape.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct BodySpec {
    /// Density (kg/m^3) the mass and inertia follow from; default 1.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub density: Option<f32>,
    /// Total mass (kg); when given, the mass and inertia are scaled to it.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub mass: Option<f32>,
    /// Initial velocity of the centre of mass (m/s).
    pub linear_velocity: Vec3,
    /// Initial spin (rad/s, axis times rate).
    pub angular_velocity: Vec3,
}

/// The shape of a collider, named by its key, e.g.
/// `{"sphere": {"center": [0, 0.35, 0], "radius": 0.35}}`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum ShapeSpec {
    /// Solid below the plane through `point` facing `normal`.
    Plane {
        /// A point on the plane (m); default the origin.
        #[serde(default)]
        point: Vec3,
        /// The plane's outward normal (normalised when built); default +y.
        #[serde(default = "up")]
        normal: Vec3,
    },
    /// A solid sphere.
    Sphere {
        /// Centre (m).
        center: Vec3,
        /// Radius (m).
        radius: f32,
    },
    /// A solid box, turned about its centre.
    Box {
        /// Centre (m).
        center: Vec3,
        /// Half the box's size along its own axes (m).
        half_extents: Vec3,
        /// Euler angles X, Y, Z in degrees.
        #[serde(default)]
        rotation_degrees: Vec3,
    },
    /// A solid capsule: the points within `radius` of the segment from `a` to
    /// `b`.
    Capsule {
        /// One end of the segment (m).
        a: Vec3,
        /// The other end of the segment (m).
        b: Vec3,
        /// Radius (m).
        radius: f32,
    },
    /// A triangle mesh from an OBJ file, queried through a BVH.
    Mesh(MeshShapeSpec),
    /// A signed distance field baked from an OBJ file onto a grid.
    Sdf(SdfShapeSpec),
    /// A tube around a (p, q) torus knot, generated as a triangle mesh.
    TorusKnot(TorusKnotSpec),
    /// A sphere generated as a subdivided icosahedron.
    Icosphere(IcosphereSpec),
}

/// A mesh collider: `path` relative to the scene file's folder, each vertex
/// placed at `position * scale + translate`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MeshShapeSpec {
    /// The OBJ file, relative to the scene file's folder.
    pub path: String,
    /// Uniform scale of the file's positions; default 1.
    #[serde(default = "unit_scale")]
    pub scale: f32,
    /// Offset added after scaling (m); default zero.
    #[serde(default)]
    pub translate: Vec3,
}

/// A distance field baked from a mesh placed as in [`MeshShapeSpec`], with
/// grid cells of `cell_size` metres.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SdfShapeSpec {
    /// The OBJ file, relative to the scene file's folder.
    pub path: String,
    /// Uniform scale of the file's positions; default 1.
    #[serde(default = "unit_scale")]
    pub scale: f32,
    /// Offset added after scaling (m); default zero.
    #[serde(default)]
    pub translate: Vec3,
    /// Edge length of the distance field's grid cells (m).
    pub cell_size: f32,
}

/// A generated torus knot tube (see [`TorusKnot`]): its centre line winds
/// `p` times around the axis (y, turned by `rotation_degrees`) and `q` times
/// around the core of a torus of radii `radius` and `radius / 2`. Queried
/// through a BVH like an OBJ mesh, or baked into a distance field when
/// `sdf_cell_size` is given.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TorusKnotSpec {
    /// Centre of the knot (m).
    pub center: Vec3,
    /// Radius of the torus the knot winds around (m).
    pub radius: f32,
    /// Radius of the tube; less than what makes it intersect itself.
    pub tube: f32,
    /// Windings around the axis; default 2.
    #[serde(default = "two")]
    pub p: u32,
    /// Windings around the torus's core; default 3.
    #[serde(default = "three")]
    pub q: u32,
    /// Rings of vertices along the knot.
    #[serde(default = "knot_segments")]
    pub segments: u32,
    /// Vertices around each ring.
    #[serde(default = "knot_sides")]
    pub sides: u32,
    /// Euler angles X, Y, Z in degrees.
    #[serde(default)]
    pub rotation_degrees: Vec3,
    /// Bake the knot into a distance field with cells of this size (m); absent
    /// queries the mesh through a BVH.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sdf_cell_size: Option<f32>,
}

impl TorusKnotSpec {
    /// The generator of the knot's mesh.
    pub fn knot(&self) -> TorusKnot {
        TorusKnot {
            center: self.center,
            rotation: euler_degrees(self.rotation_degrees),
            radius: self.radius,
            tube: self.tube,
            p: self.p,
            q: self.q,
            segments: self.segments,
            sides: self.sides,
        }
    }
}

/// A generated icosphere (see [`Icosphere`]), queried through a BVH or baked
/// into a distance field when `sdf_cell_size` is given.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct IcosphereSpec {
    /// Centre (m).
    pub center: Vec3,
    /// Radius (m).
    pub radius: f32,
    /// Each splits every triangle in four: `20 * 4^subdivisions` triangles.
    #[serde(default = "icosphere_subdivisions")]
    pub subdivisions: u32,
    /// Bake the sphere into a distance field with cells of this size (m);
    /// absent queries the mesh through a BVH.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sdf_cell_size: Option<f32>,
}

impl IcosphereSpec {
    /// The generator of the sphere's mesh.
    pub fn icosphere(&self) -> Icosphere {
        Icosphere {
            center: self.center,
            radius: self.radius,
            subdivisions: self.subdivisions,
        }
    }
}

/// The rotation of Euler angles X, Y, Z in degrees.
pub fn euler_degrees(r: Vec3) -> Quat {
    Quat::from_euler(
        EulerRot::XYZ,
        r.x.to_radians(),
        r.y.to_radians(),
        r.z.to_radians(),
    )
}

fn two() -> u32 {
    2
}
fn three() -> u32 {
    3
}
fn knot_segments() -> u32 {
    256
}
fn knot_sides() -> u32 {
    16
}
fn icosphere_subdivisions() -> u32 {
    4
}

fn up() -> Vec3 {
    Vec3::Y
}
