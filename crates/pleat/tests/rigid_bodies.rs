//! Dynamic rigid bodies: mass properties against the analytic formulas, free
//! fall, momentum through cloth-body contacts, a ball resting on a pinned
//! cloth, a box resting on the ground, thread-count independence and the
//! tablecloth pull.

use pleat::collide::rigid_body::MassProperties;
use pleat::collide::{MeshCollider, RigidBody};
use pleat::glam::{Mat3, Quat, Vec3};
use pleat::mesh::generate::Icosphere;
use pleat::mesh::Mesh;
use pleat::scene::Scene;
use pleat::Simulation;
use std::path::Path;

fn scenes_dir() -> &'static Path {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../../scenes"))
}

fn simulation(json: &str) -> (Scene, Simulation) {
    let scene = Scene::parse(json, "rigid.json").expect("valid scene");
    let sim = scene.build(scenes_dir(), "rigid.json").expect("builds");
    (scene, sim)
}

fn body(sim: &Simulation, i: usize) -> &RigidBody {
    sim.world.colliders[i]
        .body
        .as_ref()
        .expect("a dynamic collider")
}

/// A closed box mesh, outward winding, from `-half` to `half`.
fn box_mesh(half: Vec3) -> Mesh {
    let positions = (0..8)
        .map(|i| {
            Vec3::new(
                if i & 1 == 0 { -half.x } else { half.x },
                if i & 2 == 0 { -half.y } else { half.y },
                if i & 4 == 0 { -half.z } else { half.z },
            )
        })
        .collect();
    let quads = [
        [0, 2, 3, 1], // -z
        [4, 5, 7, 6], // +z
        [0, 1, 5, 4], // -y
        [2, 6, 7, 3], // +y
        [0, 4, 6, 2], // -x
        [1, 3, 7, 5], // +x
    ];
    let triangles = quads
        .iter()
        .flat_map(|[a, b, c, d]| [[*a, *b, *c], [*a, *c, *d]])
        .collect();
    Mesh {
        positions,
        triangles,
        grid: None,
    }
}

fn assert_mat_close(a: Mat3, b: Mat3, tolerance: f32) {
    let scale = b.to_cols_array().iter().fold(0f32, |m, x| m.max(x.abs()));
    for (x, y) in a.to_cols_array().iter().zip(b.to_cols_array()) {
        assert!(
            (x - y).abs() <= tolerance * scale,
            "{a} vs {b} (tolerance {tolerance})"
        );
    }
}

#[test]
fn box_mesh_inertia_matches_the_formula() {
    let half = Vec3::new(0.3, 0.1, 0.2);
    let rotation = Quat::from_euler(pleat::glam::EulerRot::XYZ, 0.3, 0.5, -0.2);
    let offset = Vec3::new(1.0, 2.0, -0.5);
    let mut mesh = box_mesh(half);
    for p in &mut mesh.positions {
        *p = rotation * *p + offset;
    }
    let collider = MeshCollider::new(&mesh);
    let props = MassProperties::mesh(collider.triangles(), 800.0).unwrap();
    let exact = MassProperties::cuboid(offset, half, rotation, 800.0);
    println!(
        "box mesh: mass {} (exact {}), inertia {} (exact {})",
        props.mass, exact.mass, props.inertia, exact.inertia
    );
    assert!((props.mass - exact.mass).abs() < 1e-4 * exact.mass);
    assert!(props.center_of_mass.distance(offset) < 1e-5);
    assert_mat_close(props.inertia, exact.inertia, 1e-4);
    // Inward winding gives the same solid.
    for t in &mut mesh.triangles {
        t.swap(1, 2);
    }
    let flipped = MassProperties::mesh(MeshCollider::new(&mesh).triangles(), 800.0).unwrap();
    assert_mat_close(flipped.inertia, exact.inertia, 1e-4);
}

