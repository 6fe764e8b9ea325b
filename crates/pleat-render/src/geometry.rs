//! What the GPU draws, built on the CPU once: the cloth's texture
//! coordinates, the triangles around each particle (for the normals pass),
//! the lines of the wireframe and constraint views, and the colliders and
//! ground as triangle meshes.

use crate::camera::Bounds;
use bytemuck::{Pod, Zeroable};
use glam::{Affine3A, Quat, Vec2, Vec3};
use pleat::collide::{Collider, Shape};
use pleat::origami::pattern::Assignment;
use pleat::Model;
use std::collections::HashMap;
use std::f32::consts::PI;

/// Texture tiles per metre of cloth.
const TILES_PER_METRE: f32 = 8.0;

/// Texture coordinates of each particle: its rest position projected on
/// the plane of the two longest sides of its cloth's rest bounds, in
/// texture tiles. Grid cloths and crease-pattern sheets are flat at rest,
/// so this is their own parametrisation.
pub fn planar_uvs(model: &Model) -> Vec<Vec2> {
    let mut uvs = vec![Vec2::ZERO; model.particle_count()];
    for cloth in &model.cloths {
        let rest = &model.rest[cloth.particles()];
        let Some(bounds) = Bounds::of(rest.iter().copied()) else {
            continue;
        };
        let extent = bounds.max - bounds.min;
        // The axis the sheet is thinnest along is left out.
        let (u_axis, v_axis) = match extent.min_position() {
            0 => (2, 1),
            1 => (0, 2),
            _ => (0, 1),
        };
        for (uv, p) in uvs[cloth.particles()].iter_mut().zip(rest) {
            let d = *p - bounds.min;
            // v grows downwards in the texture.
            *uv = Vec2::new(d[u_axis], extent[v_axis] - d[v_axis]) * TILES_PER_METRE;
        }
    }
    uvs
}

/// The triangles around each particle, compressed: particle `i`'s are
/// `triangles[start[i]..start[i + 1]]`.
pub struct Incidence {
    pub start: Vec<u32>,
    pub triangles: Vec<u32>,
}

impl Incidence {
    pub fn new(particles: usize, triangles: &[[u32; 3]]) -> Self {
        let incidence =
            pleat::mesh::incidence::Incidence::new(triangles, particles, |t| t.as_slice());
        let (start, slots) = incidence.rows();
        Incidence {
            start: start.to_vec(),
            triangles: slots.iter().map(|s| s.element).collect(),
        }
    }
}

/// A line between two particles, with its colour (linear RGB, alpha 1).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct Line {
    pub ends: [u32; 2],
    pub color: [f32; 4],
}

/// Kinds of constraint the constraint view tells apart, with their colours.
pub const CONSTRAINT_KINDS: [(&str, [f32; 3]); 6] = [
    ("stretch", [0.1, 0.55, 0.85]),
    ("shear", [0.15, 0.7, 0.25]),
    ("bend", [0.95, 0.6, 0.1]),
    ("mountain", [0.85, 0.1, 0.1]),
    ("valley", [0.15, 0.2, 0.95]),
    ("facet", [0.55, 0.55, 0.55]),
];

fn line(a: u32, b: u32, kind: usize) -> Line {
    let [r, g, b_] = CONSTRAINT_KINDS[kind].1;
    Line {
        ends: [a, b],
        color: [r, g, b_, 1.0],
    }
}

/// Every edge of the model, dark grey.
pub fn wireframe_lines(model: &Model) -> Vec<Line> {
    model
        .edges
        .iter()
        .map(|e| Line {
            ends: e.v,
            color: [0.08, 0.08, 0.1, 1.0],
        })
        .collect()
}

/// The constraints, coloured by kind: on cloth, edges are stretch (shear
/// for grid diagonals) and each pair of adjacent triangles is a bending
/// element drawn between its two wing tips; on paper, creases are mountain
/// or valley, other hinges facet, and the boundary stretch.
pub fn constraint_lines(model: &Model) -> Vec<Line> {
    let mut lines = Vec::new();
    for cloth in &model.cloths {
        let global = |v: u32| cloth.global(v);
        match &cloth.paper {
            Some(paper) => {
                let mut hinged = std::collections::HashSet::new();
                for h in &paper.hinges {
                    let kind = match h.assignment {
                        Assignment::Mountain => 3,
                        Assignment::Valley => 4,
                        _ => 5,
                    };
                    hinged.insert([h.v[0].min(h.v[1]), h.v[0].max(h.v[1])]);
                    lines.push(line(global(h.v[0]), global(h.v[1]), kind));
                }
                for e in &cloth.topology.edges {
                    if !hinged.contains(&e.v) {
                        lines.push(line(global(e.v[0]), global(e.v[1]), 0));
                    }
                }
            }
            None => {
                for p in &cloth.topology.pairs {
                    lines.push(line(global(p.v[2]), global(p.v[3]), 2));
                }
                for e in &cloth.topology.edges {
                    let kind = if cloth.mesh.is_grid_diagonal(e.v[0], e.v[1]) {
                        1
                    } else {
                        0
                    };
                    lines.push(line(global(e.v[0]), global(e.v[1]), kind));
                }
            }
        }
    }
    lines
}

