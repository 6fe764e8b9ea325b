//! [`GpuBackend`]: the XPBD substep of the core as a sequence of compute
//! dispatches, one frame per queue submission. Constraints are projected
//! colour by colour (one dispatch per colour, the slice chosen by a dynamic
//! uniform offset), in the core's order, so the result follows the CPU
//! backend's to round-off. Pin targets and collider poses of every substep
//! of a frame are computed on the CPU from their scripts and uploaded once
//! per frame (a few bytes per pin and collider), with the colliders'
//! friction when the world's has changed.

use crate::buffers::{entry, sized_entry, storage, zeroed};
use crate::context::{GpuContext, GpuError};
use crate::data::{self, Attachment, Counts, GpuCollider, GpuPose, Params, Range};
use crate::health::{HealthInputs, HealthWatch, PaperEdges};
use crate::kernels::{workgroups, Kernels, COMPLIANCE_SLOTS, UNIFORM_STRIDE};
use crate::momentum::Momentum;
use crate::readback::Readback;
use crate::timing::{TimedStage, Timestamps};
use bytemuck::Pod;
use glam::Vec3;
use pleat::collide::ColliderPose;
use pleat::constraint::{Compliances, DistanceConstraint};
use pleat::control::Control;
use pleat::mesh::incidence::Incidence;
use pleat::model::Model;
use pleat::solver::jacobi::JacobiConstraints;
use pleat::solver::parallel::ColoredConstraints;
use pleat::solver::position_based::attachments;
use pleat::solver::xpbd::{FoldLimits, XpbdConstraints};
use pleat::solver::{substep_times, SolverKind, SolverSettings, StageTimes};
use pleat::{Backend, Particles, World};
use wgpu::util::DeviceExt;

/// Bytes of one particle in the state buffers (`vec4<f32>`).
const PARTICLE_BYTES: u64 = 16;

/// One kernel with its buffers bound, and the slices it is dispatched on.
struct Stage {
    pipeline: wgpu::ComputePipeline,
    bind_group: wgpu::BindGroup,
    /// Dynamic offset into the range buffer and invocation count, per dispatch.
    dispatches: Vec<(u32, u32)>,
}

/// The ranges of every dispatch, 256 bytes apart, built before upload.
#[derive(Default)]
struct RangeTable(Vec<Range>);

impl RangeTable {
    /// Adds a slice and returns its dynamic offset and count.
    fn push(&mut self, first: u32, count: u32) -> (u32, u32) {
        self.0.push(Range { first, count });
        (
            (self.0.len() as u64 - 1) as u32 * UNIFORM_STRIDE as u32,
            count,
        )
    }

    fn colours<C>(&mut self, set: &ColoredConstraints<C>) -> Vec<(u32, u32)> {
        set.colors()
            .iter()
            .filter(|r| !r.is_empty())
            .map(|r| self.push(r.start as u32, r.len() as u32))
            .collect()
    }

    fn bytes(&self) -> Vec<u8> {
        let mut bytes = vec![0u8; self.0.len().max(1) * UNIFORM_STRIDE as usize];
        for (k, r) in self.0.iter().enumerate() {
            let at = k * UNIFORM_STRIDE as usize;
            bytes[at..at + size_of::<Range>()].copy_from_slice(bytemuck::bytes_of(r));
        }
        bytes
    }
}

/// The per-substep parameters, pin targets and collider poses of a frame,
/// written on the CPU before upload.
#[derive(Default)]
struct FrameData {
    /// One [`Params`] every [`UNIFORM_STRIDE`] bytes.
    params: Vec<u8>,
    targets: Vec<[f32; 4]>,
    poses: Vec<GpuPose>,
    /// The live compliance table, [`COMPLIANCE_SLOTS`] long.
    compliances: Vec<f32>,
}

/// Buffers whose size depends on the number of substeps per frame.
struct PerSubstep {
    capacity: u32,
    params: wgpu::Buffer,
    targets: wgpu::Buffer,
    poses: wgpu::Buffer,
}

/// Polls a blocking read of the state makes before it reports the state
/// lost ([`GpuBackend::read_state`]): eight were not always enough on
/// lavapipe with the devices of parallel tests busy (a CI check lost the
/// crane's state after 30 frames); a poll of an idle device is cheap.
const READBACK_POLLS: u32 = 10_000;

/// The XPBD solver on a GPU.
pub struct GpuBackend {
    context: GpuContext,
    kernels: Kernels,
    counts: Counts,
    constraint_count: usize,
    pos: wgpu::Buffer,
    prev: wgpu::Buffer,
    vel: wgpu::Buffer,
    /// The live compliance table (a uniform), written at every frame.
    compliance_table: wgpu::Buffer,
    /// Lambda buffers, cleared at the start of every substep.
    lambdas: Vec<wgpu::Buffer>,
    ranges: wgpu::Buffer,
    /// Kernel buffers kept for rebinding when the per-substep buffers grow.
    buffers: KernelBuffers,
    per_substep: PerSubstep,
    stages: Stages,
    /// Per-stage GPU times, where the adapter has timestamp queries.
    timestamps: Option<Timestamps>,
    /// Non-finite values, energy and paper strain after each frame.
    health: HealthWatch,
    /// The free cloths turned back by the angle their projection turned them.
    momentum: Option<Momentum>,
    /// A read of the state asked for and not yet taken.
    pending: Option<Readback>,
    /// The mappable buffer every read of the state goes through.
    staging: wgpu::Buffer,
    /// What each frame uploads, kept so that a step allocates nothing.
    frame_data: FrameData,
    hard_pins: Vec<pleat::constraint::Attachment>,
    soft_pins: Vec<pleat::constraint::Attachment>,
    /// The distance constraints as the items buffer holds them, and their
    /// strain limits for a held fold and a moving one (paper's give while
    /// it moves); `None` where the two are the same.
    fold_limits: Option<(FoldLimits, Vec<DistanceConstraint>)>,
}

