//! GPU resources: the headless device, buffers and textures made from CPU
//! data (the cloth's buffers, its lines, its material, the environment),
//! and the bind-group layout entries the pipelines share.

use super::COLOR_FORMAT;
use crate::error::RenderError;
use crate::geometry::{constraint_lines, planar_uvs, wireframe_lines, Incidence, Line, MeshVertex};
use crate::settings::{RenderSettings, View};
use crate::textures::{self, Texture, ENVIRONMENT_SIZE};
use glam::Vec3;
use pleat::Model;
use wgpu::util::DeviceExt;

/// A device of its own, with no window.
pub struct Headless {
    /// The device.
    pub device: wgpu::Device,
    /// Its queue.
    pub queue: wgpu::Queue,
    /// What the adapter is: name, backend, type (a CPU for lavapipe).
    pub adapter: wgpu::AdapterInfo,
}

impl Headless {
    /// The adapter's name, backend and type, e.g. `llvmpipe (LLVM 15.0.6, 256 bits), Vulkan, Cpu`.
    pub fn describe(&self) -> String {
        let a = &self.adapter;
        format!("{}, {:?}, {:?}", a.name, a.backend, a.device_type)
    }
}

/// Opens a device on the best adapter there is (a software one such as
/// Mesa lavapipe will do), for rendering with no window.
pub fn headless_device() -> Result<Headless, RenderError> {
    let instance =
        wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle_from_env());
    let adapter = pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions {
        power_preference: wgpu::PowerPreference::HighPerformance,
        force_fallback_adapter: false,
        compatible_surface: None,
        apply_limit_buckets: false,
    }))
    .map_err(|e| RenderError::NoAdapter(e.to_string()))?;
    let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
        label: Some("pleat-render"),
        required_limits: adapter.limits(),
        ..Default::default()
    }))
    .map_err(|e| RenderError::Device(e.to_string()))?;
    Ok(Headless {
        device,
        queue,
        adapter: adapter.get_info(),
    })
}

pub(super) fn storage_entry(
    binding: u32,
    visibility: wgpu::ShaderStages,
    read_only: bool,
) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Storage { read_only },
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    }
}

pub(super) fn uniform_entry(
    binding: u32,
    visibility: wgpu::ShaderStages,
) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Uniform,
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    }
}

pub(super) fn texture_entry(
    binding: u32,
    visibility: wgpu::ShaderStages,
    sample_type: wgpu::TextureSampleType,
    view_dimension: wgpu::TextureViewDimension,
) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility,
        ty: wgpu::BindingType::Texture {
            sample_type,
            view_dimension,
            multisampled: false,
        },
        count: None,
    }
}

pub(super) fn sampler_entry(
    binding: u32,
    visibility: wgpu::ShaderStages,
    kind: wgpu::SamplerBindingType,
) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility,
        ty: wgpu::BindingType::Sampler(kind),
        count: None,
    }
}

/// A buffer holding `contents`, at least 16 bytes (empty bindings are invalid).
pub(super) fn buffer_init(
    device: &wgpu::Device,
    label: &str,
    contents: &[u8],
    usage: wgpu::BufferUsages,
) -> wgpu::Buffer {
    let mut bytes = contents.to_vec();
    bytes.resize(bytes.len().max(16).next_multiple_of(4), 0);
    device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some(label),
        contents: &bytes,
        usage,
    })
}

pub(super) fn vec4s(points: &[Vec3]) -> Vec<[f32; 4]> {
    points.iter().map(|p| p.extend(0.0).to_array()).collect()
}

/// sRGB colour to linear, alpha 1.
pub(super) fn linear(srgb: Vec3) -> [f32; 4] {
    let f = |c: f32| {
        if c <= 0.040_45 {
            c / 12.92
        } else {
            ((c + 0.055) / 1.055).powf(2.4)
        }
    };
    [f(srgb.x), f(srgb.y), f(srgb.z), 1.0]
}

