//! From a validated scene to a model, a world and a simulation: meshes are
//! built or loaded, pins resolved to vertices, colliders placed.

use super::{
    BodySpec, ClothSpec, ColliderSpec, Corner, CreaseSelection, FileError, FoldSpec, FoldStepSpec,
    MeshSpec, MotionSpec, PatternMeshSpec, PinSpec, Scene, SceneError, SceneErrors, SceneFiles,
    SceneWarning, ShapeSpec, Side,
};
use crate::backend::{Backend, CpuBackend};
use crate::collide::rigid_body::{mesh_samples, sample_points};
use crate::collide::{
    Collider, MassError, MassProperties, MeshCollider, Motion, RigidBody, SdfError, SdfGrid, Shape,
};
use crate::fold_steps::{sheet_step_angles, FoldSteps};
use crate::mesh::obj::{parse_obj, ObjError};
use crate::mesh::{GridSpec, Mesh};
use crate::metrics::intersections::count_self_intersections;
use crate::model::{Model, Pin};
use crate::origami::{
    builtin, parse_pattern, parse_pattern_steps, Assignment, CreasePattern, PatternError, Sheet,
    SheetOptions,
};
use crate::simulation::Simulation;
use crate::world::World;
use glam::{EulerRot, Quat, Vec3};
use std::path::Path;
use std::sync::Arc;

impl Scene {
    /// The simulation this scene describes; OBJ paths are relative to `base_dir`,
    /// and `file` names the scene in errors.
    pub fn build(&self, base_dir: &Path, file: &str) -> Result<Simulation, SceneErrors> {
        self.build_with(&super::Folder(base_dir), file)
    }

    /// As [`Scene::build`], with the scene's meshes and patterns read from
    /// `files` (in memory, for the app and the web).
    pub fn build_with(
        &self,
        files: &dyn SceneFiles,
        file: &str,
    ) -> Result<Simulation, SceneErrors> {
        let (model, world) = self.model_with(files, file)?;
        let backend = Box::new(CpuBackend::new(&model, &self.solver));
        Ok(self.simulation(model, world, backend))
    }

    /// The simulation of this scene's `model` and `world` (from
    /// [`Scene::model`]) on `backend`, built for them: with the scene's
    /// fold ramp where it has paper.
    pub fn simulation(&self, model: Model, world: World, backend: Box<dyn Backend>) -> Simulation {
        let folds = model.cloths.iter().any(|c| c.paper.is_some());
        let mut sim = Simulation::with_backend(model, world, self.solver, backend);
        if folds {
            let fold = self.fold.clone().unwrap_or_default();
            sim.fold_ramp = Some(fold.ramp());
            sim.fold_steps = FoldSteps::of_model(&sim.model, &fold.step_frames());
        }
        sim
    }

    /// The model and world of this scene, without building a solver (the
    /// warnings of its files' importers dropped: [`Scene::model_and_warnings`]
    /// gives them).
    pub fn model(&self, base_dir: &Path, file: &str) -> Result<(Model, World), SceneErrors> {
        self.model_with(&super::Folder(base_dir), file)
    }

    /// As [`Scene::model`], with the scene's files read from `files`.
    pub fn model_with(
        &self,
        files: &dyn SceneFiles,
        file: &str,
    ) -> Result<(Model, World), SceneErrors> {
        let (model, world, _) = self.model_and_warnings_with(files, file)?;
        Ok((model, world))
    }

    /// As [`Scene::model`], with the warnings of the importers of the
    /// scene's crease patterns (a flat fold with no direction, say), each
    /// under the JSON path of the cloth's pattern.
    pub fn model_and_warnings(
        &self,
        base_dir: &Path,
        file: &str,
    ) -> Result<(Model, World, Vec<SceneWarning>), SceneErrors> {
        self.model_and_warnings_with(&super::Folder(base_dir), file)
    }

