//! Every kind of bad scene file is refused with a message that names the
//! file, the JSON path and the reason (DESIGN.md section 5).

use pleat::scene::Scene;
use std::path::Path;

const GOOD: &str = r#"{
  "cloths": [ { "mesh": { "grid": { "resolution": [4, 4] } }, "pins": [ { "corners": ["top_left"] } ] } ],
  "colliders": [ { "shape": { "sphere": { "center": [0, 0, 0], "radius": 0.5 } } } ]
}"#;

/// The single error message for `json`, parsed and built as `bad.json`.
fn error_of(json: &str) -> String {
    let scene = match Scene::parse(json, "bad.json") {
        Ok(scene) => scene,
        Err(e) => return e.to_string(),
    };
    match scene.model(Path::new("."), "bad.json") {
        Ok(_) => panic!("accepted: {json}"),
        Err(e) => e.to_string(),
    }
}

fn assert_error(json: &str, path: &str, reason: &str) {
    let message = error_of(json);
    assert!(message.starts_with("bad.json: "), "no file name: {message}");
    assert!(message.contains(path), "no path '{path}' in: {message}");
    assert!(
        message.contains(reason),
        "no reason '{reason}' in: {message}"
    );
}

#[test]
fn good_scene_is_accepted() {
    let scene = Scene::parse(GOOD, "good.json").unwrap();
    assert_eq!(scene.name, "good");
    scene.model(Path::new("."), "good.json").unwrap();
}

#[test]
fn syntax_error_gives_line_and_column() {
    assert_error("{\n  \"cloths\": [ }\n", "", "line 2, column");
}

#[test]
fn unknown_field() {
    let json = GOOD.replace("\"resolution\"", "\"resolutoin\"");
    assert_error(&json, "cloths[0].mesh.grid", "unknown field `resolutoin`");
}