#[test]
fn icosphere_inertia_approaches_the_sphere() {
    let radius = 0.5;
    let mesh = Icosphere {
        center: Vec3::new(0.0, 3.0, 0.0),
        radius,
        subdivisions: 4,
    }
    .mesh();
    let props = MassProperties::mesh(MeshCollider::new(&mesh).triangles(), 1000.0).unwrap();
    let exact = MassProperties::sphere(Vec3::new(0.0, 3.0, 0.0), radius, 1000.0);
    let ratio = props.inertia.x_axis.x / exact.inertia.x_axis.x;
    println!(
        "icosphere ({} triangles): mass {} (sphere {}), Ixx {} (sphere {}), ratio {ratio}",
        mesh.triangles.len(),
        props.mass,
        exact.mass,
        props.inertia.x_axis.x,
        exact.inertia.x_axis.x
    );
    // The inscribed polyhedron is slightly smaller than the sphere.
    assert!(props.mass < exact.mass && props.mass > 0.99 * exact.mass);
    assert!(props.center_of_mass.distance(exact.center_of_mass) < 1e-4);
    assert_mat_close(props.inertia, exact.inertia, 0.02);
}

/// A small pinned cloth far from everything, since a scene needs one.
const BYSTANDER: &str = r#"{ "mesh": { "grid": { "resolution": [3, 3], "size": [0.2, 0.2], "center": [50, 5, 50] } },
  "pins": [ { "corners": ["top_left", "top_right", "bottom_left", "bottom_right"] } ] }"#;

#[test]
fn free_fall_follows_g_t_squared_over_two() {
    let json = format!(
        r#"{{ "cloths": [ {BYSTANDER} ],
        "colliders": [ {{ "shape": {{ "box": {{ "center": [0, 10, 0], "half_extents": [0.1, 0.2, 0.3] }} }},
                         "body": {{ "density": 300, "angular_velocity": [1, 2, 3] }} }} ] }}"#
    );
    let (scene, mut sim) = simulation(&json);
    let frames = 60;
    for _ in 0..frames {
        sim.step(scene.frame_dt());
    }
    let t = sim.world.time;
    let b = body(&sim, 0);
    let fallen = 10.0 - b.position.y;
    let expected = 0.5 * 9.81 * t * t;
    println!("fell {fallen} m in {t} s; g t^2 / 2 = {expected} m");
    // Semi-implicit Euler falls g t dt / 2 further than the exact parabola.
    let dt = scene.frame_dt() / scene.solver.substeps as f32;
    assert!((fallen - expected).abs() <= 0.5 * 9.81 * t * dt * 1.01 + 1e-4);
    assert!((b.linear_velocity.y + 9.81 * t).abs() < 1e-3);
    assert!(b.position.x.abs() < 1e-5 && b.position.z.abs() < 1e-5);
}

#[test]
fn cloth_thrown_at_a_free_body_keeps_momentum() {
    let json = r#"{ "gravity": [0, 0, 0], "solver": { "damping": 0 },
      "cloths": [ { "mesh": { "grid": { "resolution": [12, 12], "size": [0.6, 0.6], "orientation": "vertical", "center": [0, 0, 0.5] } },
                    "material": { "density": 0.5 } } ],
      "colliders": [ { "shape": { "sphere": { "center": [0.1, 0.05, 0], "radius": 0.15 } },
                       "friction": { "static": 0.5, "kinetic": 0.4 },
                       "body": { "mass": 0.3 } } ] }"#;
    let (scene, mut sim) = simulation(json);
    sim.particles.v.fill(Vec3::new(0.0, 0.0, -3.0));
    let momentum = |sim: &Simulation| sim.particles.momentum() + body(sim, 0).momentum();
    let before = momentum(&sim);
    for _ in 0..40 {
        sim.step(scene.frame_dt());
    }
    let after = momentum(&sim);
    let b = body(&sim, 0);
    println!(
        "momentum before {before}, after {after}; body velocity {} spin {}",
        b.linear_velocity, b.angular_velocity
    );
    assert!(
        b.linear_velocity.z < -0.5,
        "the cloth hit the body: {}",
        b.linear_velocity
    );
    assert!(
        (after - before).length() < 1e-3 * before.length(),
        "{before} -> {after}"
    );
    assert!(!sim.metrics().nan);
}