/// Buffers of the kernels of group 1, by kernel.
struct KernelBuffers {
    /// Items and lambdas of each constraint kind, in projection order.
    constraints: Vec<ConstraintBuffers>,
    /// The distances' strain limits, where an edge has one.
    strain_limit: Option<StrainLimitBuffers>,
    hard_pins: wgpu::Buffer,
    pin_dispatch: (u32, u32),
    track_dispatch: (u32, u32),
    triangles: wgpu::Buffer,
    triangle_force: wgpu::Buffer,
    around_start: wgpu::Buffer,
    around: wgpu::Buffer,
    colliders: wgpu::Buffer,
    /// What `colliders` holds, its friction refreshed from the world.
    collider_shapes: Vec<GpuCollider>,
    sdf_values: wgpu::Buffer,
    thickness: wgpu::Buffer,
    whole: (u32, u32),
    self_contact: Option<SelfContactBuffers>,
}

/// The self-contact hash grid and its inputs and outputs.
struct SelfContactBuffers {
    /// Bucket counts and starts, fill counters, sorted particles, scan sums.
    grid: wgpu::Buffer,
    /// Triangles, then the triangles each vertex owns (compressed rows).
    topology: wgpu::Buffer,
    /// Rest positions, for the rest-neighbour exclusion.
    rest: wgpu::Buffer,
    /// Fixed-point corrections and contact counts per particle.
    accum: wgpu::Buffer,
    cell: f32,
    /// Hash table size: a power of two, a multiple of the scan block.
    buckets: u32,
}

/// What the strain limits' sweeps need besides the distances' items.
struct StrainLimitBuffers {
    /// The sweeps after the iterations before the further ones: the CPU's
    /// [`pleat::solver::xpbd::STRAIN_LIMIT_SWEEPS`].
    sweeps: u32,
    /// Each colour's slice of the distances, for the further sweeps.
    colours: wgpu::Buffer,
    /// Whether the last sweep found an edge far beyond its limit.
    beyond: wgpu::Buffer,
}

impl StrainLimitBuffers {
    fn new(device: &wgpu::Device, sweeps: u32, colours: &[Range]) -> Option<Self> {
        (sweeps > 0).then(|| StrainLimitBuffers {
            sweeps,
            colours: storage(device, "distance colours", colours),
            beyond: zeroed(device, "beyond the slack", 4),
        })
    }
}

/// Most a rest edge may stretch and still find its triangles' contacts.
const CONTACT_EDGE_STRETCH: f32 = 1.5;

impl SelfContactBuffers {
    fn new(device: &wgpu::Device, model: &Model, thickness: f32, triangles: &[u32]) -> Self {
        let n = model.particle_count() as u32;
        let longest = model
            .edges
            .iter()
            .map(|e| e.rest_length)
            .fold(0.0, f32::max);
        let buckets = (2 * n).next_power_of_two().max(crate::kernels::WORKGROUP);
        let grid_len = 2 * buckets as u64 + n as u64 + (buckets / crate::kernels::WORKGROUP) as u64;
        let (start, owned) = owned_triangles(model);
        let topology: Vec<u32> = [triangles, &start, &owned].concat();
        let rest: Vec<[f32; 4]> = model
            .rest
            .iter()
            .map(|p| p.extend(0.0).to_array())
            .collect();
        SelfContactBuffers {
            grid: zeroed(device, "contact grid", grid_len * 4),
            topology: storage(device, "topology", &topology),
            rest: storage(device, "rest positions", &rest),
            accum: zeroed(device, "contact corrections", n as u64 * 16),
            cell: CONTACT_EDGE_STRETCH * longest + thickness,
            buckets,
        }
    }
}

/// Each triangle under its vertex of lowest index, in compressed rows
/// (starts, then triangles): a particle's contact search takes the
/// triangles its neighbours own, so it meets each triangle once.
fn owned_triangles(model: &Model) -> (Vec<u32>, Vec<u32>) {
    fn lowest(t: &[u32; 3]) -> &[u32] {
        let k = (0..3).min_by_key(|&k| t[k]).unwrap_or(0);
        &t[k..k + 1]
    }
    let incidence = Incidence::new(&model.triangles, model.particle_count(), lowest);
    let (start, slots) = incidence.rows();
    (start.to_vec(), slots.iter().map(|s| s.element).collect())
}

/// One constraint kind's buffers and its dispatches (by colour).
struct ConstraintBuffers {
    items: wgpu::Buffer,
    /// The Lagrange multipliers (cleared every substep), or Jacobi's corrections.
    lambda: wgpu::Buffer,
    /// Bindings 2 and 3; `None`: the pin targets and the items again.
    extra: Option<[wgpu::Buffer; 2]>,
    dispatches: Vec<(u32, u32)>,
    kind: ConstraintKind,
}

#[derive(Clone, Copy, PartialEq, Eq)]
enum ConstraintKind {
    Hinge,
    Distance,
    Bending,
    Isometric,
    Attachment,
    Tether,
    JacobiCorrect,
    JacobiGather,
}

