//! Upload and buffers: [`GpuBackend::new`] checks what the backend can
//! run, builds the model's buffers (the state, the kernels' inputs, the
//! per-substep buffers and the range table) and uploads them; the state is
//! uploaded again when the caller replaces it, and the distances when the
//! fold's strain limits change.

use super::bindings::Stages;
use super::persistent::{self, Persistent};
use super::projection::{
    jacobi_projection, xpbd_projection, ConstraintBuffers, ConstraintKind, Projection,
};
use super::record::FrameData;
use super::{GpuBackend, PARTICLE_BYTES};
use crate::buffers::{storage, zeroed};
use crate::context::{GpuContext, GpuError};
use crate::data::{self, Counts, GpuCollider, GpuPose, Range};
use crate::health::{HealthInputs, HealthWatch, TearEdges};
use crate::kernels::{workgroups, Kernels, BUILD_KERNELS, COMPLIANCE_SLOTS, UNIFORM_STRIDE};
use crate::momentum::Momentum;
use crate::timing::Timestamps;
use glam::Vec3;
use pleat::constraint::Compliances;
use pleat::mesh::incidence::Incidence;
use pleat::model::Model;
use pleat::solver::grab_reach::GrabReach;
use pleat::solver::parallel::ColoredConstraints;
use pleat::solver::position_based::attachments;
use pleat::solver::{SolverKind, SolverSettings};
use pleat::{Particles, World};
use wgpu::util::DeviceExt;

/// The ranges of every dispatch, 256 bytes apart, built before upload.
#[derive(Default)]
pub(super) struct RangeTable(Vec<Range>);

impl RangeTable {
    /// Adds a slice and returns its dynamic offset and count.
    pub(super) fn push(&mut self, first: u32, count: u32) -> (u32, u32) {
        self.0.push(Range { first, count });
        (
            (self.0.len() as u64 - 1) as u32 * UNIFORM_STRIDE as u32,
            count,
        )
    }

    pub(super) fn colours<C>(&mut self, set: &ColoredConstraints<C>) -> Vec<(u32, u32)> {
        set.colors()
            .iter()
            .filter(|r| !r.is_empty())
            .map(|r| self.push(r.start as u32, r.len() as u32))
            .collect()
    }

    /// The slice at dynamic offset `offset`.
    pub(super) fn at(&self, offset: u32) -> Range {
        self.0[(offset as u64 / UNIFORM_STRIDE) as usize]
    }

    pub(super) fn bytes(&self) -> Vec<u8> {
        let mut bytes = vec![0u8; self.0.len().max(1) * UNIFORM_STRIDE as usize];
        for (k, r) in self.0.iter().enumerate() {
            let at = k * UNIFORM_STRIDE as usize;
            bytes[at..at + size_of::<Range>()].copy_from_slice(bytemuck::bytes_of(r));
        }
        bytes
    }
}

/// Buffers whose size depends on the number of substeps per frame.
pub(super) struct PerSubstep {
    pub(super) capacity: u32,
    pub(super) params: wgpu::Buffer,
    pub(super) targets: wgpu::Buffer,
    pub(super) poses: wgpu::Buffer,
}

/// Buffers of the kernels of group 1, by kernel.
pub(super) struct KernelBuffers {
    /// Items and lambdas of each constraint kind, in projection order.
    pub(super) constraints: Vec<ConstraintBuffers>,
    /// The distances' strain limits, where an edge has one.
    pub(super) strain_limit: Option<StrainLimitBuffers>,
    pub(super) hard_pins: wgpu::Buffer,
    pub(super) pin_dispatch: (u32, u32),
    pub(super) track_dispatch: (u32, u32),
    pub(super) triangles: wgpu::Buffer,
    pub(super) triangle_force: wgpu::Buffer,
    pub(super) around_start: wgpu::Buffer,
    pub(super) around: wgpu::Buffer,
    pub(super) colliders: wgpu::Buffer,
    /// What `colliders` holds, its friction refreshed from the world.
    pub(super) collider_shapes: Vec<GpuCollider>,
    pub(super) sdf_values: wgpu::Buffer,
    pub(super) thickness: wgpu::Buffer,
    pub(super) whole: (u32, u32),
    pub(super) self_contact: Option<SelfContactBuffers>,
    /// The grabbed particle's reach (XPBD): rest positions with reach
    /// factors, each particle's cloth, the dispatch over the particles.
    pub(super) grab_reach: Option<([wgpu::Buffer; 2], (u32, u32))>,
}

