//! Where a frame is drawn (shadow map, multisampled colour and depth, the
//! resolved picture) and how it comes back to the CPU.

use super::{COLOR_FORMAT, DEPTH_FORMAT, SHADOW_SIZE};
use crate::error::RenderError;
use image::RgbaImage;

/// The frame's attachments and readback buffers.
pub(super) struct Targets {
    pub(super) shadow: wgpu::TextureView,
    pub(super) color: Option<wgpu::TextureView>,
    pub(super) depth: wgpu::TextureView,
    pub(super) resolved: wgpu::Texture,
    pub(super) readback: wgpu::Buffer,
    pub(super) padded_row: u32,
    pub(super) strain_readback: wgpu::Buffer,
}

impl Targets {
    pub(super) fn new(
        device: &wgpu::Device,
        width: u32,
        height: u32,
        msaa: u32,
        particles: usize,
    ) -> Self {
        let texture = |label: &str, w: u32, h: u32, samples: u32, format, usage| {
            device.create_texture(&wgpu::TextureDescriptor {
                label: Some(label),
                size: wgpu::Extent3d {
                    width: w,
                    height: h,
                    depth_or_array_layers: 1,
                },
                mip_level_count: 1,
                sample_count: samples,
                dimension: wgpu::TextureDimension::D2,
                format,
                usage,
                view_formats: &[],
            })
        };
        let attachment = wgpu::TextureUsages::RENDER_ATTACHMENT;
        let view = |t: wgpu::Texture| t.create_view(&wgpu::TextureViewDescriptor::default());
        let padded_row = (width * 4).next_multiple_of(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT);
        Targets {
            shadow: view(texture(
                "shadow map",
                SHADOW_SIZE,
                SHADOW_SIZE,
                1,
                DEPTH_FORMAT,
                attachment | wgpu::TextureUsages::TEXTURE_BINDING,
            )),
            color: (msaa > 1).then(|| {
                view(texture(
                    "colour",
                    width,
                    height,
                    msaa,
                    COLOR_FORMAT,
                    attachment,
                ))
            }),
            depth: view(texture(
                "depth",
                width,
                height,
                msaa,
                DEPTH_FORMAT,
                attachment,
            )),
            resolved: texture(
                "picture",
                width,
                height,
                1,
                COLOR_FORMAT,
                attachment | wgpu::TextureUsages::COPY_SRC | wgpu::TextureUsages::TEXTURE_BINDING,
            ),
            readback: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("picture readback"),
                size: padded_row as u64 * height as u64,
                usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
                mapped_at_creation: false,
            }),
            padded_row,
            strain_readback: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("strain readback"),
                size: (particles as u64 * 16).max(16),
                usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
                mapped_at_creation: false,
            }),
        }
    }

    /// Copies the picture out, submits `encoder` and waits for the pixels.
    pub(super) fn read_back(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        mut encoder: wgpu::CommandEncoder,
        width: u32,
        height: u32,
    ) -> Result<RgbaImage, RenderError> {
        encoder.copy_texture_to_buffer(
            wgpu::TexelCopyTextureInfo {
                texture: &self.resolved,
                mip_level: 0,
                origin: wgpu::Origin3d::ZERO,
                aspect: wgpu::TextureAspect::All,
            },
            wgpu::TexelCopyBufferInfo {
                buffer: &self.readback,
                layout: wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(self.padded_row),
                    rows_per_image: Some(height),
                },
            },
            wgpu::Extent3d {
                width,
                height,
                depth_or_array_layers: 1,
            },
        );
        queue.submit([encoder.finish()]);
        let bytes = map_read(device, &self.readback)?;
        let row = (width * 4) as usize;
        let mut pixels = Vec::with_capacity(row * height as usize);
        for padded in bytes.chunks(self.padded_row as usize).take(height as usize) {
            pixels.extend_from_slice(&padded[..row]);
        }
        RgbaImage::from_raw(width, height, pixels)
            .ok_or_else(|| RenderError::Readback("the picture came back short".into()))
    }

    /// The largest edge strain of the last frame (already copied out).
    pub(super) fn max_strain(
        &self,
        device: &wgpu::Device,
        particles: usize,
    ) -> Result<f32, RenderError> {
        let bytes = map_read(device, &self.strain_readback)?;
        let normals: &[[f32; 4]] = bytemuck::cast_slice(&bytes[..particles * 16]);
        Ok(normals.iter().map(|n| n[3]).fold(0.0, f32::max))
    }
}

/// Maps `buffer` (after its copy was submitted), waits and copies it out.
pub(super) fn map_read(
    device: &wgpu::Device,
    buffer: &wgpu::Buffer,
) -> Result<Vec<u8>, RenderError> {
    let (sender, receiver) = std::sync::mpsc::channel();
    buffer.map_async(wgpu::MapMode::Read, .., move |result| {
        // The receiver waits below; a send can only fail if it is gone.
        let _ = sender.send(result);
    });
    device
        .poll(wgpu::PollType::Wait {
            submission_index: None,
            timeout: None,
        })
        .map_err(|e| RenderError::Readback(e.to_string()))?;
    receiver
        .recv()
        .map_err(|e| RenderError::Readback(e.to_string()))?
        .map_err(|e| RenderError::Readback(e.to_string()))?;
    let bytes = buffer
        .get_mapped_range(..)
        .map_err(|e| RenderError::Readback(e.to_string()))?
        .to_vec();
    buffer.unmap();
    Ok(bytes)
}
