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
pub mod backend_trial;
pub mod demos;
pub mod device;
pub mod dropped;
mod legend;
mod orbit;
mod panels;
pub mod params;
mod platform;
mod plot;
pub mod probe;
pub mod recovery;
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

#[cfg(target_arch = "wasm32")]
thread_local! {
    /// The page's one runner: a new start (after a lost device) replaces
    /// the app it runs.
    static RUNNER: eframe::WebRunner = eframe::WebRunner::new();
}

/// Starts the app on the page's `<canvas id="pleat">`, with the demo and
/// backend the URL asks for (`?demo=fold&backend=cpu`; without a backend,
/// the faster on each scene).
#[cfg(target_arch = "wasm32")]
#[wasm_bindgen::prelude::wasm_bindgen(start)]
pub fn start() {
    note_panics_on_page();
    start_on_page();
}

/// Puts a panic's message and place in `window.pleatPanic` before the
/// panic stops the app, so that the page can say why it stopped (eframe's
/// own hook, installed later, logs it to the console and calls this one).
#[cfg(target_arch = "wasm32")]
fn note_panics_on_page() {
    let previous = std::panic::take_hook();
    std::panic::set_hook(Box::new(move |info| {
        let payload = info.payload();
        let message = (payload.downcast_ref::<&str>().copied())
            .or_else(|| payload.downcast_ref::<String>().map(String::as_str))
            .unwrap_or("a panic");
        let text = match info.location() {
            Some(at) => format!("{message} (at {}:{})", at.file(), at.line()),
            None => message.to_string(),
        };
        if let Some(window) = web_sys::window() {
            let _ = js_sys::Reflect::set(&window, &"pleatPanic".into(), &text.into());
        }
        previous(info);
    }));
}

/// Starts eframe on the page's canvas (again, after a lost device: a new
/// device, and the run handed over resumes on it), after the current
/// frame; a failure goes to `window.pleatStartError`.
#[cfg(target_arch = "wasm32")]
pub(crate) fn start_on_page() {
    wasm_bindgen_futures::spawn_local(async {
        if let Err(e) = run_on_page().await {
            let message = format!("pleat could not start: {e}");
            if let Some(window) = web_sys::window() {
                let _ = js_sys::Reflect::set(&window, &"pleatStartError".into(), &message.into());
            }
        }
    });
}

#[cfg(target_arch = "wasm32")]
async fn run_on_page() -> Result<(), String> {
    use wasm_bindgen::JsCast;
    let canvas = web_sys::window()
        .and_then(|w| w.document())
        .and_then(|d| d.get_element_by_id("pleat"))
        .and_then(|e| e.dyn_into::<web_sys::HtmlCanvasElement>().ok())
        .ok_or("the page has no <canvas id=\"pleat\">")?;
    let web_options = eframe::WebOptions {
        wgpu_options: wgpu_options(),
        ..Default::default()
    };
    let runner = RUNNER.with(Clone::clone);
    runner
        .start(
            canvas,
            web_options,
            Box::new(|cc| {
                Ok(Box::new(match recovery::take() {
                    Some(run) => PleatApp::resume(cc, run),
                    None => PleatApp::new(cc, url_options()),
                }))
            }),
        )
        .await
        .map_err(|e| format!("{e:?}"))
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
        options.backend = match params.get("backend").as_deref() {
            Some("cpu") => Some(BackendChoice::Cpu),
            Some("gpu") => Some(BackendChoice::Gpu),
            _ => None,
        };
    }
    options
}
