//! Pipelines and bind groups: every kernel with its buffers bound
//! ([`Stages`]), rebuilt when the per-substep buffers grow.

use super::kernel_buffers::{KernelBuffers, PerSubstep};
use super::projection::ConstraintKind;
use super::GpuBackend;
use crate::buffers::{entry, sized_entry, zeroed};
use crate::data::{Params, Range};
use crate::health::ContactCounts;
use crate::kernels::{ContactSolve, DistanceLimit, Kernels, SelfContactKernels};

/// One kernel with its buffers bound, and the slices it is dispatched on.
pub(super) struct Stage {
    pub(super) pipeline: wgpu::ComputePipeline,
    pub(super) bind_group: wgpu::BindGroup,
    /// Dynamic offset into the range buffer and invocation count, per dispatch.
    pub(super) dispatches: Vec<(u32, u32)>,
}

/// The self-contact kernels with their bind groups.
pub(super) struct SelfContactStage {
    /// The broad phase's: grid, topology, rest, candidates.
    pub(super) grid: wgpu::BindGroup,
    /// The dispatch counts': counts, topology, rest, candidates.
    pub(super) arm: wgpu::BindGroup,
    /// The solve's: candidates, topology, rest, corrections.
    pub(super) solve: wgpu::BindGroup,
    pub(super) kernels: SelfContactKernels,
    /// The solve's kernels: each contact's corrections scaled as one
    /// (paper's) or each particle's averaged (cloth's).
    pub(super) solve_kernels: ContactSolve,
    /// The indirect dispatches' workgroup counts.
    pub(super) args: wgpu::Buffer,
    /// Jacobi iterations a substep ([`pleat::collide::self_contact::iterations`]).
    pub(super) iterations: u32,
    /// Whether a build takes edge pairs (the model has paper).
    pub(super) edge_pairs: bool,
}

/// Every kernel with its bind group, in the order a substep runs them.
pub(super) struct Stages {
    pub(super) state: wgpu::BindGroup,
    pub(super) wind: [Stage; 2],
    /// Kernels of the state alone (group 0).
    pub(super) predict: wgpu::ComputePipeline,
    pub(super) pins: Option<Stage>,
    /// In projection order: the hierarchy, hinges, distances, bending,
    /// isometric, soft attachments, tethers.
    pub(super) constraints: Vec<Stage>,
    /// The distances' strain limits alone.
    pub(super) strain_limit: Option<StrainLimitStages>,
    pub(super) track: Option<Stage>,
    pub(super) grab: wgpu::ComputePipeline,
    /// The grabbed particle's reach over its cloth, after the grab (XPBD).
    pub(super) grab_reach: Option<Stage>,
    pub(super) self_contact: Option<SelfContactStage>,
    pub(super) collide: Option<Stage>,
    pub(super) update_velocities: wgpu::ComputePipeline,
}

/// Most distances whose strain limits one workgroup sweeps, every sweep of
/// a substep in one dispatch: up to this, it walks each colour in a few
/// rounds. On lavapipe the rigid demo's 12,033 distances ran faster so
/// than with a dispatch per colour and sweep (BENCHMARKS.md); the bound
/// itself is not measured.
const ONE_WORKGROUP_EDGES: u32 = 16_384;

/// The strain limits' sweeps after the iterations, as the CPU runs them
/// (`Xpbd`'s `sweep_strain_limits`): the first sweeps, the last of them
/// noting whether an edge is beyond [`pleat::solver::xpbd::STRAIN_LIMIT_SLACK`]
/// times its limit, then while one is, further sweeps up to
/// [`pleat::solver::xpbd::MAX_STRAIN_LIMIT_SWEEPS`] in all. The further
/// sweeps run in one workgroup of one dispatch, a barrier between
/// colours, so that they stop themselves with no read back; a sheet that
/// is not jammed pays one empty dispatch.
/// The held limits are met in one such dispatch too, or in rounds of
/// them where the paper has self-contacts.
pub(super) struct StrainLimitStages {
    pub(super) substep: SubstepSweeps,
    pub(super) held: Stage,
    pub(super) held_round: Stage,
}

/// How a substep's strain-limit sweeps are dispatched.
pub(super) enum SubstepSweeps {
    /// A sheet of at most [`ONE_WORKGROUP_EDGES`] distances: every sweep
    /// in one dispatch of one workgroup, the first
    /// [`pleat::solver::xpbd::STRAIN_LIMIT_SWEEPS`] then the further ones.
    InOneWorkgroup(Stage),
    /// `sweeps - 1` sweeps and the one that measures, a dispatch per colour
    /// each, then the further sweeps in one workgroup.
    PerColour {
        sweep: Stage,
        measured: Stage,
        further: Stage,
        sweeps: u32,
    },
}