/// The self-contacts' hash grid, candidates and dispatch counts, and their
/// inputs and outputs.
pub(super) struct SelfContactBuffers {
    /// Bucket counts and starts, fill counters, sorted particles, scan sums.
    pub(super) grid: wgpu::Buffer,
    /// Triangles, then the triangles each vertex owns (compressed rows).
    pub(super) topology: wgpu::Buffer,
    /// Rest positions with the cloth's index in w, then the positions at
    /// the last build.
    pub(super) rest: wgpu::Buffer,
    /// Fixed-point corrections and contact counts per particle.
    pub(super) accum: wgpu::Buffer,
    /// Header (pairs found, fresh, counters, the margin's state), then the pairs.
    pub(super) candidates: wgpu::Buffer,
    /// The indirect dispatches' workgroup counts: the build's, the solve's,
    /// then the build's when it runs.
    pub(super) args: wgpu::Buffer,
    /// Hash grid cell size with the margin (less the margin without it).
    pub(super) cell: f32,
    /// Hash table size: a power of two, a multiple of the scan block.
    pub(super) buckets: u32,
    pub(super) margin: f32,
    pub(super) exclusion: f32,
    /// Most candidate pairs kept.
    pub(super) capacity: u32,
    /// Jacobi iterations a substep, the CPU backend's
    /// ([`pleat::collide::self_contact::iterations`]).
    pub(super) iterations: u32,
    /// Whether it has been said that they cannot grow.
    pub(super) told_full: bool,
}

/// What the strain limits' sweeps need besides the distances' items.
pub(super) struct StrainLimitBuffers {
    /// The sweeps after the iterations before the further ones: the CPU's
    /// [`pleat::solver::xpbd::STRAIN_LIMIT_SWEEPS`].
    pub(super) sweeps: u32,
    /// Each colour's slice of the distances, for the further sweeps.
    pub(super) colours: wgpu::Buffer,
    /// Whether the last sweep found an edge far beyond its limit.
    pub(super) beyond: wgpu::Buffer,
}

impl StrainLimitBuffers {
    pub(super) fn new(device: &wgpu::Device, sweeps: u32, colours: &[Range]) -> Option<Self> {
        (sweeps > 0).then(|| StrainLimitBuffers {
            sweeps,
            colours: storage(device, "distance colours", colours),
            beyond: zeroed(device, "beyond the slack", 4),
        })
    }
}

/// Most a rest edge may stretch and still find its triangles' contacts.
const CONTACT_EDGE_STRETCH: f32 = 1.5;
/// A cloth's pairs closer at rest than this many thicknesses never collide.
const CONTACT_EXCLUSION: f32 = 2.0;
/// How much farther than the thickness a candidate pair may lie, in
/// thicknesses: below the exclusion radius less one, so that flat cloth,
/// and cloth compressed by up to an eighth, gives no candidates.
const CONTACT_MARGIN: f32 = 0.75;
/// Candidate pairs per particle kept at most.
const CANDIDATES_PER_PARTICLE: u64 = 16;
/// Words of the candidates' header (`HEADER` in lib/contact.wgsl).
const CANDIDATE_HEADER: u64 = 16;
/// The first word of the margin's state in that header (`FRAME_BUILDS`),
/// and its words.
const MARGIN_STATE: (u64, u64) = (12, 4);

impl SelfContactBuffers {
    pub(super) fn new(
        device: &wgpu::Device,
        model: &Model,
        thickness: f32,
        triangles: &[u32],
    ) -> Self {
        let n = model.particle_count() as u32;
        let longest = model
            .edges
            .iter()
            .map(|e| e.rest_length)
            .fold(0.0, f32::max);
        let exclusion = CONTACT_EXCLUSION * thickness;
        let margin = CONTACT_MARGIN * thickness;
        let buckets = (2 * n).next_power_of_two().max(crate::kernels::WORKGROUP);
        let grid_len = 2 * buckets as u64 + n as u64 + (buckets / crate::kernels::WORKGROUP) as u64;
        let (start, owned) = owned_triangles(model);
        let topology: Vec<u32> = [triangles, &start, &owned].concat();
        let mut rest = vec![[0.0; 4]; 2 * n as usize];
        for (k, cloth) in model.cloths.iter().enumerate() {
            for i in cloth.particles() {
                rest[i] = model.rest[i].extend(k as f32).to_array();
            }
        }
        let capacity = (CANDIDATES_PER_PARTICLE * u64::from(n))
            .min(largest_capacity(device))
            .max(1);
        let narrow_cell = CONTACT_EDGE_STRETCH * longest + thickness;
        SelfContactBuffers {
            grid: zeroed(device, "contact grid", grid_len * 4),
            topology: storage(device, "topology", &topology),
            rest: storage(device, "rest positions", &rest),
            accum: zeroed(device, "contact corrections", n as u64 * 16),
            args: indirect_args(device, build_workgroups(n, buckets)),
            candidates: candidates(device, capacity),
            cell: narrow_cell + margin,
            buckets,
            margin,
            exclusion,
            capacity: capacity as u32,
            iterations: pleat::collide::self_contact::iterations(model) as u32,
            told_full: false,
        }
    }

