//! Upload: [`GpuBackend::new`] checks what the backend can run, builds the
//! model's buffers (the state, the kernels' inputs, the per-substep buffers
//! and the range table) and uploads them; the state is
//! uploaded again when the caller replaces it, and the distances when the
//! fold's strain limits change.

use super::bindings::Stages;
use super::kernel_buffers::{
    self, KernelBuffers, PerSubstep, SelfContactBuffers, StrainLimitBuffers,
};
use super::persistent::{self, Persistent};
use super::projection::{jacobi_projection, xpbd_projection, ConstraintKind, Projection};
use super::ranges::RangeTable;
use super::{GpuBackend, PARTICLE_BYTES};
use crate::buffers::{check_size, storage, zeroed};
use crate::context::{GpuContext, GpuError};
use crate::data::{self, Counts};
use crate::health::{HealthInputs, HealthWatch, TearEdges};
use crate::kernels::{Kernels, COMPLIANCE_SLOTS};
use crate::momentum::Momentum;
use crate::timing::Timestamps;
use glam::Vec3;
use pleat::constraint::Compliances;
use pleat::mesh::incidence::Incidence;
use pleat::model::Model;
use pleat::solver::grab_reach::GrabReach;
use pleat::solver::position_based::attachments;
use pleat::solver::{SolverKind, SolverSettings};
use pleat::{Particles, World};
use wgpu::util::DeviceExt;

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
            limits_after_contacts,
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
        // Paper's self-contacts, where the persistent kernel can take them.
        let contacts = buffers.self_contact.as_ref().and_then(|c| {
            let pairs = kernel_buffers::contact_pairs(model, c.exclusion)?;
            Some(persistent::ContactPairs {
                topology: kernel_buffers::contact_topology(model, &flat_triangles),
                pairs,
                iterations: c.iterations,
            })
        });
        let sheet = persistent::Sheet {
            kinds: &buffers.constraints,
            table: &table,
            strain_limit_sweeps,
            iterations: settings.iterations,
            free_parts: &free_part_ranges,
            particles: n,
            has_more: settings.kind != SolverKind::Xpbd
                || !hard_indices.is_empty()
                || !buffers.collider_shapes.is_empty()
                || (buffers.self_contact.is_some() && contacts.is_none()),
            contacts,
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
        let mut health = HealthWatch::new(
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
        if let Some((counts, offset)) = persistent.as_ref().and_then(Persistent::contact_counts) {
            health.set_persistent_counts(counts, offset);
        }
        let touches = stages.collide.is_some() || stages.self_contact.is_some();
        let backend = GpuBackend {
            limits_after_contacts: limits_after_contacts && touches,
            context: context.clone(),
            health,
            momentum,
            timestamps: Timestamps::new(device, &context.queue, settings.substeps.max(1)),
            pending: None,
            staging: crate::readback::staging(device, 3 * n as u64 * PARTICLE_BYTES),
            frame_data: Default::default(),
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
