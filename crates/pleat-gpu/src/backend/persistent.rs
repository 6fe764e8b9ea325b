//! The persistent kernel (`shaders/persistent.wgsl`): for a small sheet
//! whose constraints are hinges and distances alone (paper, free of pins,
//! colliders and wind), one workgroup runs every substep of a frame in one
//! dispatch, colour after colour with a barrier between them, instead of a
//! dispatch per colour, kind and substep. Paper with a thickness takes its
//! self-contacts there too, over a list of pairs made once by the host
//! (every vertex-triangle and edge-edge pair that the rest mesh does not
//! keep apart), where the sheet and that list are small enough. On a CPU
//! adapter a frame is split into dispatches short enough for its loop
//! limit ([`CPU_LOOP_BUDGET`]). A crease
//! pattern folds with 160 substeps of a few dozen constraints a colour:
//! per-dispatch costs, not arithmetic, decide its frame time, and one
//! workgroup holds every colour of it. The sheet's positions live in the
//! workgroup's memory for the dispatch, where every colour reads and
//! writes them, so the kernel takes sheets whose positions fit there
//! beside its other workgroup words ([`positions_fit`]).
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
/// Loop iterations an invocation may run in one dispatch on a CPU adapter.
/// Mesa's llvmpipe (lavapipe) ends every loop of a shader once they have
/// run 65,535 iterations together (`LP_MAX_TGSI_LOOP_ITERATIONS`), which
/// cut a frame short without a word: Origami_Sphere_16Flaps.svg folded 12
/// to 25 degrees off, helloworld.svg 33. A frame is split into dispatches
/// of as many substeps as fit half of that, by [`loop_iterations`]; the
/// other half is left to the strain limits' sweeps beyond the first ones,
/// which run only while an edge stays beyond its slack.
const CPU_LOOP_BUDGET: u32 = 32_768;
/// Fewest substeps a dispatch with self-contacts runs on a CPU adapter;
/// fewer, and the per-substep path is taken. When each dispatch built its
/// kept pairs anew from all the pairs, hypar.svg with a thickness (a
/// substep a dispatch) took 1,391 ms a frame on lavapipe against the
/// per-substep path's 999, the crane (three a dispatch) 237 against 839.
const MIN_CONTACT_CHUNK: u32 = 2;
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
    pub(crate) contact_pairs: u32,
    pub(crate) contact_pairs_start: u32,
    pub(crate) contact_iterations: u32,
    pub(crate) contact_counts: u32,
    pub(crate) slices: [[u32; 4]; SLICES],
}

/// A sheet's self-contacts as the persistent kernel solves them.
pub(super) struct ContactPairs {
    /// The self-contacts' topology (`contact_topology`), then the pairs
    /// (`contact_pairs`).
    pub(super) topology: Vec<u32>,
    pub(super) pairs: Vec<u32>,
    /// Jacobi iterations a substep.
    pub(super) iterations: u32,
}

/// Storage buffers the kernel with self-contacts binds: one more than
/// WebGPU's default limit.
const CONTACT_STORAGE_BUFFERS: u32 = 9;

/// The hinges and distances of a sheet the persistent kernel can run.
pub(super) struct Sheet<'a> {
    pub(super) kinds: &'a [ConstraintBuffers],
    pub(super) table: &'a RangeTable,
    pub(super) strain_limit_sweeps: u32,
    /// Gauss-Seidel iterations a substep.
    pub(super) iterations: u32,
    pub(super) free_parts: &'a [std::ops::Range<usize>],
    pub(super) particles: usize,
    /// Hard pins, colliders, self-contact but `contacts`: anything the
    /// kernel does not run.
    pub(super) has_more: bool,
    /// The self-contacts, where the kernel solves them.
    pub(super) contacts: Option<ContactPairs>,
}