impl GpuBackend {
    /// The backend for `model` in `world` on `context`'s device, and notes
    /// for the user (mesh colliders baked into distance fields). Refuses
    /// what the GPU backend does not have yet, naming the scene field.
    pub fn new(
        context: &GpuContext,
        model: &Model,
        world: &World,
        settings: &SolverSettings,
    ) -> Result<(Self, Vec<String>), GpuError> {
        check_supported(settings)?;
        check_compliance_slots(model)?;
        let data::Colliders {
            shapes: colliders,
            sdf_values,
            notes,
        } = data::colliders(world)?;
        let device = &context.device;
        let n = model.particle_count();
        check_size(context, n as u64 * PARTICLE_BYTES, "particle state")?;
        let (hard, soft) = attachments(model);
        let hard_pins = hard.attachments().to_vec();
        let mut table = RangeTable::default();
        let whole = table.push(0, 0);
        let paper = PaperEdges::of(model);
        let paper_range = table.push(0, paper.len());
        let projection = match settings.kind {
            SolverKind::JacobiPbd => {
                jacobi_projection(context, model, soft, hard_pins.len(), &mut table)?
            }
            _ => xpbd_projection(context, model, hard_pins.len(), &mut table)?,
        };
        let Projection {
            kinds,
            soft_pins,
            hinge_count,
            strain_limit_sweeps,
            distance_colours,
            constraint_count,
            free_parts,
            fold_limits,
        } = projection;
        let free_parts: Vec<(u32, u32)> = free_parts
            .iter()
            .map(|r| table.push(r.start as u32, r.len() as u32))
            .collect();
        let hard_indices: Vec<u32> = hard_pins.iter().map(|a| a.particle[0]).collect();
        let incidence = Incidence::new(&model.triangles, n, |t| t.as_slice());
        let (start, slots) = incidence.rows();
        let around: Vec<u32> = slots.iter().map(|s| s.element).collect();
        let flat_triangles: Vec<u32> = model.triangles.iter().flatten().copied().collect();
        let contact = settings.self_collision.enabled.then(|| {
            SelfContactBuffers::new(
                device,
                model,
                settings.self_collision.thickness,
                &flat_triangles,
            )
        });
        let buffers = KernelBuffers {
            pin_dispatch: table.push(0, hard_indices.len() as u32),
            track_dispatch: table.push(0, hinge_count),
            constraints: kinds,
            strain_limit: StrainLimitBuffers::new(device, strain_limit_sweeps, &distance_colours),
            hard_pins: storage(device, "hard pins", &hard_indices),
            triangles: storage(device, "triangles", &flat_triangles),
            triangle_force: zeroed(device, "triangle forces", model.triangles.len() as u64 * 16),
            around_start: storage(device, "around start", start),
            around: storage(device, "around", &around),
            colliders: storage(device, "colliders", &colliders),
            sdf_values: storage(device, "distance fields", &sdf_values),
            thickness: storage(device, "thickness", &model.thickness),
            whole,
            collider_shapes: colliders,
            self_contact: contact,
        };
        let ranges = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("ranges"),
            contents: &table.bytes(),
            usage: wgpu::BufferUsages::UNIFORM,
        });
        let state_usage = wgpu::BufferUsages::STORAGE
            | wgpu::BufferUsages::COPY_DST
            | wgpu::BufferUsages::COPY_SRC
            | wgpu::BufferUsages::VERTEX;
        let state = |label| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: (n as u64 * PARTICLE_BYTES).max(PARTICLE_BYTES),
                usage: state_usage,
                mapped_at_creation: false,
            })
        };
        let (pos, prev, vel) = (
            state("positions"),
            state("previous positions"),
            state("velocities"),
        );
        let compliance_table = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("compliances"),
            size: COMPLIANCE_SLOTS as u64 * 4,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let kernels = Kernels::new(device);
        let counts = Counts {
            particles: n as u32,
            triangles: model.triangles.len() as u32,
            pins: (hard_pins.len() + soft_pins.len()) as u32,
            colliders: buffers.collider_shapes.len() as u32,
            contact_cell: buffers.self_contact.as_ref().map_or(0.0, |c| c.cell),
            contact_buckets: buffers.self_contact.as_ref().map_or(0, |c| c.buckets),
        };
        let per_substep = PerSubstep::new(device, &counts, settings.substeps.max(1));
        let lambdas = buffers
            .constraints
            .iter()
            .map(|k| k.lambda.clone())
            .collect();
        let stages = Stages::new(
            device,
            &kernels,
            [&pos, &prev, &vel, &compliance_table],
            &buffers,
            &per_substep,
            &ranges,
        );
        let health = HealthWatch::new(
            device,
            &kernels,
            HealthInputs {
                model,
                paper: &paper,
                ranges: (&ranges, paper_range.0),
            },
        );
        let momentum = Momentum::new(device, &kernels, (&ranges, free_parts), n as u32);
        let backend = GpuBackend {
            context: context.clone(),
            health,
            momentum,
            timestamps: Timestamps::new(device, &context.queue, settings.substeps.max(1)),
            pending: None,
            staging: crate::readback::staging(device, 3 * n as u64 * PARTICLE_BYTES),
            frame_data: FrameData::default(),
            stages,
            kernels,
            counts,
            constraint_count,
            pos,
            prev,
            vel,
            compliance_table,
            lambdas,
            ranges,
            buffers,
            per_substep,
            hard_pins,
            soft_pins,
            fold_limits,
        };
        Ok((backend, notes))
    }

    /// The particle positions, `array<vec4<f32>>` with the inverse mass in
    /// w, usable as a vertex buffer (16-byte stride) by a renderer on the
    /// same device.
    pub fn positions(&self) -> &wgpu::Buffer {
        &self.pos
    }

    /// The context the backend runs on.
    pub fn context(&self) -> &GpuContext {
        &self.context
    }
}

/// The self-contact kernels with their bind group.
struct SelfContactStage {
    bind_group: wgpu::BindGroup,
    /// clear, count, scan_blocks, scan_sums, scan_add, scatter, contacts, apply.
    pipelines: [wgpu::ComputePipeline; 8],
    buckets: u32,
}

impl SelfContactStage {
    /// Builds the hash grid and solves the contacts of `particles` particles.
    fn record(&self, pass: &mut wgpu::ComputePass<'_>, particles: u32) {
        let [clear, count, scan_blocks, scan_sums, scan_add, scatter, contacts, apply] =
            &self.pipelines;
        pass.set_bind_group(1, &self.bind_group, &[0]);
        let over = |pass: &mut wgpu::ComputePass<'_>, pipeline, n: u32| {
            pass.set_pipeline(pipeline);
            let (x, y) = workgroups(n);
            pass.dispatch_workgroups(x, y, 1);
        };
        over(pass, clear, (2 * self.buckets).max(4 * particles));
        over(pass, count, particles);
        pass.set_pipeline(scan_blocks);
        pass.dispatch_workgroups(self.buckets / crate::kernels::WORKGROUP, 1, 1);
        pass.set_pipeline(scan_sums);
        pass.dispatch_workgroups(1, 1, 1);
        over(pass, scan_add, self.buckets);
        over(pass, scatter, particles);
        over(pass, contacts, particles);
        over(pass, apply, particles);
    }
}

