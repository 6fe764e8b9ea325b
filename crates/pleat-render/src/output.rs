//! Pictures to files: PNG frames and one animated GIF.

use crate::error::RenderError;
use image::codecs::gif::{GifEncoder, Repeat};
use image::{Delay, Frame, RgbaImage};
use std::fs::File;
use std::io::BufWriter;
use std::path::{Path, PathBuf};

/// Writes `image` as a PNG file.
pub fn save_png(image: &RgbaImage, path: &Path) -> Result<(), RenderError> {
    image.save(path).map_err(|e| RenderError::Write {
        path: path.to_path_buf(),
        reason: e.to_string(),
    })
}

/// An animated GIF written a frame at a time, looping forever.
pub struct GifWriter {
    encoder: GifEncoder<BufWriter<File>>,
    path: PathBuf,
    delay: Delay,
}

/// Colour quantisation speed of the GIF encoder (1 best, 30 fastest).
const GIF_SPEED: i32 = 10;

impl GifWriter {
    /// Creates `path`; each frame shows for `frame_seconds`.
    pub fn create(path: &Path, frame_seconds: f32) -> Result<Self, RenderError> {
        let write_error = |reason: String| RenderError::Write {
            path: path.to_path_buf(),
            reason,
        };
        let file = File::create(path).map_err(|e| write_error(e.to_string()))?;
        let mut encoder = GifEncoder::new_with_speed(BufWriter::new(file), GIF_SPEED);
        encoder
            .set_repeat(Repeat::Infinite)
            .map_err(|e| write_error(e.to_string()))?;
        let ms = (frame_seconds * 1000.0).round().clamp(10.0, 655_350.0) as u32;
        Ok(GifWriter {
            encoder,
            path: path.to_path_buf(),
            delay: Delay::from_numer_denom_ms(ms, 1),
        })
    }

    /// Appends a frame.
    pub fn push(&mut self, image: &RgbaImage) -> Result<(), RenderError> {
        self.encoder
            .encode_frame(Frame::from_parts(image.clone(), 0, 0, self.delay))
            .map_err(|e| RenderError::Write {
                path: self.path.clone(),
                reason: e.to_string(),
            })
    }
}