/// The persistent kernel, bound to a sheet's buffers.
pub(super) struct Persistent {
    pipeline: wgpu::ComputePipeline,
    state_layout: wgpu::BindGroupLayout,
    state: wgpu::BindGroup,
    kernel: wgpu::BindGroup,
    program: Program,
    program_buffer: wgpu::Buffer,
    /// The self-contacts' topology, pairs and counts, and their bind group.
    contacts: Option<(wgpu::Buffer, wgpu::BindGroup)>,
    /// Substeps a dispatch runs (`chunk` in the kernel): a whole frame on a
    /// GPU, fewer on a CPU adapter ([`CPU_LOOP_BUDGET`]).
    chunk: u32,
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
        let mut program = program(sheet)?;
        let with_contacts = sheet.contacts.as_ref().inspect(|c| {
            program.contact_pairs = (c.pairs.len() / 2) as u32;
            program.contact_pairs_start = c.topology.len() as u32;
            program.contact_counts = (c.topology.len() + c.pairs.len()) as u32;
            program.contact_iterations = c.iterations;
        });
        if with_contacts.is_some()
            && device.limits().max_storage_buffers_per_shader_stage < CONTACT_STORAGE_BUFFERS
        {
            return None;
        }
        let threads = threads(&program, device_type);
        if !positions_fit(device, sheet.particles, threads, with_contacts.is_some()) {
            return None;
        }
        let chunk = match device_type {
            wgpu::DeviceType::Cpu => {
                let per_substep = loop_iterations(&program, sheet, threads);
                (CPU_LOOP_BUDGET / per_substep).min(MAX_SUBSTEPS)
            }
            _ => MAX_SUBSTEPS,
        };
        if chunk
            < if with_contacts.is_some() {
                MIN_CONTACT_CHUNK
            } else {
                1
            }
        {
            return None;
        }
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
        // Dispatch k's first substep and the substeps a dispatch runs, a
        // slot of UNIFORM_STRIDE bytes each (a dynamic offset).
        let slots: Vec<u32> = (0..MAX_SUBSTEPS)
            .flat_map(|k| {
                let mut slot = vec![0; UNIFORM_STRIDE as usize / 4];
                slot[..2].copy_from_slice(&[k * chunk, chunk]);
                slot
            })
            .collect();
        let chunks = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("persistent chunks"),
            contents: bytemuck::cast_slice(&slots),
            usage: wgpu::BufferUsages::UNIFORM,
        });
        let (state_layout, kernel_layout) = layouts(device);
        let contact_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("persistent contacts"),
            entries: &[storage(0)],
        });
        let contacts = with_contacts.map(|c| {
            // Then the frame's three counts, the kept pairs' count and
            // reach, the kept pairs and their build's positions (written
            // by the kernel).
            let room = 3 + 2 + c.pairs.len() / 2 + 3 * sheet.particles;
            let words = [&c.topology[..], &c.pairs, &vec![0; room]].concat();
            let buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("persistent contacts"),
                contents: bytemuck::cast_slice(&words),
                usage: wgpu::BufferUsages::STORAGE
                    | wgpu::BufferUsages::COPY_SRC
                    | wgpu::BufferUsages::COPY_DST,
            });
            let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("persistent contacts"),
                layout: &contact_layout,
                entries: &[entry(0, &buffer)],
            });
            (buffer, group)
        });
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
                wgpu::BindGroupEntry {
                    binding: 7,
                    resource: wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                        buffer: &chunks,
                        offset: 0,
                        size: wgpu::BufferSize::new(16),
                    }),
                },
            ],
        });
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some(shaders::PERSISTENT.name),
            source: wgpu::ShaderSource::Wgsl(Cow::Owned(shaders::PERSISTENT.source())),
        });
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("persistent"),
            bind_group_layouts: &[
                Some(&state_layout),
                Some(&kernel_layout),
                contacts.as_ref().map(|_| &contact_layout),
            ],
            immediate_size: 0,
        });
        let constants = [
            ("THREADS", f64::from(threads)),
            ("PARTICLES", sheet.particles as f64),
        ];
        let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some("persistent frame"),
            layout: Some(&layout),
            module: &module,
            entry_point: Some(match contacts {
                Some(_) => "frame_with_contacts",
                None => "frame",
            }),
            compilation_options: wgpu::PipelineCompilationOptions {
                constants: &constants,
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
            contacts,
            chunk,
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
    /// as dispatches of one workgroup (one on a GPU), stamped as the
    /// constraints of one substep (the other stages' passes empty) where
    /// the frame is timed; returns the dispatches.
    pub(super) fn record(
        &mut self,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        (substeps, iterations): (u32, u32),
        timestamps: Option<&Timestamps>,
    ) -> u32 {
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
                if let Some((_, group)) = &self.contacts {
                    pass.set_bind_group(2, group, &[]);
                }
                for k in 0..substeps.div_ceil(self.chunk) {
                    let slot = k * UNIFORM_STRIDE as u32;
                    pass.set_bind_group(1, &self.kernel, &[slot]);
                    pass.dispatch_workgroups(1, 1, 1);
                }
            }
        }
        substeps.div_ceil(self.chunk)
    }

    /// The self-contacts' counters (pairs solved, contacts that acted,
    /// builds, summed over frames until the host clears them): the buffer
    /// and their byte offset in it, where the kernel has contacts.
    pub(super) fn contact_counts(&self) -> Option<(&wgpu::Buffer, u64)> {
        let at = u64::from(self.program.contact_counts) * 4;
        self.contacts.as_ref().map(|(buffer, _)| (buffer, at))
    }
}

