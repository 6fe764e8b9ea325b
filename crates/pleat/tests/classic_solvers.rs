//! The classic solvers beside XPBD on whole scenes: each keeps a pinned
//! cloth hanging; mass-spring at a large step blows up and is reported
//! unstable where XPBD stays finite; shape matching restores deformed
//! shapes; Jacobi and Gauss-Seidel PBD reach the same rest state.

use pleat::constraint::{project_once, Constraint, Substep};
use pleat::constraint::{PairShape, TriangleShape};
use pleat::glam::{Mat3, Vec3};
use pleat::material::BendingModel;
use pleat::mesh::GridOrientation;
use pleat::scene::presets::hanging_cloth;
use pleat::scene::{MeshSpec, Scene};
use pleat::{Simulation, SolverKind};
use std::path::Path;

fn simulate(scene: &Scene, frames: u32) -> Simulation {
    let mut sim = scene.build(Path::new("."), &scene.name).unwrap();
    for _ in 0..frames {
        sim.step(scene.frame_dt());
    }
    sim
}

fn with_solver(mut scene: Scene, kind: SolverKind) -> Scene {
    scene.solver.kind = kind;
    scene
}

fn lowest(sim: &Simulation) -> f32 {
    sim.particles
        .x
        .iter()
        .map(|x| x.y)
        .fold(f32::INFINITY, f32::min)
}

/// The standard hanging cloth, but starting horizontal so that it falls,
/// and damped so that it comes to rest hanging.
fn falling_cloth(n: u32, kind: SolverKind) -> Scene {
    let mut scene = with_solver(hanging_cloth(n, 10, false), kind);
    if let MeshSpec::Grid(g) = &mut scene.cloths[0].mesh {
        g.orientation = GridOrientation::Horizontal;
    }
    scene.solver.damping = 3.0;
    scene
}

#[test]
fn every_solver_keeps_a_pinned_cloth_hanging() {
    for kind in SolverKind::ALL {
        let scene = falling_cloth(16, kind);
        let start = scene.build(Path::new("."), "start").unwrap();
        let sim = simulate(&scene, 240);
        let m = sim.metrics();
        assert!(!m.nan && !m.unstable, "{kind:?}: {m:?}");
        assert!(
            lowest(&sim) < lowest(&start) - 0.5,
            "{kind:?} did not hang: {}",
            lowest(&sim)
        );
        for pin in &sim.model.pins {
            let i = pin.particle as usize;
            assert!(
                sim.particles.x[i].distance(sim.model.rest[i]) < 1e-6,
                "{kind:?}: pin {i} moved"
            );
        }
        println!(
            "{kind:?}: lowest point {:.3} -> {:.3} m, max stretch {:.3}",
            lowest(&start),
            lowest(&sim),
            m.max_stretch
        );
    }
}

#[test]
fn stiff_mass_spring_at_a_large_step_is_reported_unstable_where_xpbd_is_not() {
    let mut scene = hanging_cloth(32, 1, false);
    scene.cloths[0].material.spring_stiffness.structural = 50_000.0;
    scene.cloths[0].material.spring_stiffness.shear = 50_000.0;
    scene.cloths[0].material.stretch_compliance = 1.0 / 50_000.0;
    scene.cloths[0].material.shear_compliance = 1.0 / 50_000.0;
    let springs = simulate(&with_solver(scene.clone(), SolverKind::MassSpring), 60);
    assert!(springs.metrics().unstable, "{:?}", springs.metrics());
    let (t, why) = springs.stability.first.unwrap();
    println!("mass-spring unstable at t = {t} s: {why:?}");
    let xpbd = simulate(&with_solver(scene, SolverKind::Xpbd), 60);
    let m = xpbd.metrics();
    assert!(!m.nan && !m.unstable, "{m:?}");
}

#[test]
fn shape_matching_restores_sheared_and_inverted_shapes() {
    let rest = [
        Vec3::ZERO,
        Vec3::X,
        Vec3::new(0.3, 0.9, 0.0),
        Vec3::new(0.7, -0.8, 0.4),
    ];
    let inv_mass = [1.0; 4];
    let shear = Mat3::from_cols(Vec3::X, Vec3::new(1.2, 1.0, 0.0), Vec3::Z);
    let mirror = Mat3::from_diagonal(Vec3::new(-1.0, 0.6, 1.0));
    for deform in [shear, mirror] {
        let triangle = TriangleShape::at_rest([0, 1, 2], &rest, &inv_mass, 1.0);
        let pair = PairShape::at_rest([0, 1, 2, 3], &rest, &inv_mass, 1.0);
        for (c, n) in [(&triangle as &dyn Constraint, 3), (&pair, 4)] {
            let mut x: Vec<Vec3> = rest.iter().map(|&p| deform * p).collect();
            project_once(c, &mut 0.0, &mut x, &inv_mass, &Substep::as_built(0.0, 0.0));
            for i in 0..n {
                for j in i + 1..n {
                    let (d, d0) = (x[i].distance(x[j]), rest[i].distance(rest[j]));
                    assert!(
                        (d - d0).abs() < 1e-4,
                        "{deform}: |x{i} - x{j}| = {d}, rest {d0}"
                    );
                }
            }
        }
    }
}

/// The small standard hanging cloth, with rigid stretch, shear and skip-one
/// bending, its particles thrown off their rest positions by up to 5 cm in
/// its own plane. Triangulated and pinned at two corners, it is rigid in
/// its plane (out of it, distance constraints hold only to second order and
/// leave millimetre wrinkles), so every converged solver must find the
/// hanging rest state.
fn crumpled_hanging_sheet(kind: SolverKind, iterations: u32) -> Simulation {
    let mut scene = with_solver(hanging_cloth(8, 10, false), kind);
    let cloth = &mut scene.cloths[0];
    cloth.material.bending = BendingModel::SkipOne;
    cloth.material.shear_compliance = 0.0;
    cloth.material.bend_compliance = 0.0;
    cloth.material.pbd_stiffness.bend = 1.0;
    scene.solver.iterations = iterations;
    scene.solver.damping = 3.0;
    let mut sim = scene.build(Path::new("."), "crumpled").unwrap();
    let mut seed = 1u32;
    let mut noise = || {
        seed = seed.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
        ((seed >> 8) as f32 / (1u32 << 24) as f32 - 0.5) * 0.1
    };
    for (x, &w) in sim.particles.x.iter_mut().zip(&sim.particles.inv_mass) {
        if w > 0.0 {
            *x += Vec3::new(noise(), noise(), 0.0);
        }
    }
    for _ in 0..240 {
        sim.step(scene.frame_dt());
    }
    sim
}

#[test]
fn jacobi_and_gauss_seidel_pbd_reach_the_same_rest_state() {
    // XPBD with compliance zero is Gauss-Seidel PBD with stiffness 1.
    let gauss_seidel = crumpled_hanging_sheet(SolverKind::Xpbd, 20);
    let jacobi = crumpled_hanging_sheet(SolverKind::JacobiPbd, 100);
    let gap = |a: &Simulation, b: &[Vec3]| {
        a.particles
            .x
            .iter()
            .zip(b)
            .map(|(p, q)| p.distance(*q))
            .fold(0.0, f32::max)
    };
    let between = gap(&gauss_seidel, &jacobi.particles.x);
    let from_rest = gap(&jacobi, &jacobi.model.rest);
    println!(
        "largest gap: Jacobi to Gauss-Seidel {between:.2e} m, Jacobi to rest {from_rest:.2e} m"
    );
    assert!(between < 1e-3 && from_rest < 1e-3, "{between} {from_rest}");
}
