//! The renderer: one frame drawn offscreen and read back as an RGBA image.
//! Its GPU resources are made in `resources`, its pipelines in `pipelines`,
//! and it draws into and reads back from `targets`.
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
use crate::textures::{self, ENVIRONMENT_SIZE};
use bytemuck::{Pod, Zeroable};
use glam::{Affine3A, Mat4, Vec2, Vec3, Vec4};
use image::RgbaImage;
use pipelines::{Layouts, Pipelines};
use pleat::collide::Motion;
use pleat::{Model, World};
use resources::{buffer_init, linear, upload_texture, vec4s, whole};
use targets::Targets;
use wgpu::util::DeviceExt;

mod pipelines;
mod resources;
mod targets;

pub use resources::{headless_device, Headless};

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

/// Draws frames of one model (its cloths) and world (its colliders).
pub struct Renderer {
    device: wgpu::Device,
    queue: wgpu::Queue,
    settings: RenderSettings,
    particles: usize,
    index_count: u32,
    camera: Camera,
    view_proj: Mat4,
    light_view_proj: Mat4,
    /// Radius of the scene's bounding sphere: where the near and far planes go.
    radius: f32,
    globals: wgpu::Buffer,
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
            wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
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

        let layouts = Layouts::new(&device);
        let global_bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("globals"),
            layout: &layouts.global,
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
            layout: &layouts.shadow,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: globals.as_entire_binding(),
            }],
        });
        let pipelines = Pipelines::new(&device, &layouts, settings.msaa);

        Ok(Renderer {
            device,
            queue,
            settings,
            particles,
            index_count: model.triangles.len() as u32 * 3,
            camera,
            view_proj,
            light_view_proj,
            radius,
            globals,
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
        let mut encoder = self.encode_frame(positions, world)?;
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
            View::Constraints => draw_constraint_legend(&mut image, &self.constraint_kinds()),
            _ => {}
        }
        Ok(image)
    }

    /// Draws one frame into [`Renderer::picture`] and submits it without
    /// reading it back: for a window that shows the texture (the app),
    /// where waiting for the pixels would stall (WebGPU cannot wait at all).
    /// Legends are the window's to draw.
    pub fn draw(&mut self, positions: Positions<'_>, world: &World) -> Result<(), RenderError> {
        let encoder = self.encode_frame(positions, world)?;
        self.queue.submit([encoder.finish()]);
        Ok(())
    }

    /// Uploads the frame's meshes and records its passes.
    fn encode_frame(
        &mut self,
        positions: Positions<'_>,
        world: &World,
    ) -> Result<wgpu::CommandEncoder, RenderError> {
        let positions = self.positions_buffer(positions)?;
        self.upload_meshes(world);
        let mut encoder = self
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("frame"),
            });
        self.encode(&mut encoder, &positions);
        Ok(encoder)
    }

    /// The texture frames are drawn into (sRGB, `width` x `height`, can be
    /// sampled): the picture of the last [`Renderer::draw`].
    pub fn picture(&self) -> &wgpu::Texture {
        &self.targets.resolved
    }

    /// The constraint kinds the constraint view colours (name, linear RGB),
    /// in legend order.
    pub fn constraint_kinds(&self) -> Vec<(&'static str, [f32; 3])> {
        if self.is_paper {
            [&CONSTRAINT_KINDS[3..], &CONSTRAINT_KINDS[..1]].concat()
        } else {
            CONSTRAINT_KINDS[..3].to_vec()
        }
    }

    /// Strain drawn full red in the strain view.
    pub fn strain_range(&self) -> f32 {
        self.strain_range
    }

    /// The camera frames are drawn from.
    pub fn camera(&self) -> Camera {
        self.camera
    }

    /// Moves the camera: later frames are drawn from `camera` (the app's orbit).
    pub fn set_camera(&mut self, camera: Camera) {
        self.camera = camera;
        self.settings.camera = Some(camera);
        self.write_globals();
    }

    /// Changes the picture's size (a window resized).
    pub fn resize(&mut self, width: u32, height: u32) -> Result<(), RenderError> {
        let max = self.device.limits().max_texture_dimension_2d;
        if !(1..=max).contains(&width) || !(1..=max).contains(&height) {
            return Err(RenderError::Size { width, height, max });
        }
        if (width, height) != (self.settings.width, self.settings.height) {
            self.settings.width = width;
            self.settings.height = height;
            let mut targets = Targets::new(
                &self.device,
                width,
                height,
                self.settings.msaa,
                self.particles,
            );
            // The global bind group samples this shadow map: keep it.
            targets.shadow = self.targets.shadow.clone();
            self.targets = targets;
            self.write_globals();
        }
        Ok(())
    }

    /// Recomputes the camera's matrix and writes the uniforms.
    fn write_globals(&mut self) {
        let aspect = self.settings.width as f32 / self.settings.height as f32;
        self.view_proj = self.camera.view_proj(aspect, self.radius);
        let globals = Self::globals(
            &self.settings,
            &self.camera,
            [self.view_proj, self.light_view_proj],
            self.strain_range,
            self.is_paper,
        );
        self.queue
            .write_buffer(&self.globals, 0, bytemuck::bytes_of(&globals));
    }

    /// The buffer that holds `positions`, after checking it fits the model.
    fn positions_buffer(&self, positions: Positions<'_>) -> Result<wgpu::Buffer, RenderError> {
        Ok(match positions {
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
                if !buffer.usage().contains(wgpu::BufferUsages::STORAGE) {
                    return Err(RenderError::Setting(
                        "the position buffer needs BufferUsages::STORAGE".into(),
                    ));
                }
                let held = (buffer.size() / 16) as usize;
                if held < self.particles {
                    return Err(RenderError::ParticleCount {
                        got: held,
                        expected: self.particles,
                    });
                }
                buffer.clone()
            }
        })
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
        pass.set_bind_group(1, &cloth_group, &[]);
        pass.set_index_buffer(self.indices.slice(..), wgpu::IndexFormat::Uint32);
        for pipeline in [&self.pipelines.cloth_back, &self.pipelines.cloth_front] {
            pass.set_pipeline(pipeline);
            pass.draw_indexed(0..self.index_count, 0, 0..1);
        }
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