/// `texture` and its mipmaps (2 x 2 box filter), packed one after the other.
pub(super) fn mip_chain(texture: &Texture) -> (u32, Vec<u8>) {
    let (mut w, mut h) = (texture.width, texture.height);
    let mut level = texture.rgba.clone();
    let mut data = level.clone();
    let mut levels = 1;
    while w > 1 || h > 1 {
        let (nw, nh) = ((w / 2).max(1), (h / 2).max(1));
        let mut next = Vec::with_capacity((nw * nh * 4) as usize);
        for y in 0..nh {
            for x in 0..nw {
                for c in 0..4 {
                    let texel = |dx: u32, dy: u32| {
                        let (sx, sy) = ((2 * x + dx).min(w - 1), (2 * y + dy).min(h - 1));
                        level[((sy * w + sx) * 4 + c) as usize] as u32
                    };
                    next.push(
                        ((texel(0, 0) + texel(1, 0) + texel(0, 1) + texel(1, 1) + 2) / 4) as u8,
                    );
                }
            }
        }
        data.extend_from_slice(&next);
        level = next;
        (w, h, levels) = (nw, nh, levels + 1);
    }
    (levels, data)
}

pub(super) fn upload_texture(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    label: &str,
    texture: &Texture,
    format: wgpu::TextureFormat,
) -> wgpu::TextureView {
    let (levels, data) = mip_chain(texture);
    device
        .create_texture_with_data(
            queue,
            &wgpu::TextureDescriptor {
                label: Some(label),
                size: wgpu::Extent3d {
                    width: texture.width,
                    height: texture.height,
                    depth_or_array_layers: 1,
                },
                mip_level_count: levels,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format,
                usage: wgpu::TextureUsages::TEXTURE_BINDING,
                view_formats: &[],
            },
            wgpu::util::TextureDataOrder::LayerMajor,
            &data,
        )
        .create_view(&wgpu::TextureViewDescriptor::default())
}

pub(super) fn whole(buffer: &wgpu::Buffer) -> wgpu::BindingResource<'_> {
    buffer.as_entire_binding()
}

/// The cloth's buffers: its own positions (for positions given on the
/// CPU), the normals the normals pass writes and what it reads, texture
/// coordinates and triangle indices.
pub(super) struct ClothBuffers {
    pub(super) own_positions: wgpu::Buffer,
    pub(super) normals: wgpu::Buffer,
    pub(super) uvs: wgpu::Buffer,
    pub(super) indices: wgpu::Buffer,
    pub(super) normals_inputs: NormalsInputs,
}

/// What the normals pass reads besides the positions.
pub(super) struct NormalsInputs {
    pub(super) params: wgpu::Buffer,
    pub(super) rest: wgpu::Buffer,
    pub(super) triangles: wgpu::Buffer,
    pub(super) incidence_start: wgpu::Buffer,
    pub(super) incidence: wgpu::Buffer,
}

impl ClothBuffers {
    /// The buffers of `model`'s cloths, positions at rest.
    pub(super) fn new(device: &wgpu::Device, model: &Model) -> Self {
        let particles = model.particle_count();
        let storage = wgpu::BufferUsages::STORAGE;
        let incidence = Incidence::new(particles, &model.triangles);
        let rest = bytemuck::cast_slice(&vec4s(&model.rest)).to_vec();
        let triangles: &[u8] = bytemuck::cast_slice(&model.triangles);
        ClothBuffers {
            own_positions: buffer_init(
                device,
                "positions",
                &rest,
                storage | wgpu::BufferUsages::COPY_DST,
            ),
            normals: buffer_init(
                device,
                "normals",
                &vec![0u8; particles * 16],
                storage | wgpu::BufferUsages::COPY_SRC,
            ),
            uvs: buffer_init(
                device,
                "uvs",
                bytemuck::cast_slice(&planar_uvs(model)),
                storage,
            ),
            indices: buffer_init(device, "indices", triangles, wgpu::BufferUsages::INDEX),
            normals_inputs: NormalsInputs {
                params: buffer_init(
                    device,
                    "normals params",
                    bytemuck::cast_slice(&[particles as u32, 0, 0, 0]),
                    wgpu::BufferUsages::UNIFORM,
                ),
                rest: buffer_init(device, "rest", &rest, storage),
                triangles: buffer_init(device, "triangles", triangles, storage),
                incidence_start: buffer_init(
                    device,
                    "incidence start",
                    bytemuck::cast_slice(&incidence.start),
                    storage,
                ),
                incidence: buffer_init(
                    device,
                    "incidence",
                    bytemuck::cast_slice(&incidence.triangles),
                    storage,
                ),
            },
        }
    }
}