/// Bytes of workgroup memory a particle's position takes.
const POSITION_BYTES: u32 = 16;
/// Bytes of one free cloth's partial sums (`Sums`), of which the kernel
/// keeps one per summing invocation (`SUMMING`, at most 64).
const SUMS_BYTES: u32 = 7 * 16;
/// Bytes of the kernel's other workgroup words: the turn, the sweeps' and
/// the contacts' counters.
const WORDS_BYTES: u32 = 64;
/// Bytes of the self-contacts' sums per particle (`accum`).
const ACCUM_BYTES: u32 = 4 * 2048;

/// Whether the positions of `particles` fit in the workgroup memory
/// `device` allows beside the rest of the kernel's, with `threads`
/// invocations.
fn positions_fit(
    device: &wgpu::Device,
    particles: usize,
    threads: u32,
    with_contacts: bool,
) -> bool {
    let others =
        threads.min(64) * SUMS_BYTES + WORDS_BYTES + if with_contacts { ACCUM_BYTES } else { 0 };
    let room = device
        .limits()
        .max_compute_workgroup_storage_size
        .saturating_sub(others);
    particles > 0 && particles <= (room / POSITION_BYTES) as usize
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

/// An upper bound on the loop iterations one invocation of `threads` runs
/// in a substep of `sheet` (with `program`'s colours): the iterations'
/// colours, the strain limits' first sweeps, the loops over particles and
/// constraints and, with self-contacts, a build and every iteration over
/// all the pairs.
fn loop_iterations(program: &Program, sheet: &Sheet<'_>, threads: u32) -> u32 {
    let rounds = |count: u32| count.div_ceil(threads);
    let colours = |slices: &[[u32; 4]]| slices.iter().map(|s| 1 + rounds(s[1])).sum::<u32>();
    let hinge_colours = program.hinge_colours as usize;
    let distance_colours = hinge_colours + program.distance_colours as usize;
    let hinges = colours(&program.slices[..hinge_colours]);
    let distances = colours(&program.slices[hinge_colours..distance_colours]);
    let parts = &program.slices[distance_colours..distance_colours + program.free_parts as usize];
    let turns: u32 = parts
        .iter()
        .map(|p| 2 + rounds(p[1]) + p[1].div_ceil(64))
        .sum();
    let particles = rounds(sheet.particles as u32);
    let constraints = rounds(program.distance_count) + 2 * rounds(program.hinge_count);
    let contacts = sheet.contacts.as_ref().map_or(0, |c| {
        let pairs = rounds((c.pairs.len() / 2) as u32);
        3 * particles + (1 + c.iterations) * (1 + pairs + particles)
    });
    1 + sheet.iterations.max(1) * (1 + hinges + distances)
        + program.strain_limit_sweeps * (1 + distances)
        + 3 * particles
        + constraints
        + turns
        + contacts
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
        contact_pairs: 0,
        contact_pairs_start: 0,
        contact_iterations: 0,
        contact_counts: 0,
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
            wgpu::BindGroupLayoutEntry {
                binding: 7,
                visibility: wgpu::ShaderStages::COMPUTE,
                ty: wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Uniform,
                    has_dynamic_offset: true,
                    min_binding_size: wgpu::BufferSize::new(16),
                },
                count: None,
            },
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