/// A ball dropped on an elastic sheet pinned at its corners (it stretches
/// up to 10 %: an inextensible one, its corners as far apart as at rest,
/// could not give under it).
const BALL_ON_CLOTH: &str = r#"{ "solver": { "substeps": 20, "iterations": 4, "damping": 5 },
  "cloths": [ { "mesh": { "grid": { "resolution": [24, 24], "size": [1, 1], "center": [0, 1, 0] } },
                "material": { "density": 0.3, "thickness": 0.01, "stretch_compliance": 1e-3, "max_strain": 0.1 },
                "pins": [ { "corners": ["top_left", "top_right", "bottom_left", "bottom_right"] } ] } ],
  "colliders": [ { "shape": { "sphere": { "center": [0.02, 1.3, -0.03], "radius": 0.12 } },
                   "friction": { "static": 0.6, "kinetic": 0.5 },
                   "body": { "mass": 0.3 } },
                 { "shape": { "plane": {} } } ] }"#;

#[test]
fn ball_dropped_on_a_pinned_cloth_comes_to_rest_on_it() {
    let (scene, mut sim) = simulation(BALL_ON_CLOTH);
    let mut heights = Vec::new();
    for _ in 0..360 {
        sim.step(scene.frame_dt());
        heights.push(body(&sim, 0).position.y);
    }
    let m = sim.metrics();
    let b = body(&sim, 0);
    let lowest_cloth = sim.particles.x.iter().map(|x| x.y).fold(f32::MAX, f32::min);
    let under = sim
        .particles
        .x
        .iter()
        .filter(|x| (x.x - b.position.x).hypot(x.z - b.position.z) < 0.05)
        .map(|x| x.y)
        .fold(f32::MIN, f32::max);
    let last = &heights[heights.len() - 60..];
    let spread =
        last.iter().fold(f32::MIN, |a, &b| a.max(b)) - last.iter().fold(f32::MAX, |a, &b| a.min(b));
    println!(
        "ball at {} (mass {} kg), cloth under it at {under}, lowest cloth {lowest_cloth}, \
         height spread over the last second {spread} m, speed {}, penetrations {}",
        b.position,
        b.mass,
        b.linear_velocity.length(),
        m.collider_penetrations
    );
    assert!(!m.nan && !m.unstable);
    assert_eq!(m.collider_penetrations, 0);
    assert!(lowest_cloth < 0.95, "the cloth sags under the ball");
    assert!(
        b.position.y - 0.12 > under - 0.005,
        "the ball is above the cloth"
    );
    assert!(b.position.y > 0.5, "the ball did not fall through");
    assert!(spread < 0.01, "the ball's height is steady: {spread}");
    assert!(b.linear_velocity.length() < 0.1);
}

#[test]
fn box_resting_on_the_ground_stays() {
    let json = format!(
        r#"{{ "cloths": [ {BYSTANDER} ],
        "colliders": [ {{ "shape": {{ "box": {{ "center": [0.3, 0.1, -0.2], "half_extents": [0.2, 0.1, 0.15] }} }},
                         "body": {{ "density": 500 }} }},
                       {{ "shape": {{ "plane": {{}} }} }} ] }}"#
    );
    let (scene, mut sim) = simulation(&json);
    for _ in 0..180 {
        sim.step(scene.frame_dt());
    }
    let b = body(&sim, 0);
    let drift = (b.position - Vec3::new(0.3, 0.1, -0.2)).length();
    let turn = b.orientation.angle_between(Quat::IDENTITY);
    println!(
        "box after 3 s: position {}, sank {} m, drift {drift} m, turned {turn} rad, speed {}",
        b.position,
        0.1 - b.position.y,
        b.linear_velocity.length()
    );
    assert!(
        (b.position.y - 0.1).abs() < 1e-3,
        "no sinking: {}",
        b.position
    );
    assert!(drift < 1e-3, "no drift: {drift}");
    assert!(turn < 1e-3);
    assert!(b.linear_velocity.length() < 1e-2);
}

