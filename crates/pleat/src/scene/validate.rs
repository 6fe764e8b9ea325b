//! Checks of values that parse but make no sense: zero resolutions, negative
//! densities, zero radii. Every error found is reported, each with its path.

use super::{
    BodySpec, ClothSpec, ColliderSpec, CreaseSelection, FoldSpec, MeshSpec, MotionSpec,
    PatternMeshSpec, RenderSpec, Scene, SceneError, ShapeSpec,
};
use crate::collide::SelfCollision;
use crate::force::Wind;
use crate::material::Material;
use crate::mesh::generate::ParameterError;
use crate::origami::{builtin, BUILTIN_NAMES};
use crate::solver::SolverKind;
use glam::Vec3;

/// Collects the range errors of `scene`.
pub fn validate(scene: &Scene, file: &str) -> Vec<SceneError> {
    let mut v = Validator {
        file,
        errors: Vec::new(),
    };
    v.check(scene.frames >= 1, "frames", "must be at least 1");
    v.positive("fps", scene.fps);
    v.finite3("gravity", scene.gravity.to_array());
    v.check(
        (1..=1000).contains(&scene.solver.substeps),
        "solver.substeps",
        "must be between 1 and 1000",
    );
    v.check(
        (1..=1000).contains(&scene.solver.iterations),
        "solver.iterations",
        "must be between 1 and 1000",
    );
    v.non_negative("solver.damping", scene.solver.damping);
    v.self_collision(&scene.solver.self_collision);
    v.check(
        (0.0..=100.0).contains(&scene.solver.global_damping),
        "solver.global_damping",
        "must be a percentage between 0 and 100",
    );
    v.check(
        scene.solver.relaxation > 0.0 && scene.solver.relaxation <= 2.0,
        "solver.relaxation",
        "must be in (0, 2]",
    );
    v.check(
        !scene.cloths.is_empty(),
        "cloths",
        "a scene needs at least one cloth",
    );
    for (i, cloth) in scene.cloths.iter().enumerate() {
        v.cloth(&format!("cloths[{i}]"), cloth);
    }
    for (i, collider) in scene.colliders.iter().enumerate() {
        v.collider(&format!("colliders[{i}]"), collider);
    }
    if let Some(wind) = &scene.wind {
        v.wind(wind);
    }
    let has_pattern = scene
        .cloths
        .iter()
        .any(|c| matches!(c.mesh, MeshSpec::Pattern(_)));
    if has_pattern {
        v.check(
            scene.solver.kind == SolverKind::Xpbd,
            "solver.kind",
            "pattern cloths fold only with the xpbd solver",
        );
    }
    if scene.solver.self_collision.enabled {
        v.check(
            scene.solver.kind == SolverKind::Xpbd,
            "solver.self_collision",
            "self-collision is solved only by the xpbd solver",
        );
    }
    if let Some(fold) = &scene.fold {
        v.check(
            has_pattern,
            "fold",
            "the scene has no pattern cloth to fold",
        );
        v.fold(fold);
    }
    if let Some(render) = &scene.render {
        v.render(render);
    }
    v.errors
}

struct Validator<'a> {
    file: &'a str,
    errors: Vec<SceneError>,
}

