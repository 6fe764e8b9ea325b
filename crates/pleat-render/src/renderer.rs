//! The renderer: GPU resources and pipelines, and one frame drawn offscreen
//! and read back as an RGBA image.
//!
//! A frame is a compute pass (smooth normals and edge strain from the
//! positions), a shadow pass (depth from the light), and a multisampled
//! main pass: the sky (environment cube map), the ground and colliders,
//! the cloth, and the lines of the wireframe or constraint view. Positions
//! come from a CPU slice (uploaded to the renderer's own buffer) or from a
//! caller's storage buffer on the same device (the GPU backend's), read
//! where it is: they never come back to the CPU.

use crate::camera::{project, Bounds, Camera, Light};
use crate::error::RenderError;
use crate::geometry::{
    collider_color, constraint_lines, ground, ground_plane, planar_uvs, wireframe_lines,
    ColliderMesh, Incidence, Line, MeshVertex, Surface, CONSTRAINT_KINDS,
};
use crate::legend::{draw_constraint_legend, draw_strain_legend};
use crate::settings::{RenderSettings, View};
use crate::shaders;
use crate::textures::{self, Texture, ENVIRONMENT_SIZE};
use bytemuck::{Pod, Zeroable};
use glam::{Affine3A, Mat4, Vec2, Vec3, Vec4};
use image::RgbaImage;
use pleat::collide::Motion;
use pleat::{Model, World};
use wgpu::util::DeviceExt;

