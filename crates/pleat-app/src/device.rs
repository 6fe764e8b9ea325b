//! Device loss: a [`DeviceWatch`] on the app's wgpu device hears wgpu's
//! device-lost callback (a driver reset, a browser that takes the GPU
//! back, `destroy()`) and its uncaptured errors (a submit to a lost
//! device, an out-of-memory), which wgpu would otherwise turn into a panic.
//! The app reads both each frame: an error is shown, a loss starts the
//! recovery ([`crate::recovery`]).

use std::sync::{Arc, Mutex};

/// A device and what its callbacks have heard since the app last looked.
pub struct DeviceWatch {
    device: wgpu::Device,
    heard: Arc<Mutex<Heard>>,
}

#[derive(Debug, Default)]
struct Heard {
    /// Why the device was lost, once it has been.
    lost: Option<String>,
    /// The uncaptured errors not yet taken.
    errors: Vec<String>,
}

impl DeviceWatch {
    /// Listens on `device`: its loss and its uncaptured errors.
    pub fn attach(device: &wgpu::Device) -> Self {
        let watch = DeviceWatch {
            device: device.clone(),
            heard: Arc::default(),
        };
        let heard = watch.heard.clone();
        device.set_device_lost_callback(move |reason, message| {
            let why = match reason {
                wgpu::DeviceLostReason::Destroyed => "destroyed",
                wgpu::DeviceLostReason::Unknown => "lost",
            };
            let message = message.trim();
            let text = if message.is_empty() {
                why.to_string()
            } else {
                format!("{why}: {message}")
            };
            lock(&heard).lost.get_or_insert(text);
        });
        let heard = watch.heard.clone();
        device.on_uncaptured_error(Arc::new(move |error| {
            let mut heard = lock(&heard);
            // One of a kind is enough: a lost device fails every frame.
            let text = one_line(&error.to_string());
            if !heard.errors.contains(&text) {
                heard.errors.push(text);
            }
        }));
        watch
    }

    /// Why the device was lost, if it has been.
    pub fn lost(&self) -> Option<String> {
        lock(&self.heard).lost.clone()
    }

    /// The uncaptured errors since the last call.
    pub fn take_errors(&self) -> Vec<String> {
        std::mem::take(&mut lock(&self.heard).errors)
    }

    /// Loses the device on purpose, as a driver reset would (for tests:
    /// the page's `pleatLoseDevice()`, the native app's `--lose-device-at`).
    pub fn destroy(&self) {
        self.device.destroy();
    }
}

/// The lock, even if a thread panicked holding it (the data is plain).
fn lock(heard: &Mutex<Heard>) -> std::sync::MutexGuard<'_, Heard> {
    heard.lock().unwrap_or_else(|e| e.into_inner())
}

/// wgpu's errors run over several lines (the error and its causes): one
/// line for the panel, at most [`ERROR_CHARS`] characters.
fn one_line(text: &str) -> String {
    let line = (text.lines().map(str::trim))
        .filter(|l| !l.is_empty())
        .collect::<Vec<_>>()
        .join(" ");
    match line.char_indices().nth(ERROR_CHARS) {
        Some((cut, _)) => format!("{}…", &line[..cut]),
        None => line,
    }
}

/// The longest error line shown.
const ERROR_CHARS: usize = 240;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_error_is_one_line_of_bounded_length() {
        assert_eq!(
            one_line("Validation Error\n\nCaused by:\n  In Queue::submit\n"),
            "Validation Error Caused by: In Queue::submit"
        );
        assert_eq!(one_line(&"x".repeat(500)).chars().count(), ERROR_CHARS + 1);
    }
}