/// A vertex of a collider or the ground.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct MeshVertex {
    pub position: [f32; 3],
    pub normal: [f32; 3],
    /// Linear RGB, alpha 1.
    pub color: [f32; 4],
    /// Where the point is in the collider's own frame, in pattern cells
    /// (a patterned collider's checks turn and move with it).
    pub body: [f32; 3],
    /// 0 matte, 1 mirror, 2 ground, 3 patterned (see meshes.wgsl).
    pub kind: u32,
}

/// Surface of a mesh vertex.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Surface {
    Matte = 0,
    Mirror = 1,
    Ground = 2,
    /// Matte, with checks in the body frame: turning and shape read at a glance.
    Patterned = 3,
}

/// Checks across a collider's longest side.
const PATTERN_CELLS: f32 = 6.0;

/// A collider as triangles at time zero, moved each frame by its pose.
pub struct ColliderMesh {
    pub positions: Vec<Vec3>,
    pub normals: Vec<Vec3>,
    /// The body frame's pattern: time-zero positions to checks (the
    /// shape's own axes, its centre at the origin, a check a unit).
    pattern: Affine3A,
}

impl ColliderMesh {
    /// Triangles (three vertices each) of `shape`; `None` for a plane,
    /// which is drawn as the ground.
    pub fn of(shape: &Shape) -> Option<ColliderMesh> {
        let axes = match shape {
            Shape::Box { rotation, .. } => *rotation,
            Shape::Capsule { a, b, .. } => {
                Quat::from_rotation_arc(Vec3::Y, (*b - *a).normalize_or(Vec3::Y))
            }
            _ => Quat::IDENTITY,
        };
        let mesh = match shape {
            Shape::Plane { .. } => return None,
            Shape::Sphere { center, radius } => {
                capsule(*center, *center, *radius, Quat::IDENTITY, SMOOTH)
            }
            Shape::Capsule { a, b, radius } => {
                let axis = (*b - *a).normalize_or(Vec3::Y);
                capsule(
                    *a,
                    *b,
                    *radius,
                    Quat::from_rotation_arc(Vec3::Y, axis),
                    SMOOTH,
                )
            }
            Shape::Box {
                center,
                half_extents,
                rotation,
            } => cuboid(*center, *half_extents, *rotation),
            Shape::Mesh(mesh) => smooth(mesh.triangles().collect()),
            Shape::Sdf(grid) => smooth(grid.surface().to_vec()),
        };
        Some(mesh.with_pattern(axes))
    }

    /// The mesh with checks along `axes`, [`PATTERN_CELLS`] across its
    /// longest side.
    fn with_pattern(mut self, axes: Quat) -> Self {
        let turn = Affine3A::from_quat(axes.inverse());
        if let Some(b) = Bounds::of(self.positions.iter().map(|p| turn.transform_point3(*p))) {
            let side = (b.max - b.min).max_element().max(1e-6);
            let to_cells = Affine3A::from_scale(Vec3::splat(PATTERN_CELLS / side))
                * Affine3A::from_translation(-(b.min + b.max) * 0.5);
            self.pattern = to_cells * turn;
        }
        self
    }

    /// A small ball of `radius` at the origin, to mark a pin.
    pub fn pin_marker(radius: f32) -> ColliderMesh {
        capsule(Vec3::ZERO, Vec3::ZERO, radius, Quat::IDENTITY, [6, 10])
    }

    /// Bounds at time zero.
    pub fn bounds(&self) -> Option<Bounds> {
        Bounds::of(self.positions.iter().copied())
    }

    /// The vertices placed by `pose`, with `color` and `surface`.
    pub fn vertices(&self, pose: &Affine3A, color: Vec3, surface: Surface) -> Vec<MeshVertex> {
        self.positions
            .iter()
            .zip(&self.normals)
            .map(|(p, n)| MeshVertex {
                position: pose.transform_point3(*p).to_array(),
                normal: pose.transform_vector3(*n).normalize_or_zero().to_array(),
                color: color.extend(1.0).to_array(),
                body: self.pattern.transform_point3(*p).to_array(),
                kind: surface as u32,
            })
            .collect()
    }
}

