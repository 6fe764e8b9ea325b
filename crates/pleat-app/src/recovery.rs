//! Recovery from a lost device. eframe draws on the device it made at the
//! start and cannot make another, so a lost device means a new start: the
//! app hands its run over ([`hand_over`]: the scene, the state last read
//! back, the panels, the counters), the page (or the native window) starts
//! eframe again, which makes a new device, and [`crate::PleatApp::resume`]
//! takes the run from there, saying on screen what happened.

use crate::app::PleatApp;
use std::cell::RefCell;

thread_local! {
    /// The run between the app that lost its device and the one that
    /// resumes it (both on the UI thread).
    static HANDOVER: RefCell<Option<PleatApp>> = const { RefCell::new(None) };
}

/// Keeps `app` (its device gone) for the next start of eframe.
pub fn hand_over(app: PleatApp) {
    HANDOVER.with(|h| *h.borrow_mut() = Some(app));
}

/// Whether a run waits for the next start.
pub fn is_pending() -> bool {
    HANDOVER.with(|h| h.borrow().is_some())
}

/// The run handed over, if any: the next start resumes it.
pub fn take() -> Option<PleatApp> {
    HANDOVER.with(|h| h.borrow_mut().take())
}
