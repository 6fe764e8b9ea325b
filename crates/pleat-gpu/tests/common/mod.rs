//! Scenes stepped on both backends, for the GPU tests.

use pleat::scene::Scene;
use pleat::Simulation;
use pleat_gpu::{GpuBackend, GpuContext};
use std::path::Path;
use std::sync::OnceLock;

/// One device for every test of a binary: a missing adapter fails the test (never skips).
pub fn context() -> &'static GpuContext {
    static CONTEXT: OnceLock<GpuContext> = OnceLock::new();
    CONTEXT.get_or_init(|| GpuContext::new().expect("a GPU adapter (in CI: Mesa lavapipe)"))
}

/// The scene in `text`, with scene-relative paths from the project's scenes/.
pub fn scene(text: &str) -> Scene {
    Scene::parse(text, "test scene").unwrap()
}

pub fn scenes_dir() -> &'static Path {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../../scenes"))
}

/// The project's scene file `name`.
#[allow(dead_code)]
pub fn scene_file(name: &str) -> Scene {
    Scene::load(&scenes_dir().join(name)).unwrap()
}

/// `scene` on the CPU backend.
pub fn cpu(scene: &Scene) -> Simulation {
    scene.build(scenes_dir(), "test scene").unwrap()
}

/// `scene` on the GPU backend.
pub fn gpu(scene: &Scene) -> Simulation {
    gpu_with(scene, true)
}

/// `scene` on the GPU backend, a small sheet's frames in one dispatch
/// where `persistent` allows it (the default) or a dispatch per colour.
pub fn gpu_with(scene: &Scene, persistent: bool) -> Simulation {
    let (model, world) = scene.model(scenes_dir(), "test scene").unwrap();
    let (mut backend, _) = GpuBackend::new(context(), &model, &world, &scene.solver).unwrap();
    backend.allow_persistent(persistent);
    scene.simulation(model, world, Box::new(backend))
}

/// Steps `sim` for `frames` frames of the scene's frame time, without
/// reading the state back.
pub fn steps(sim: &mut Simulation, scene: &Scene, frames: u32) {
    for _ in 0..frames {
        sim.step(scene.frame_dt());
    }
}

/// Steps `sim` for `frames` frames of the scene's frame time and syncs.
pub fn run(sim: &mut Simulation, scene: &Scene, frames: u32) {
    steps(sim, scene, frames);
    sim.sync();
}

/// Mean distance between the two simulations' particles.
#[allow(dead_code)]
pub fn mean_distance(a: &Simulation, b: &Simulation) -> f32 {
    let n = a.particles.len();
    a.particles
        .x
        .iter()
        .zip(&b.particles.x)
        .map(|(p, q)| p.distance(*q))
        .sum::<f32>()
        / n as f32
}

/// Largest distance between the two simulations' particles.
#[allow(dead_code)]
pub fn max_distance(a: &Simulation, b: &Simulation) -> f32 {
    a.particles
        .x
        .iter()
        .zip(&b.particles.x)
        .map(|(p, q)| p.distance(*q))
        .fold(0.0, f32::max)
}
