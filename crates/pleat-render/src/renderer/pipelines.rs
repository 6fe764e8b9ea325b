//! The render and compute pipelines, the bind-group layouts of the
//! passes, and the bind groups of the per-frame uniforms.

use super::resources::{sampler_entry, storage_entry, texture_entry, uniform_entry};
use super::{COLOR_FORMAT, DEPTH_FORMAT};
use crate::geometry::{Line, MeshVertex};
use crate::shaders;

/// Bind-group layouts: group 0 of the main pass (`global`) and of the
/// shadow pass (`shadow`), group 1 of the cloth and of the lines, and the
/// normals pass.
pub(super) struct Layouts {
    pub(super) global: wgpu::BindGroupLayout,
    pub(super) shadow: wgpu::BindGroupLayout,
    pub(super) cloth: wgpu::BindGroupLayout,
    pub(super) lines: wgpu::BindGroupLayout,
    pub(super) normals: wgpu::BindGroupLayout,
}

impl Layouts {
    pub(super) fn new(device: &wgpu::Device) -> Self {
        let vertex = wgpu::ShaderStages::VERTEX;
        let fragment = wgpu::ShaderStages::FRAGMENT;
        let both = vertex | fragment;
        let float = wgpu::TextureSampleType::Float { filterable: true };
        let d2 = wgpu::TextureViewDimension::D2;
        let global = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("globals"),
            entries: &[
                uniform_entry(0, both),
                texture_entry(1, fragment, wgpu::TextureSampleType::Depth, d2),
                sampler_entry(2, fragment, wgpu::SamplerBindingType::Comparison),
                texture_entry(3, fragment, float, wgpu::TextureViewDimension::Cube),
                sampler_entry(4, fragment, wgpu::SamplerBindingType::Filtering),
            ],
        });
        let shadow = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("shadow globals"),
            entries: &[uniform_entry(0, vertex)],
        });
        Layouts {
            global,
            shadow,
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
        }
    }
}

/// Group 0 of the main pass and of the shadow pass: the uniforms `globals`,
/// with the shadow map and the environment (view, sampler) in the main pass.
pub(super) struct GlobalGroups {
    pub(super) main: wgpu::BindGroup,
    pub(super) shadow: wgpu::BindGroup,
}

impl GlobalGroups {
    pub(super) fn new(
        device: &wgpu::Device,
        layouts: &Layouts,
        globals: &wgpu::Buffer,
        shadow_map: &wgpu::TextureView,
        (environment, environment_sampler): &(wgpu::TextureView, wgpu::Sampler),
    ) -> Self {
        let shadow_sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("shadow"),
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            compare: Some(wgpu::CompareFunction::LessEqual),
            ..Default::default()
        });
        let main = [
            (0, globals.as_entire_binding()),
            (1, wgpu::BindingResource::TextureView(shadow_map)),
            (2, wgpu::BindingResource::Sampler(&shadow_sampler)),
            (3, wgpu::BindingResource::TextureView(environment)),
            (4, wgpu::BindingResource::Sampler(environment_sampler)),
        ]
        .map(|(binding, resource)| wgpu::BindGroupEntry { binding, resource });
        GlobalGroups {
            main: device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("globals"),
                layout: &layouts.global,
                entries: &main,
            }),
            shadow: device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("shadow globals"),
                layout: &layouts.shadow,
                entries: &[wgpu::BindGroupEntry {
                    binding: 0,
                    resource: globals.as_entire_binding(),
                }],
            }),
        }
    }
}

/// Depth bias of the cloth's front faces: a flat fold lays layers of paper
/// in one plane, and a sheet without thickness has no order for them, so
/// coplanar front and back faces would fight pixel by pixel (stripes of
/// the two paper colours). Where they coincide, the face turned toward the
/// camera is drawn. Slope-scaled, so a layer seen at a grazing angle
/// still wins; a few depth units otherwise, far below the gap between
/// layers that are apart.
const FRONT_FACES_FIRST: wgpu::DepthBiasState = wgpu::DepthBiasState {
    constant: -4,
    slope_scale: -1.0,
    clamp: 0.0,
};

/// Every pipeline a frame uses.
pub(super) struct Pipelines {
    pub(super) normals: wgpu::ComputePipeline,
    /// The cloth's faces turned toward the camera, drawn a little nearer
    /// than they are ([`FRONT_FACES_FIRST`]), and those turned away.
    pub(super) cloth_front: wgpu::RenderPipeline,
    pub(super) cloth_back: wgpu::RenderPipeline,
    pub(super) cloth_shadow: wgpu::RenderPipeline,
    pub(super) meshes: wgpu::RenderPipeline,
    pub(super) meshes_shadow: wgpu::RenderPipeline,
    pub(super) sky: wgpu::RenderPipeline,
    pub(super) lines: wgpu::RenderPipeline,
}

impl Pipelines {
    /// The pipelines, drawing with `msaa` samples per pixel.
    pub(super) fn new(device: &wgpu::Device, layouts: &Layouts, msaa: u32) -> Self {
        let (global, shadow) = (&layouts.global, &layouts.shadow);
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
        let mesh_attributes = wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3, 2 => Float32x4, 3 => Float32x3, 4 => Uint32];
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
            cull_mode: Option<wgpu::Face>,
            bias: wgpu::DepthBiasState,
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
                    cull_mode: d.cull_mode,
                    ..Default::default()
                },
                depth_stencil: Some(wgpu::DepthStencilState {
                    format: DEPTH_FORMAT,
                    depth_write_enabled: Some(d.depth_write),
                    depth_compare: Some(d.depth_compare),
                    stencil: Default::default(),
                    bias: d.bias,
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
        let cloth_draw = || Draw {
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
            cull_mode: None,
            bias: Default::default(),
        };
        Pipelines {
            normals: device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some("normals"),
                layout: Some(&layout(&[&layouts.normals])),
                module: &normals,
                entry_point: Some("main"),
                compilation_options: Default::default(),
                cache: None,
            }),
            cloth_front: pipeline(Draw {
                label: "cloth front faces",
                cull_mode: Some(wgpu::Face::Back),
                bias: FRONT_FACES_FIRST,
                ..cloth_draw()
            }),
            cloth_back: pipeline(Draw {
                label: "cloth back faces",
                cull_mode: Some(wgpu::Face::Front),
                ..cloth_draw()
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
                cull_mode: None,
                bias: Default::default(),
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
                cull_mode: None,
                bias: Default::default(),
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
                cull_mode: None,
                bias: Default::default(),
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
                cull_mode: None,
                bias: Default::default(),
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
                cull_mode: None,
                bias: Default::default(),
            }),
        }
    }
}
