//! The constraint kinds' buffers, by solver: XPBD's coloured kinds (the
//! hierarchy's levels, hinges, distances, bending, isometric bending, soft
//! attachments, tethers) or
//! Jacobi PBD's corrections and gather, each with the dispatches of its
//! colours in the range table.

use super::ranges::RangeTable;
use crate::buffers::{check_size, storage, zeroed};
use crate::context::{GpuContext, GpuError};
use crate::data::{Attachment, Range};
use bytemuck::Pod;
use pleat::constraint::DistanceConstraint;
use pleat::model::Model;
use pleat::solver::hierarchy::Hierarchy;
use pleat::solver::jacobi::JacobiConstraints;
use pleat::solver::parallel::ColoredConstraints;
use pleat::solver::xpbd::{FoldLimits, XpbdConstraints};

/// One constraint kind's buffers and its dispatches (by colour).
pub(super) struct ConstraintBuffers {
    pub(super) items: wgpu::Buffer,
    /// The Lagrange multipliers (cleared every substep), or Jacobi's corrections.
    pub(super) lambda: wgpu::Buffer,
    /// Bindings 2 and 3; `None`: the pin targets and the items again.
    pub(super) extra: Option<[wgpu::Buffer; 2]>,
    pub(super) dispatches: Vec<(u32, u32)>,
    pub(super) kind: ConstraintKind,
}

#[derive(Clone, Copy, PartialEq, Eq)]
pub(super) enum ConstraintKind {
    Hinge,
    Distance,
    Bending,
    Isometric,
    Attachment,
    Tether,
    JacobiCorrect,
    JacobiGather,
    /// The hierarchy: the positions noted, a level's coarse edges, its
    /// prolongation (their "lambda" buffer: the noted positions, which the
    /// coarse edges read as their floors and the prolongation as its start).
    Snapshot,
    LongRange,
    Prolongate,
}

impl ConstraintKind {
    /// Whether the kind's second buffer holds per-substep multipliers (or
    /// Jacobi's corrections), cleared at the start of every substep.
    pub(super) fn has_multipliers(self) -> bool {
        !matches!(
            self,
            ConstraintKind::Snapshot | ConstraintKind::LongRange | ConstraintKind::Prolongate
        )
    }
}

/// How a backend projects the cloth's constraints: the kinds it
/// dispatches in order, and what else the rest of the backend needs.
pub(super) struct Projection {
    pub(super) kinds: Vec<ConstraintBuffers>,
    /// Soft attachments in the order of their kernel (their targets follow
    /// the hard pins' in the per-substep target array).
    pub(super) soft_pins: Vec<pleat::constraint::Attachment>,
    pub(super) hinge_count: u32,
    /// Sweeps of the distances' strain limits after the iterations, before
    /// the further ones.
    pub(super) strain_limit_sweeps: u32,
    /// Whether the strain limits are swept again after the contacts, where
    /// anything touches the cloth (`XpbdConstraints::limits_after_contacts`).
    pub(super) limits_after_contacts: bool,
    /// Each colour's slice of the distances.
    pub(super) distance_colours: Vec<Range>,
    /// Constraints projected per iteration, pins included.
    pub(super) constraint_count: usize,
    /// The particles of each cloth nothing outside holds, whose projection
    /// must not turn them ([`pleat::solver::momentum`]); none for Jacobi.
    pub(super) free_parts: Vec<std::ops::Range<usize>>,
    /// See [`super::GpuBackend`]'s `fold_limits`; none for Jacobi.
    pub(super) fold_limits: Option<(FoldLimits, Vec<DistanceConstraint>)>,
    /// The hinges as the items buffer holds them (their tracked angles as
    /// built); none for Jacobi.
    pub(super) hinges: Vec<pleat::constraint::OrigamiHinge>,
}