/// A sphere of `radius` around the segment `a`-`b` turned by `rotation`
/// (a sphere when `a == b`): a UV sphere whose upper half sits on `b`, its
/// lower half on `a`, and a cylinder between the two copies of the equator.
/// Rings (even) and segments of a smooth sphere.
const SMOOTH: [usize; 2] = [24, 48];

fn capsule(
    a: Vec3,
    b: Vec3,
    radius: f32,
    rotation: Quat,
    [rings_count, segments]: [usize; 2],
) -> ColliderMesh {
    let half = rings_count / 2;
    let rings: Vec<(usize, Vec3)> = (0..=half)
        .map(|r| (r, b))
        .chain((half..=rings_count).map(|r| (r, a)))
        .collect();
    let vertex = |(ring, end): (usize, Vec3), seg: usize| {
        let theta = PI * ring as f32 / rings_count as f32;
        let phi = 2.0 * PI * seg as f32 / segments as f32;
        let n = rotation
            * Vec3::new(
                theta.sin() * phi.cos(),
                theta.cos(),
                theta.sin() * phi.sin(),
            );
        (end + n * radius, n)
    };
    let mut mesh = ColliderMesh {
        positions: Vec::new(),
        normals: Vec::new(),
        pattern: Affine3A::IDENTITY,
    };
    for w in rings.windows(2) {
        for s in 0..segments {
            for (ring, seg) in [
                (w[0], s),
                (w[1], s),
                (w[1], s + 1),
                (w[0], s),
                (w[1], s + 1),
                (w[0], s + 1),
            ] {
                let (p, n) = vertex(ring, seg);
                mesh.positions.push(p);
                mesh.normals.push(n);
            }
        }
    }
    mesh
}

fn cuboid(center: Vec3, half: Vec3, rotation: Quat) -> ColliderMesh {
    let mut mesh = ColliderMesh {
        positions: Vec::new(),
        normals: Vec::new(),
        pattern: Affine3A::IDENTITY,
    };
    for axis in 0..3 {
        for sign in [-1.0f32, 1.0] {
            let mut n = Vec3::ZERO;
            n[axis] = sign;
            let mut t1 = Vec3::ZERO;
            t1[(axis + 1) % 3] = 1.0;
            let mut t2 = Vec3::ZERO;
            t2[(axis + 2) % 3] = 1.0;
            let corner = |a: f32, b: f32| center + rotation * ((n + t1 * a + t2 * b) * half);
            let quad = [
                corner(-1.0, -1.0),
                corner(1.0, -1.0),
                corner(1.0, 1.0),
                corner(-1.0, -1.0),
                corner(1.0, 1.0),
                corner(-1.0, 1.0),
            ];
            for p in quad {
                mesh.positions.push(p);
                mesh.normals.push(rotation * n);
            }
        }
    }
    mesh
}

/// Triangles with normals averaged over the triangles that share a vertex
/// position (smooth shading for OBJ meshes and generated ones).
fn smooth(triangles: Vec<[Vec3; 3]>) -> ColliderMesh {
    let key = |p: Vec3| p.to_array().map(f32::to_bits);
    let mut sums: HashMap<[u32; 3], Vec3> = HashMap::new();
    for [a, b, c] in &triangles {
        let n = (*b - *a).cross(*c - *a);
        for p in [a, b, c] {
            *sums.entry(key(*p)).or_default() += n;
        }
    }
    let positions: Vec<Vec3> = triangles.iter().flatten().copied().collect();
    let normals = positions
        .iter()
        .map(|p| sums[&key(*p)].normalize_or(Vec3::Y))
        .collect();
    ColliderMesh {
        positions,
        normals,
        pattern: Affine3A::IDENTITY,
    }
}

/// Colour of the `i`-th collider (sRGB): a few calm colours in turn.
pub fn collider_color(i: usize) -> Vec3 {
    const COLORS: [[f32; 3]; 4] = [
        [0.62, 0.66, 0.72],
        [0.75, 0.68, 0.55],
        [0.55, 0.68, 0.6],
        [0.7, 0.58, 0.66],
    ];
    Vec3::from_array(COLORS[i % COLORS.len()])
}