    /// As [`Scene::model_and_warnings`], with the scene's files read from
    /// `files`.
    pub fn model_and_warnings_with(
        &self,
        files: &dyn SceneFiles,
        file: &str,
    ) -> Result<(Model, World, Vec<SceneWarning>), SceneErrors> {
        let mut model = Model::default();
        let mut errors = Vec::new();
        let mut warnings = Vec::new();
        for (i, cloth) in self.cloths.iter().enumerate() {
            let name = if cloth.name.is_empty() {
                format!("cloth{i}")
            } else {
                cloth.name.clone()
            };
            let mut said = Vec::new();
            let built = add_cloth(
                &mut model,
                &name,
                (cloth, self.fold.as_ref()),
                files,
                &mut said,
            );
            warnings.extend(said.into_iter().map(|(sub, reason)| SceneWarning {
                file: file.into(),
                path: format!("cloths[{i}].{sub}"),
                reason,
            }));
            if let Err((sub, reason)) = built {
                errors.push(SceneError {
                    file: file.into(),
                    // Errors of the scene's fold steps name their own path.
                    path: if sub.starts_with("fold.") {
                        sub
                    } else {
                        format!("cloths[{i}].{sub}")
                    },
                    reason: reason.to_string(),
                });
            }
        }
        let mut colliders = Vec::with_capacity(self.colliders.len());
        for (i, spec) in self.colliders.iter().enumerate() {
            match collider(spec, files) {
                Ok(c) => colliders.push(c),
                Err((sub, reason)) => errors.push(SceneError {
                    file: file.into(),
                    path: format!("colliders[{i}].{sub}"),
                    reason: reason.to_string(),
                }),
            }
        }
        if !errors.is_empty() {
            return Err(SceneErrors(errors));
        }
        let world = World {
            gravity: self.gravity,
            wind: self.wind,
            colliders,
            time: 0.0,
        };
        Ok((model, world, warnings))
    }
}