/// XPBD: the hierarchy's levels, then hinges, distances, bending,
/// isometric bending, soft attachments and tethers, each coloured.
pub(super) fn xpbd_projection(
    context: &GpuContext,
    model: &Model,
    hard_pins: usize,
    table: &mut RangeTable,
) -> Result<Projection, GpuError> {
    let c = XpbdConstraints::new(model);
    let (soft_kind, soft_pins) = soft_attachments(context, table, &c.soft_attachments, hard_pins)?;
    let mut kinds = hierarchy(context, table, &c.hierarchy, model.particle_count())?;
    kinds.extend([
        as_is(context, table, (ConstraintKind::Hinge, "hinges"), &c.hinges)?,
        as_is(
            context,
            table,
            (ConstraintKind::Distance, "distance constraints"),
            &c.distance,
        )?,
        as_is(
            context,
            table,
            (ConstraintKind::Bending, "bending"),
            &c.bending,
        )?,
        as_is(
            context,
            table,
            (ConstraintKind::Isometric, "isometric bending"),
            &c.isometric,
        )?,
        soft_kind,
        as_is(
            context,
            table,
            (ConstraintKind::Tether, "tethers"),
            &c.tethers,
        )?,
    ]);
    Ok(Projection {
        kinds,
        soft_pins,
        hinge_count: c.hinges.len() as u32,
        strain_limit_sweeps: c.strain_limit_sweeps,
        limits_after_contacts: c.limits_after_contacts,
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
        hinges: c.hinges.items().to_vec(),
    })
}

/// The hierarchy as the CPU solves it ([`Hierarchy::solve`]): the
/// positions noted, then each level, coarsest first, its coarse edges by
/// colour and its prolongation in one dispatch. None without levels.
fn hierarchy(
    context: &GpuContext,
    table: &mut RangeTable,
    hierarchy: &Hierarchy,
    particles: usize,
) -> Result<Vec<ConstraintBuffers>, GpuError> {
    if hierarchy.is_empty() {
        return Ok(Vec::new());
    }
    let device = &context.device;
    check_size(context, particles as u64 * 16, "hierarchy")?;
    let start = zeroed(device, "hierarchy start", particles as u64 * 16);
    let unused = || zeroed(device, "unused", 16);
    let mut kinds = vec![ConstraintBuffers {
        items: unused(),
        lambda: start.clone(),
        extra: None,
        dispatches: vec![table.push(0, particles as u32)],
        kind: ConstraintKind::Snapshot,
    }];
    for level in hierarchy.levels().iter().rev() {
        let limits = level.limits.items();
        check_size(context, size_of_val(limits) as u64, "hierarchy levels")?;
        check_size(
            context,
            size_of_val(&level.prolongation[..]) as u64,
            "hierarchy levels",
        )?;
        kinds.push(ConstraintBuffers {
            items: storage(device, "coarse edges", limits),
            // The noted positions: each edge's floor.
            lambda: start.clone(),
            extra: None,
            dispatches: table.colours(&level.limits),
            kind: ConstraintKind::LongRange,
        });
        kinds.push(ConstraintBuffers {
            items: storage(device, "prolongation", &level.prolongation),
            lambda: start.clone(),
            extra: None,
            dispatches: vec![table.push(0, level.prolongation.len() as u32)],
            kind: ConstraintKind::Prolongate,
        });
    }
    Ok(kinds)
}

/// Jacobi PBD: corrections, their gather, then the soft attachments (as
/// the CPU's position-based loop solves them after each iteration).
pub(super) fn jacobi_projection(
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
        limits_after_contacts: false,
        distance_colours: Vec::new(),
        free_parts: Vec::new(),
        fold_limits: None,
        hinges: Vec::new(),
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

/// An XPBD constraint kind whose kernel reads the core's items as they are.
fn as_is<C: Pod>(
    context: &GpuContext,
    table: &mut RangeTable,
    kind: (ConstraintKind, &str),
    set: &ColoredConstraints<C>,
) -> Result<ConstraintBuffers, GpuError> {
    xpbd_kind(context, table, kind, set, set.items())
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