/// Where a frame's particle positions are.
#[derive(Clone, Copy, Debug)]
pub enum Positions<'a> {
    /// On the CPU, one per particle of the model.
    Cpu(&'a [Vec3]),
    /// In a storage buffer on the renderer's device laid out as
    /// `array<vec4<f32>>` (16 bytes a particle: xyz the position, w the
    /// inverse mass), as the GPU backend keeps them. It needs
    /// `BufferUsages::STORAGE`.
    Gpu(&'a wgpu::Buffer),
}

/// Pixel format of the pictures: 8-bit sRGB, as PNG and GIF store them.
const COLOR_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8UnormSrgb;
const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;
/// Texels along each side of the shadow map.
const SHADOW_SIZE: u32 = 2048;
/// Workgroup size of normals.wgsl.
const NORMALS_WORKGROUP: u32 = 64;

/// The uniforms of common.wgsl, field for field.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
struct Globals {
    view_proj: [[f32; 4]; 4],
    light_view_proj: [[f32; 4]; 4],
    inv_view_proj: [[f32; 4]; 4],
    camera_position: [f32; 4],
    light_direction: [f32; 4],
    light_color: [f32; 4],
    front_color: [f32; 4],
    back_color: [f32; 4],
    material: [f32; 4],
    misc: [f32; 4],
    mode: [u32; 4],
}

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

/// Draws frames of one model (its cloths) and world (its colliders).
pub struct Renderer {
    device: wgpu::Device,
    queue: wgpu::Queue,
    settings: RenderSettings,
    particles: usize,
    index_count: u32,
    view_proj: Mat4,
    strain_range: f32,
    /// The model holds paper (crease patterns): paper colours and constraint kinds.
    is_paper: bool,
    global_bind_group: wgpu::BindGroup,
    shadow_bind_group: wgpu::BindGroup,
    own_positions: wgpu::Buffer,
    normals: wgpu::Buffer,
    uvs: wgpu::Buffer,
    indices: wgpu::Buffer,
    normals_inputs: NormalsInputs,
    lines: Option<(wgpu::Buffer, u32)>,
    colliders: Vec<(ColliderMesh, Vec3)>,
    /// A ball drawn at each pin, and where the pins are at time zero and how they move.
    pin_marker: ColliderMesh,
    pins: Vec<(Vec3, Motion)>,
    ground: Vec<MeshVertex>,
    mesh_vertices: wgpu::Buffer,
    mesh_vertex_count: u32,
    albedo: wgpu::TextureView,
    height_map: wgpu::TextureView,
    material_sampler: wgpu::Sampler,
    layouts: Layouts,
    pipelines: Pipelines,
    targets: Targets,
}

/// What the normals pass reads besides the positions.
struct NormalsInputs {
    params: wgpu::Buffer,
    rest: wgpu::Buffer,
    triangles: wgpu::Buffer,
    incidence_start: wgpu::Buffer,
    incidence: wgpu::Buffer,
}

struct Layouts {
    cloth: wgpu::BindGroupLayout,
    lines: wgpu::BindGroupLayout,
    normals: wgpu::BindGroupLayout,
}

struct Pipelines {
    normals: wgpu::ComputePipeline,
    cloth: wgpu::RenderPipeline,
    cloth_shadow: wgpu::RenderPipeline,
    meshes: wgpu::RenderPipeline,
    meshes_shadow: wgpu::RenderPipeline,
    sky: wgpu::RenderPipeline,
    lines: wgpu::RenderPipeline,
}

struct Targets {
    shadow: wgpu::TextureView,
    color: Option<wgpu::TextureView>,
    depth: wgpu::TextureView,
    resolved: wgpu::Texture,
    readback: wgpu::Buffer,
    padded_row: u32,
    strain_readback: wgpu::Buffer,
}

fn storage_entry(
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

fn uniform_entry(binding: u32, visibility: wgpu::ShaderStages) -> wgpu::BindGroupLayoutEntry {
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

fn texture_entry(
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

fn sampler_entry(
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
fn buffer_init(
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

fn vec4s(points: &[Vec3]) -> Vec<[f32; 4]> {
    points.iter().map(|p| p.extend(0.0).to_array()).collect()
}

/// sRGB colour to linear, alpha 1.
fn linear(srgb: Vec3) -> [f32; 4] {
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
fn mip_chain(texture: &Texture) -> (u32, Vec<u8>) {
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

fn upload_texture(
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

impl Renderer {
    /// A renderer on its own headless device (see [`headless_device`]).
    pub fn headless(
        model: &Model,
        world: &World,
        settings: RenderSettings,
    ) -> Result<Self, RenderError> {
        let Headless { device, queue, .. } = headless_device()?;
        Renderer::new(device, queue, model, world, settings)
    }

    /// A renderer on the caller's device and queue (shared with the app or
    /// the GPU backend), for `model`'s cloths and `world`'s colliders as
    /// they are now: the camera frames them unless the settings place it.
    pub fn new(
        device: wgpu::Device,
        queue: wgpu::Queue,
        model: &Model,
        world: &World,
        settings: RenderSettings,
    ) -> Result<Self, RenderError> {
        let max = device.limits().max_texture_dimension_2d;
        let (width, height) = (settings.width, settings.height);
        if !(1..=max).contains(&width) || !(1..=max).contains(&height) {
            return Err(RenderError::Size { width, height, max });
        }
        if ![1, 4].contains(&settings.msaa) {
            return Err(RenderError::Setting(format!(
                "msaa must be 1 or 4 samples, got {}",
                settings.msaa
            )));
        }
        let colliders: Vec<(ColliderMesh, Vec3)> = world
            .colliders
            .iter()
            .enumerate()
            .filter_map(|(i, c)| ColliderMesh::of(&c.shape).map(|m| (m, collider_color(i))))
            .collect();
        let bounds = colliders
            .iter()
            .filter_map(|(m, _)| m.bounds())
            .chain(Bounds::of(model.rest.iter().copied()))
            .reduce(Bounds::union)
            .unwrap_or(Bounds {
                min: Vec3::splat(-0.5),
                max: Vec3::splat(0.5),
            });
        let (center, radius) = (bounds.center(), bounds.radius());
        let (plane_point, plane_normal) = ground_plane(&world.colliders, &bounds);
        let ground = ground(plane_point, plane_normal, center, radius * 25.0);
        // The light's box holds the scene and the ground under it.
        let foot = center - plane_normal * (center - plane_point).dot(plane_normal);
        let lit = bounds.union(Bounds {
            min: foot,
            max: foot,
        });
        let light_view_proj = settings.light.view_proj(lit.center(), lit.radius());

        let aspect = width as f32 / height as f32;
        let camera = settings
            .camera
            .unwrap_or_else(|| Camera::framing(&bounds, aspect));
        let view_proj = camera.view_proj(aspect, radius);
        let is_paper = model.cloths.iter().any(|c| c.paper.is_some());
        let strain_range = settings
            .strain_range
            .unwrap_or(if is_paper { 0.02 } else { 0.1 });
        let globals = Self::globals(
            &settings,
            &camera,
            [view_proj, light_view_proj],
            strain_range,
            is_paper,
        );
        let globals = buffer_init(
            &device,
            "globals",
            bytemuck::bytes_of(&globals),
            wgpu::BufferUsages::UNIFORM,
        );

        // The cloth's buffers.
        let particles = model.particle_count();
        let storage = wgpu::BufferUsages::STORAGE;
        let own_positions = buffer_init(
            &device,
            "positions",
            bytemuck::cast_slice(&vec4s(&model.rest)),
            storage | wgpu::BufferUsages::COPY_DST,
        );
        let normals = buffer_init(
            &device,
            "normals",
            &vec![0u8; particles * 16],
            storage | wgpu::BufferUsages::COPY_SRC,
        );
        let uvs = buffer_init(
            &device,
            "uvs",
            bytemuck::cast_slice(&planar_uvs(model)),
            storage,
        );
        let indices = buffer_init(
            &device,
            "indices",
            bytemuck::cast_slice(&model.triangles),
            wgpu::BufferUsages::INDEX,
        );
        let incidence = Incidence::new(particles, &model.triangles);
        let normals_inputs = NormalsInputs {
            params: buffer_init(
                &device,
                "normals params",
                bytemuck::cast_slice(&[particles as u32, 0, 0, 0]),
                wgpu::BufferUsages::UNIFORM,
            ),
            rest: buffer_init(
                &device,
                "rest",
                bytemuck::cast_slice(&vec4s(&model.rest)),
                storage,
            ),
            triangles: buffer_init(
                &device,
                "triangles",
                bytemuck::cast_slice(&model.triangles),
                storage,
            ),
            incidence_start: buffer_init(
                &device,
                "incidence start",
                bytemuck::cast_slice(&incidence.start),
                storage,
            ),
            incidence: buffer_init(
                &device,
                "incidence",
                bytemuck::cast_slice(&incidence.triangles),
                storage,
            ),
        };
        let lines: Option<Vec<Line>> = match settings.view {
            View::Wireframe => Some(wireframe_lines(model)),
            View::Constraints => Some(constraint_lines(model)),
            _ => None,
        };
        let lines = lines.map(|l| {
            let buffer = buffer_init(
                &device,
                "lines",
                bytemuck::cast_slice(&l),
                wgpu::BufferUsages::VERTEX,
            );
            (buffer, l.len() as u32)
        });
        let pin_marker = ColliderMesh::pin_marker(radius * 0.012);
        let pins: Vec<(Vec3, Motion)> = model
            .pins
            .iter()
            .map(|p| (model.rest[p.particle as usize], p.motion))
            .collect();
        let mesh_vertex_count = (ground.len()
            + colliders
                .iter()
                .map(|(m, _)| m.positions.len())
                .sum::<usize>()
            + pins.len() * pin_marker.positions.len()) as u32;
        let mesh_vertices = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("mesh vertices"),
            size: (mesh_vertex_count as u64 * std::mem::size_of::<MeshVertex>() as u64).max(16),
            usage: wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });

        // Textures: the cloth's colour and height, the environment.
        let (fabric_color, fabric_height) = textures::fabric();
        let default_albedo = if is_paper {
            textures::plain(255)
        } else {
            fabric_color
        };
        let default_height = if is_paper {
            textures::plain(128)
        } else {
            fabric_height
        };
        let albedo = upload_texture(
            &device,
            &queue,
            "albedo",
            settings.texture.as_ref().unwrap_or(&default_albedo),
            COLOR_FORMAT,
        );
        let height_map = upload_texture(
            &device,
            &queue,
            "height map",
            settings.height_map.as_ref().unwrap_or(&default_height),
            wgpu::TextureFormat::Rgba8Unorm,
        );
        let material_sampler = device.create_sampler(&wgpu::SamplerDescriptor {
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
        });
        let environment = device
            .create_texture_with_data(
                &queue,
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
                &textures::environment(settings.light.direction),
            )
            .create_view(&wgpu::TextureViewDescriptor {
                dimension: Some(wgpu::TextureViewDimension::Cube),
                ..Default::default()
            });
        let environment_sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("environment"),
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            ..Default::default()
        });
        let shadow_sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("shadow"),
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            compare: Some(wgpu::CompareFunction::LessEqual),
            ..Default::default()
        });
        let targets = Targets::new(&device, width, height, settings.msaa, particles);

        // Layouts and bind groups.
        let vertex = wgpu::ShaderStages::VERTEX;
        let fragment = wgpu::ShaderStages::FRAGMENT;
        let both = vertex | fragment;
        let float = wgpu::TextureSampleType::Float { filterable: true };
        let d2 = wgpu::TextureViewDimension::D2;
        let global_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("globals"),
            entries: &[
                uniform_entry(0, both),
                texture_entry(1, fragment, wgpu::TextureSampleType::Depth, d2),
                sampler_entry(2, fragment, wgpu::SamplerBindingType::Comparison),
                texture_entry(3, fragment, float, wgpu::TextureViewDimension::Cube),
                sampler_entry(4, fragment, wgpu::SamplerBindingType::Filtering),
            ],
        });
        let shadow_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("shadow globals"),
            entries: &[uniform_entry(0, vertex)],
        });
        let layouts = Layouts {
            cloth: device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("cloth"),
                entries: &[
                    storage_entry(0, vertex, true),
                    storage_entry(1, vertex, true),
                    storage_entry(2, vertex, true),
                    texture_entry(3, fragment, float, d2),
                    texture_entry(4, both, float, d2),
                    sampler_entry(5, both, wgpu::SamplerBindingType::Filtering),
                ],
            }),
            lines: device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("lines"),
                entries: &[storage_entry(0, vertex, true)],
            }),
            normals: device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("normals"),
                entries: &[
                    uniform_entry(0, wgpu::ShaderStages::COMPUTE),
                    storage_entry(1, wgpu::ShaderStages::COMPUTE, true),
                    storage_entry(2, wgpu::ShaderStages::COMPUTE, true),
                    storage_entry(3, wgpu::ShaderStages::COMPUTE, true),
                    storage_entry(4, wgpu::ShaderStages::COMPUTE, true),
                    storage_entry(5, wgpu::ShaderStages::COMPUTE, true),
                    storage_entry(6, wgpu::ShaderStages::COMPUTE, false),
                ],
            }),
        };
        let global_bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("globals"),
            layout: &global_layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: globals.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: wgpu::BindingResource::TextureView(&targets.shadow),
                },
                wgpu::BindGroupEntry {
                    binding: 2,
                    resource: wgpu::BindingResource::Sampler(&shadow_sampler),
                },
                wgpu::BindGroupEntry {
                    binding: 3,
                    resource: wgpu::BindingResource::TextureView(&environment),
                },
                wgpu::BindGroupEntry {
                    binding: 4,
                    resource: wgpu::BindingResource::Sampler(&environment_sampler),
                },
            ],
        });
        let shadow_bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("shadow globals"),
            layout: &shadow_layout,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: globals.as_entire_binding(),
            }],
        });
        let pipelines = Pipelines::new(
            &device,
            &global_layout,
            &shadow_layout,
            &layouts,
            settings.msaa,
        );

        Ok(Renderer {
            device,
            queue,
            settings,
            particles,
            index_count: model.triangles.len() as u32 * 3,
            view_proj,
            strain_range,
            is_paper,
            global_bind_group,
            shadow_bind_group,
            own_positions,
            normals,
            uvs,
            indices,
            normals_inputs,
            lines,
            colliders,
            pin_marker,
            pins,
            ground,
            mesh_vertices,
            mesh_vertex_count,
            albedo,
            height_map,
            material_sampler,
            layouts,
            pipelines,
            targets,
        })
    }

    /// The uniforms: `matrices` are the camera's and the light's world to clip.
    fn globals(
        settings: &RenderSettings,
        camera: &Camera,
        [view_proj, light_view_proj]: [Mat4; 2],
        strain_range: f32,
        is_paper: bool,
    ) -> Globals {
        let Light { direction, color } = settings.light;
        let (front, back, bump) = if is_paper {
            (Vec3::new(0.96, 0.95, 0.92), Vec3::new(0.85, 0.3, 0.25), 0.0)
        } else {
            (
                Vec3::new(0.8, 0.22, 0.18),
                Vec3::new(0.92, 0.86, 0.74),
                0.0015,
            )
        };
        let front = settings.front_color.unwrap_or(front);
        let back = settings.back_color.unwrap_or(back);
        let shininess = if is_paper { 24.0 } else { 12.0 };
        let specular = if is_paper { 0.12 } else { 0.08 };
        Globals {
            view_proj: view_proj.to_cols_array_2d(),
            light_view_proj: light_view_proj.to_cols_array_2d(),
            inv_view_proj: view_proj.inverse().to_cols_array_2d(),
            camera_position: camera.position.extend(1.0).to_array(),
            light_direction: (-direction.normalize_or(Vec3::NEG_Y))
                .extend(0.0)
                .to_array(),
            light_color: color.extend(1.0).to_array(),
            front_color: linear(front),
            back_color: linear(back),
            material: [
                settings.bump.unwrap_or(bump),
                settings.displacement,
                strain_range.max(1e-6),
                shininess,
            ],
            misc: [1.0 / SHADOW_SIZE as f32, 2e-4, specular, 0.0],
            mode: [settings.view.index(), u32::from(is_paper), 0, 0],
        }
    }

    /// The device the renderer draws with (for buffers given as [`Positions::Gpu`]).
    pub fn device(&self) -> &wgpu::Device {
        &self.device
    }

    /// The settings it draws with.
    pub fn settings(&self) -> &RenderSettings {
        &self.settings
    }

    /// World to clip space of the pictures.
    pub fn view_proj(&self) -> Mat4 {
        self.view_proj
    }

    /// Where the world point `p` lands in the picture (pixels from the
    /// top-left corner); `None` behind the camera.
    pub fn project(&self, p: Vec3) -> Option<Vec2> {
        project(
            &self.view_proj,
            p,
            self.settings.width,
            self.settings.height,
        )
    }

    /// Draws one frame: the cloth at `positions`, the colliders where
    /// `world` has them now. Returns the picture, with the legend of the
    /// strain and constraint views.
    pub fn render(
        &mut self,
        positions: Positions<'_>,
        world: &World,
    ) -> Result<RgbaImage, RenderError> {
        let positions = match positions {
            Positions::Cpu(x) => {
                if x.len() != self.particles {
                    return Err(RenderError::ParticleCount {
                        got: x.len(),
                        expected: self.particles,
                    });
                }
                if !x.is_empty() {
                    self.queue.write_buffer(
                        &self.own_positions,
                        0,
                        bytemuck::cast_slice(&vec4s(x)),
                    );
                }
                self.own_positions.clone()
            }
            Positions::Gpu(buffer) => {
                let held = (buffer.size() / 16) as usize;
                if held < self.particles {
                    return Err(RenderError::ParticleCount {
                        got: held,
                        expected: self.particles,
                    });
                }
                buffer.clone()
            }
        };
        self.upload_meshes(world);
        let mut encoder = self
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("frame"),
            });
        self.encode(&mut encoder, &positions);
        let strain = self.settings.view == View::Strain && self.particles > 0;
        if strain {
            encoder.copy_buffer_to_buffer(
                &self.normals,
                0,
                &self.targets.strain_readback,
                0,
                self.particles as u64 * 16,
            );
        }
        let mut image = self.targets.read_back(
            &self.device,
            &self.queue,
            encoder,
            self.settings.width,
            self.settings.height,
        )?;
        match self.settings.view {
            View::Strain => {
                let max = if strain {
                    self.targets.max_strain(&self.device, self.particles)?
                } else {
                    0.0
                };
                draw_strain_legend(&mut image, self.strain_range, max);
            }
            View::Constraints => {
                let kinds = if self.is_paper {
                    [&CONSTRAINT_KINDS[3..], &CONSTRAINT_KINDS[..1]].concat()
                } else {
                    CONSTRAINT_KINDS[..3].to_vec()
                };
                draw_constraint_legend(&mut image, &kinds);
            }
            _ => {}
        }
        Ok(image)
    }

    /// Writes the ground, the colliders and the pins, placed at the world's time.
    fn upload_meshes(&self, world: &World) {
        let mut vertices = self.ground.clone();
        let surface = if self.settings.mirror_colliders {
            Surface::Mirror
        } else {
            Surface::Matte
        };
        let placed = world
            .colliders
            .iter()
            .filter(|c| !matches!(c.shape, pleat::collide::Shape::Plane { .. }));
        for ((mesh, color), collider) in self.colliders.iter().zip(placed) {
            let tint = if surface == Surface::Mirror {
                Vec3::splat(0.9)
            } else {
                *color
            };
            let linear_tint = Vec4::from_array(linear(tint)).truncate();
            vertices.extend(mesh.vertices(&collider.pose_at(world.time), linear_tint, surface));
        }
        let pin_color = Vec4::from_array(linear(Vec3::splat(0.15))).truncate();
        for (anchor, motion) in &self.pins {
            let at = motion.pose_at(world.time).transform_point3(*anchor);
            let pose = Affine3A::from_translation(at);
            vertices.extend(self.pin_marker.vertices(&pose, pin_color, Surface::Matte));
        }
        vertices.truncate(self.mesh_vertex_count as usize);
        if !vertices.is_empty() {
            self.queue
                .write_buffer(&self.mesh_vertices, 0, bytemuck::cast_slice(&vertices));
        }
    }

    /// Records the normals, shadow and main passes.
    fn encode(&self, encoder: &mut wgpu::CommandEncoder, positions: &wgpu::Buffer) {
        let n = &self.normals_inputs;
        let normals_group = self.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("normals"),
            layout: &self.layouts.normals,
            entries: &[
                (0, whole(&n.params)),
                (1, whole(positions)),
                (2, whole(&n.rest)),
                (3, whole(&n.triangles)),
                (4, whole(&n.incidence_start)),
                (5, whole(&n.incidence)),
                (6, whole(&self.normals)),
            ]
            .map(|(binding, resource)| wgpu::BindGroupEntry { binding, resource }),
        });
        let cloth_group = self.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("cloth"),
            layout: &self.layouts.cloth,
            entries: &[
                (0, whole(positions)),
                (1, whole(&self.normals)),
                (2, whole(&self.uvs)),
                (3, wgpu::BindingResource::TextureView(&self.albedo)),
                (4, wgpu::BindingResource::TextureView(&self.height_map)),
                (5, wgpu::BindingResource::Sampler(&self.material_sampler)),
            ]
            .map(|(binding, resource)| wgpu::BindGroupEntry { binding, resource }),
        });
        if self.particles > 0 {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("normals"),
                timestamp_writes: None,
            });
            pass.set_pipeline(&self.pipelines.normals);
            pass.set_bind_group(0, &normals_group, &[]);
            pass.dispatch_workgroups((self.particles as u32).div_ceil(NORMALS_WORKGROUP), 1, 1);
        }
        let ground_vertices = self.ground.len() as u32;
        {
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("shadow"),
                color_attachments: &[],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: &self.targets.shadow,
                    depth_ops: Some(wgpu::Operations {
                        load: wgpu::LoadOp::Clear(1.0),
                        store: wgpu::StoreOp::Store,
                    }),
                    stencil_ops: None,
                }),
                ..Default::default()
            });
            pass.set_bind_group(0, &self.shadow_bind_group, &[]);
            pass.set_pipeline(&self.pipelines.meshes_shadow);
            pass.set_vertex_buffer(0, self.mesh_vertices.slice(..));
            pass.draw(ground_vertices..self.mesh_vertex_count, 0..1);
            pass.set_pipeline(&self.pipelines.cloth_shadow);
            pass.set_bind_group(1, &cloth_group, &[]);
            pass.set_index_buffer(self.indices.slice(..), wgpu::IndexFormat::Uint32);
            pass.draw_indexed(0..self.index_count, 0, 0..1);
        }
        let t = &self.targets;
        let resolved = t
            .resolved
            .create_view(&wgpu::TextureViewDescriptor::default());
        let (view, resolve_target) = match &t.color {
            Some(msaa) => (msaa, Some(&resolved)),
            None => (&resolved, None),
        };
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("main"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view,
                depth_slice: None,
                resolve_target,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(wgpu::Color::BLACK),
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &t.depth,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Clear(1.0),
                    store: wgpu::StoreOp::Discard,
                }),
                stencil_ops: None,
            }),
            ..Default::default()
        });
        pass.set_bind_group(0, &self.global_bind_group, &[]);
        pass.set_pipeline(&self.pipelines.sky);
        pass.draw(0..3, 0..1);
        pass.set_pipeline(&self.pipelines.meshes);
        pass.set_vertex_buffer(0, self.mesh_vertices.slice(..));
        pass.draw(0..self.mesh_vertex_count, 0..1);
        pass.set_pipeline(&self.pipelines.cloth);
        pass.set_bind_group(1, &cloth_group, &[]);
        pass.set_index_buffer(self.indices.slice(..), wgpu::IndexFormat::Uint32);
        pass.draw_indexed(0..self.index_count, 0, 0..1);
        if let Some((lines, count)) = &self.lines {
            let lines_group = self.device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("lines"),
                layout: &self.layouts.lines,
                entries: &[wgpu::BindGroupEntry {
                    binding: 0,
                    resource: whole(positions),
                }],
            });
            pass.set_pipeline(&self.pipelines.lines);
            pass.set_bind_group(1, &lines_group, &[]);
            pass.set_vertex_buffer(0, lines.slice(..));
            pass.draw(0..2, 0..*count);
        }
    }
}

