//! pleat-render: pictures of cloth and paper with wgpu.
//!
//! A [`Renderer`] draws one model (its cloths) and world (its colliders)
//! offscreen, on its own headless device ([`Renderer::headless`]; a
//! software adapter such as Mesa lavapipe will do) or on a device the
//! caller shares ([`Renderer::new`]), and reads each frame back as an RGBA
//! image. Positions come from the CPU or straight from the GPU backend's
//! buffer ([`Positions`]). Views ([`View`]): textured Blinn-Phong with
//! bump and displacement mapping, two-sided colours, a shadowed ground and
//! the colliders (optionally as mirrors of the sky); the wireframe; the
//! constraints by kind; the edge strain as a colour map with a legend.
//! [`save_png`] and [`GifWriter`] write the pictures.
//!
//! ```no_run
//! use pleat_render::{Positions, RenderSettings, Renderer};
//! # fn main() -> Result<(), Box<dyn std::error::Error>> {
//! let scene = pleat::scene::Scene::load(std::path::Path::new("scenes/drape.json"))?;
//! let mut sim = scene.build(std::path::Path::new("scenes"), "drape.json")?;
//! let mut renderer = Renderer::headless(&sim.model, &sim.world, RenderSettings::default())?;
//! sim.step(scene.frame_dt());
//! let picture = renderer.render(Positions::Cpu(&sim.particles.x), &sim.world)?;
//! pleat_render::save_png(&picture, std::path::Path::new("drape.png"))?;
//! # Ok(())
//! # }
//! ```

#![warn(missing_docs)]

mod camera;
mod error;
mod geometry;
mod legend;
mod output;
mod renderer;
mod settings;
pub mod shaders;
mod textures;

pub use camera::{project, Bounds, Camera, Light};
pub use error::RenderError;
pub use geometry::CONSTRAINT_KINDS;
pub use output::{save_png, GifWriter};
pub use renderer::{headless_device, Headless, Positions, Renderer};
pub use settings::{RenderSettings, View};
pub use textures::Texture;
