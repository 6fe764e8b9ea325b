//! What differs between the native window and the web page: where dropped
//! files' bytes come from (a path, or an asynchronous browser read), where
//! exports go (a file, or a download), how tests reach the app (the
//! command line, or `window.pleatState`, `pleat_set`, `pleat_lose_device`
//! and `pleat_crash` on the page), and how the app starts again after
//! its device was lost (a new window, or a new start on the page's canvas).

use crate::probe::Probe;
use eframe::egui;
use std::sync::{Arc, Mutex};

/// Files read since the last frame (dropped files arrive asynchronously in
/// a browser), as (name, bytes or why they could not be read).
pub type Inbox = Arc<Mutex<Vec<(String, Result<Vec<u8>, String>)>>>;

#[cfg(not(target_arch = "wasm32"))]
pub use native::*;
#[cfg(target_arch = "wasm32")]
pub use web::*;

#[cfg(not(target_arch = "wasm32"))]
mod native {
    use super::*;

    /// Reads the files dropped on the window into `inbox`.
    pub fn receive_drops(ctx: &egui::Context, inbox: &Inbox) {
        let dropped = ctx.input(|i| i.raw.dropped_files.clone());
        let mut inbox = inbox.lock().expect("inbox");
        for file in dropped {
            let name = file
                .path()
                .file_name()
                .map_or("dropped".into(), |n| n.to_string_lossy().into_owned());
            inbox.push((name, file.bytes()));
        }
    }

    /// Writes `bytes` to the file `name` in the working folder.
    pub fn save(name: &str, bytes: &[u8]) -> Result<(), String> {
        std::fs::write(name, bytes).map_err(|e| format!("cannot write {name}: {e}"))?;
        eprintln!("wrote {name}");
        Ok(())
    }

    /// Natively, parameters come from the command line (`--set`).
    pub fn take_commands() -> Vec<(String, f64)> {
        Vec::new()
    }

    /// Natively the probe is printed on exit by `main`.
    pub fn publish(_probe: &Probe) {}

    /// Natively a test loses the device with `--lose-device-at`.
    pub fn take_lose_request() -> bool {
        false
    }

    /// Natively a crash ends the process and says why on the terminal.
    pub fn take_crash_request() -> Option<String> {
        None
    }

    /// Closes the window: `main` opens a new one, which resumes the run
    /// handed over ([`crate::recovery`]).
    pub fn restart(ctx: &egui::Context) {
        ctx.send_viewport_cmd(egui::ViewportCommand::Close);
    }
}

#[cfg(target_arch = "wasm32")]
mod web {
    use super::*;
    use std::cell::{Cell, RefCell};
    use wasm_bindgen::prelude::*;

    thread_local! {
        static COMMANDS: RefCell<Vec<(String, f64)>> = const { RefCell::new(Vec::new()) };
        static LOSE_DEVICE: Cell<bool> = const { Cell::new(false) };
        static CRASH: RefCell<Option<String>> = const { RefCell::new(None) };
    }

    /// Loses the app's WebGPU device (`GPUDevice.destroy()`) at the next
    /// frame, as a driver reset or the browser would: the page's hook for
    /// tests of the recovery.
    #[wasm_bindgen]
    pub fn pleat_lose_device() {
        LOSE_DEVICE.with(|l| l.set(true));
    }

    /// Whether the page asked to lose the device since the last frame.
    pub fn take_lose_request() -> bool {
        LOSE_DEVICE.with(|l| l.replace(false))
    }

    /// Makes the app panic with `reason` at its next frame, as a bug would
    /// stop it: the page's hook for tests that a crash is shown.
    #[wasm_bindgen]
    pub fn pleat_crash(reason: &str) {
        CRASH.with(|c| *c.borrow_mut() = Some(reason.to_string()));
    }

    /// The reason the page asked the app to crash with, if it did.
    pub fn take_crash_request() -> Option<String> {
        CRASH.with(|c| c.borrow_mut().take())
    }

    /// Starts the app again on the page's canvas (after the current
    /// frame), which makes a new device and resumes the run handed over.
    pub fn restart(_ctx: &egui::Context) {
        crate::start_on_page();
    }

    /// Sets the parameter `name` (as on the panels) from JavaScript: the
    /// page's hook for tests and scripts. Applied at the next frame; an
    /// unknown name shows as the app's last error.
    #[wasm_bindgen]
    pub fn pleat_set(name: &str, value: f64) {
        COMMANDS.with(|c| c.borrow_mut().push((name.to_string(), value)));
    }

    /// The parameters set from JavaScript since the last frame.
    pub fn take_commands() -> Vec<(String, f64)> {
        COMMANDS.with(|c| std::mem::take(&mut *c.borrow_mut()))
    }

    /// Starts reading the files dropped on the page; they land in `inbox`.
    pub fn receive_drops(ctx: &egui::Context, inbox: &Inbox) {
        let dropped = ctx.input(|i| i.raw.dropped_files.clone());
        for file in dropped {
            let inbox = inbox.clone();
            let ctx = ctx.clone();
            wasm_bindgen_futures::spawn_local(async move {
                let name = file.path().to_string_lossy().into_owned();
                let bytes = file.bytes_async().await;
                inbox.lock().expect("inbox").push((name, bytes));
                ctx.request_repaint();
            });
        }
    }

    /// Offers `bytes` as a download named `name`.
    pub fn save(name: &str, bytes: &[u8]) -> Result<(), String> {
        let fail = |e: JsValue| format!("cannot download {name}: {e:?}");
        let array = js_sys::Uint8Array::from(bytes);
        let parts = js_sys::Array::of1(&array);
        let blob = web_sys::Blob::new_with_u8_array_sequence(&parts).map_err(fail)?;
        let url = web_sys::Url::create_object_url_with_blob(&blob).map_err(fail)?;
        let document = web_sys::window()
            .and_then(|w| w.document())
            .ok_or("no document")?;
        let link: web_sys::HtmlAnchorElement = document
            .create_element("a")
            .map_err(fail)?
            .dyn_into()
            .map_err(|_| "not an anchor".to_string())?;
        link.set_href(&url);
        link.set_download(name);
        link.click();
        web_sys::Url::revoke_object_url(&url).map_err(fail)
    }

    /// Publishes the probe as `window.pleatState` (JSON text).
    pub fn publish(probe: &Probe) {
        if let Some(window) = web_sys::window() {
            let _ = js_sys::Reflect::set(&window, &"pleatState".into(), &probe.to_json().into());
        }
    }
}