impl Targets {
    fn new(device: &wgpu::Device, width: u32, height: u32, msaa: u32, particles: usize) -> Self {
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
                attachment | wgpu::TextureUsages::COPY_SRC,
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
    fn read_back(
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
    fn max_strain(&self, device: &wgpu::Device, particles: usize) -> Result<f32, RenderError> {
        let bytes = map_read(device, &self.strain_readback)?;
        let normals: &[[f32; 4]] = bytemuck::cast_slice(&bytes[..particles * 16]);
        Ok(normals.iter().map(|n| n[3]).fold(0.0, f32::max))
    }
}

fn whole(buffer: &wgpu::Buffer) -> wgpu::BindingResource<'_> {
    buffer.as_entire_binding()
}

/// Maps `buffer` (after its copy was submitted), waits and copies it out.
fn map_read(device: &wgpu::Device, buffer: &wgpu::Buffer) -> Result<Vec<u8>, RenderError> {
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

impl Pipelines {
    fn new(
        device: &wgpu::Device,
        global: &wgpu::BindGroupLayout,
        shadow: &wgpu::BindGroupLayout,
        layouts: &Layouts,
        msaa: u32,
    ) -> Self {
        let module = |label: &str, source: String| {
            device.create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some(label),
                source: wgpu::ShaderSource::Wgsl(source.into()),
            })
        };
        let cloth = module("cloth", shaders::with_common(shaders::CLOTH));
        let lines = module("lines", shaders::with_common(shaders::LINES));
        let meshes = module("meshes", shaders::with_common(shaders::MESHES));
        let normals = module("normals", shaders::NORMALS.to_string());
        let layout = |groups: &[&wgpu::BindGroupLayout]| {
            let groups: Vec<Option<&wgpu::BindGroupLayout>> =
                groups.iter().map(|g| Some(*g)).collect();
            device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: None,
                bind_group_layouts: &groups,
                immediate_size: 0,
            })
        };
        let mesh_attributes =
            wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3, 2 => Float32x4, 3 => Uint32];
        let mesh_buffers = [Some(wgpu::VertexBufferLayout {
            array_stride: std::mem::size_of::<MeshVertex>() as u64,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &mesh_attributes,
        })];
        let line_attributes = wgpu::vertex_attr_array![0 => Uint32x2, 1 => Float32x4];
        let line_buffers = [Some(wgpu::VertexBufferLayout {
            array_stride: std::mem::size_of::<Line>() as u64,
            step_mode: wgpu::VertexStepMode::Instance,
            attributes: &line_attributes,
        })];
        struct Draw<'a> {
            label: &'a str,
            layout: wgpu::PipelineLayout,
            module: &'a wgpu::ShaderModule,
            vertex: &'a str,
            fragment: Option<&'a str>,
            buffers: &'a [Option<wgpu::VertexBufferLayout<'a>>],
            topology: wgpu::PrimitiveTopology,
            depth_write: bool,
            depth_compare: wgpu::CompareFunction,
            samples: u32,
        }
        let pipeline = |d: Draw<'_>| {
            let targets = [Some(wgpu::ColorTargetState {
                format: COLOR_FORMAT,
                blend: None,
                write_mask: wgpu::ColorWrites::ALL,
            })];
            device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some(d.label),
                layout: Some(&d.layout),
                vertex: wgpu::VertexState {
                    module: d.module,
                    entry_point: Some(d.vertex),
                    compilation_options: Default::default(),
                    buffers: d.buffers,
                },
                primitive: wgpu::PrimitiveState {
                    topology: d.topology,
                    cull_mode: None,
                    ..Default::default()
                },
                depth_stencil: Some(wgpu::DepthStencilState {
                    format: DEPTH_FORMAT,
                    depth_write_enabled: Some(d.depth_write),
                    depth_compare: Some(d.depth_compare),
                    stencil: Default::default(),
                    bias: Default::default(),
                }),
                multisample: wgpu::MultisampleState {
                    count: d.samples,
                    ..Default::default()
                },
                fragment: d.fragment.map(|entry| wgpu::FragmentState {
                    module: d.module,
                    entry_point: Some(entry),
                    compilation_options: Default::default(),
                    targets: &targets,
                }),
                multiview_mask: None,
                cache: None,
            })
        };
        let triangles = wgpu::PrimitiveTopology::TriangleList;
        let less = wgpu::CompareFunction::LessEqual;
        Pipelines {
            normals: device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some("normals"),
                layout: Some(&layout(&[&layouts.normals])),
                module: &normals,
                entry_point: Some("main"),
                compilation_options: Default::default(),
                cache: None,
            }),
            cloth: pipeline(Draw {
                label: "cloth",
                layout: layout(&[global, &layouts.cloth]),
                module: &cloth,
                vertex: "vs_main",
                fragment: Some("fs_main"),
                buffers: &[],
                topology: triangles,
                depth_write: true,
                depth_compare: less,
                samples: msaa,
            }),
            cloth_shadow: pipeline(Draw {
                label: "cloth shadow",
                layout: layout(&[shadow, &layouts.cloth]),
                module: &cloth,
                vertex: "vs_shadow",
                fragment: None,
                buffers: &[],
                topology: triangles,
                depth_write: true,
                depth_compare: less,
                samples: 1,
            }),
            meshes: pipeline(Draw {
                label: "meshes",
                layout: layout(&[global]),
                module: &meshes,
                vertex: "vs_main",
                fragment: Some("fs_main"),
                buffers: &mesh_buffers,
                topology: triangles,
                depth_write: true,
                depth_compare: less,
                samples: msaa,
            }),
            meshes_shadow: pipeline(Draw {
                label: "meshes shadow",
                layout: layout(&[shadow]),
                module: &meshes,
                vertex: "vs_shadow",
                fragment: None,
                buffers: &mesh_buffers,
                topology: triangles,
                depth_write: true,
                depth_compare: less,
                samples: 1,
            }),
            sky: pipeline(Draw {
                label: "sky",
                layout: layout(&[global]),
                module: &meshes,
                vertex: "vs_sky",
                fragment: Some("fs_sky"),
                buffers: &[],
                topology: triangles,
                depth_write: false,
                depth_compare: wgpu::CompareFunction::Always,
                samples: msaa,
            }),
            lines: pipeline(Draw {
                label: "lines",
                layout: layout(&[global, &layouts.lines]),
                module: &lines,
                vertex: "vs_main",
                fragment: Some("fs_main"),
                buffers: &line_buffers,
                topology: wgpu::PrimitiveTopology::LineList,
                depth_write: true,
                depth_compare: less,
                samples: msaa,
            }),
        }
    }
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

    #[test]
    fn globals_match_the_wgsl_layout() {
        // Three matrices, eight vec4s.
        assert_eq!(std::mem::size_of::<Globals>(), 3 * 64 + 8 * 16);
    }

    #[test]
    fn vertex_layouts_match_the_shaders() {
        assert_eq!(std::mem::size_of::<MeshVertex>(), 48);
        assert_eq!(std::mem::size_of::<Line>(), 24);
    }
}
