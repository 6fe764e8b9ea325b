//! The inputs a caller changes from frame to frame (the frame's length,
//! the fold's drive, the grabbed particle), handed to every step as one
//! value beside the settings, so that no backend keeps a copy of its own.

use crate::constraint::{FoldDrive, Grab};

/// What one step is driven by, besides the world and the settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Control {
    /// Length of the frame to step (s).
    pub frame_dt: f32,
    /// The fold progress origami hinges are driven to, and whether it is held.
    pub fold: FoldDrive,
    /// The particle a person drags, and where to.
    pub grab: Option<Grab>,
}

impl Control {
    /// A frame of `frame_dt` with the fold flat and held, nothing grabbed.
    pub fn frame(frame_dt: f32) -> Self {
        Control {
            frame_dt,
            fold: FoldDrive {
                progress: 0.0,
                held: true,
                flat: false,
            },
            grab: None,
        }
    }
}