/// Every kernel with its bind group, in the order a substep runs them.
struct Stages {
    state: wgpu::BindGroup,
    wind: [Stage; 2],
    /// Kernels of the state alone (group 0).
    predict: wgpu::ComputePipeline,
    pins: Option<Stage>,
    /// In projection order: hinges, distances, bending, isometric, soft attachments, tethers.
    constraints: Vec<Stage>,
    /// The distances' strain limits alone.
    strain_limit: Option<StrainLimitStages>,
    track: Option<Stage>,
    grab: wgpu::ComputePipeline,
    self_contact: Option<SelfContactStage>,
    collide: Option<Stage>,
    update_velocities: wgpu::ComputePipeline,
}

/// The strain limits' sweeps after the iterations, as the CPU runs them
/// (`Xpbd`'s `sweep_strain_limits`): the first sweeps, the last of them
/// noting whether an edge is beyond [`pleat::solver::xpbd::STRAIN_LIMIT_SLACK`]
/// times its limit, then while one is, further sweeps up to
/// [`pleat::solver::xpbd::MAX_STRAIN_LIMIT_SWEEPS`] in all. The further
/// sweeps run in one workgroup of one dispatch, a barrier between
/// colours, so that they stop themselves with no read back; a sheet that
/// is not jammed pays one empty dispatch.
/// The held limits are met in one such dispatch too.
struct StrainLimitStages {
    sweep: Stage,
    measured: Stage,
    further: Stage,
    held: Stage,
    sweeps: u32,
}

impl StrainLimitStages {
    fn record(&self, pass: &mut wgpu::ComputePass<'_>) {
        for _ in 1..self.sweeps {
            dispatch(pass, &self.sweep, None);
        }
        dispatch(pass, &self.measured, None);
        dispatch(pass, &self.further, Some(1));
    }
}

impl Stages {
    fn new(
        device: &wgpu::Device,
        kernels: &Kernels,
        [pos, prev, vel, compliances]: [&wgpu::Buffer; 4],
        b: &KernelBuffers,
        per_substep: &PerSubstep,
        ranges: &wgpu::Buffer,
    ) -> Self {
        let state = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("state"),
            layout: &kernels.state_layout,
            entries: &[
                entry(0, pos),
                entry(1, prev),
                entry(2, vel),
                sized_entry(3, &per_substep.params, size_of::<Params>()),
                entry(4, compliances),
            ],
        });
        let group = |buffers: [&wgpu::Buffer; 4]| {
            device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: None,
                layout: &kernels.kernel_layout,
                entries: &[
                    entry(0, buffers[0]),
                    entry(1, buffers[1]),
                    entry(2, buffers[2]),
                    entry(3, buffers[3]),
                    sized_entry(4, ranges, size_of::<Range>()),
                ],
            })
        };
        let stage = |pipeline: &wgpu::ComputePipeline, buffers, dispatches| Stage {
            pipeline: pipeline.clone(),
            bind_group: group(buffers),
            dispatches,
        };
        // Fillers for the slots a kernel does not use: WebGPU forbids one
        // buffer in two writable slots of a group.
        let spare = [0, 1, 2].map(|_| zeroed(device, "unused slot", 16));
        let wind_buffers = [&b.triangles, &b.triangle_force, &b.around_start, &b.around];
        let constraints = b
            .constraints
            .iter()
            .filter(|k| !k.dispatches.is_empty())
            .map(|k| {
                let pipeline = match k.kind {
                    ConstraintKind::Hinge => &kernels.hinge,
                    ConstraintKind::Distance => &kernels.distance,
                    ConstraintKind::Bending => &kernels.bending,
                    ConstraintKind::Isometric => &kernels.isometric,
                    ConstraintKind::Attachment => &kernels.attachment,
                    ConstraintKind::Tether => &kernels.tether,
                    ConstraintKind::JacobiCorrect => &kernels.jacobi_correct,
                    ConstraintKind::JacobiGather => &kernels.jacobi_gather,
                };
                let [third, fourth] = match &k.extra {
                    Some([a, b]) => [a, b],
                    None => [&per_substep.targets, &spare[0]],
                };
                stage(
                    pipeline,
                    [&k.items, &k.lambda, third, fourth],
                    k.dispatches.clone(),
                )
            })
            .collect();
        let hinges = b
            .constraints
            .iter()
            .find(|k| k.kind == ConstraintKind::Hinge)
            .map_or(pos, |k| &k.items);
        let strain_limit = b
            .constraints
            .iter()
            .find(|k| k.kind == ConstraintKind::Distance)
            .zip(b.strain_limit.as_ref())
            .map(|(k, limits)| {
                let buffers = [&k.items, &k.lambda, &limits.colours, &limits.beyond];
                let [sweep, measured, further, held] = kernels
                    .distance_limit
                    .each_ref()
                    .map(|pipeline| stage(pipeline, buffers, k.dispatches.clone()));
                StrainLimitStages {
                    sweep,
                    measured,
                    further,
                    held,
                    sweeps: limits.sweeps,
                }
            });
        Stages {
            wind: [
                stage(&kernels.triangle_forces, wind_buffers, vec![b.whole]),
                stage(&kernels.gather, wind_buffers, vec![b.whole]),
            ],
            predict: kernels.predict.clone(),
            pins: (b.pin_dispatch.1 > 0).then(|| {
                stage(
                    &kernels.place_pins,
                    [&b.hard_pins, &spare[0], &per_substep.targets, &spare[1]],
                    vec![b.pin_dispatch],
                )
            }),
            constraints,
            strain_limit,
            track: (b.track_dispatch.1 > 0).then(|| {
                stage(
                    &kernels.track,
                    [hinges, &spare[0], &spare[1], &spare[2]],
                    vec![b.track_dispatch],
                )
            }),
            grab: kernels.grab.clone(),
            self_contact: b.self_contact.as_ref().map(|c| SelfContactStage {
                bind_group: group([&c.grid, &c.topology, &c.rest, &c.accum]),
                pipelines: kernels.self_contact.clone(),
                buckets: c.buckets,
            }),
            collide: (!b.collider_shapes.is_empty()).then(|| {
                stage(
                    &kernels.resolve,
                    [
                        &b.colliders,
                        &per_substep.poses,
                        &b.sdf_values,
                        &b.thickness,
                    ],
                    vec![b.whole],
                )
            }),
            update_velocities: kernels.update_velocities.clone(),
            state,
        }
    }
}

