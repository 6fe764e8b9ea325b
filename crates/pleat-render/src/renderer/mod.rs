//! The renderer: one frame drawn offscreen and read back as an RGBA image.
//! What it draws around the cloth and where from is worked out in `stage`,
//! its GPU resources are made in `resources`, its pipelines and bind
//! groups in `pipelines`, and it draws into and reads back from `targets`.
//!
//! A frame is a compute pass (smooth normals and edge strain from the
//! positions), a shadow pass (depth from the light), and a multisampled
//! main pass: the sky (environment cube map), the ground and colliders,
//! the cloth, and the lines of the wireframe or constraint view. Positions
//! come from a CPU slice (uploaded to the renderer's own buffer) or from a
//! caller's storage buffer on the same device (the GPU backend's), read
//! where it is: they never come back to the CPU.

use crate::camera::{face_on_axis, project, Camera, Light};
use crate::error::RenderError;
use crate::geometry::CONSTRAINT_KINDS;
use crate::legend::{draw_constraint_legend, draw_strain_legend};
use crate::settings::{RenderSettings, View};
use bytemuck::{Pod, Zeroable};
use glam::{Mat4, Vec2, Vec3};
use image::RgbaImage;
use pipelines::{GlobalGroups, Layouts, Pipelines};
use pleat::{Model, World};
use resources::{buffer_init, linear, vec4s, whole, ClothBuffers, Material};
use stage::Stage;
use targets::Targets;