impl Validator<'_> {
    fn check(&mut self, ok: bool, path: &str, reason: &str) {
        if !ok {
            self.errors.push(SceneError {
                file: self.file.into(),
                path: path.into(),
                reason: reason.into(),
            });
        }
    }

    fn positive(&mut self, path: &str, x: f32) {
        self.check(
            x.is_finite() && x > 0.0,
            path,
            &format!("must be a positive number, got {x}"),
        );
    }

    fn non_negative(&mut self, path: &str, x: f32) {
        self.check(
            x.is_finite() && x >= 0.0,
            path,
            &format!("must be zero or positive, got {x}"),
        );
    }

    fn finite3(&mut self, path: &str, x: [f32; 3]) {
        self.check(
            x.iter().all(|c| c.is_finite()),
            path,
            "must be three finite numbers",
        );
    }

    fn cloth(&mut self, path: &str, cloth: &ClothSpec) {
        match &cloth.mesh {
            MeshSpec::Grid(g) => {
                for (k, &r) in g.resolution.iter().enumerate() {
                    self.check(
                        (2..=4096).contains(&r),
                        &format!("{path}.mesh.grid.resolution[{k}]"),
                        &format!("must be between 2 and 4096 vertices, got {r}"),
                    );
                }
                for (k, &s) in g.size.iter().enumerate() {
                    self.positive(&format!("{path}.mesh.grid.size[{k}]"), s);
                }
                self.finite3(&format!("{path}.mesh.grid.center"), g.center.to_array());
            }
            MeshSpec::Obj(o) => {
                self.positive(&format!("{path}.mesh.obj.scale"), o.scale);
                self.check(
                    !o.path.is_empty(),
                    &format!("{path}.mesh.obj.path"),
                    "must name an OBJ file",
                );
            }
            MeshSpec::Pattern(p) => self.pattern(&format!("{path}.mesh.pattern"), p),
        }
        if matches!(cloth.mesh, MeshSpec::Pattern(_)) {
            self.check(
                cloth.pins.is_empty(),
                &format!("{path}.pins"),
                "pattern cloths cannot be pinned",
            );
            self.check(
                !cloth.tethers,
                &format!("{path}.tethers"),
                "pattern cloths have no pins to tether to",
            );
        }
        let m = &cloth.material;
        self.positive(&format!("{path}.material.density"), m.density);
        self.non_negative(
            &format!("{path}.material.stretch_compliance"),
            m.stretch_compliance,
        );
        self.non_negative(
            &format!("{path}.material.shear_compliance"),
            m.shear_compliance,
        );
        if let Some(s) = m.max_strain {
            self.positive(&format!("{path}.material.max_strain"), s);
        }
        self.non_negative(
            &format!("{path}.material.bend_compliance"),
            m.bend_compliance,
        );
        self.non_negative(&format!("{path}.material.thickness"), m.thickness);
        self.classic_material(&format!("{path}.material"), m);
        for (k, &w) in cloth.stiffness_weights.iter().enumerate() {
            self.non_negative(&format!("{path}.stiffness_weights[{k}]"), w);
        }
        for (i, pin) in cloth.pins.iter().enumerate() {
            let p = format!("{path}.pins[{i}]");
            self.non_negative(&format!("{p}.compliance"), pin.compliance);
            self.check(
                !(pin.corners.is_empty() && pin.edges.is_empty() && pin.indices.is_empty()),
                &p,
                "a pin group needs corners, edges or indices",
            );
        }
    }

    fn pattern(&mut self, path: &str, p: &PatternMeshSpec) {
        match (&p.path, &p.builtin) {
            (Some(file), None) => self.check(
                !file.is_empty(),
                &format!("{path}.path"),
                "must name a .cp, .fold or .svg file",
            ),
            (None, Some(name)) => self.check(
                builtin(name).is_some(),
                &format!("{path}.builtin"),
                &format!(
                    "unknown pattern '{name}': expected one of {}",
                    BUILTIN_NAMES.join(", ")
                ),
            ),
            _ => self.check(false, path, "give either path or builtin"),
        }
        self.positive(&format!("{path}.size"), p.size);
        if let Some(e) = p.max_edge {
            self.positive(&format!("{path}.max_edge"), e);
        }
        self.finite3(&format!("{path}.center"), p.center.to_array());
        self.non_negative(
            &format!("{path}.stiffness.crease_compliance"),
            p.stiffness.crease_compliance,
        );
        self.non_negative(
            &format!("{path}.stiffness.facet_compliance"),
            p.stiffness.facet_compliance,
        );
    }

    fn fold(&mut self, f: &FoldSpec) {
        self.check(
            (0.0..=1.0).contains(&f.progress),
            "fold.progress",
            &format!("must be between 0 and 1, got {}", f.progress),
        );
        for (k, step) in f.steps.iter().enumerate() {
            let path = format!("fold.steps[{k}]");
            self.check(
                (0.0..=1.0).contains(&step.fraction),
                &format!("{path}.fraction"),
                &format!("must be between 0 and 1, got {}", step.fraction),
            );
            let frames = step.frames.unwrap_or(f.frames_to_fold);
            self.check(
                frames >= 1,
                &format!("{path}.frames"),
                "a step needs at least 1 frame (frames, or fold.frames_to_fold where it gives none)",
            );
            if let CreaseSelection::Kind(kind) = &step.creases {
                self.check(
                    matches!(kind.as_str(), "all" | "M" | "V"),
                    &format!("{path}.creases"),
                    &format!(
                        "expected \"all\", \"M\", \"V\" or a list of edge indices, got \"{kind}\""
                    ),
                );
            }
        }
    }

    /// Spring constants, PBD stiffness factors and the stiffness gradient.
    fn classic_material(&mut self, path: &str, m: &Material) {
        for (name, c) in [
            ("spring_stiffness", m.spring_stiffness),
            ("spring_damping", m.spring_damping),
        ] {
            self.non_negative(&format!("{path}.{name}.structural"), c.structural);
            self.non_negative(&format!("{path}.{name}.shear"), c.shear);
            self.non_negative(&format!("{path}.{name}.bend"), c.bend);
        }
        for (name, k) in [
            ("stretch", m.pbd_stiffness.stretch),
            ("bend", m.pbd_stiffness.bend),
        ] {
            self.check(
                (0.0..=1.0).contains(&k),
                &format!("{path}.pbd_stiffness.{name}"),
                &format!("must be between 0 and 1, got {k}"),
            );
        }
        self.check(
            (0.0..1.0).contains(&m.stiffness_gradient),
            &format!("{path}.stiffness_gradient"),
            &format!(
                "must be at least 0 and less than 1, got {}",
                m.stiffness_gradient
            ),
        );
    }

    fn collider(&mut self, path: &str, c: &ColliderSpec) {
        match &c.shape {
            ShapeSpec::Plane { normal, .. } => self.check(
                normal.length() > 1e-6,
                &format!("{path}.shape.plane.normal"),
                "must not be zero",
            ),
            ShapeSpec::Sphere { radius, .. } => {
                self.positive(&format!("{path}.shape.sphere.radius"), *radius)
            }
            ShapeSpec::Box { half_extents, .. } => {
                for (k, h) in half_extents.to_array().into_iter().enumerate() {
                    self.positive(&format!("{path}.shape.box.half_extents[{k}]"), h);
                }
            }
            ShapeSpec::Capsule { radius, .. } => {
                self.positive(&format!("{path}.shape.capsule.radius"), *radius)
            }
            ShapeSpec::Mesh(m) => {
                self.placed_file(&format!("{path}.shape.mesh"), &m.path, m.scale, m.translate)
            }
            ShapeSpec::Sdf(s) => {
                let p = format!("{path}.shape.sdf");
                self.placed_file(&p, &s.path, s.scale, s.translate);
                self.positive(&format!("{p}.cell_size"), s.cell_size);
            }
            ShapeSpec::TorusKnot(k) => {
                let p = format!("{path}.shape.torus_knot");
                self.finite3(
                    &format!("{p}.rotation_degrees"),
                    k.rotation_degrees.to_array(),
                );
                self.generated(&p, k.knot().check(), k.sdf_cell_size);
            }
            ShapeSpec::Icosphere(s) => {
                let p = format!("{path}.shape.icosphere");
                self.generated(&p, s.icosphere().check(), s.sdf_cell_size);
            }
        }
        if let Some(body) = &c.body {
            self.body(path, c, body);
        }
        self.non_negative(
            &format!("{path}.friction.static"),
            c.friction.static_coefficient,
        );
        self.non_negative(
            &format!("{path}.friction.kinetic"),
            c.friction.kinetic_coefficient,
        );
    }

    /// A dynamic body: a mass, a shape that has one, no scripted motion.
    fn body(&mut self, path: &str, c: &ColliderSpec, body: &BodySpec) {
        let p = format!("{path}.body");
        self.check(
            !matches!(c.shape, ShapeSpec::Plane { .. }),
            &p,
            "a plane cannot be dynamic: it has no finite mass",
        );
        self.check(
            c.motion == MotionSpec::default(),
            &p,
            "a collider is either scripted (motion) or dynamic (body), not both",
        );
        match (body.density, body.mass) {
            (Some(density), None) => self.positive(&format!("{p}.density"), density),
            (None, Some(mass)) => self.positive(&format!("{p}.mass"), mass),
            _ => self.check(false, &p, "give either density or mass"),
        }
        self.finite3(
            &format!("{p}.linear_velocity"),
            body.linear_velocity.to_array(),
        );
        self.finite3(
            &format!("{p}.angular_velocity"),
            body.angular_velocity.to_array(),
        );
    }

    /// The file, scale and translation of a mesh placed in the scene.
    fn placed_file(&mut self, path: &str, file: &str, scale: f32, translate: Vec3) {
        self.check(
            !file.is_empty(),
            &format!("{path}.path"),
            "must name an OBJ file",
        );
        self.positive(&format!("{path}.scale"), scale);
        self.finite3(&format!("{path}.translate"), translate.to_array());
    }

    /// The parameter errors of a generated mesh, and its optional cell size.
    fn generated(
        &mut self,
        path: &str,
        check: Result<(), Vec<ParameterError>>,
        sdf_cell_size: Option<f32>,
    ) {
        for (field, reason) in check.err().unwrap_or_default() {
            self.check(false, &format!("{path}.{field}"), &reason);
        }
        if let Some(cell) = sdf_cell_size {
            self.positive(&format!("{path}.sdf_cell_size"), cell);
        }
    }

    fn self_collision(&mut self, s: &SelfCollision) {
        self.positive("solver.self_collision.thickness", s.thickness);
        self.non_negative(
            "solver.self_collision.friction.static",
            s.friction.static_coefficient,
        );
        self.non_negative(
            "solver.self_collision.friction.kinetic",
            s.friction.kinetic_coefficient,
        );
    }

    fn render(&mut self, r: &RenderSpec) {
        if let Some(c) = &r.camera {
            self.finite3("render.camera.position", c.position.to_array());
            self.finite3("render.camera.target", c.target.to_array());
            self.check(
                c.position.distance(c.target) > 1e-6,
                "render.camera",
                "position and target must differ",
            );
            self.check(
                c.fov_degrees > 1.0 && c.fov_degrees < 179.0,
                "render.camera.fov_degrees",
                &format!("must be between 1 and 179 degrees, got {}", c.fov_degrees),
            );
        }
        if let Some(l) = &r.light {
            self.finite3("render.light.direction", l.direction.to_array());
            self.check(
                l.direction.length() > 1e-6,
                "render.light.direction",
                "must not be zero",
            );
            for (k, &c) in l.color.iter().enumerate() {
                self.non_negative(&format!("render.light.color[{k}]"), c);
            }
        }
        for (name, file) in [("texture", &r.texture), ("height_map", &r.height_map)] {
            if let Some(file) = file {
                self.check(
                    !file.is_empty(),
                    &format!("render.{name}"),
                    "must name a PNG file (or, for texture, fabric, checker or plain)",
                );
            }
        }
        if let Some(bump) = r.bump {
            self.non_negative("render.bump", bump);
        }
        if let Some(d) = r.displacement {
            self.non_negative("render.displacement", d);
        }
        for (name, color) in [("front_color", r.front_color), ("back_color", r.back_color)] {
            for (k, c) in color.into_iter().flatten().enumerate() {
                self.check(
                    (0.0..=1.0).contains(&c),
                    &format!("render.{name}[{k}]"),
                    &format!("must be between 0 and 1, got {c}"),
                );
            }
        }
    }

    fn wind(&mut self, w: &Wind) {
        self.non_negative("wind.drag", w.drag);
        self.non_negative("wind.lift", w.lift);
        self.non_negative("wind.air_density", w.air_density);
        self.non_negative("wind.turbulence", w.turbulence);
        self.positive("wind.turbulence_scale", w.turbulence_scale);
        self.non_negative("wind.turbulence_frequency", w.turbulence_frequency);
    }
}