/// Why one cloth or collider of a valid scene cannot be built; its message
/// becomes the [`SceneError`]'s reason, under the JSON path of the field.
#[derive(Debug, thiserror::Error)]
enum BuildError {
    /// A scene's file could not be read.
    #[error("{file}: {source}")]
    File {
        /// The file as [`SceneFiles::display`] names it.
        file: String,
        source: FileError,
    },
    /// A mesh file is not text.
    #[error("{file}: not UTF-8 text")]
    NotUtf8 {
        /// The file as [`SceneFiles::display`] names it.
        file: String,
    },
    /// A mesh file is not a valid OBJ mesh.
    #[error(transparent)]
    Obj(#[from] ObjError),
    /// A crease pattern could not be read or triangulated.
    #[error(transparent)]
    Pattern(#[from] PatternError),
    /// A distance field could not be baked.
    #[error(transparent)]
    Sdf(#[from] SdfError),
    /// A dynamic collider could not be weighed.
    #[error(transparent)]
    Mass(#[from] MassError),
    /// A scene's fold steps do not fit a pattern.
    #[error("{0}")]
    Steps(String),
    /// `stiffness_weights` does not give one weight a vertex.
    #[error("has {given} weights, the mesh has {vertices} vertices")]
    WeightCount { given: usize, vertices: usize },
    /// Named corners or edges pin a mesh that is not a grid.
    #[error("named corners and edges need a grid mesh; use indices")]
    NamedPinsNeedGrid,
    /// A pin's vertex index is past the mesh's vertices.
    #[error("vertex {vertex} does not exist: the mesh has {vertices} vertices")]
    NoSuchVertex { vertex: u32, vertices: usize },
    /// A generated torus knot's tube meets itself.
    #[error(
        "the tube's mesh intersects itself ({pairs} pairs of triangles): use a thinner tube or more segments"
    )]
    TubeIntersects {
        /// Pairs of triangles that intersect.
        pairs: usize,
    },
}

/// Multiplies the scene's per-vertex weights into the cloth just added.
fn apply_stiffness_weights(model: &mut Model, cloth: &ClothSpec) -> Result<(), BuildError> {
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
        given => Err(BuildError::WeightCount {
            given,
            vertices: part.stiffness_weights.len(),
        }),
    }
}

/// An error inside a cloth: the path below `cloths[i]` and the reason.
type ClothError = (String, BuildError);

/// Builds one cloth of the scene (a mesh with pins, or a sheet of paper,
/// with the scene's fold) into `model`; its pattern's importer warnings go
/// to `warnings` (the path below `cloths[i]`, and what).
fn add_cloth(
    model: &mut Model,
    name: &str,
    (cloth, fold): (&ClothSpec, Option<&FoldSpec>),
    files: &dyn SceneFiles,
    warnings: &mut Vec<(String, String)>,
) -> Result<(), ClothError> {
    let (mesh, grid) = match &cloth.mesh {
        MeshSpec::Pattern(spec) => {
            let in_pattern = |e: PatternError| ("mesh.pattern".to_string(), e.into());
            let PatternSheet {
                sheet,
                pattern,
                steps: file_steps,
                options,
                warnings: said,
            } = pattern_sheet(spec, files).map_err(in_pattern)?;
            warnings.extend(said.into_iter().map(|w| ("mesh.pattern".to_string(), w)));
            let scene_steps = fold.map_or(&[][..], |f| f.steps.as_slice());
            let steps = match (scene_steps.is_empty(), file_steps.is_empty()) {
                (true, _) => file_steps,
                (false, true) => scene_step_angles(&pattern, scene_steps)?,
                (false, false) => {
                    return Err((
                        "fold.steps".to_string(),
                        BuildError::Steps(format!(
                            "the pattern of cloth '{name}' has steps of its own (a multi-frame FOLD file): give one or the other"
                        )),
                    ))
                }
            };
            let steps =
                sheet_step_angles(&pattern, &options, &sheet, &steps).map_err(in_pattern)?;
            model.add_paper(name, &sheet, cloth.material, spec.stiffness);
            if let Some(paper) = model.cloths.last_mut().and_then(|c| c.paper.as_mut()) {
                paper.steps = steps;
            }
            return Ok(());
        }
        MeshSpec::Grid(g) => {
            let spec = GridSpec {
                cols: g.resolution[0] as usize,
                rows: g.resolution[1] as usize,
                size: g.size,
                orientation: g.orientation,
                center: g.center,
                alternate_diagonals: g.alternate_diagonals,
            };
            (spec.build(), Some(spec))
        }
        MeshSpec::Obj(o) => {
            let mut mesh =
                read_obj(files, &o.path).map_err(|reason| ("mesh.obj.path".to_string(), reason))?;
            for p in &mut mesh.positions {
                *p = *p * o.scale + o.translate;
            }
            (mesh, None)
        }
    };
    let pins = pins(cloth, &mesh, grid.as_ref())?;
    model.add_cloth(name, mesh, cloth.material, &pins, cloth.tethers);
    apply_stiffness_weights(model, cloth)
        .map_err(|reason| ("stiffness_weights".to_string(), reason))
}

/// Each step's edge angles (degrees, signed) from a scene's `fold.steps`:
/// the creases a step names go to its fraction of their full angle, the
/// others hold where the step before left them (flat before the first).
fn scene_step_angles(
    pattern: &CreasePattern,
    steps: &[FoldStepSpec],
) -> Result<Vec<Vec<Option<f64>>>, ClothError> {
    let full = |e: usize| {
        let edge = &pattern.edges[e];
        let sign = edge.assignment.fold_sign()?;
        Some(sign * edge.fold_angle.map_or(180.0, f64::abs))
    };
    let mut fraction = vec![0.0f64; pattern.edges.len()];
    let mut out = Vec::with_capacity(steps.len());
    for (k, step) in steps.iter().enumerate() {
        let chosen: Vec<usize> = match &step.creases {
            CreaseSelection::Kind(kind) => {
                let wanted = |a: Assignment| match kind.as_str() {
                    "M" => a == Assignment::Mountain,
                    "V" => a == Assignment::Valley,
                    _ => a.fold_sign().is_some(),
                };
                (0..pattern.edges.len())
                    .filter(|&e| wanted(pattern.edges[e].assignment))
                    .collect()
            }
            CreaseSelection::Edges(edges) => {
                for (j, &e) in edges.iter().enumerate() {
                    let path = format!("fold.steps[{k}].creases[{j}]");
                    let reason = match pattern.edges.get(e) {
                        None => format!(
                            "edge {e} does not exist: the pattern has {} edges",
                            pattern.edges.len()
                        ),
                        Some(edge) if edge.assignment.fold_sign().is_none() => format!(
                            "edge {e} is not a crease (its assignment is {:?}): only mountains and valleys fold",
                            edge.assignment
                        ),
                        Some(_) => continue,
                    };
                    return Err((path, BuildError::Steps(reason)));
                }
                edges.clone()
            }
        };
        for e in chosen {
            fraction[e] = step.fraction as f64;
        }
        out.push(
            (0..pattern.edges.len())
                .map(|e| full(e).map(|a| a * fraction[e]))
                .collect(),
        );
    }
    Ok(out)
}

/// A pattern cloth's sheet, placed at its centre.
struct PatternSheet {
    sheet: Sheet,
    /// The pattern it is made of.
    pattern: CreasePattern,
    /// The steps of the pattern's file: each edge's angle at each step's
    /// end (none but for a multi-frame FOLD file).
    steps: Vec<Vec<Option<f64>>>,
    /// The options it was triangulated with.
    options: SheetOptions,
    /// The warnings of the pattern file's importer, each after the file's
    /// name.
    warnings: Vec<String>,
}

/// The sheet of a pattern cloth, read from its file or built in.
fn pattern_sheet(
    spec: &PatternMeshSpec,
    files: &dyn SceneFiles,
) -> Result<PatternSheet, PatternError> {
    let mut steps = Vec::new();
    let mut warnings = Vec::new();
    let pattern = match (&spec.path, &spec.builtin) {
        (Some(path), _) => {
            let name = files.display(path);
            let bytes = files
                .read(path)
                .map_err(|e| PatternError::new("", e.to_string()).with_file(name.clone()))?;
            let (pattern, said) = parse_pattern(&name, &bytes)?;
            warnings = said.into_iter().map(|w| format!("{name}: {w}")).collect();
            steps = parse_pattern_steps(&name, &bytes, &pattern)?;
            pattern
        }
        (None, Some(name)) => builtin(name)
            .ok_or_else(|| PatternError::new("builtin", format!("unknown pattern '{name}'")))?,
        (None, None) => return Err(PatternError::new("", "give either path or builtin")),
    };
    let options = SheetOptions {
        size: spec.size as f64,
        max_edge: spec.max_edge.map(f64::from),
        ..SheetOptions::default()
    };
    let mut sheet = Sheet::from_pattern(&pattern, &options)?;
    for p in &mut sheet.positions {
        *p += spec.center;
    }
    Ok(PatternSheet {
        sheet,
        pattern,
        steps,
        options,
        warnings,
    })
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
        let grid = grid.ok_or((field.to_string(), BuildError::NamedPinsNeedGrid))?;
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
                BuildError::NoSuchVertex {
                    vertex: i,
                    vertices: n,
                },
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

/// An error inside a collider: the path below `colliders[i]` and the reason.
type ColliderError = (String, BuildError);

fn collider(spec: &ColliderSpec, files: &dyn SceneFiles) -> Result<Collider, ColliderError> {
    // Distance fields and generated shapes of a dynamic collider are weighed
    // and sampled through their meshes.
    let mut baked_from = None;
    let (shape, centre) = match spec.shape.clone() {
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
        ShapeSpec::Mesh(m) => {
            let mesh = placed_mesh(files, &m.path, m.scale, m.translate)
                .map_err(|reason| ("shape.mesh.path".to_string(), reason))?;
            let centre = mesh_centre(&mesh);
            (Shape::Mesh(Arc::new(mesh)), centre)
        }
        ShapeSpec::Sdf(s) => {
            let mesh = placed_mesh(files, &s.path, s.scale, s.translate)
                .map_err(|reason| ("shape.sdf.path".to_string(), reason))?;
            let grid = SdfGrid::bake(&mesh, s.cell_size)
                .map_err(|e| ("shape.sdf.cell_size".to_string(), e.into()))?;
            let centre = mesh_centre(&mesh);
            baked_from = Some(mesh);
            (Shape::Sdf(Arc::new(grid)), centre)
        }
        ShapeSpec::TorusKnot(k) => {
            let mesh = k.knot().mesh();
            let crossings = count_self_intersections(&mesh.positions, &mesh.triangles);
            if crossings > 0 {
                return Err((
                    "shape.torus_knot.tube".to_string(),
                    BuildError::TubeIntersects { pairs: crossings },
                ));
            }
            let shape = generated_shape(&mesh, k.sdf_cell_size)
                .map_err(|e| ("shape.torus_knot.sdf_cell_size".to_string(), e.into()))?;
            if spec.body.is_some() {
                baked_from = Some(MeshCollider::new(&mesh));
            }
            (shape, k.center)
        }
        ShapeSpec::Icosphere(s) => {
            let mesh = s.icosphere().mesh();
            let shape = generated_shape(&mesh, s.sdf_cell_size)
                .map_err(|e| ("shape.icosphere.sdf_cell_size".to_string(), e.into()))?;
            if spec.body.is_some() {
                baked_from = Some(MeshCollider::new(&mesh));
            }
            (shape, s.center)
        }
    };
    let body = match &spec.body {
        Some(b) => Some(
            dynamic_body(&shape, baked_from.as_ref(), b)
                .map_err(|e| ("body".to_string(), e.into()))?,
        ),
        None => None,
    };
    Ok(Collider {
        shape,
        motion: motion(&spec.motion, centre),
        friction: spec.friction,
        body,
    })
}

/// The rigid body of a dynamic collider, at rest where its shape is placed
/// and then given the spec's initial velocities.
fn dynamic_body(
    shape: &Shape,
    baked_from: Option<&MeshCollider>,
    spec: &BodySpec,
) -> Result<RigidBody, MassError> {
    let density = spec.density.unwrap_or(1.0);
    let (props, samples) = match baked_from {
        Some(mesh) => (
            MassProperties::mesh(mesh.triangles(), density)?,
            mesh_samples(mesh),
        ),
        None => (
            MassProperties::of_shape(shape, density)?,
            sample_points(shape),
        ),
    };
    let props = match spec.mass {
        Some(mass) => props.with_mass(mass),
        None => props,
    };
    let mut body = RigidBody::new(props, samples);
    body.linear_velocity = spec.linear_velocity;
    body.angular_velocity = spec.angular_velocity;
    Ok(body)
}

/// The OBJ mesh at `path` among the scene's `files`.
fn read_obj(files: &dyn SceneFiles, path: &str) -> Result<Mesh, BuildError> {
    let file = files.display(path);
    let bytes = match files.read(path) {
        Ok(bytes) => bytes,
        Err(source) => return Err(BuildError::File { file, source }),
    };
    let Ok(text) = String::from_utf8(bytes) else {
        return Err(BuildError::NotUtf8 { file });
    };
    Ok(parse_obj(&text, &file)?)
}

/// A collider mesh read from `path` among the scene's `files` and placed
/// at `position * scale + translate`.
fn placed_mesh(
    files: &dyn SceneFiles,
    path: &str,
    scale: f32,
    translate: Vec3,
) -> Result<MeshCollider, BuildError> {
    let mut mesh = read_obj(files, path)?;
    for p in &mut mesh.positions {
        *p = *p * scale + translate;
    }
    Ok(MeshCollider::new(&mesh))
}

/// A generated mesh as a collider: its BVH, or a distance field baked from
/// it with cells of `sdf_cell_size`.
fn generated_shape(mesh: &Mesh, sdf_cell_size: Option<f32>) -> Result<Shape, SdfError> {
    let collider = MeshCollider::new(mesh);
    Ok(match sdf_cell_size {
        None => Shape::Mesh(Arc::new(collider)),
        Some(cell) => Shape::Sdf(Arc::new(SdfGrid::bake(&collider, cell)?)),
    })
}

/// The centre of a mesh's box: where its rotation turns by default.
fn mesh_centre(mesh: &MeshCollider) -> Vec3 {
    let b = mesh.bounds();
    (b.min + b.max) * 0.5
}
