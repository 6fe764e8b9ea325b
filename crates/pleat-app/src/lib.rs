//! pleat-app: cloth and origami live, in a native window or a browser tab.
//!
//! One code base on eframe/egui over wgpu: [`PleatApp`] shows the demos
//! ([`demos`]), every parameter on a panel ([`params`]), the cloth drawn by
//! pleat-render on the app's own device and simulated by the GPU backend
//! where the adapter has compute shaders (else on the CPU, said on screen).
//! The mouse orbits the camera or drags the cloth; dropped scenes, meshes
//! and crease patterns open ([`dropped`]). The web build starts from
//! `start` on a page made by `cargo xtask web`.

pub mod app;
pub mod demos;
pub mod dropped;
mod legend;
mod orbit;
mod panels;
pub mod params;
mod platform;
mod plot;
pub mod probe;
pub mod session;
mod software;
mod viewport;

pub use app::{Options, PleatApp};
pub use session::BackendChoice;

use std::sync::Arc;

/// eframe's wgpu set-up for pleat: the device asks for timestamp queries
/// where the adapter has them (per-stage GPU times) and for buffers as
/// large as the adapter allows (large cloths), within WebGPU's other limits.
pub fn wgpu_options() -> eframe::egui_wgpu::WgpuConfiguration {
    use eframe::egui_wgpu::{WgpuConfiguration, WgpuSetup, WgpuSetupCreateNew};
    let mut setup = WgpuSetupCreateNew::without_display_handle();
    setup.device_descriptor = Arc::new(|adapter| {
        // WebGL2 (no compute) cannot give WebGPU's limits.
        let base = if adapter.get_info().backend == wgpu::Backend::Gl {
            wgpu::Limits::downlevel_webgl2_defaults()
        } else {
            pleat_gpu::GpuContext::limits(&adapter.limits())
        };
        wgpu::DeviceDescriptor {
            label: Some("pleat-app"),
            required_features: adapter.features() & wgpu::Features::TIMESTAMP_QUERY,
            required_limits: wgpu::Limits {
                max_texture_dimension_2d: adapter.limits().max_texture_dimension_2d.min(8192),
                ..base
            },
            ..Default::default()
        }
    });
    WgpuConfiguration {
        wgpu_setup: WgpuSetup::CreateNew(setup),
        ..Default::default()
    }
}

/// Starts the app on the page's `<canvas id="pleat">`, with the demo and
/// backend the URL asks for (`?demo=fold&backend=cpu`).
#[cfg(target_arch = "wasm32")]
#[wasm_bindgen::prelude::wasm_bindgen(start)]
pub fn start() {
    use wasm_bindgen::JsCast;
    let options = url_options();
    let web_options = eframe::WebOptions {
        wgpu_options: wgpu_options(),
        ..Default::default()
    };
    wasm_bindgen_futures::spawn_local(async move {
        let document = web_sys::window()
            .and_then(|w| w.document())
            .expect("a document");
        let canvas = document
            .get_element_by_id("pleat")
            .and_then(|e| e.dyn_into::<web_sys::HtmlCanvasElement>().ok())
            .expect("a <canvas id=\"pleat\">");
        let started = eframe::WebRunner::new()
            .start(
                canvas,
                web_options,
                Box::new(|cc| Ok(Box::new(PleatApp::new(cc, options)))),
            )
            .await;
        if let Err(e) = started {
            let message = format!("pleat could not start: {e:?}");
            let _ = js_sys::Reflect::set(
                &web_sys::window().expect("a window"),
                &"pleatStartError".into(),
                &message.into(),
            );
        }
    });
}

/// The options the page's URL gives.
#[cfg(target_arch = "wasm32")]
fn url_options() -> Options {
    let mut options = Options::default();
    let search = web_sys::window()
        .and_then(|w| w.location().search().ok())
        .unwrap_or_default();
    if let Ok(params) = web_sys::UrlSearchParams::new_with_str(&search) {
        if let Some(demo) = params.get("demo") {
            options.demo = demo;
        }
        if params.get("backend").as_deref() == Some("cpu") {
            options.backend = BackendChoice::Cpu;
        }
    }
    options
}