#[cfg(test)]
mod tests {
    use super::*;

    /// The WGSL struct `name` of `source`: its size as naga lays it out,
    /// and its members' names and offsets.
    fn wgsl_struct(source: &str, name: &str) -> (usize, Vec<(String, usize)>) {
        let module = naga::front::wgsl::parse_str(source).expect("parses");
        let mut layouter = naga::proc::Layouter::default();
        layouter.update(module.to_ctx()).expect("naga lays it out");
        let (handle, ty) = module
            .types
            .iter()
            .find(|(_, t)| t.name.as_deref() == Some(name))
            .unwrap_or_else(|| panic!("no struct {name}"));
        let naga::TypeInner::Struct { members, .. } = &ty.inner else {
            panic!("{name} is not a struct");
        };
        let members = members.iter().map(|m| {
            let name = m.name.clone().unwrap_or_default();
            (name, m.offset as usize)
        });
        (layouter[handle].size as usize, members.collect())
    }

    /// Globals has the size and field offsets naga computes for
    /// common.wgsl's Globals. The pattern lists every Rust field, so one
    /// added on the Rust side alone stops the build; one added in WGSL
    /// alone fails the comparison.
    #[test]
    fn globals_match_the_wgsl_layout() {
        macro_rules! fields {
            ($($field:ident),+) => {{
                let Globals { $($field: _),+ } = Globals::zeroed();
                vec![$((stringify!($field).to_string(), std::mem::offset_of!(Globals, $field))),+]
            }};
        }
        let rust = fields!(
            view_proj,
            light_view_proj,
            inv_view_proj,
            camera_position,
            light_direction,
            light_color,
            front_color,
            back_color,
            material,
            misc,
            mode
        );
        let (size, wgsl) = wgsl_struct(crate::shaders::COMMON, "Globals");
        assert_eq!(
            wgsl, rust,
            "Globals: WGSL (left) and Rust (right) members and offsets"
        );
        assert_eq!(
            size,
            std::mem::size_of::<Globals>(),
            "Globals: WGSL and Rust sizes"
        );
        // The normals pass's uniform is the particle count in a [u32; 4].
        let (size, wgsl) = wgsl_struct(crate::shaders::NORMALS, "Counts");
        let counts = vec![("counts".to_string(), 0)];
        assert_eq!((size, wgsl), (std::mem::size_of::<[u32; 4]>(), counts));
    }

    #[test]
    fn vertex_layouts_match_the_shaders() {
        assert_eq!(std::mem::size_of::<MeshVertex>(), 48);
        assert_eq!(std::mem::size_of::<Line>(), 24);
    }
}