impl PerSubstep {
    fn new(device: &wgpu::Device, counts: &Counts, capacity: u32) -> Self {
        let buffer = |label, size: u64, usage| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: size.max(16),
                usage: usage | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            })
        };
        let c = capacity as u64;
        PerSubstep {
            capacity,
            params: buffer("params", c * UNIFORM_STRIDE, wgpu::BufferUsages::UNIFORM),
            targets: buffer(
                "pin targets",
                c * counts.pins as u64 * 16,
                wgpu::BufferUsages::STORAGE,
            ),
            poses: buffer(
                "collider poses",
                c * counts.colliders as u64 * size_of::<GpuPose>() as u64,
                wgpu::BufferUsages::STORAGE,
            ),
        }
    }
}

/// How a backend projects the cloth's constraints: the kinds it
/// dispatches in order, and what else the rest of the backend needs.
struct Projection {
    kinds: Vec<ConstraintBuffers>,
    /// Soft attachments in the order of their kernel (their targets follow
    /// the hard pins' in the per-substep target array).
    soft_pins: Vec<pleat::constraint::Attachment>,
    hinge_count: u32,
    /// Sweeps of the distances' strain limits after the iterations, before
    /// the further ones.
    strain_limit_sweeps: u32,
    /// Each colour's slice of the distances.
    distance_colours: Vec<Range>,
    /// Constraints projected per iteration, pins included.
    constraint_count: usize,
    /// The particles of each cloth nothing outside holds, whose projection
    /// must not turn them ([`pleat::solver::momentum`]); none for Jacobi.
    free_parts: Vec<std::ops::Range<usize>>,
    /// See [`GpuBackend::fold_limits`]; none for Jacobi.
    fold_limits: Option<(FoldLimits, Vec<DistanceConstraint>)>,
}

/// XPBD: hinges, distances, bending, isometric bending, soft attachments
/// and tethers, each coloured.
fn xpbd_projection(
    context: &GpuContext,
    model: &Model,
    hard_pins: usize,
    table: &mut RangeTable,
) -> Result<Projection, GpuError> {
    let c = XpbdConstraints::new(model);
    let (soft_kind, soft_pins) = soft_attachments(context, table, &c.soft_attachments, hard_pins)?;
    let kinds = vec![
        xpbd_kind(
            context,
            table,
            (ConstraintKind::Hinge, "hinges"),
            &c.hinges,
            c.hinges.items(),
        )?,
        xpbd_kind(
            context,
            table,
            (ConstraintKind::Distance, "distance constraints"),
            &c.distance,
            c.distance.items(),
        )?,
        xpbd_kind(
            context,
            table,
            (ConstraintKind::Bending, "bending"),
            &c.bending,
            c.bending.items(),
        )?,
        xpbd_kind(
            context,
            table,
            (ConstraintKind::Isometric, "isometric bending"),
            &c.isometric,
            c.isometric.items(),
        )?,
        soft_kind,
        xpbd_kind(
            context,
            table,
            (ConstraintKind::Tether, "tethers"),
            &c.tethers,
            c.tethers.items(),
        )?,
    ];
    Ok(Projection {
        kinds,
        soft_pins,
        hinge_count: c.hinges.len() as u32,
        strain_limit_sweeps: c.strain_limit_sweeps,
        distance_colours: c
            .distance
            .colors()
            .iter()
            .map(|r| Range {
                first: r.start as u32,
                count: r.len() as u32,
            })
            .collect(),
        constraint_count: c.len() + hard_pins,
        free_parts: c.free_parts.ranges().to_vec(),
        fold_limits: c
            .fold_limits
            .differ()
            .then(|| (c.fold_limits.clone(), c.distance.items().to_vec())),
    })
}

/// Jacobi PBD: corrections, their gather, then the soft attachments (as
/// the CPU's position-based loop solves them after each iteration).
fn jacobi_projection(
    context: &GpuContext,
    model: &Model,
    soft: Vec<pleat::constraint::Attachment>,
    hard_pins: usize,
    table: &mut RangeTable,
) -> Result<Projection, GpuError> {
    let jacobi = JacobiConstraints::new(model);
    check_size(
        context,
        jacobi.constraints.len() as u64 * 32,
        "Jacobi corrections",
    )?;
    let soft = ColoredConstraints::new(soft, model.particle_count());
    let [correct, gather] = jacobi_buffers(
        &context.device,
        &jacobi,
        model.particle_count() as u32,
        table,
    );
    let (soft_kind, soft_pins) = soft_attachments(context, table, &soft, hard_pins)?;
    Ok(Projection {
        kinds: vec![correct, gather, soft_kind],
        constraint_count: jacobi.constraints.len() + hard_pins + soft_pins.len(),
        soft_pins,
        hinge_count: 0,
        strain_limit_sweeps: 0,
        distance_colours: Vec::new(),
        free_parts: Vec::new(),
        fold_limits: None,
    })
}

