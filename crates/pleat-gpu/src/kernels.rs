//! The compute pipelines and the two bind group layouts they share:
//! group 0 the particle state, the substep's parameters and the live
//! compliance table, group 1 a
//! kernel's own buffers (four storage buffers) and the slice it works on.

use crate::data::{Params, Range};
use crate::shaders::{self, Module};
use std::borrow::Cow;

/// Invocations per workgroup in every kernel (`WORKGROUP` in common.wgsl).
pub const WORKGROUP: u32 = 256;
/// Most workgroups along one dimension of a dispatch (WebGPU's default limit).
const MAX_GROUPS: u32 = 65535;
/// Stride of dynamic uniform offsets (WebGPU's default alignment).
pub const UNIFORM_STRIDE: u64 = 256;
/// Slots of the live compliance table (`compliances` in common.wgsl).
pub const COMPLIANCE_SLOTS: usize = 1024;

/// Workgroups for `count` invocations: along x, then rows of x along y.
pub fn workgroups(count: u32) -> (u32, u32) {
    let groups = count.div_ceil(WORKGROUP);
    if groups <= MAX_GROUPS {
        (groups, 1)
    } else {
        (MAX_GROUPS, groups.div_ceil(MAX_GROUPS))
    }
}

/// Sweeps of a round of the held strain limits where the paper has
/// self-contacts, each round's motion then checked by the contacts: one,
/// where the CPU backend's rounds are of ten, since the GPU's edge pairs
/// have no continuous detection. Origami Simulator's whirlpool twist,
/// folded on the GPU, crossed itself twice as its limits tightened with
/// rounds of three (each contact's corrections scaled as one,
/// lib/contact_solve.wgsl); with one, not. Rounds that move nothing solve
/// no contact (contact_dispatch.wgsl's `arm_round_solve`).
pub const HOLD_ROUND_SWEEPS: u32 = 1;

/// The kernels of the distances' strain limits alone (distance.wgsl).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DistanceLimit {
    /// One sweep, a dispatch per colour.
    Sweep,
    /// The sweep that notes whether an edge is beyond the slack.
    Measured,
    /// The further sweeps, in one workgroup that stops itself.
    Further,
    /// The held limits met, in one workgroup.
    Held,
    /// One round of the held limits' sweeps, in one workgroup, where the
    /// paper has self-contacts to check each round.
    HeldRound,
    /// Every sweep of a substep, in one workgroup.
    Alone,
}

impl DistanceLimit {
    pub const ALL: [DistanceLimit; 6] = [
        DistanceLimit::Sweep,
        DistanceLimit::Measured,
        DistanceLimit::Further,
        DistanceLimit::Held,
        DistanceLimit::HeldRound,
        DistanceLimit::Alone,
    ];

    /// Its entry point in distance.wgsl.
    pub fn entry_point(self) -> &'static str {
        match self {
            DistanceLimit::Sweep => "limit",
            DistanceLimit::Measured => "limit_measured",
            DistanceLimit::Further => "limit_further",
            DistanceLimit::Held => "limit_held",
            DistanceLimit::HeldRound => "limit_held_round",
            DistanceLimit::Alone => "limit_alone",
        }
    }
}

/// Every pipeline of the backend.
pub struct Kernels {
    pub state_layout: wgpu::BindGroupLayout,
    pub kernel_layout: wgpu::BindGroupLayout,
    pub predict: wgpu::ComputePipeline,
    pub update_velocities: wgpu::ComputePipeline,
    pub grab: wgpu::ComputePipeline,
    pub place_pins: wgpu::ComputePipeline,
    pub triangle_forces: wgpu::ComputePipeline,
    pub gather: wgpu::ComputePipeline,
    pub resolve: wgpu::ComputePipeline,
    pub distance: wgpu::ComputePipeline,
    /// The distances' strain limits alone (hard, no multipliers), indexed
    /// by [`DistanceLimit`].
    pub distance_limit: [wgpu::ComputePipeline; DistanceLimit::ALL.len()],
    pub bending: wgpu::ComputePipeline,
    pub isometric: wgpu::ComputePipeline,
    pub hinge: wgpu::ComputePipeline,
    pub track: wgpu::ComputePipeline,
    pub tether: wgpu::ComputePipeline,
    /// The hierarchy: the positions noted, a level's coarse edges, its prolongation.
    pub snapshot: wgpu::ComputePipeline,
    pub long_range: wgpu::ComputePipeline,
    pub prolongate: wgpu::ComputePipeline,
    /// The grabbed particle's reach over its cloth (XPBD).
    pub grab_reach: wgpu::ComputePipeline,
    pub attachment: wgpu::ComputePipeline,
    pub jacobi_correct: wgpu::ComputePipeline,
    pub jacobi_gather: wgpu::ComputePipeline,
    /// The health reduction: per workgroup, then over the workgroups.
    pub health: [wgpu::ComputePipeline; 2],
    /// The free cloths' turn: sums per workgroup, the turn, its application.
    pub momentum: [wgpu::ComputePipeline; 3],
    pub self_contact: SelfContactKernels,
}