    /// After a build found `found` pairs, more than the candidates hold
    /// (those beyond were not solved), a buffer for [`GROWTH`] times as
    /// many (twice the last at least), up to the largest a binding takes,
    /// zeroed so that the next substep builds afresh but for the margin's
    /// state, carried over. False when it is that large already.
    pub(super) fn grow(
        &mut self,
        (device, queue): (&wgpu::Device, &wgpu::Queue),
        found: u64,
    ) -> bool {
        let wanted = (found as f64 * GROWTH) as u64;
        let capacity = wanted
            .max(2 * u64::from(self.capacity))
            .min(largest_capacity(device));
        if capacity <= u64::from(self.capacity) {
            return false;
        }
        let grown = candidates(device, capacity);
        let mut encoder = device.create_command_encoder(&Default::default());
        let (first, words) = MARGIN_STATE;
        encoder.copy_buffer_to_buffer(&self.candidates, 4 * first, &grown, 4 * first, 4 * words);
        queue.submit([encoder.finish()]);
        self.candidates = grown;
        self.capacity = capacity as u32;
        true
    }
}

/// Room for how many times the pairs a build found, when they overflowed
/// the candidates: a cloth that settles into more layers finds more.
const GROWTH: f64 = 1.5;

/// The most candidate pairs one binding of `device` holds.
fn largest_capacity(device: &wgpu::Device) -> u64 {
    let words = device.limits().max_storage_buffer_binding_size / 4;
    ((words - CANDIDATE_HEADER) / 2).min(u64::from(u32::MAX))
}

/// A candidates buffer of `capacity` pairs, zeroed: not fresh, so the
/// first substep builds.
fn candidates(device: &wgpu::Device, capacity: u64) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("contact candidates"),
        size: (CANDIDATE_HEADER + 2 * capacity) * 4,
        usage: wgpu::BufferUsages::STORAGE
            | wgpu::BufferUsages::COPY_DST
            | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    })
}

/// The workgroups of the build's kernels over `n` particles and `buckets`
/// buckets: clear, count, scan_blocks, scan_sums, scan_add, scatter, find.
fn build_workgroups(n: u32, buckets: u32) -> [(u32, u32); BUILD_KERNELS] {
    [
        workgroups(2 * buckets),
        workgroups(n),
        workgroups(buckets / crate::kernels::WORKGROUP),
        (1, 1),
        workgroups(buckets),
        workgroups(n),
        workgroups(n),
    ]
}

/// The indirect dispatches' buffer: the build's and the solve's counts
/// (written on the GPU), then the build's when it runs.
fn indirect_args(device: &wgpu::Device, build: [(u32, u32); BUILD_KERNELS]) -> wgpu::Buffer {
    let mut words = vec![0u32; 3 * (BUILD_KERNELS + 1)];
    words.extend(build.iter().flat_map(|&(x, y)| [x, y, 1]));
    device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("contact dispatches"),
        contents: bytemuck::cast_slice(&words),
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::INDIRECT,
    })
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

impl GpuBackend {
    /// Writes `particles`' state (positions and previous positions with
    /// the inverse mass in w, velocities) into the state buffers.
    pub(super) fn upload_state(&mut self, particles: &Particles) {
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
        // Positions set from outside: the self-contacts' candidates are stale.
        if let Some(contact) = &self.buffers.self_contact {
            queue.write_buffer(&contact.candidates, 4, bytemuck::bytes_of(&0u32));
        }
    }