mod pipelines;
mod resources;
mod stage;
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
    globals: wgpu::Buffer,
    strain_range: f32,
    /// The model holds paper (crease patterns): paper colours and constraint
    /// kinds, and (unless the settings place the camera) a camera that
    /// follows the paper face-on.
    is_paper: bool,
    /// Paper alone (no collider but planes): the camera follows the paper
    /// face-on unless the settings place it.
    paper_alone: bool,
    /// The axis the last face-on framing looked along.
    face_on: Option<Vec3>,
    /// The paper's triangles, whose normals the face-on framing follows
    /// (empty unless the model is paper alone).
    paper_triangles: Vec<[u32; 3]>,
    global_groups: GlobalGroups,
    cloth: ClothBuffers,
    lines: Option<(wgpu::Buffer, u32)>,
    /// The colliders, the ground and the pins, and the light.
    stage: Stage,
    mesh_vertices: wgpu::Buffer,
    mesh_vertex_count: u32,
    material: Material,
    layouts: Layouts,
    pipelines: Pipelines,
    targets: Targets,
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
        check_size(&device, &settings)?;
        let stage = Stage::new(model, world, &settings);
        let aspect = settings.width as f32 / settings.height as f32;
        let is_paper = model.cloths.iter().any(|c| c.paper.is_some());
        let paper_alone = is_paper
            && world
                .colliders
                .iter()
                .all(|c| matches!(c.shape, pleat::collide::Shape::Plane { .. }));
        let face_on = (paper_alone && settings.camera.is_none())
            .then(|| face_on_axis(&model.rest, &model.triangles, None))
            .flatten();
        let camera = face_on
            .and_then(|axis| Camera::facing(&model.rest, axis, aspect))
            .unwrap_or_else(|| stage.camera(&settings, aspect));
        let view_proj = camera.view_proj(aspect, stage.radius);
        let strain_range = settings
            .strain_range
            .unwrap_or(if is_paper { 0.02 } else { 0.1 });
        let globals = Self::globals(
            &settings,
            &camera,
            [view_proj, stage.light_view_proj],
            strain_range,
            is_paper,
        );
        let globals = buffer_init(
            &device,
            "globals",
            bytemuck::bytes_of(&globals),
            wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        );
        let particles = model.particle_count();
        let targets = Targets::new(
            &device,
            settings.width,
            settings.height,
            settings.msaa,
            particles,
        );
        let layouts = Layouts::new(&device);
        let environment = resources::environment(&device, &queue, settings.light.direction);
        let global_groups =
            GlobalGroups::new(&device, &layouts, &globals, &targets.shadow, &environment);
        let mesh_vertex_count = stage.mesh_vertex_count();
        Ok(Renderer {
            particles,
            index_count: model.triangles.len() as u32 * 3,
            camera,
            view_proj,
            globals,
            strain_range,
            is_paper,
            paper_alone,
            face_on,
            paper_triangles: if paper_alone {
                model.triangles.clone()
            } else {
                Vec::new()
            },
            global_groups,
            cloth: ClothBuffers::new(&device, model),
            lines: resources::line_buffer(&device, model, settings.view),
            stage,
            mesh_vertices: resources::mesh_vertex_buffer(&device, mesh_vertex_count),
            mesh_vertex_count,
            material: Material::new(&device, &queue, &settings, is_paper),
            pipelines: Pipelines::new(&device, &layouts, settings.msaa),
            layouts,
            targets,
            device,
            queue,
            settings,
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
                &self.cloth.normals,
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
        if let Positions::Cpu(x) = positions {
            self.frame_paper(x);
        }
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

    /// Whether the camera follows the paper: the model holds paper, the
    /// world no collider but planes, and the settings do not place the camera. Then [`Renderer::frame_paper`]
    /// frames each picture, which [`Renderer::render`] and
    /// [`Renderer::draw`] do by themselves with positions on the CPU.
    pub fn follows_paper(&self) -> bool {
        self.paper_alone && self.settings.camera.is_none()
    }

    /// Frames `points` (the paper as it is now) face-on, when the camera
    /// follows the paper: it looks along the way most of the paper's area
    /// faces, tilted a little, from as close as shows it all. The axis of
    /// the last framing is kept while nearly as much faces it (no flipping
    /// between two near-equal ways).
    pub fn frame_paper(&mut self, points: &[Vec3]) {
        if !self.follows_paper() || points.len() != self.particles {
            return;
        }
        let aspect = self.settings.width as f32 / self.settings.height as f32;
        let Some(axis) = face_on_axis(points, &self.paper_triangles, self.face_on) else {
            return;
        };
        if let Some(camera) = Camera::facing(points, axis, aspect) {
            self.face_on = Some(axis);
            self.camera = camera;
            self.write_globals();
        }
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
        self.view_proj = self.camera.view_proj(aspect, self.stage.radius);
        let globals = Self::globals(
            &self.settings,
            &self.camera,
            [self.view_proj, self.stage.light_view_proj],
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
                        &self.cloth.own_positions,
                        0,
                        bytemuck::cast_slice(&vec4s(x)),
                    );
                }
                self.cloth.own_positions.clone()
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
        let vertices = self.stage.vertices(world, self.settings.mirror_colliders);
        if !vertices.is_empty() {
            self.queue
                .write_buffer(&self.mesh_vertices, 0, bytemuck::cast_slice(&vertices));
        }
    }

    /// Records the normals, shadow and main passes.
    fn encode(&self, encoder: &mut wgpu::CommandEncoder, positions: &wgpu::Buffer) {
        let n = &self.cloth.normals_inputs;
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
                (6, whole(&self.cloth.normals)),
            ]
            .map(|(binding, resource)| wgpu::BindGroupEntry { binding, resource }),
        });
        let cloth_group = self.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("cloth"),
            layout: &self.layouts.cloth,
            entries: &[
                (0, whole(positions)),
                (1, whole(&self.cloth.normals)),
                (2, whole(&self.cloth.uvs)),
                (3, wgpu::BindingResource::TextureView(&self.material.albedo)),
                (
                    4,
                    wgpu::BindingResource::TextureView(&self.material.height_map),
                ),
                (5, wgpu::BindingResource::Sampler(&self.material.sampler)),
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
        let ground_vertices = self.stage.ground.len() as u32;
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
            pass.set_bind_group(0, &self.global_groups.shadow, &[]);
            pass.set_pipeline(&self.pipelines.meshes_shadow);
            pass.set_vertex_buffer(0, self.mesh_vertices.slice(..));
            pass.draw(ground_vertices..self.mesh_vertex_count, 0..1);
            pass.set_pipeline(&self.pipelines.cloth_shadow);
            pass.set_bind_group(1, &cloth_group, &[]);
            pass.set_index_buffer(self.cloth.indices.slice(..), wgpu::IndexFormat::Uint32);
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
        pass.set_bind_group(0, &self.global_groups.main, &[]);
        pass.set_pipeline(&self.pipelines.sky);
        pass.draw(0..3, 0..1);
        pass.set_pipeline(&self.pipelines.meshes);
        pass.set_vertex_buffer(0, self.mesh_vertices.slice(..));
        pass.draw(0..self.mesh_vertex_count, 0..1);
        pass.set_bind_group(1, &cloth_group, &[]);
        pass.set_index_buffer(self.cloth.indices.slice(..), wgpu::IndexFormat::Uint32);
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

/// Refuses a picture size the device cannot draw and a sample count other
/// than 1 or 4.
fn check_size(device: &wgpu::Device, settings: &RenderSettings) -> Result<(), RenderError> {
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
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{Line, MeshVertex};

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
        // Position, normal, colour, body-frame point, kind: 12 + 12 + 16 + 12 + 4.
        assert_eq!(std::mem::size_of::<MeshVertex>(), 56);
        assert_eq!(std::mem::size_of::<Line>(), 24);
    }
}