/// The ground: a square of `half` metres around `center` on the plane
/// through `point` with unit `normal`.
pub fn ground(point: Vec3, normal: Vec3, center: Vec3, half: f32) -> Vec<MeshVertex> {
    let n = normal.normalize_or(Vec3::Y);
    let middle = center - n * (center - point).dot(n);
    let t1 = n.any_orthonormal_vector();
    let t2 = n.cross(t1);
    let corner = |a: f32, b: f32| middle + (t1 * a + t2 * b) * half;
    [
        corner(-1.0, -1.0),
        corner(1.0, -1.0),
        corner(1.0, 1.0),
        corner(-1.0, -1.0),
        corner(1.0, 1.0),
        corner(-1.0, 1.0),
    ]
    .map(|p| MeshVertex {
        position: p.to_array(),
        normal: n.to_array(),
        color: [0.8, 0.78, 0.74, 1.0],
        body: [0.0; 3],
        kind: Surface::Ground as u32,
    })
    .to_vec()
}

/// Where the ground goes: the first plane collider, else the horizontal
/// plane y = 0, or one just below `bounds` if they reach lower.
pub fn ground_plane(colliders: &[Collider], bounds: &Bounds) -> (Vec3, Vec3) {
    colliders
        .iter()
        .find_map(|c| match c.shape {
            Shape::Plane { point, normal } => Some((point, normal)),
            _ => None,
        })
        .unwrap_or_else(|| {
            // At y = 0, or just below the scene if it reaches lower.
            let below = (bounds.min.y - 0.05 * bounds.radius()).min(0.0);
            (Vec3::new(0.0, below, 0.0), Vec3::Y)
        })
}

#[cfg(test)]
mod tests {
    use super::*;
    use pleat::mesh::GridSpec;
    use pleat::Material;

    fn grid_model(orientation: pleat::mesh::GridOrientation) -> Model {
        let mut model = Model::default();
        let mesh = GridSpec {
            orientation,
            ..GridSpec::new(3, 3, [1.0, 0.5])
        }
        .build();
        model.add_cloth("sheet", mesh, Material::default(), &[], false);
        model
    }

    #[test]
    fn incidence_lists_the_triangles_around_each_particle() {
        let incidence = Incidence::new(4, &[[0, 1, 2], [2, 1, 3]]);
        assert_eq!(incidence.start, [0, 1, 3, 5, 6]);
        assert_eq!(incidence.triangles, [0, 0, 1, 0, 1, 1]);
    }

    #[test]
    fn uvs_span_the_sheet_in_its_own_plane() {
        for orientation in [
            pleat::mesh::GridOrientation::Horizontal,
            pleat::mesh::GridOrientation::Vertical,
        ] {
            let uvs = planar_uvs(&grid_model(orientation));
            let max = uvs.iter().fold(Vec2::ZERO, |m, uv| m.max(*uv));
            let min = uvs.iter().fold(Vec2::MAX, |m, uv| m.min(*uv));
            assert_eq!(min, Vec2::ZERO);
            assert!(
                max.abs_diff_eq(Vec2::new(1.0, 0.5) * TILES_PER_METRE, 1e-5),
                "{max}"
            );
        }
    }

    #[test]
    fn cloth_constraints_are_stretch_shear_and_bend() {
        let model = grid_model(pleat::mesh::GridOrientation::Horizontal);
        let lines = constraint_lines(&model);
        let cloth = &model.cloths[0];
        assert_eq!(
            lines.len(),
            cloth.topology.edges.len() + cloth.topology.pairs.len()
        );
        let count = |kind: usize| {
            let [r, g, b] = CONSTRAINT_KINDS[kind].1;
            lines.iter().filter(|l| l.color == [r, g, b, 1.0]).count()
        };
        // 3 x 3 vertices: 12 structural edges, 4 diagonals, a bending pair per interior edge.
        assert_eq!(count(0), 12);
        assert_eq!(count(1), 4);
        assert_eq!(count(2), cloth.topology.pairs.len());
        assert_eq!(wireframe_lines(&model).len(), 16);
    }

    #[test]
    fn collider_meshes_close_around_their_shapes() {
        let sphere = ColliderMesh::of(&Shape::Sphere {
            center: Vec3::ONE,
            radius: 0.5,
        })
        .unwrap();
        for p in &sphere.positions {
            assert!((p.distance(Vec3::ONE) - 0.5).abs() < 1e-5);
        }
        let capsule = ColliderMesh::of(&Shape::Capsule {
            a: Vec3::ZERO,
            b: Vec3::X,
            radius: 0.2,
        })
        .unwrap();
        let b = capsule.bounds().unwrap();
        assert!(
            b.min.abs_diff_eq(Vec3::new(-0.2, -0.2, -0.2), 1e-5),
            "{b:?}"
        );
        assert!(b.max.abs_diff_eq(Vec3::new(1.2, 0.2, 0.2), 1e-5), "{b:?}");
        assert!(ColliderMesh::of(&Shape::Plane {
            point: Vec3::ZERO,
            normal: Vec3::Y
        })
        .is_none());
    }
}