#[test]
fn results_do_not_depend_on_thread_count() {
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            let (scene, mut sim) = simulation(BALL_ON_CLOTH);
            for _ in 0..40 {
                sim.step(scene.frame_dt());
            }
            let b = body(&sim, 0).clone();
            (sim.particles.x, b.position, b.orientation)
        })
    };
    let bits = |v: Vec3| v.to_array().map(f32::to_bits);
    let (one, two) = (run(1), run(2));
    assert!(one.0.iter().zip(&two.0).all(|(a, b)| bits(*a) == bits(*b)));
    assert_eq!(bits(one.1), bits(two.1));
    assert_eq!(
        one.2.to_array().map(f32::to_bits),
        two.2.to_array().map(f32::to_bits)
    );
}

#[test]
fn tablecloth_pulled_off_leaves_the_dishes_on_the_table() {
    let scene = Scene::load(&scenes_dir().join("tablecloth_pull.json")).expect("shipped scene");
    let mut sim = scene
        .build(scenes_dir(), "tablecloth_pull")
        .expect("builds");
    let dishes: Vec<usize> = (0..sim.world.colliders.len())
        .filter(|&i| sim.world.colliders[i].is_dynamic())
        .collect();
    let start: Vec<Vec3> = dishes.iter().map(|&i| body(&sim, i).position).collect();
    for f in 0..scene.frames {
        sim.step(scene.frame_dt());
        if f % 10 == 9 {
            let xs = sim.particles.x.iter().map(|x| x.x).fold(f32::MAX, f32::min);
            println!(
                "frame {}: cloth from x = {xs}, dishes {:?}",
                f + 1,
                dishes
                    .iter()
                    .map(|&i| body(&sim, i).position)
                    .collect::<Vec<_>>()
            );
        }
    }
    let m = sim.metrics();
    // The table top: 1.2 m x 0.8 m at y = 0.75.
    let on_table = sim
        .particles
        .x
        .iter()
        .filter(|x| x.x.abs() < 0.6 && x.z.abs() < 0.4 && x.y > 0.74)
        .count();
    println!(
        "tablecloth: {} particles left on the table top, penetrations {}, nan {}, max stretch {}",
        on_table, m.collider_penetrations, m.nan, m.max_stretch
    );
    for (k, &i) in dishes.iter().enumerate() {
        let b = body(&sim, i);
        let lowest = b
            .samples
            .iter()
            .map(|s| b.pose().transform_point3(s.local).y - s.radius)
            .fold(f32::MAX, f32::min);
        println!(
            "dish {k}: from {} to {} (moved {} m), lowest point {lowest}, speed {}",
            start[k],
            b.position,
            (b.position - start[k]).length(),
            b.linear_velocity.length()
        );
        assert!(
            b.position.x.abs() < 0.6 && b.position.z.abs() < 0.4,
            "dish {k} is over the table: {}",
            b.position
        );
        let slid = (b.position - start[k]).with_y(0.0).length();
        assert!(slid < 0.05, "dish {k} stayed where it stood: slid {slid} m");
        assert!(b.linear_velocity.length() < 0.05, "dish {k} is at rest");
        assert!(
            (lowest - 0.75).abs() < 0.01,
            "dish {k} stands on the table top: lowest point at {lowest}"
        );
    }
    assert!(!m.nan && !m.unstable);
    assert_eq!(on_table, 0, "the cloth is off the table");
    assert_eq!(m.collider_penetrations, 0);
}