/// The soft attachments' kernel data: each with the slot of its target
/// after the `hard_pins` hard pins' targets.
fn soft_attachments(
    context: &GpuContext,
    table: &mut RangeTable,
    set: &ColoredConstraints<pleat::constraint::Attachment>,
    hard_pins: usize,
) -> Result<(ConstraintBuffers, Vec<pleat::constraint::Attachment>), GpuError> {
    let gpu: Vec<Attachment> = set
        .items()
        .iter()
        .enumerate()
        .map(|(k, a)| Attachment {
            particle: a.particle[0],
            compliance: a.compliance,
            slot: (hard_pins + k) as u32,
            pad: 0,
        })
        .collect();
    let kind = xpbd_kind(
        context,
        table,
        (ConstraintKind::Attachment, "soft attachments"),
        set,
        &gpu,
    )?;
    Ok((kind, set.items().to_vec()))
}

/// One XPBD constraint kind on the GPU: its items as the kernel reads
/// them (`gpu_items`), coloured as `set`, with a multiplier each.
fn xpbd_kind<C, G: Pod>(
    context: &GpuContext,
    table: &mut RangeTable,
    (kind, label): (ConstraintKind, &str),
    set: &ColoredConstraints<C>,
    gpu_items: &[G],
) -> Result<ConstraintBuffers, GpuError> {
    check_size(context, size_of_val(gpu_items) as u64, label)?;
    let device = &context.device;
    Ok(ConstraintBuffers {
        items: storage(device, label, gpu_items),
        lambda: zeroed(device, "lambda", gpu_items.len() as u64 * 4),
        extra: None,
        dispatches: table.colours(set),
        kind,
    })
}

/// Jacobi PBD's two kernels: corrections per constraint (stiffness in the
/// compliance slot), then the gather over particles.
fn jacobi_buffers(
    device: &wgpu::Device,
    jacobi: &JacobiConstraints,
    particles: u32,
    table: &mut RangeTable,
) -> [ConstraintBuffers; 2] {
    let items: Vec<DistanceConstraint> = jacobi
        .constraints
        .iter()
        .zip(&jacobi.stiffness)
        .map(|(c, &k)| DistanceConstraint {
            compliance: k,
            ..*c
        })
        .collect();
    let (start, slots) = jacobi.incidence.rows();
    let slots: Vec<u32> = slots.iter().map(|s| 2 * s.element + s.end).collect();
    let items = storage(device, "jacobi constraints", &items);
    let corrections = zeroed(
        device,
        "jacobi corrections",
        jacobi.constraints.len() as u64 * 32,
    );
    let extra = [
        storage(device, "incidence start", start),
        storage(device, "incidence", &slots),
    ];
    [
        ConstraintBuffers {
            items: items.clone(),
            lambda: corrections.clone(),
            extra: Some(extra.clone()),
            dispatches: vec![table.push(0, jacobi.constraints.len() as u32)],
            kind: ConstraintKind::JacobiCorrect,
        },
        ConstraintBuffers {
            items,
            lambda: corrections,
            extra: Some(extra),
            dispatches: vec![table.push(0, particles)],
            kind: ConstraintKind::JacobiGather,
        },
    ]
}

/// Refuses solvers and features the GPU backend does not have yet.
fn check_supported(settings: &SolverSettings) -> Result<(), GpuError> {
    if !matches!(settings.kind, SolverKind::Xpbd | SolverKind::JacobiPbd) {
        return Err(GpuError::Unsupported {
            field: "solver.kind".into(),
            reason: format!(
                "the {} solver runs on the CPU backend only (the GPU backend runs xpbd and jacobi_pbd)",
                settings.kind.name()
            ),
        });
    }
    if settings.self_collision.enabled && settings.kind != SolverKind::Xpbd {
        return Err(GpuError::Unsupported {
            field: "solver.self_collision".into(),
            reason: "self-collision runs with the xpbd solver only".into(),
        });
    }
    Ok(())
}

/// Refuses more cloths than the live compliance table has slots for.
fn check_compliance_slots(model: &Model) -> Result<(), GpuError> {
    let slots = Compliances::of(model).len();
    if slots > COMPLIANCE_SLOTS {
        return Err(GpuError::TooLarge(format!(
            "{} cloths need {slots} compliance slots, more than the {COMPLIANCE_SLOTS} of the GPU backend's table",
            model.cloths.len()
        )));
    }
    Ok(())
}

/// Refuses a buffer larger than one binding may be.
fn check_size(context: &GpuContext, bytes: u64, what: &str) -> Result<(), GpuError> {
    let limit = context.device.limits().max_storage_buffer_binding_size;
    if bytes > limit {
        return Err(GpuError::TooLarge(format!(
            "the {what} take {} MiB, more than the {} MiB one buffer may hold on {}",
            bytes >> 20,
            limit >> 20,
            context.adapter
        )));
    }
    Ok(())
}

impl GpuBackend {
    /// Grows the per-substep buffers and the timestamp queries to hold
    /// `substeps` substeps.
    fn reserve(&mut self, substeps: u32) {
        let device = &self.context.device;
        if let Some(t) = &mut self.timestamps {
            t.reserve(device, substeps);
        }
        if substeps <= self.per_substep.capacity {
            return;
        }
        self.per_substep = PerSubstep::new(device, &self.counts, substeps);
        self.stages = Stages::new(
            device,
            &self.kernels,
            [&self.pos, &self.prev, &self.vel, &self.compliance_table],
            &self.buffers,
            &self.per_substep,
            &self.ranges,
        );
    }

