//! The persistent kernel (`shaders/persistent.wgsl`): for a small sheet
//! whose constraints are hinges and distances alone (paper, free of pins,
//! colliders, wind and self-contact), one workgroup runs every substep of
//! a frame in one dispatch, colour after colour with a barrier between
//! them, instead of a dispatch per colour, kind and substep. A crease
//! pattern folds with 160 substeps of a few dozen constraints a colour:
//! per-dispatch costs, not arithmetic, decide its frame time, and one
//! workgroup holds every colour of it.
//!
//! It runs the same library code as the kernels dispatched per colour, in
//! the same order, so both paths follow the CPU to round-off; the backend
//! takes it for a frame where it [`Persistent::runs`], and the per-colour
//! path otherwise (a grab, wind switched on, more substeps than its
//! parameters hold).

use super::projection::{ConstraintBuffers, ConstraintKind};
use super::ranges::RangeTable;
use crate::buffers::entry;
use crate::data::Range;
use crate::kernels::{storage, COMPLIANCE_SLOTS, UNIFORM_STRIDE};
use crate::shaders;
use crate::timing::{TimedStage, Timestamps};
use bytemuck::{Pod, Zeroable};
use std::borrow::Cow;
use wgpu::util::DeviceExt;

/// Most substeps a frame of the persistent kernel has (`MAX_SUBSTEPS`):
/// their parameters fill WebGPU's default 64 KiB uniform binding.
pub(super) const MAX_SUBSTEPS: u32 = 256;
/// Most particles a sheet may have to take the persistent path: up to
/// this, one workgroup walks each colour in a few rounds.
pub(super) const MAX_PARTICLES: usize = 2048;
/// Invocations a CPU adapter runs at once: lanes of a 256-bit vector.
const CPU_LANES: u32 = 8;
/// Colour slices and free cloths the program holds (`slices`).
const SLICES: usize = 256;

/// What a frame of the persistent kernel runs (`Program` in structs.wgsl):
/// counts, then the colours' and free cloths' slices.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub(crate) struct Program {
    pub(crate) substeps: u32,
    pub(crate) iterations: u32,
    pub(crate) hinge_colours: u32,
    pub(crate) distance_colours: u32,
    pub(crate) hinge_count: u32,
    pub(crate) distance_count: u32,
    pub(crate) strain_limit_sweeps: u32,
    pub(crate) free_parts: u32,
    pub(crate) slices: [[u32; 4]; SLICES],
}

/// The hinges and distances of a sheet the persistent kernel can run.
pub(super) struct Sheet<'a> {
    pub(super) kinds: &'a [ConstraintBuffers],
    pub(super) table: &'a RangeTable,
    pub(super) strain_limit_sweeps: u32,
    pub(super) free_parts: &'a [std::ops::Range<usize>],
    pub(super) particles: usize,
    /// Hard pins, colliders, self-contact: anything the kernel does not run.
    pub(super) has_more: bool,
}

/// The persistent kernel, bound to a sheet's buffers.
pub(super) struct Persistent {
    pipeline: wgpu::ComputePipeline,
    state_layout: wgpu::BindGroupLayout,
    state: wgpu::BindGroup,
    kernel: wgpu::BindGroup,
    program: Program,
    program_buffer: wgpu::Buffer,
}

/// The buffers the persistent kernel binds in group 0.
pub(super) struct StateBuffers<'a> {
    pub(super) pos: &'a wgpu::Buffer,
    pub(super) prev: &'a wgpu::Buffer,
    pub(super) vel: &'a wgpu::Buffer,
    /// Every substep's parameters, at least [`MAX_SUBSTEPS`] of them.
    pub(super) params: &'a wgpu::Buffer,
    pub(super) compliances: &'a wgpu::Buffer,
}