impl Stages {
    pub(super) fn new(
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
                    ConstraintKind::Snapshot => &kernels.snapshot,
                    ConstraintKind::LongRange => &kernels.long_range,
                    ConstraintKind::Prolongate => &kernels.prolongate,
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
                let limit_stage = |kernel: DistanceLimit| {
                    let pipeline = &kernels.distance_limit[kernel as usize];
                    stage(pipeline, buffers, k.dispatches.clone())
                };
                let edges: u32 = k.dispatches.iter().map(|&(_, count)| count).sum();
                let substep = if edges <= ONE_WORKGROUP_EDGES {
                    SubstepSweeps::InOneWorkgroup(limit_stage(DistanceLimit::Alone))
                } else {
                    SubstepSweeps::PerColour {
                        sweep: limit_stage(DistanceLimit::Sweep),
                        measured: limit_stage(DistanceLimit::Measured),
                        further: limit_stage(DistanceLimit::Further),
                        sweeps: limits.sweeps,
                    }
                };
                StrainLimitStages {
                    substep,
                    held: limit_stage(DistanceLimit::Held),
                    held_round: limit_stage(DistanceLimit::HeldRound),
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
            grab_reach: b.grab_reach.as_ref().map(|([rest, cloth], dispatch)| {
                stage(
                    &kernels.grab_reach,
                    [rest, cloth, &spare[0], &spare[1]],
                    vec![*dispatch],
                )
            }),
            self_contact: b.self_contact.as_ref().map(|c| SelfContactStage {
                grid: group([&c.grid, &c.topology, &c.rest, &c.candidates]),
                arm: group([&c.args, &c.topology, &c.rest, &c.candidates]),
                solve: group([&c.candidates, &c.topology, &c.rest, &c.accum]),
                kernels: kernels.self_contact.clone(),
                solve_kernels: if c.scaled {
                    kernels.self_contact.scaled.clone()
                } else {
                    kernels.self_contact.averaged.clone()
                },
                args: c.args.clone(),
                iterations: c.iterations,
                edge_pairs: c.edge_pairs,
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

impl GpuBackend {
    /// Grows the per-substep buffers and the timestamp queries to hold
    /// `substeps` substeps.
    pub(super) fn reserve(&mut self, substeps: u32) {
        let device = &self.context.device;
        if let Some(t) = &mut self.timestamps {
            t.reserve(device, substeps);
        }
        if substeps <= self.per_substep.capacity {
            return;
        }
        self.per_substep = PerSubstep::new(device, &self.counts, substeps);
        if let Some(p) = &mut self.persistent {
            p.rebind_state(
                device,
                &super::persistent::StateBuffers {
                    pos: &self.pos,
                    prev: &self.prev,
                    vel: &self.vel,
                    params: &self.per_substep.params,
                    compliances: &self.compliance_table,
                },
            );
        }
        self.rebind_stages();
    }

    /// Binds every kernel to the buffers anew (after one was replaced).
    fn rebind_stages(&mut self) {
        self.stages = Stages::new(
            &self.context.device,
            &self.kernels,
            [&self.pos, &self.prev, &self.vel, &self.compliance_table],
            &self.buffers,
            &self.per_substep,
            &self.ranges,
        );
    }

    /// Grows the self-contacts' candidates when a build that came back
    /// found more pairs than they hold, and binds the larger buffer; says
    /// once when they cannot grow (those beyond are then not solved).
    pub(super) fn grow_candidates(&mut self, counts: Option<ContactCounts>) {
        let Some(contact) = &mut self.buffers.self_contact else {
            return;
        };
        let Some(found) = counts.map(|c| c.overflowed).filter(|&found| found > 0) else {
            return;
        };
        if !contact.grow((&self.context.device, &self.context.queue), found) {
            if !contact.told_full {
                contact.told_full = true;
                eprintln!(
                    "warning: the self-contacts found more candidate pairs than the GPU's \
                     largest buffer holds ({}); those beyond were dropped (a thickness \
                     many times the cloth's edge length finds hundreds of pairs a particle)",
                    contact.capacity
                );
            }
            return;
        }
        self.counts.contact_capacity = contact.capacity;
        self.health.set_contact_counts(&contact.candidates);
        self.rebind_stages();
    }
}