    /// Gives paper's strain limits those of a fold that is `held` or
    /// moves, writing the distance constraints again where they change
    /// ([`pleat::solver::xpbd::FoldLimits::apply`]).
    pub(super) fn hold_fold(&mut self, held: bool) {
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

    /// Gives the hinges the start and end angles of a fold's step: writes
    /// each changed hinge's `full_angle` and `start_angle` (side by side)
    /// into the items buffer, leaving the tracked `angle` the GPU keeps.
    pub(super) fn write_hinge_targets(&mut self, targets: &pleat::fold_steps::HingeTargets) {
        use pleat::constraint::OrigamiHinge;
        const FULL: usize = std::mem::offset_of!(OrigamiHinge, full_angle);
        const START: usize = std::mem::offset_of!(OrigamiHinge, start_angle);
        const _: () = assert!(START == FULL + 4, "start_angle must follow full_angle");
        let Some(buffer) = self
            .buffers
            .constraints
            .iter()
            .find(|c| c.kind == ConstraintKind::Hinge)
        else {
            return;
        };
        let size = std::mem::size_of::<OrigamiHinge>();
        for (i, h) in self.hinges.iter_mut().enumerate() {
            if targets.apply(h) {
                let bytes = [h.full_angle, h.start_angle];
                self.context.queue.write_buffer(
                    &buffer.items,
                    (i * size + FULL) as u64,
                    bytemuck::cast_slice(&bytes),
                );
            }
        }
    }

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
        let tears = TearEdges::of(model);
        let tear_range = table.push(0, tears.len());
        let grab_reach = (settings.kind != SolverKind::JacobiPbd).then(|| {
            let reach = GrabReach::new(model);
            (
                [
                    storage(device, "grab reach", &reach.rest),
                    storage(device, "cloth of each particle", &reach.cloth),
                ],
                table.push(0, n as u32),
            )
        });
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
            hinges,
        } = projection;
        let free_part_ranges = free_parts;
        let free_parts: Vec<(u32, u32)> = free_part_ranges
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
            grab_reach,
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
        let contact = buffers.self_contact.as_ref();
        let counts = Counts {
            particles: n as u32,
            triangles: model.triangles.len() as u32,
            pins: (hard_pins.len() + soft_pins.len()) as u32,
            colliders: buffers.collider_shapes.len() as u32,
            contact_cell: contact.map_or(0.0, |c| c.cell),
            contact_buckets: contact.map_or(0, |c| c.buckets),
            contact_margin: contact.map_or(0.0, |c| c.margin),
            contact_exclusion: contact.map_or(0.0, |c| c.exclusion),
            contact_capacity: contact.map_or(0, |c| c.capacity),
        };
        let sheet = persistent::Sheet {
            kinds: &buffers.constraints,
            table: &table,
            strain_limit_sweeps,
            free_parts: &free_part_ranges,
            particles: n,
            has_more: settings.kind != SolverKind::Xpbd
                || !hard_indices.is_empty()
                || !buffers.collider_shapes.is_empty()
                || buffers.self_contact.is_some(),
        };
        // The persistent kernel binds the parameters of MAX_SUBSTEPS substeps.
        let may_persist = persistent::may_run(&sheet);
        let capacity = match may_persist {
            true => settings.substeps.max(persistent::MAX_SUBSTEPS),
            false => settings.substeps.max(1),
        };
        let per_substep = PerSubstep::new(device, &counts, capacity);
        let lambdas = buffers
            .constraints
            .iter()
            .filter(|k| k.kind.has_multipliers())
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
                tears: &tears,
                ranges: (&ranges, tear_range.0),
                contact_counts: buffers.self_contact.as_ref().map(|c| &c.candidates),
            },
        );
        let momentum = Momentum::new(device, &kernels, (&ranges, free_parts), n as u32);
        let persistent = may_persist
            .then(|| {
                let state = persistent::StateBuffers {
                    pos: &pos,
                    prev: &prev,
                    vel: &vel,
                    params: &per_substep.params,
                    compliances: &compliance_table,
                };
                let left = momentum.as_ref().map(Momentum::left);
                Persistent::new((device, context.device_type), &sheet, left, &state)
            })
            .flatten();
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
            hinges,
            persistent,
            persistent_allowed: true,
            dispatches: 0,
        };
        Ok((backend, notes))
    }
}

impl PerSubstep {
    pub(super) fn new(device: &wgpu::Device, counts: &Counts, capacity: u32) -> Self {
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
pub(super) fn check_size(context: &GpuContext, bytes: u64, what: &str) -> Result<(), GpuError> {
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