impl Persistent {
    /// The kernel for `sheet`, or `None` where it has more than the kernel
    /// runs or is too large for one workgroup. `left` is the free cloths'
    /// turn round-off, shared with the per-colour path.
    pub(super) fn new(
        (device, device_type): (&wgpu::Device, wgpu::DeviceType),
        sheet: &Sheet<'_>,
        left: Option<&wgpu::Buffer>,
        state: &StateBuffers<'_>,
    ) -> Option<Self> {
        let program = program(sheet)?;
        let kind = |k: ConstraintKind| sheet.kinds.iter().find(|c| c.kind == k);
        // WebGPU forbids one buffer in two writable slots of a group: an
        // absent kind binds spares of its own.
        let spares = [0, 1, 2, 3, 4].map(|_| crate::buffers::zeroed(device, "unused slot", 16));
        let [distances, distance_lambda] = kind(ConstraintKind::Distance)
            .map_or([&spares[0], &spares[1]], |c| [&c.items, &c.lambda]);
        let [hinges, hinge_lambda] =
            kind(ConstraintKind::Hinge).map_or([&spares[2], &spares[3]], |c| [&c.items, &c.lambda]);
        let program_buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("persistent program"),
            contents: bytemuck::bytes_of(&program),
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        });
        let (state_layout, kernel_layout) = layouts(device);
        let kernel = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("persistent sheet"),
            layout: &kernel_layout,
            entries: &[
                entry(0, distances),
                entry(1, distance_lambda),
                entry(2, hinges),
                entry(3, hinge_lambda),
                entry(5, left.unwrap_or(&spares[4])),
                entry(6, &program_buffer),
            ],
        });
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some(shaders::PERSISTENT.name),
            source: wgpu::ShaderSource::Wgsl(Cow::Owned(shaders::PERSISTENT.source())),
        });
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("persistent"),
            bind_group_layouts: &[Some(&state_layout), Some(&kernel_layout)],
            immediate_size: 0,
        });
        let threads = [("THREADS", threads(&program, device_type) as f64)];
        let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some("persistent frame"),
            layout: Some(&layout),
            module: &module,
            entry_point: Some("frame"),
            compilation_options: wgpu::PipelineCompilationOptions {
                constants: &threads,
                ..Default::default()
            },
            cache: None,
        });
        let state = bind_state(device, &state_layout, state);
        Some(Persistent {
            pipeline,
            state_layout,
            state,
            kernel,
            program,
            program_buffer,
        })
    }

    /// Binds the state again (after the parameters' buffer grew).
    pub(super) fn rebind_state(&mut self, device: &wgpu::Device, state: &StateBuffers<'_>) {
        self.state = bind_state(device, &self.state_layout, state);
    }

    /// Whether a frame of `substeps` substeps can run here.
    pub(super) fn runs(&self, substeps: u32) -> bool {
        substeps <= MAX_SUBSTEPS
    }

    /// Records the frame's `substeps` substeps of `iterations` iterations
    /// as one dispatch of one workgroup, stamped as the constraints of one
    /// substep (the other stages' passes empty) where the frame is timed.
    pub(super) fn record(
        &mut self,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        (substeps, iterations): (u32, u32),
        timestamps: Option<&Timestamps>,
    ) {
        self.program.substeps = substeps;
        self.program.iterations = iterations;
        let header = &bytemuck::bytes_of(&self.program)[..8];
        queue.write_buffer(&self.program_buffer, 0, header);
        for stage in TimedStage::ALL {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("persistent frame"),
                timestamp_writes: timestamps.and_then(|t| t.writes(0, stage)),
            });
            if stage == TimedStage::Constraints {
                pass.set_pipeline(&self.pipeline);
                pass.set_bind_group(0, &self.state, &[]);
                pass.set_bind_group(1, &self.kernel, &[]);
                pass.dispatch_workgroups(1, 1, 1);
            }
        }
    }
}

/// Invocations of the workgroup (`THREADS`). On a GPU, the largest
/// colour's size rounded up to a power of two, 32 to 256: each colour in
/// one round, a small sheet in one warp. A CPU adapter (lavapipe) runs
/// the workgroup on one core, a vector of [`CPU_LANES`] at a time, and
/// pays for every vector at each barrier: one vector.
fn threads(program: &Program, device_type: wgpu::DeviceType) -> u32 {
    if device_type == wgpu::DeviceType::Cpu {
        return CPU_LANES;
    }
    let colours = (program.hinge_colours + program.distance_colours) as usize;
    let largest = program.slices[..colours]
        .iter()
        .map(|s| s[1])
        .max()
        .unwrap_or(0);
    largest.next_power_of_two().clamp(32, 256)
}

