//! pleat-gpu: the GPU backend of pleat. The XPBD pipeline of the core
//! (wind, prediction, pins, coloured Gauss-Seidel constraint projection,
//! collider contacts with friction, velocity update) runs in WGSL compute
//! shaders on wgpu, so the same simulation steps on Vulkan, Metal, DX12 and
//! WebGPU. Every buffer stays on the GPU while it steps; the state comes
//! back only when asked ([`pleat::Backend::download`]).
//!
//! ```no_run
//! use pleat::scene::Scene;
//! use pleat_gpu::{GpuBackend, GpuContext};
//!
//! let scene = Scene::parse(include_str!("../../../scenes/drape.json"), "drape.json").unwrap();
//! let (model, world) = scene.model(std::path::Path::new("scenes"), "drape.json").unwrap();
//! let context = GpuContext::new().unwrap();
//! let (backend, _notes) = GpuBackend::new(&context, &model, &world, &scene.solver).unwrap();
//! let mut sim = pleat::Simulation::with_backend(model, world, scene.solver, Box::new(backend));
//! sim.step(1.0 / 60.0);
//! println!("max stretch {}", { sim.sync(); sim.metrics().max_stretch });
//! ```

#![warn(missing_docs)]

mod backend;
mod buffers;
mod context;
mod data;
mod health;
mod kernels;
#[cfg(test)]
mod layout;
mod momentum;
mod readback;
pub mod shaders;
mod timing;

pub use backend::GpuBackend;
pub use context::{GpuContext, GpuError};