#[test]
fn a_mesh_or_shape_of_the_wrong_kind_names_what_is_expected() {
    assert_error(
        r#"{"cloths": [{"mesh": 5}]}"#,
        "cloths[0].mesh",
        "expected an object with `grid`, `obj` or `pattern`, got the number 5 (line 1, column",
    );
    let json = GOOD.replace(
        r#"{ "sphere": { "center": [0, 0, 0], "radius": 0.5 } }"#,
        r#"[1, 2]"#,
    );
    assert_error(
        &json,
        "colliders[0].shape",
        "expected an object with `plane`, `sphere`, `box`, `capsule`, `mesh`, `sdf`, \
         `torus_knot` or `icosphere`, got a list",
    );
    // A syntax error keeps serde's own words.
    assert_error(r#"{"cloths": [{"mesh": }]}"#, "", "expected value");
}

#[test]
fn wrong_type() {
    let json = GOOD.replace("\"radius\": 0.5", "\"radius\": \"big\"");
    assert_error(
        &json,
        "colliders[0].shape.sphere.radius",
        "invalid type: string \"big\"",
    );
}

#[test]
fn missing_field() {
    let json = GOOD.replace("\"center\": [0, 0, 0], ", "");
    assert_error(&json, "colliders[0].shape.sphere", "missing field `center`");
}

#[test]
fn unknown_variant() {
    let json = GOOD.replace("top_left", "top_middle");
    assert_error(
        &json,
        "cloths[0].pins[0].corners[0]",
        "unknown variant `top_middle`",
    );
}

#[test]
fn negative_resolution_is_a_type_error() {
    let json = GOOD.replace("[4, 4]", "[4, -4]");
    assert_error(
        &json,
        "cloths[0].mesh.grid.resolution[1]",
        "invalid value: integer `-4`",
    );
}

#[test]
fn zero_resolution() {
    let json = GOOD.replace("[4, 4]", "[0, 4]");
    assert_error(
        &json,
        "cloths[0].mesh.grid.resolution[0]",
        "between 2 and 4096",
    );
}

#[test]
fn negative_density() {
    let json = GOOD.replace("\"pins\"", "\"material\": { \"density\": -1 }, \"pins\"");
    assert_error(
        &json,
        "cloths[0].material.density",
        "must be a positive number, got -1",
    );
}

#[test]
fn negative_compliance() {
    let json = GOOD.replace(
        "\"pins\"",
        "\"material\": { \"bend_compliance\": -0.1 }, \"pins\"",
    );
    assert_error(
        &json,
        "cloths[0].material.bend_compliance",
        "must be zero or positive",
    );
}

#[test]
fn number_too_large_for_a_float() {
    let json = GOOD.replace("\"radius\": 0.5", "\"radius\": 1e999");
    assert_error(
        &json,
        "colliders[0].shape.sphere.radius",
        "number out of range",
    );
}

#[test]
fn zero_radius() {
    let json = GOOD.replace("\"radius\": 0.5", "\"radius\": 0");
    assert_error(
        &json,
        "colliders[0].shape.sphere.radius",
        "must be a positive number",
    );
}

#[test]
fn zero_plane_normal() {
    let json = GOOD.replace(
        "{ \"sphere\": { \"center\": [0, 0, 0], \"radius\": 0.5 } }",
        "{ \"plane\": { \"normal\": [0, 0, 0] } }",
    );
    assert_error(&json, "colliders[0].shape.plane.normal", "must not be zero");
}

#[test]
fn negative_friction() {
    let json = GOOD.replace(
        "\"radius\": 0.5 } }",
        "\"radius\": 0.5 } }, \"friction\": { \"static\": -1, \"kinetic\": 0.2 }",
    );
    assert_error(
        &json,
        "colliders[0].friction.static",
        "must be zero or positive",
    );
}

#[test]
fn zero_substeps() {
    let json = GOOD.replacen('{', "{ \"solver\": { \"substeps\": 0 },", 1);
    assert_error(&json, "solver.substeps", "between 1 and 1000");
}

#[test]
fn zero_fps() {
    let json = GOOD.replacen('{', "{ \"fps\": 0,", 1);
    assert_error(&json, "fps", "must be a positive number");
}

#[test]
fn no_cloth() {
    assert_error("{ \"cloths\": [] }", "cloths", "at least one cloth");
}

#[test]
fn bad_wind() {
    let json = GOOD.replacen(
        '{',
        "{ \"wind\": { \"velocity\": [5, 0, 0], \"turbulence_scale\": 0 },",
        1,
    );
    assert_error(&json, "wind.turbulence_scale", "must be a positive number");
}

#[test]
fn empty_pin_group() {
    let json = GOOD.replace("{ \"corners\": [\"top_left\"] }", "{ \"compliance\": 0 }");
    assert_error(
        &json,
        "cloths[0].pins[0]",
        "needs corners, edges or indices",
    );
}

#[test]
fn pin_index_out_of_range() {
    let json = GOOD.replace(
        "{ \"corners\": [\"top_left\"] }",
        "{ \"indices\": [3, 16] }",
    );
    assert_error(
        &json,
        "cloths[0].pins[0].indices[1]",
        "vertex 16 does not exist: the mesh has 16 vertices",
    );
}

#[test]
fn named_pins_need_a_grid() {
    let dir = std::env::temp_dir().join(format!("pleat-scene-errors-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("tri.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    let json = GOOD.replace(
        "{ \"grid\": { \"resolution\": [4, 4] } }",
        "{ \"obj\": { \"path\": \"tri.obj\" } }",
    );
    let scene = Scene::parse(&json, "bad.json").unwrap();
    let e = scene.model(&dir, "bad.json").unwrap_err().to_string();
    assert!(
        e.contains("cloths[0].pins[0].corners") && e.contains("need a grid mesh"),
        "{e}"
    );
}

#[test]
fn missing_obj_file() {
    let json = GOOD.replace(
        "{ \"grid\": { \"resolution\": [4, 4] } }",
        "{ \"obj\": { \"path\": \"nowhere.obj\" } }",
    );
    assert_error(&json, "cloths[0].mesh.obj.path", "cannot open the file");
}

#[test]
fn every_range_error_is_reported_at_once() {
    let json = GOOD
        .replace("\"radius\": 0.5", "\"radius\": -2")
        .replace("[4, 4]", "[1, 4]");
    let message = error_of(&json);
    assert_eq!(message.lines().count(), 2, "{message}");
}

#[test]
fn unreadable_file() {
    let e = Scene::load(Path::new("/nonexistent/scene.json"))
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("/nonexistent/scene.json") && e.contains("cannot read the file"),
        "{e}"
    );
}

/// GOOD with `fields` added to the cloth's material.
fn with_material(fields: &str) -> String {
    GOOD.replace(
        "\"pins\"",
        &format!("\"material\": {{ {fields} }}, \"pins\""),
    )
}

#[test]
fn negative_spring_stiffness() {
    let json =
        with_material("\"spring_stiffness\": { \"structural\": -5, \"shear\": 1, \"bend\": 0.1 }");
    assert_error(
        &json,
        "cloths[0].material.spring_stiffness.structural",
        "must be zero or positive",
    );
}

#[test]
fn negative_spring_damping() {
    let json =
        with_material("\"spring_damping\": { \"structural\": 0, \"shear\": 0, \"bend\": -1 }");
    assert_error(
        &json,
        "cloths[0].material.spring_damping.bend",
        "must be zero or positive",
    );
}

#[test]
fn unknown_spring_kind() {
    let json = with_material(
        "\"spring_stiffness\": { \"structural\": 5, \"shear\": 1, \"bend\": 0.1, \"twist\": 1 }",
    );
    assert_error(
        &json,
        "cloths[0].material.spring_stiffness",
        "unknown field `twist`",
    );
}

#[test]
fn pbd_stiffness_above_one() {
    let json = with_material("\"pbd_stiffness\": { \"stretch\": 1.5, \"bend\": 0.1 }");
    assert_error(
        &json,
        "cloths[0].material.pbd_stiffness.stretch",
        "must be between 0 and 1",
    );
}

#[test]
fn stiffness_gradient_of_one() {
    let json = with_material("\"stiffness_gradient\": 1.0");
    assert_error(
        &json,
        "cloths[0].material.stiffness_gradient",
        "less than 1",
    );
}

#[test]
fn negative_strain_limit() {
    let json = with_material("\"max_strain\": -0.01");
    assert_error(
        &json,
        "cloths[0].material.max_strain",
        "must be a positive number",
    );
}

#[test]
fn stiffness_weights_of_the_wrong_count() {
    let json = GOOD.replace("\"pins\"", "\"stiffness_weights\": [1, 1, 1], \"pins\"");
    assert_error(
        &json,
        "cloths[0].stiffness_weights",
        "has 3 weights, the mesh has 16 vertices",
    );
}

#[test]
fn negative_stiffness_weight() {
    let weights = format!("[{}-1]", "1, ".repeat(15));
    let json = GOOD.replace(
        "\"pins\"",
        &format!("\"stiffness_weights\": {weights}, \"pins\""),
    );
    assert_error(
        &json,
        "cloths[0].stiffness_weights[15]",
        "must be zero or positive",
    );
}

#[test]
fn global_damping_over_a_hundred_percent() {
    let json = GOOD.replacen(
        '{',
        "{ \"solver\": { \"kind\": \"mass_spring\", \"global_damping\": 150 },",
        1,
    );
    assert_error(&json, "solver.global_damping", "between 0 and 100");
}

#[test]
fn relaxation_above_two() {
    let json = GOOD.replacen(
        '{',
        "{ \"solver\": { \"kind\": \"jacobi_pbd\", \"relaxation\": 3 },",
        1,
    );
    assert_error(&json, "solver.relaxation", "must be in (0, 2]");
}

#[test]
fn unknown_solver_kind() {
    let json = GOOD.replacen('{', "{ \"solver\": { \"kind\": \"implicit_euler\" },", 1);
    assert_error(&json, "solver.kind", "unknown variant `implicit_euler`");
}

#[test]
fn self_collision_needs_xpbd() {
    let json = GOOD.replacen(
        '{',
        "{ \"solver\": { \"kind\": \"mass_spring\", \"self_collision\": { \"enabled\": true } },",
        1,
    );
    assert_error(&json, "solver.self_collision", "only by the xpbd solver");
}

/// `GOOD` with its sphere collider replaced by `shape`.
fn with_collider_shape(shape: &str) -> String {
    GOOD.replace(
        "{ \"sphere\": { \"center\": [0, 0, 0], \"radius\": 0.5 } }",
        shape,
    )
}

#[test]
fn missing_mesh_collider_file() {
    let json = with_collider_shape("{ \"mesh\": { \"path\": \"nowhere.obj\", \"scale\": 0.05 } }");
    assert_error(
        &json,
        "colliders[0].shape.mesh.path",
        "nowhere.obj: cannot open the file",
    );
}

#[test]
fn malformed_sdf_collider_file() {
    let dir = std::env::temp_dir().join(format!("pleat-scene-errors-sdf-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("broken.obj"), "v 0 0 0\nv 1 0 0\nf 1 2 9\n").unwrap();
    let json = with_collider_shape("{ \"sdf\": { \"path\": \"broken.obj\", \"cell_size\": 0.1 } }");
    let scene = Scene::parse(&json, "bad.json").unwrap();
    let e = scene.model(&dir, "bad.json").unwrap_err().to_string();
    assert!(
        e.contains("colliders[0].shape.sdf.path")
            && e.contains("broken.obj: a face refers to a vertex that does not exist"),
        "{e}"
    );
}

#[test]
fn non_positive_sdf_cell_size() {
    let json =
        with_collider_shape("{ \"sdf\": { \"path\": \"meshes/bunny.obj\", \"cell_size\": 0 } }");
    assert_error(
        &json,
        "colliders[0].shape.sdf.cell_size",
        "must be a positive number, got 0",
    );
}

#[test]
fn sdf_cell_size_too_small_for_the_mesh() {
    let dir = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../../scenes"));
    let json =
        with_collider_shape("{ \"sdf\": { \"path\": \"meshes/bunny.obj\", \"cell_size\": 1e-4 } }");
    let scene = Scene::parse(&json, "bad.json").unwrap();
    let e = scene.model(dir, "bad.json").unwrap_err().to_string();
    assert!(
        e.contains("colliders[0].shape.sdf.cell_size") && e.contains("use a larger cell size"),
        "{e}"
    );
}

#[test]
fn mesh_collider_scale_and_unknown_field() {
    let json = with_collider_shape("{ \"mesh\": { \"path\": \"a.obj\", \"scale\": -1 } }");
    assert_error(
        &json,
        "colliders[0].shape.mesh.scale",
        "must be a positive number",
    );
    let json = with_collider_shape("{ \"mesh\": { \"path\": \"a.obj\", \"cell_size\": 1 } }");
    assert_error(
        &json,
        "colliders[0].shape.mesh",
        "unknown field `cell_size`",
    );
}

/// `GOOD` with a torus knot collider of radius 0.3 and the given extra fields.
fn with_torus_knot(fields: &str) -> String {
    with_collider_shape(&format!(
        "{{ \"torus_knot\": {{ \"center\": [0, 0, 0], \"radius\": 0.3, {fields} }} }}"
    ))
}

#[test]
fn generated_colliders_are_accepted() {
    for json in [
        with_torus_knot("\"tube\": 0.05"),
        with_torus_knot("\"tube\": 0.05, \"p\": 3, \"q\": 5, \"segments\": 200, \"sides\": 8, \"rotation_degrees\": [90, 0, 0], \"sdf_cell_size\": 0.05"),
        with_collider_shape("{ \"icosphere\": { \"center\": [0, 1, 0], \"radius\": 0.3 } }"),
        with_collider_shape("{ \"icosphere\": { \"center\": [0, 1, 0], \"radius\": 0.3, \"subdivisions\": 2, \"sdf_cell_size\": 0.05 } }"),
    ] {
        let scene = Scene::parse(&json, "good.json").unwrap();
        scene.model(Path::new("."), "good.json").unwrap();
    }
}

#[test]
fn torus_knot_tube_that_intersects_itself() {
    // The strands of a (2, 3) knot of radius 0.3 pass about 0.25 apart.
    assert_error(
        &with_torus_knot("\"tube\": 0.2"),
        "colliders[0].shape.torus_knot.tube",
        "must be less than 0.12",
    );
    assert_error(
        &with_torus_knot("\"tube\": 0.2"),
        "colliders[0].shape.torus_knot.tube",
        "a thicker tube intersects itself",
    );
}

#[test]
fn torus_knot_mesh_too_coarse_for_its_tube() {
    // Thin enough for the smooth tube, but 8 rings per winding cut corners
    // through the neighbouring strands: refused when the mesh is built.
    let json = with_torus_knot("\"tube\": 0.0195, \"p\": 16, \"q\": 15, \"segments\": 128");
    assert_error(
        &json,
        "colliders[0].shape.torus_knot.tube",
        "the tube's mesh intersects itself",
    );
}

#[test]
fn torus_knot_windings_must_be_coprime() {
    assert_error(
        &with_torus_knot("\"tube\": 0.05, \"p\": 2, \"q\": 4"),
        "colliders[0].shape.torus_knot.q",
        "share the factor 2",
    );
    assert_error(
        &with_torus_knot("\"tube\": 0.05, \"p\": 0"),
        "colliders[0].shape.torus_knot.p",
        "must be between 1 and 16, got 0",
    );
}

#[test]
fn torus_knot_counts() {
    assert_error(
        &with_torus_knot("\"tube\": 0.05, \"segments\": 0"),
        "colliders[0].shape.torus_knot.segments",
        "must be at least 24 (8 per winding) for p = 2 and q = 3, got 0",
    );
    assert_error(
        &with_torus_knot("\"tube\": 0.05, \"sides\": 2"),
        "colliders[0].shape.torus_knot.sides",
        "must be between 3 and 1024, got 2",
    );
    assert_error(
        &with_torus_knot("\"tube\": 0.05, \"segments\": -3"),
        "colliders[0].shape.torus_knot.segments",
        "invalid value: integer `-3`",
    );
    assert_error(
        &with_torus_knot("\"tube\": 0.05, \"segments\": 100000, \"sides\": 1000"),
        "colliders[0].shape.torus_knot.segments",
        "more than 4194304",
    );
}

#[test]
fn torus_knot_sizes_and_fields() {
    let message = error_of(&with_torus_knot("\"tube\": 0").replace("0.3", "-1"));
    assert!(
        message.contains("colliders[0].shape.torus_knot.radius: must be a positive number, got -1")
            && message
                .contains("colliders[0].shape.torus_knot.tube: must be a positive number, got 0"),
        "{message}"
    );
    assert_error(
        &with_torus_knot("\"tube\": 0.05, \"sdf_cell_size\": 0"),
        "colliders[0].shape.torus_knot.sdf_cell_size",
        "must be a positive number, got 0",
    );
    assert_error(
        &with_torus_knot("\"tube\": 0.05, \"cell_size\": 0.01"),
        "colliders[0].shape.torus_knot",
        "unknown field `cell_size`",
    );
    assert_error(
        &with_collider_shape("{ \"torus_knot\": { \"center\": [0, 0, 0], \"radius\": 0.3 } }"),
        "colliders[0].shape.torus_knot",
        "missing field `tube`",
    );
}

#[test]
fn icosphere_parameters() {
    assert_error(
        &with_collider_shape(
            "{ \"icosphere\": { \"center\": [0, 0, 0], \"radius\": 0.3, \"subdivisions\": 9 } }",
        ),
        "colliders[0].shape.icosphere.subdivisions",
        "must be at most 7, got 9",
    );
    assert_error(
        &with_collider_shape("{ \"icosphere\": { \"center\": [0, 0, 0], \"radius\": 0 } }"),
        "colliders[0].shape.icosphere.radius",
        "must be a positive number, got 0",
    );
}

/// GOOD with `body` (JSON) on its sphere collider.
fn with_body(body: &str) -> String {
    GOOD.replace(
        "\"radius\": 0.5 } }",
        &format!("\"radius\": 0.5 }} }}, \"body\": {body}"),
    )
}

#[test]
fn dynamic_body_is_accepted() {
    let json = with_body("{ \"density\": 500, \"linear_velocity\": [1, 0, 0] }");
    let scene = Scene::parse(&json, "good.json").unwrap();
    let (_, world) = scene.model(Path::new("."), "good.json").unwrap();
    let body = world.colliders[0].body.as_ref().unwrap();
    assert!((body.mass - 500.0 * 4.0 / 3.0 * std::f32::consts::PI * 0.125).abs() < 1e-2);
    let json = with_body("{ \"mass\": 2 }");
    let (_, world) = Scene::parse(&json, "good.json")
        .unwrap()
        .model(Path::new("."), "good.json")
        .unwrap();
    assert_eq!(world.colliders[0].body.as_ref().unwrap().mass, 2.0);
}

#[test]
fn zero_or_negative_body_density() {
    for density in ["0", "-500"] {
        let json = with_body(&format!("{{ \"density\": {density} }}"));
        assert_error(
            &json,
            "colliders[0].body.density",
            "must be a positive number",
        );
    }
    let json = with_body("{ \"mass\": -1 }");
    assert_error(&json, "colliders[0].body.mass", "must be a positive number");
}

#[test]
fn body_needs_exactly_one_of_density_and_mass() {
    for body in ["{}", "{ \"density\": 500, \"mass\": 1 }"] {
        assert_error(
            &with_body(body),
            "colliders[0].body",
            "give either density or mass",
        );
    }
    assert_error(
        &with_body("{ \"density\": 500, \"weight\": 1 }"),
        "colliders[0].body",
        "unknown field `weight`",
    );
}

#[test]
fn plane_cannot_be_dynamic() {
    let json = with_collider_shape("{ \"plane\": {} }, \"body\": { \"density\": 500 }");
    assert_error(&json, "colliders[0].body", "a plane cannot be dynamic");
}

#[test]
fn body_and_motion_exclude_each_other() {
    let json = with_body("{ \"density\": 500 }, \"motion\": { \"angular_velocity\": [0, 1, 0] }");
    assert_error(
        &json,
        "colliders[0].body",
        "either scripted (motion) or dynamic (body), not both",
    );
}

#[test]
fn dynamic_mesh_must_be_closed() {
    let dir = std::env::temp_dir().join(format!("pleat-open-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("open.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    let json = with_collider_shape(
        "{ \"mesh\": { \"path\": \"open.obj\" } }, \"body\": { \"density\": 500 }",
    );
    let scene = Scene::parse(&json, "bad.json").unwrap();
    let e = scene.model(&dir, "bad.json").unwrap_err().to_string();
    assert!(
        e.contains("colliders[0].body") && e.contains("must be closed"),
        "{e}"
    );
}

#[test]
fn render_section_is_checked() {
    let with_render = |render: &str| GOOD.replacen('{', &format!("{{ \"render\": {render},"), 1);
    Scene::parse(
        &with_render(
            r#"{ "camera": { "position": [0, 1, 3], "target": [0, 0, 0], "fov_degrees": 35 },
                 "light": { "direction": [0, -1, 0.2] }, "texture": "checker", "bump": 0.5,
                 "front_color": [1, 0.5, 0], "mirror_colliders": true }"#,
        ),
        "good.json",
    )
    .unwrap();
    assert_error(
        &with_render(r#"{ "camera": { "position": [0, 1, 3], "target": [0, 0, 0], "fov": 35 } }"#),
        "render.camera",
        "unknown field `fov`",
    );
    assert_error(
        &with_render(
            r#"{ "camera": { "position": [0, 1, 3], "target": [0, 0, 0], "fov_degrees": 0 } }"#,
        ),
        "render.camera.fov_degrees",
        "must be between 1 and 179",
    );
    assert_error(
        &with_render(r#"{ "camera": { "position": [1, 1, 1], "target": [1, 1, 1] } }"#),
        "render.camera",
        "position and target must differ",
    );
    assert_error(
        &with_render(r#"{ "light": { "direction": [0, 0, 0] } }"#),
        "render.light.direction",
        "must not be zero",
    );
    assert_error(
        &with_render(r#"{ "back_color": [0, 2, 0] }"#),
        "render.back_color[1]",
        "must be between 0 and 1",
    );
    assert_error(
        &with_render(r#"{ "displacement": -0.01 }"#),
        "render.displacement",
        "must be zero or positive",
    );
}