/// Kernels of a self-contact build (contact_grid.wgsl's after `bound` and
/// `check`), dispatched indirectly.
pub const BUILD_KERNELS: usize = 7;

/// The self-contact kernels.
#[derive(Clone)]
pub struct SelfContactKernels {
    /// `bound` and `check`, then the build's in the order they run:
    /// clear, count, scan_blocks, scan_sums, scan_add, scatter, find.
    pub grid: [wgpu::ComputePipeline; 2 + BUILD_KERNELS],
    /// The edge pairs of a build, after `find` on `find`'s workgroups,
    /// where the model has paper (find_edges).
    pub find_edges: wgpu::ComputePipeline,
    /// The indirect dispatches' counts, arm_build and arm_solve, the
    /// margin after a frame, choose_margin, and the solve's counts in a
    /// round of the held limits, arm_round_solve.
    pub arm: [wgpu::ComputePipeline; 4],
    /// The solve, each contact's corrections scaled as one (paper's).
    pub scaled: ContactSolve,
    /// The solve, each particle's corrections averaged (cloth's).
    pub averaged: ContactSolve,
}

/// The kernels of a Jacobi iteration over the candidates (self_contact.wgsl).
#[derive(Clone)]
pub struct ContactSolve {
    /// The first pass, counting per particle the contacts that move it
    /// (the scaled solve's alone).
    pub count: Option<wgpu::ComputePipeline>,
    /// The contacts' corrections summed.
    pub contacts: wgpu::ComputePipeline,
    /// The same, counting the contacts that acted (a substep's last).
    pub counted_contacts: wgpu::ComputePipeline,
    /// Each particle moved by its corrections.
    pub apply: wgpu::ComputePipeline,
}

/// The pipelines of the first `N` entry points of `module`, in its order.
fn entries<const N: usize>(
    module: Module,
    make: impl Fn(Module, &str) -> wgpu::ComputePipeline,
) -> [wgpu::ComputePipeline; N] {
    std::array::from_fn(|k| make(module, module.entry_points[k]))
}

pub(crate) fn storage(binding: u32) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Storage { read_only: false },
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    }
}

fn dynamic_uniform(binding: u32, size: usize) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Uniform,
            has_dynamic_offset: true,
            min_binding_size: wgpu::BufferSize::new(size as u64),
        },
        count: None,
    }
}

