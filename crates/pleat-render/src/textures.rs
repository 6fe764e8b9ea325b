//! Textures made here rather than shipped: a woven fabric (colour and height),
//! a checker, plain paper, and the environment cube map (sky over a ground)
//! that mirrors reflect and the background shows; and images read from PNG.

use crate::error::RenderError;
use glam::Vec3;
use std::f32::consts::PI;
use std::path::Path;

/// An RGBA8 image, row by row from the top.
#[derive(Clone, Debug, PartialEq)]
pub struct Texture {
    pub(crate) width: u32,
    pub(crate) height: u32,
    pub(crate) rgba: Vec<u8>,
}

impl Texture {
    /// Reads a PNG file.
    pub fn load(path: &Path) -> Result<Texture, RenderError> {
        let image = image::open(path).map_err(|e| RenderError::ReadImage {
            path: path.to_path_buf(),
            reason: e.to_string(),
        })?;
        let rgba = image.to_rgba8();
        Ok(Texture {
            width: rgba.width(),
            height: rgba.height(),
            rgba: rgba.into_raw(),
        })
    }

    /// One texel of colour `rgba` (sRGB), which the sampler repeats.
    pub fn solid(rgba: [u8; 4]) -> Texture {
        Texture {
            width: 1,
            height: 1,
            rgba: rgba.to_vec(),
        }
    }

    fn from_fn(size: u32, f: impl Fn(f32, f32) -> [u8; 4]) -> Texture {
        let mut rgba = Vec::with_capacity((size * size * 4) as usize);
        for y in 0..size {
            for x in 0..size {
                let (u, v) = (
                    (x as f32 + 0.5) / size as f32,
                    (y as f32 + 0.5) / size as f32,
                );
                rgba.extend_from_slice(&f(u, v));
            }
        }
        Texture {
            width: size,
            height: size,
            rgba,
        }
    }
}

fn grey(x: f32) -> [u8; 4] {
    let g = (x.clamp(0.0, 1.0) * 255.0).round() as u8;
    [g, g, g, 255]
}

/// Threads across one texture tile, each way.
const THREADS_PER_TILE: f32 = 8.0;

/// A plain weave: colour (near white, to be tinted) and height (threads
/// crossing over and under each other).
pub fn fabric() -> (Texture, Texture) {
    let height = |u: f32, v: f32| {
        let (cu, cv) = (u * THREADS_PER_TILE, v * THREADS_PER_TILE);
        let (fu, fv) = (cu.fract(), cv.fract());
        let warp_on_top = (cu.floor() as i32 + cv.floor() as i32) % 2 == 0;
        // A thread is a ridge across its width that dips where it passes under.
        let (across, along) = if warp_on_top { (fu, fv) } else { (fv, fu) };
        let ridge = (PI * across).sin().powf(0.6);
        let arch = 0.75 + 0.25 * (PI * along).sin();
        ridge * arch
    };
    let color = Texture::from_fn(128, |u, v| grey(0.85 + 0.15 * height(u, v)));
    (color, Texture::from_fn(128, |u, v| grey(height(u, v))))
}

/// Light and dark squares, 4 x 4 to a tile.
pub fn checker() -> Texture {
    Texture::from_fn(64, |u, v| {
        let odd = ((u * 4.0) as i32 + (v * 4.0) as i32) % 2 == 1;
        grey(if odd { 0.35 } else { 0.95 })
    })
}

/// One grey texel of `level`: a plain colour or a flat height map (128).
pub fn plain(level: u8) -> Texture {
    Texture::solid([level, level, level, 255])
}

/// Pixels along each side of an environment cube face.
pub const ENVIRONMENT_SIZE: u32 = 128;

/// The sky in direction `d` (sRGB): blue overhead, pale at the horizon,
/// a soft sun, a warm grey ground below.
fn sky(d: Vec3, sun: Vec3) -> Vec3 {
    let d = d.normalize();
    let zenith = Vec3::new(0.32, 0.52, 0.82);
    let horizon = Vec3::new(0.82, 0.86, 0.9);
    let ground = Vec3::new(0.42, 0.4, 0.37);
    let base = if d.y >= 0.0 {
        horizon.lerp(zenith, d.y.powf(0.6))
    } else {
        horizon.lerp(ground, (-d.y * 6.0).min(1.0))
    };
    base + Vec3::splat(0.6 * d.dot(sun).max(0.0).powf(300.0))
}

/// The six faces (+x, -x, +y, -y, +z, -z) of the environment cube map,
/// with the sun opposite the light's direction of travel.
pub fn environment(light_direction: Vec3) -> Vec<u8> {
    let sun = -light_direction.normalize_or(Vec3::NEG_Y);
    let n = ENVIRONMENT_SIZE;
    let mut data = Vec::with_capacity((6 * n * n * 4) as usize);
    for face in 0..6 {
        for y in 0..n {
            for x in 0..n {
                let s = 2.0 * (x as f32 + 0.5) / n as f32 - 1.0;
                let t = 2.0 * (y as f32 + 0.5) / n as f32 - 1.0;
                let d = match face {
                    0 => Vec3::new(1.0, -t, -s),
                    1 => Vec3::new(-1.0, -t, s),
                    2 => Vec3::new(s, 1.0, t),
                    3 => Vec3::new(s, -1.0, -t),
                    4 => Vec3::new(s, -t, 1.0),
                    _ => Vec3::new(-s, -t, -1.0),
                };
                let c = sky(d, sun).clamp(Vec3::ZERO, Vec3::ONE) * 255.0;
                data.extend_from_slice(&[c.x as u8, c.y as u8, c.z as u8, 255]);
            }
        }
    }
    data
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn generated_textures_have_their_sizes() {
        let (color, height) = fabric();
        assert_eq!(color.rgba.len(), 128 * 128 * 4);
        assert_eq!(height.rgba.len(), 128 * 128 * 4);
        // The weave has relief.
        let levels: Vec<u8> = height.rgba.iter().step_by(4).copied().collect();
        assert!(levels.iter().max().unwrap() - levels.iter().min().unwrap() > 150);
        let n = ENVIRONMENT_SIZE as usize;
        let env = environment(Vec3::NEG_Y);
        assert_eq!(env.len(), 6 * n * n * 4);
        // The +y face (sky) is bluer than the -y face (ground).
        let texel = |face: usize| &env[face * n * n * 4 + (n / 2 * n + n / 2) * 4..][..3];
        assert!(texel(2)[2] > texel(3)[2]);
    }

    #[test]
    fn a_missing_image_is_an_error() {
        let err = Texture::load(Path::new("/nonexistent/texture.png")).unwrap_err();
        assert!(
            err.to_string().contains("/nonexistent/texture.png"),
            "{err}"
        );
    }
}