    /// Writes the parameters, pin targets and collider poses of every
    /// substep of the frame, and the live compliances and friction.
    fn write_frame(
        &mut self,
        world: &World,
        (settings, table): (&SolverSettings, &Compliances),
        control: &Control,
    ) -> u32 {
        let frame_dt = control.frame_dt;
        let substeps = settings.substeps.max(1);
        self.reserve(substeps);
        let FrameData {
            params,
            targets,
            poses,
            compliances,
        } = &mut self.frame_data;
        table.write_to(compliances);
        compliances.resize(COMPLIANCE_SLOTS, 0.0);
        params.clear();
        params.resize((substeps as u64 * UNIFORM_STRIDE) as usize, 0);
        targets.clear();
        poses.clear();
        for (s, (t, dt)) in substep_times(world.time, frame_dt, substeps).enumerate() {
            let p = Params::at(world, settings, &self.counts, control, (s as u32, t, dt));
            let at = s * UNIFORM_STRIDE as usize;
            params[at..at + size_of::<Params>()].copy_from_slice(bytemuck::bytes_of(&p));
            for a in self.hard_pins.iter_mut().chain(self.soft_pins.iter_mut()) {
                a.update_target(t + dt);
                targets.push(a.target.extend(0.0).to_array());
            }
            poses.extend(
                world
                    .colliders
                    .iter()
                    .map(|c| GpuPose::from(ColliderPose::over(c, t, t + dt))),
            );
        }
        let queue = &self.context.queue;
        queue.write_buffer(&self.per_substep.params, 0, params);
        queue.write_buffer(&self.compliance_table, 0, bytemuck::cast_slice(compliances));
        if !targets.is_empty() {
            queue.write_buffer(&self.per_substep.targets, 0, bytemuck::cast_slice(targets));
        }
        if !poses.is_empty() {
            queue.write_buffer(&self.per_substep.poses, 0, bytemuck::cast_slice(poses));
        }
        let shapes = &mut self.buffers.collider_shapes;
        if data::refresh_friction(shapes, world) {
            queue.write_buffer(&self.buffers.colliders, 0, bytemuck::cast_slice(shapes));
        }
        substeps
    }

    /// Sweeps of the strain limits over the positions alone, before the
    /// frame's first prediction, until no edge is beyond its limit (up to
    /// [`pleat::solver::xpbd::FOLD_HOLD_SWEEPS`], in one dispatch): the velocities stay as they
    /// are ([`XpbdConstraints::meet_held_limits`]).
    fn record_held_limits(&self, encoder: &mut wgpu::CommandEncoder) {
        let Some(limits) = &self.stages.strain_limit else {
            return;
        };
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("held fold limits"),
            timestamp_writes: None,
        });
        pass.set_bind_group(0, &self.stages.state, &[0]);
        dispatch(&mut pass, &limits.held, Some(1));
    }

    /// Records one substep as four passes (stamped where the adapter has
    /// timestamps): prediction, constraints, self-contacts, collisions.
    /// Gives paper's strain limits those of a fold that is `held` or
    /// moves, writing the distance constraints again where they change
    /// ([`FoldLimits::apply`]).
    fn hold_fold(&mut self, held: bool) {
        let Some((limits, distances)) = &mut self.fold_limits else {
            return;
        };
        let Some(new) = limits.apply(held) else {
            return;
        };
        for (d, &limit) in distances.iter_mut().zip(new) {
            d.max_stretch = limit;
        }
        let buffer = self
            .buffers
            .constraints
            .iter()
            .find(|c| c.kind == ConstraintKind::Distance);
        if let Some(buffer) = buffer {
            let bytes = bytemuck::cast_slice(distances.as_slice());
            self.context.queue.write_buffer(&buffer.items, 0, bytes);
        }
    }

    fn record_substep(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        s: u32,
        (world, control): (&World, &Control),
        iterations: u32,
    ) {
        let st = &self.stages;
        let particles = self.counts.particles;
        let mut pass = |stage: TimedStage, record: &mut dyn FnMut(&mut wgpu::ComputePass<'_>)| {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("substep"),
                timestamp_writes: self.timestamps.as_ref().and_then(|t| t.writes(s, stage)),
            });
            pass.set_bind_group(0, &st.state, &[s * UNIFORM_STRIDE as u32]);
            record(&mut pass);
        };
        pass(TimedStage::Predict, &mut |pass| {
            if world.wind.is_some() {
                dispatch(pass, &st.wind[0], Some(self.counts.triangles));
                dispatch(pass, &st.wind[1], Some(particles));
            }
            over_particles(pass, &st.predict, particles);
            if let Some(pins) = &st.pins {
                dispatch(pass, pins, None);
            }
        });
        pass(TimedStage::Constraints, &mut |pass| {
            for _ in 0..iterations {
                for stage in &st.constraints {
                    dispatch(pass, stage, None);
                }
            }
            if let Some(limits) = &st.strain_limit {
                limits.record(pass);
            }
            if let Some(momentum) = &self.momentum {
                momentum.record(pass);
            }
            if let Some(track) = &st.track {
                dispatch(pass, track, None);
            }
            if control.grab.is_some() {
                pass.set_pipeline(&st.grab);
                pass.dispatch_workgroups(1, 1, 1);
            }
        });
        pass(TimedStage::SelfContacts, &mut |pass| {
            if let Some(contact) = &st.self_contact {
                contact.record(pass, particles);
            }
        });
        pass(TimedStage::Collisions, &mut |pass| {
            if let Some(collide) = &st.collide {
                dispatch(pass, collide, Some(particles));
            }
            over_particles(pass, &st.update_velocities, particles);
        });
    }

    /// Starts copying the three state buffers back.
    fn start_readback(&self) -> Readback {
        let size = self.counts.particles as u64 * PARTICLE_BYTES;
        Readback::start(
            (&self.context.device, &self.context.queue),
            &self.staging,
            &[&self.pos, &self.prev, &self.vel],
            size,
        )
    }

    /// Copies the three state buffers back, blocking until they arrive;
    /// a read asked for before is waited for and dropped first (it used
    /// the same buffer, and is older).
    fn read_state(&mut self) -> Result<Vec<[f32; 4]>, GpuError> {
        if let Some(older) = self.pending.take() {
            self.wait()?;
            let _ = older.try_take();
        }
        let readback = self.start_readback();
        // The map callback may only run on a later poll than the one that
        // saw the copy finish (seen once, in a CI check on lavapipe, with
        // several devices polled from parallel tests): poll again a few
        // times before giving up.
        for _ in 0..READBACK_POLLS {
            self.wait()?;
            if let Some(state) = readback.try_take() {
                return state;
            }
            std::thread::yield_now();
        }
        Err(GpuError::Readback("the state did not arrive".into()))
    }

    /// Waits until the device has run everything handed to it.
    fn wait(&self) -> Result<(), GpuError> {
        self.context
            .device
            .poll(wgpu::PollType::wait_indefinitely())
            .map(|_| ())
            .map_err(|e| GpuError::Readback(e.to_string()))
    }

    /// Puts `state` (positions, previous positions, velocities) into
    /// `particles`; a failed read leaves them NaN, so the run ends flagged,
    /// never silently wrong.
    fn unpack(state: Result<Vec<[f32; 4]>, GpuError>, particles: &mut Particles) {
        let n = particles.len();
        match state {
            Ok(state) => {
                let xyz = |k: usize| Vec3::new(state[k][0], state[k][1], state[k][2]);
                for i in 0..n {
                    particles.x[i] = xyz(i);
                    particles.x_prev[i] = xyz(n + i);
                    particles.v[i] = xyz(2 * n + i);
                }
            }
            Err(e) => {
                eprintln!("error: {e}");
                particles.x.fill(Vec3::NAN);
            }
        }
    }
}