/// The lines of the wireframe or constraint view and their count; none in
/// the other views.
pub(super) fn line_buffer(
    device: &wgpu::Device,
    model: &Model,
    view: View,
) -> Option<(wgpu::Buffer, u32)> {
    let lines: Vec<Line> = match view {
        View::Wireframe => wireframe_lines(model),
        View::Constraints => constraint_lines(model),
        _ => return None,
    };
    let contents = bytemuck::cast_slice(&lines);
    let buffer = buffer_init(device, "lines", contents, wgpu::BufferUsages::VERTEX);
    Some((buffer, lines.len() as u32))
}

/// The vertex buffer of `count` mesh vertices (ground, colliders, pins),
/// written each frame.
pub(super) fn mesh_vertex_buffer(device: &wgpu::Device, count: u32) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("mesh vertices"),
        size: (count as u64 * std::mem::size_of::<MeshVertex>() as u64).max(16),
        usage: wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}

/// The cloth's material: colour and height textures (the settings', else
/// woven fabric or plain paper), and their sampler.
pub(super) struct Material {
    pub(super) albedo: wgpu::TextureView,
    pub(super) height_map: wgpu::TextureView,
    pub(super) sampler: wgpu::Sampler,
}

impl Material {
    pub(super) fn new(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        settings: &RenderSettings,
        is_paper: bool,
    ) -> Self {
        let (default_albedo, default_height) = if is_paper {
            (textures::plain(255), textures::plain(128))
        } else {
            textures::fabric()
        };
        let albedo = settings.texture.as_ref().unwrap_or(&default_albedo);
        let height = settings.height_map.as_ref().unwrap_or(&default_height);
        Material {
            albedo: upload_texture(device, queue, "albedo", albedo, COLOR_FORMAT),
            height_map: upload_texture(
                device,
                queue,
                "height map",
                height,
                wgpu::TextureFormat::Rgba8Unorm,
            ),
            sampler: device.create_sampler(&wgpu::SamplerDescriptor {
                label: Some("material"),
                address_mode_u: wgpu::AddressMode::Repeat,
                address_mode_v: wgpu::AddressMode::Repeat,
                mag_filter: wgpu::FilterMode::Linear,
                min_filter: wgpu::FilterMode::Linear,
                // Trilinear, not anisotropic: on lavapipe 8x anisotropic
                // filtering took 1.1 of 1.75 s per 1280 x 720 picture, and the
                // mipmapped weave looks the same without it.
                mipmap_filter: wgpu::MipmapFilterMode::Linear,
                ..Default::default()
            }),
        }
    }
}

/// The environment cube map lit from `light_direction`, with its sampler.
pub(super) fn environment(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    light_direction: Vec3,
) -> (wgpu::TextureView, wgpu::Sampler) {
    let view = device
        .create_texture_with_data(
            queue,
            &wgpu::TextureDescriptor {
                label: Some("environment"),
                size: wgpu::Extent3d {
                    width: ENVIRONMENT_SIZE,
                    height: ENVIRONMENT_SIZE,
                    depth_or_array_layers: 6,
                },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format: COLOR_FORMAT,
                usage: wgpu::TextureUsages::TEXTURE_BINDING,
                view_formats: &[],
            },
            wgpu::util::TextureDataOrder::LayerMajor,
            &textures::environment(light_direction),
        )
        .create_view(&wgpu::TextureViewDescriptor {
            dimension: Some(wgpu::TextureViewDimension::Cube),
            ..Default::default()
        });
    let sampler = device.create_sampler(&wgpu::SamplerDescriptor {
        label: Some("environment"),
        mag_filter: wgpu::FilterMode::Linear,
        min_filter: wgpu::FilterMode::Linear,
        ..Default::default()
    });
    (view, sampler)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mipmaps_halve_down_to_one_texel() {
        let texture = Texture {
            width: 4,
            height: 2,
            rgba: vec![200; 32],
        };
        let (levels, data) = mip_chain(&texture);
        assert_eq!(levels, 3);
        assert_eq!(data.len(), (8 + 2 + 1) * 4);
        assert!(data.iter().all(|&b| b == 200));
    }
}