/// Whether the kernel can run `sheet`.
pub(super) fn may_run(sheet: &Sheet<'_>) -> bool {
    program(sheet).is_some()
}

/// The program of `sheet`, or `None` where the kernel cannot run it.
fn program(sheet: &Sheet<'_>) -> Option<Program> {
    if sheet.has_more || sheet.particles > MAX_PARTICLES {
        return None;
    }
    let runs = |c: &&ConstraintBuffers| !c.dispatches.is_empty();
    if sheet
        .kinds
        .iter()
        .filter(runs)
        .any(|c| !matches!(c.kind, ConstraintKind::Hinge | ConstraintKind::Distance))
    {
        return None;
    }
    let colours = |kind| -> Vec<Range> {
        sheet
            .kinds
            .iter()
            .filter(|c| c.kind == kind)
            .flat_map(|c| {
                c.dispatches
                    .iter()
                    .map(|&(offset, _)| sheet.table.at(offset))
            })
            .collect()
    };
    let (hinges, distances) = (
        colours(ConstraintKind::Hinge),
        colours(ConstraintKind::Distance),
    );
    let parts: Vec<Range> = sheet
        .free_parts
        .iter()
        .map(|r| Range {
            first: r.start as u32,
            count: r.len() as u32,
        })
        .collect();
    let all: Vec<Range> = [&hinges[..], &distances[..], &parts[..]].concat();
    if all.len() > SLICES {
        return None;
    }
    let count = |colours: &[Range]| colours.iter().map(|r| r.first + r.count).max().unwrap_or(0);
    let mut program = Program {
        substeps: 0,
        iterations: 0,
        hinge_colours: hinges.len() as u32,
        distance_colours: distances.len() as u32,
        hinge_count: count(&hinges),
        distance_count: count(&distances),
        strain_limit_sweeps: sheet.strain_limit_sweeps,
        free_parts: parts.len() as u32,
        slices: [[0; 4]; SLICES],
    };
    for (slot, r) in program.slices.iter_mut().zip(&all) {
        *slot = [r.first, r.count, 0, 0];
    }
    Some(program)
}

/// The kernel's two bind group layouts: the state with every substep's
/// parameters, and the sheet's hinges, distances, turn round-off and program.
fn layouts(device: &wgpu::Device) -> (wgpu::BindGroupLayout, wgpu::BindGroupLayout) {
    let uniform = |binding, size: u64| wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Uniform,
            has_dynamic_offset: false,
            min_binding_size: wgpu::BufferSize::new(size),
        },
        count: None,
    };
    let state = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("persistent state"),
        entries: &[
            storage(0),
            storage(1),
            storage(2),
            uniform(3, MAX_SUBSTEPS as u64 * UNIFORM_STRIDE),
            uniform(4, COMPLIANCE_SLOTS as u64 * 4),
        ],
    });
    let kernel = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("persistent sheet"),
        entries: &[
            storage(0),
            storage(1),
            storage(2),
            storage(3),
            storage(5),
            uniform(6, size_of::<Program>() as u64),
        ],
    });
    (state, kernel)
}

/// The state's bind group: positions, previous positions, velocities,
/// the first [`MAX_SUBSTEPS`] substeps' parameters, the compliances.
fn bind_state(
    device: &wgpu::Device,
    layout: &wgpu::BindGroupLayout,
    b: &StateBuffers<'_>,
) -> wgpu::BindGroup {
    let params = wgpu::BufferBinding {
        buffer: b.params,
        offset: 0,
        size: wgpu::BufferSize::new(MAX_SUBSTEPS as u64 * UNIFORM_STRIDE),
    };
    device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("persistent state"),
        layout,
        entries: &[
            entry(0, b.pos),
            entry(1, b.prev),
            entry(2, b.vel),
            wgpu::BindGroupEntry {
                binding: 3,
                resource: wgpu::BindingResource::Buffer(params),
            },
            entry(4, b.compliances),
        ],
    })
}