/// Dispatches a kernel of the state alone over `particles` invocations.
fn over_particles(
    pass: &mut wgpu::ComputePass<'_>,
    pipeline: &wgpu::ComputePipeline,
    particles: u32,
) {
    pass.set_pipeline(pipeline);
    let (x, y) = workgroups(particles);
    pass.dispatch_workgroups(x, y, 1);
}

/// Dispatches `stage` over each of its slices, or over `count` invocations.
fn dispatch(pass: &mut wgpu::ComputePass<'_>, stage: &Stage, count: Option<u32>) {
    pass.set_pipeline(&stage.pipeline);
    match count {
        Some(count) => {
            if let Some(&(offset, _)) = stage.dispatches.first() {
                pass.set_bind_group(1, &stage.bind_group, &[offset]);
            }
            let (x, y) = workgroups(count);
            pass.dispatch_workgroups(x, y, 1);
        }
        None => {
            for &(offset, count) in &stage.dispatches {
                pass.set_bind_group(1, &stage.bind_group, &[offset]);
                let (x, y) = workgroups(count);
                pass.dispatch_workgroups(x, y, 1);
            }
        }
    }
}

impl Backend for GpuBackend {
    fn name(&self) -> &'static str {
        "gpu"
    }

    fn device(&self) -> String {
        self.context.adapter.clone()
    }

    fn constraint_count(&self) -> usize {
        self.constraint_count
    }

    fn step(
        &mut self,
        _particles: &mut Particles,
        world: &mut World,
        settings: &SolverSettings,
        compliances: &Compliances,
        control: &Control,
        stages: &mut StageTimes,
    ) {
        if let Some(t) = &mut self.timestamps {
            t.collect(stages);
        }
        self.hold_fold(control.fold.held);
        let frame_dt = control.frame_dt;
        let substeps = self.write_frame(world, (settings, compliances), control);
        if let Some(t) = &mut self.timestamps {
            t.begin_frame(&self.context.device, substeps);
        }
        let mut encoder =
            self.context
                .device
                .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                    label: Some("frame"),
                });
        let came_to_rest = self
            .fold_limits
            .as_mut()
            .is_some_and(|(limits, _)| limits.take_came_to_rest());
        if came_to_rest {
            self.record_held_limits(&mut encoder);
        }
        for s in 0..substeps {
            for lambda in &self.lambdas {
                encoder.clear_buffer(lambda, 0, None);
            }
            self.record_substep(&mut encoder, s, (world, control), settings.iterations);
        }
        let last = (substeps - 1) * UNIFORM_STRIDE as u32;
        self.health.record(
            &mut encoder,
            (&self.stages.state, last),
            world.time + frame_dt,
        );
        if let Some(t) = &self.timestamps {
            t.resolve(&mut encoder, substeps);
        }
        self.context.queue.submit([encoder.finish()]);
        self.health.request();
        if let Some(t) = &mut self.timestamps {
            t.request(substeps);
        }
        // Frees the resources of finished frames without waiting.
        let _ = self.context.device.poll(wgpu::PollType::Poll);
    }

    fn finish(&mut self, stages: &mut StageTimes) {
        let _ = self
            .context
            .device
            .poll(wgpu::PollType::wait_indefinitely());
        if let Some(t) = &mut self.timestamps {
            t.collect(stages);
        }
    }

    fn steps_in_place(&self) -> bool {
        false
    }

    fn download(&mut self, particles: &mut Particles) {
        let state = self.read_state();
        Self::unpack(state, particles);
    }

    fn request_download(&mut self) {
        if self.pending.is_none() {
            self.pending = Some(self.start_readback());
        }
    }

    fn try_download(&mut self, particles: &mut Particles) -> bool {
        let _ = self.context.device.poll(wgpu::PollType::Poll);
        let Some(state) = self.pending.as_ref().and_then(Readback::try_take) else {
            return false;
        };
        self.pending = None;
        Self::unpack(state, particles);
        true
    }

    fn as_any(&self) -> &dyn std::any::Any {
        self
    }

    fn health(&mut self) -> Option<pleat::stability::Health> {
        let _ = self.context.device.poll(wgpu::PollType::Poll);
        self.health.collect()
    }

    fn upload(&mut self, particles: &Particles) {
        let with = |v: &[Vec3], w: &dyn Fn(usize) -> f32| -> Vec<[f32; 4]> {
            v.iter()
                .enumerate()
                .map(|(i, p)| [p.x, p.y, p.z, w(i)])
                .collect()
        };
        let inv_mass = |i: usize| particles.inv_mass[i];
        let queue = &self.context.queue;
        if particles.is_empty() {
            return;
        }
        queue.write_buffer(
            &self.pos,
            0,
            bytemuck::cast_slice(&with(&particles.x, &inv_mass)),
        );
        queue.write_buffer(
            &self.prev,
            0,
            bytemuck::cast_slice(&with(&particles.x_prev, &inv_mass)),
        );
        queue.write_buffer(
            &self.vel,
            0,
            bytemuck::cast_slice(&with(&particles.v, &|_| 0.0)),
        );
    }
}
