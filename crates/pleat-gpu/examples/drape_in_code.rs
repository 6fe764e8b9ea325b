//! pleat as a library: a scene built in code (a level cloth pinned at two
//! corners, swinging down onto a sphere), stepped on the CPU and on the GPU, the
//! positions read back and compared, and the GPU run written as an
//! animated glb for Blender.
//!
//! ```sh
//! cargo run --release -p pleat-gpu --example drape_in_code -- out/drape_in_code.glb
//! ```
//!
//! The GPU is any wgpu adapter (Vulkan, Metal, DX12; Mesa's lavapipe on a
//! machine without one).

use std::error::Error;
use std::path::PathBuf;

use pleat::collide::{Collider, Friction, Motion, Shape};
use pleat::export::gltf::GlbAnimation;
use pleat::glam::Vec3;
use pleat::mesh::GridSpec;
use pleat::model::Pin;
use pleat::{Material, Model, Simulation, SolverSettings, World};
use pleat_gpu::{GpuBackend, GpuContext};

const FRAMES: u32 = 90;
const FRAME_DT: f32 = 1.0 / 60.0;

/// A level 1 m cloth of 32 x 32 vertices, 1 m up, pinned at the two
/// corners of its far edge, above a sphere it swings down onto.
fn scene() -> (Model, World) {
    let grid = GridSpec {
        center: Vec3::new(0.0, 1.0, 0.0),
        ..GridSpec::new(32, 32, [1.0, 1.0])
    };
    let pins = [grid.index(0, 0), grid.index(0, grid.cols - 1)].map(|particle| Pin {
        particle,
        compliance: 0.0,
        motion: Motion::default(),
    });
    let mut model = Model::default();
    model.add_cloth("cloth", grid.build(), Material::default(), &pins, false);
    let sphere = Shape::Sphere {
        center: Vec3::new(0.0, 0.35, -0.25),
        radius: 0.25,
    };
    let world = World {
        colliders: vec![Collider::scripted(
            sphere,
            Motion::default(),
            Friction::default(),
        )],
        ..World::default()
    };
    (model, world)
}

fn main() -> Result<(), Box<dyn Error>> {
    let out = std::env::args()
        .nth(1)
        .map_or_else(|| PathBuf::from("out/drape_in_code.glb"), PathBuf::from);
    let settings = SolverSettings::default();

    let (model, world) = scene();
    let mut cpu = Simulation::new(model, world, settings);

    let (model, world) = scene();
    let context = GpuContext::new()?;
    let (backend, _notes) = GpuBackend::new(&context, &model, &world, &settings)?;
    let mut gpu = Simulation::with_backend(model, world, settings, Box::new(backend));
    println!("GPU: {}", gpu.device());

    let mut animation = GlbAnimation::new(&gpu.model.triangles, &gpu.model.rest, FRAME_DT);
    for _ in 0..FRAMES {
        cpu.step(FRAME_DT);
        gpu.step(FRAME_DT);
        animation.push_frame(&gpu.sync().x)?;
    }

    let (x_cpu, x_gpu) = (&cpu.sync().x, &gpu.sync().x);
    let apart = x_cpu
        .iter()
        .zip(x_gpu)
        .map(|(a, b)| a.distance(*b))
        .fold(0.0, f32::max);
    let lowest = x_gpu.iter().map(|p| p.y).fold(f32::MAX, f32::min);
    let penetrations = gpu.metrics().collider_penetrations;
    println!(
        "after {FRAMES} frames: lowest point {lowest:.3} m, {penetrations} particles inside \
         the sphere, CPU and GPU at most {:.2} mm apart, max stretch {:.4} (CPU) {:.4} (GPU)",
        apart * 1e3,
        cpu.metrics().max_stretch,
        gpu.metrics().max_stretch,
    );
    if let Some(dir) = out.parent() {
        std::fs::create_dir_all(dir)?;
    }
    animation.write(&mut std::io::BufWriter::new(std::fs::File::create(&out)?))?;
    println!(
        "wrote {} ({} frames)",
        out.display(),
        animation.frame_count()
    );
    Ok(())
}