impl Kernels {
    pub fn new(device: &wgpu::Device) -> Self {
        let state_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("state"),
            entries: &[
                storage(0),
                storage(1),
                storage(2),
                dynamic_uniform(3, size_of::<Params>()),
                wgpu::BindGroupLayoutEntry {
                    binding: 4,
                    visibility: wgpu::ShaderStages::COMPUTE,
                    ty: wgpu::BindingType::Buffer {
                        ty: wgpu::BufferBindingType::Uniform,
                        has_dynamic_offset: false,
                        min_binding_size: wgpu::BufferSize::new(COMPLIANCE_SLOTS as u64 * 4),
                    },
                    count: None,
                },
            ],
        });
        let kernel_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("kernel"),
            entries: &[
                storage(0),
                storage(1),
                storage(2),
                storage(3),
                dynamic_uniform(4, size_of::<Range>()),
            ],
        });
        let state_only = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("state only"),
            bind_group_layouts: &[Some(&state_layout)],
            immediate_size: 0,
        });
        let with_kernel = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("state and kernel"),
            bind_group_layouts: &[Some(&state_layout), Some(&kernel_layout)],
            immediate_size: 0,
        });
        let modules: Vec<(Module, wgpu::ShaderModule)> = shaders::ALL
            .iter()
            .map(|m| {
                let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
                    label: Some(m.name),
                    source: wgpu::ShaderSource::Wgsl(Cow::Owned(m.source())),
                });
                (*m, module)
            })
            .collect();
        let pipeline = |m: Module, entry: &str, layout: &wgpu::PipelineLayout| {
            let (_, module) = modules
                .iter()
                .find(|(k, _)| *k == m)
                .expect("every module is compiled");
            device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(entry),
                layout: Some(layout),
                module,
                entry_point: Some(entry),
                compilation_options: Default::default(),
                cache: None,
            })
        };
        let contact = |entry| pipeline(shaders::SELF_CONTACT, entry, &with_kernel);
        Kernels {
            predict: pipeline(shaders::PREDICT, "predict", &state_only),
            update_velocities: pipeline(shaders::PREDICT, "update_velocities", &state_only),
            grab: pipeline(shaders::PREDICT, "grab", &state_only),
            place_pins: pipeline(shaders::PINS, "place_pins", &with_kernel),
            triangle_forces: pipeline(shaders::WIND, "triangle_forces", &with_kernel),
            gather: pipeline(shaders::WIND, "gather", &with_kernel),
            resolve: pipeline(shaders::COLLIDE, "resolve", &with_kernel),
            distance: pipeline(shaders::DISTANCE, "solve", &with_kernel),
            distance_limit: DistanceLimit::ALL
                .map(|k| pipeline(shaders::DISTANCE, k.entry_point(), &with_kernel)),
            bending: pipeline(shaders::BENDING, "solve", &with_kernel),
            isometric: pipeline(shaders::ISOMETRIC, "solve", &with_kernel),
            hinge: pipeline(shaders::HINGE, "solve", &with_kernel),
            track: pipeline(shaders::HINGE, "track", &with_kernel),
            tether: pipeline(shaders::TETHER, "solve", &with_kernel),
            snapshot: pipeline(shaders::PROLONGATION, "snapshot", &with_kernel),
            long_range: pipeline(shaders::LONG_RANGE, "solve", &with_kernel),
            prolongate: pipeline(shaders::PROLONGATION, "prolongate", &with_kernel),
            grab_reach: pipeline(shaders::GRAB_REACH, "reach", &with_kernel),
            attachment: pipeline(shaders::ATTACHMENT, "solve", &with_kernel),
            jacobi_correct: pipeline(shaders::JACOBI, "correct", &with_kernel),
            jacobi_gather: pipeline(shaders::JACOBI, "gather", &with_kernel),
            health: [
                pipeline(shaders::HEALTH, "reduce_blocks", &with_kernel),
                pipeline(shaders::HEALTH, "reduce_sums", &with_kernel),
            ],
            momentum: ["sum_blocks", "solve", "apply"]
                .map(|e| pipeline(shaders::MOMENTUM, e, &with_kernel)),
            self_contact: SelfContactKernels {
                grid: entries(shaders::CONTACT_GRID, |m, e| pipeline(m, e, &with_kernel)),
                find_edges: pipeline(shaders::CONTACT_GRID, "find_edges", &with_kernel),
                arm: entries(shaders::CONTACT_DISPATCH, |m, e| {
                    pipeline(m, e, &with_kernel)
                }),
                scaled: ContactSolve {
                    count: Some(contact("count")),
                    contacts: contact("contacts"),
                    counted_contacts: contact("counted_contacts"),
                    apply: contact("apply"),
                },
                averaged: ContactSolve {
                    count: None,
                    contacts: contact("averaged_contacts"),
                    counted_contacts: contact("counted_averaged_contacts"),
                    apply: contact("apply_averaged"),
                },
            },
            state_layout,
            kernel_layout,
        }
    }
}
