//! The errors of rendering: no adapter, a bad size or input, an image that
//! cannot be read or written.

use std::path::PathBuf;

/// Why a picture could not be made. The text says what happened; what a
/// user can do about it is the caller's to say.
#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    /// No GPU adapter, not even a software one.
    #[error("no usable GPU adapter ({0})")]
    NoAdapter(String),
    /// The adapter would not open a device.
    #[error("cannot open the GPU device: {0}")]
    Device(String),
    /// A picture size the device cannot draw.
    #[error("image size {width} x {height} is out of range: each side must be 1 to {max} pixels")]
    Size {
        /// Requested width in pixels.
        width: u32,
        /// Requested height in pixels.
        height: u32,
        /// Largest side the device allows.
        max: u32,
    },
    /// Positions for a different number of particles than the model has.
    #[error("positions for {got} particles given, the model has {expected}")]
    ParticleCount {
        /// Particles the positions hold.
        got: usize,
        /// Particles of the model.
        expected: usize,
    },
    /// A setting out of range.
    #[error("{0}")]
    Setting(String),
    /// An image file that cannot be read (a texture or height map).
    #[error("{path}: cannot read the image: {reason}")]
    ReadImage {
        /// The file.
        path: PathBuf,
        /// Why.
        reason: String,
    },
    /// A picture or animation that cannot be written.
    #[error("{path}: cannot write: {reason}")]
    Write {
        /// The file.
        path: PathBuf,
        /// Why.
        reason: String,
    },
    /// The GPU failed while the frame was read back.
    #[error("reading the frame back from the GPU failed: {0}")]
    Readback(String),
}
