//! Per-frame recording: the frame's uniforms (parameters, pin targets,
//! collider poses, compliances, friction) written, then its substeps
//! recorded as compute passes and submitted in a few command buffers, so
//! that the GPU starts on the first substeps while the CPU encodes the rest.

use super::bindings::{SelfContactStage, Stage, StrainLimitStages, SubstepSweeps};
use super::kernel_buffers::FrameData;
use super::GpuBackend;
use crate::data::{self, GpuPose, Params};
use crate::kernels::{
    workgroups, BUILD_KERNELS, COMPLIANCE_SLOTS, HOLD_ROUND_SWEEPS, UNIFORM_STRIDE,
};
use crate::timing::TimedStage;
use pleat::collide::ColliderPose;
use pleat::constraint::Compliances;
use pleat::control::Control;
use pleat::solver::xpbd::FOLD_HOLD_SWEEPS;
use pleat::solver::{substep_times, SolverSettings, StageTimes};
use pleat::World;

/// Command buffers a frame of substeps is submitted in, at most: the CPU
/// encodes the frame's later substeps (wgpu encodes a command buffer as it
/// finishes, a few microseconds a dispatch) while the GPU runs the earlier
/// ones, instead of the GPU waiting for the whole frame to be encoded.
#[cfg(not(target_arch = "wasm32"))]
const SUBMITS_PER_FRAME: u32 = 10;
/// In the browser a frame stays one command buffer: the split was measured
/// on native Vulkan only.
#[cfg(target_arch = "wasm32")]
const SUBMITS_PER_FRAME: u32 = 1;

/// Bytes of one indirect dispatch's workgroup counts.
const INDIRECT_ARGS: usize = 12;

impl SelfContactStage {
    /// The broad phase over `particles` particles: checks whether the
    /// candidates are stale and builds them afresh if so (indirect
    /// dispatches of no workgroups if not); returns the dispatches.
    fn record_broad_phase(&self, pass: &mut wgpu::ComputePass<'_>, particles: u32) -> u32 {
        let [bound, check, build @ ..] = &self.kernels.grid;
        pass.set_bind_group(1, &self.grid, &[0]);
        let mut n = over_particles(pass, bound, particles);
        n += over_particles(pass, check, particles);
        pass.set_bind_group(1, &self.arm, &[0]);
        n += over_particles(pass, &self.kernels.arm[0], 1);
        pass.set_bind_group(1, &self.grid, &[0]);
        for (slot, kernel) in build.iter().enumerate() {
            n += self.indirect(pass, kernel, slot);
        }
        if self.edge_pairs {
            // On `find`'s workgroups, the build's last.
            n += self.indirect(pass, &self.kernels.find_edges, BUILD_KERNELS - 1);
        }
        n
    }

    /// The margin of the next frame chosen on the GPU, with the state bound
    /// with the frame's last parameters at `params_offset` (one dispatch).
    fn record_margin(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        (state, params_offset): (&wgpu::BindGroup, u32),
    ) -> u32 {
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("contact margin"),
            timestamp_writes: None,
        });
        pass.set_bind_group(0, state, &[params_offset]);
        pass.set_bind_group(1, &self.arm, &[0]);
        over_particles(&mut pass, &self.kernels.arm[2], 1)
    }

    /// The narrow phase: the CPU backend's Jacobi iterations over
    /// the candidates of `particles` particles, all but the last
    /// iteration's corrections applied ([`Self::record_solve`] applies
    /// those).
    fn record_narrow_phase(&self, pass: &mut wgpu::ComputePass<'_>, particles: u32) -> u32 {
        self.record_narrow_phase_armed(pass, particles, &self.kernels.arm[1])
    }

    /// The narrow phase with its workgroup counts set by `arm` (arm_solve,
    /// or arm_round_solve in a round of the held limits).
    fn record_narrow_phase_armed(
        &self,
        pass: &mut wgpu::ComputePass<'_>,
        particles: u32,
        arm: &wgpu::ComputePipeline,
    ) -> u32 {
        pass.set_bind_group(1, &self.arm, &[0]);
        let mut n = over_particles(pass, arm, 1);
        pass.set_bind_group(1, &self.solve, &[0]);
        for iteration in 1..=self.iterations {
            if iteration > 1 {
                n += self.record_solve(pass, particles);
            }
            n += self.record_iteration(pass, iteration == self.iterations);
        }
        n
    }

    /// One Jacobi iteration's passes over the candidates, the `last`
    /// counting the contacts that acted; its corrections summed, not
    /// applied.
    fn record_iteration(&self, pass: &mut wgpu::ComputePass<'_>, last: bool) -> u32 {
        let solve = &self.solve_kernels;
        let contacts = if last {
            &solve.counted_contacts
        } else {
            &solve.contacts
        };
        let counted = solve
            .count
            .as_ref()
            .map_or(0, |count| self.indirect(pass, count, BUILD_KERNELS));
        counted + self.indirect(pass, contacts, BUILD_KERNELS)
    }

    /// The corrections of `particles` particles applied.
    fn record_solve(&self, pass: &mut wgpu::ComputePass<'_>, particles: u32) -> u32 {
        pass.set_bind_group(1, &self.solve, &[0]);
        over_particles(pass, &self.solve_kernels.apply, particles)
    }

    /// Dispatches `pipeline` on the workgroup counts of indirect slot
    /// `slot` (one dispatch).
    fn indirect(
        &self,
        pass: &mut wgpu::ComputePass<'_>,
        pipeline: &wgpu::ComputePipeline,
        slot: usize,
    ) -> u32 {
        pass.set_pipeline(pipeline);
        pass.dispatch_workgroups_indirect(&self.args, (slot * INDIRECT_ARGS) as u64);
        1
    }
}

impl StrainLimitStages {
    /// Records the sweeps; returns the dispatches they took.
    fn record(&self, pass: &mut wgpu::ComputePass<'_>) -> u32 {
        match &self.substep {
            SubstepSweeps::InOneWorkgroup(all) => dispatch(pass, all, Some(1)),
            SubstepSweeps::PerColour {
                sweep,
                measured,
                further,
                sweeps,
            } => {
                let mut n = 0;
                for _ in 1..*sweeps {
                    n += dispatch(pass, sweep, None);
                }
                n + dispatch(pass, measured, None) + dispatch(pass, further, Some(1))
            }
        }
    }
}

impl GpuBackend {
    /// Gives paper the strain limits of a fold held or moving, writes the
    /// frame's uniforms, records its substeps (the held limits first where
    /// the fold came to rest) and the health reduction, and
    /// submits them; `stages` takes the GPU times and the self-contacts'
    /// counts of earlier frames.
    pub(super) fn record_frame(
        &mut self,
        world: &World,
        (settings, compliances): (&SolverSettings, &Compliances),
        control: &Control,
        stages: &mut StageTimes,
    ) {
        let frame_dt = control.frame_dt;
        if let Some(t) = &mut self.timestamps {
            t.collect(stages);
        }
        let counts = self.health.take_contact_counts();
        if let Some(c) = counts {
            stages.self_contact_candidates += c.candidates;
            stages.self_contacts += c.acted;
            stages.self_contact_builds += c.builds;
        }
        self.grow_candidates(counts);
        self.hold_fold(control.fold.held);
        let substeps = self.write_frame(world, (settings, compliances), control);
        let persistent = self.runs_persistent(world, control, substeps);
        // A persistent frame is stamped as one substep.
        let stamped = if persistent { 1 } else { substeps };
        if let Some(t) = &mut self.timestamps {
            t.begin_frame(&self.context.device, stamped);
        }
        let mut encoder = self.frame_encoder();
        let came_to_rest = self
            .fold_limits
            .as_mut()
            .is_some_and(|(limits, _)| limits.take_came_to_rest());
        self.dispatches = 0;
        if came_to_rest {
            self.dispatches += self.record_held_limits(&mut encoder);
        }
        if persistent {
            let (queue, timestamps) = (&self.context.queue, self.timestamps.as_ref());
            if let Some(p) = &mut self.persistent {
                self.dispatches += p.record(
                    queue,
                    &mut encoder,
                    (substeps, settings.iterations),
                    timestamps,
                );
            }
        } else {
            let per_submit = substeps.div_ceil(SUBMITS_PER_FRAME);
            for s in 0..substeps {
                if s > 0 && s % per_submit == 0 {
                    // The GPU runs what is recorded while the rest is encoded.
                    let recorded = std::mem::replace(&mut encoder, self.frame_encoder());
                    self.context.queue.submit([recorded.finish()]);
                }
                for lambda in &self.lambdas {
                    encoder.clear_buffer(lambda, 0, None);
                }
                self.dispatches +=
                    self.record_substep(&mut encoder, s, (world, control), settings.iterations);
            }
        }
        let last = (substeps - 1) * UNIFORM_STRIDE as u32;
        if let Some(contact) = &self.stages.self_contact {
            self.dispatches += contact.record_margin(&mut encoder, (&self.stages.state, last));
        }
        self.dispatches += self.health.record(
            &mut encoder,
            (&self.stages.state, last),
            world.time + frame_dt,
        );
        if let Some(t) = &self.timestamps {
            t.resolve(&mut encoder, stamped);
        }
        self.context.queue.submit([encoder.finish()]);
        stages.dispatches += u64::from(self.dispatches);
        self.health.request();
        if let Some(t) = &mut self.timestamps {
            t.request(stamped);
        }
        // Frees the resources of finished frames without waiting.
        let _ = self.context.device.poll(wgpu::PollType::Poll);
    }

    /// An encoder for (part of) a frame's commands.
    fn frame_encoder(&self) -> wgpu::CommandEncoder {
        self.context
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("frame"),
            })
    }

    /// Whether the frame runs as the persistent kernel's one dispatch: the
    /// sheet is one it runs, it is allowed, and nothing it does not run
    /// acts this frame (a grab, wind).
    fn runs_persistent(&self, world: &World, control: &Control, substeps: u32) -> bool {
        self.persistent_allowed
            && control.grab.is_none()
            && world.wind.is_none()
            && self.persistent.as_ref().is_some_and(|p| p.runs(substeps))
    }

    /// Writes the parameters, pin targets and collider poses of every
    /// substep of the frame, and the live compliances and friction.
    fn write_frame(
        &mut self,
        world: &World,
        (settings, table): (&SolverSettings, &Compliances),
        control: &Control,
    ) -> u32 {
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
        for (s, (t, dt, control)) in substep_times(world.time, control, substeps).enumerate() {
            let p = Params::at(world, settings, &self.counts, &control, (s as u32, t, dt));
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
    /// [`FOLD_HOLD_SWEEPS`], in one dispatch): the velocities stay as they
    /// are ([`pleat::solver::xpbd::XpbdConstraints::meet_held_limits`]).
    /// Where the paper has self-contacts, in rounds of [`HOLD_ROUND_SWEEPS`]
    /// (shorter than the CPU's), each round's motion then checked by the
    /// contacts as a substep's is (from the round's start, copied into the
    /// previous positions, which the next prediction sets again), so that
    /// no layer is carried through another; the rounds after the limits
    /// are met sweep once, move nothing and solve no contact.
    fn record_held_limits(&self, encoder: &mut wgpu::CommandEncoder) -> u32 {
        let Some(limits) = &self.stages.strain_limit else {
            return 0;
        };
        let Some(contact) = &self.stages.self_contact else {
            let mut pass = held_pass(encoder, &self.stages.state);
            return dispatch(&mut pass, &limits.held, Some(1));
        };
        let particles = self.counts.particles;
        let mut n = 0;
        for _ in 0..FOLD_HOLD_SWEEPS.div_ceil(HOLD_ROUND_SWEEPS) {
            encoder.copy_buffer_to_buffer(&self.pos, 0, &self.prev, 0, self.pos.size());
            let mut pass = held_pass(encoder, &self.stages.state);
            n += dispatch(&mut pass, &limits.held_round, Some(1));
            n += contact.record_broad_phase(&mut pass, particles);
            let arm = &contact.kernels.arm[3];
            n += contact.record_narrow_phase_armed(&mut pass, particles, arm);
            n += contact.record_solve(&mut pass, particles);
        }
        n
    }

    /// Records one substep as six passes (stamped where the adapter has
    /// timestamps): prediction, constraints, the self-contacts' broad
    /// phase, narrow phase and solve, collisions (and the strain limits
    /// again, where [`GpuBackend::limits_after_contacts`]);
    /// returns the dispatches it recorded.
    fn record_substep(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        s: u32,
        (world, control): (&World, &Control),
        iterations: u32,
    ) -> u32 {
        let st = &self.stages;
        let particles = self.counts.particles;
        let mut n = 0;
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
                n += dispatch(pass, &st.wind[0], Some(self.counts.triangles));
                n += dispatch(pass, &st.wind[1], Some(particles));
            }
            n += over_particles(pass, &st.predict, particles);
            if let Some(pins) = &st.pins {
                n += dispatch(pass, pins, None);
            }
        });
        pass(TimedStage::Constraints, &mut |pass| {
            for _ in 0..iterations {
                for stage in &st.constraints {
                    n += dispatch(pass, stage, None);
                }
            }
            if let Some(limits) = &st.strain_limit {
                n += limits.record(pass);
            }
            if let Some(momentum) = &self.momentum {
                n += momentum.record(pass);
            }
            if let Some(track) = &st.track {
                n += dispatch(pass, track, None);
            }
            if control.grab.is_some() {
                pass.set_pipeline(&st.grab);
                pass.dispatch_workgroups(1, 1, 1);
                n += 1;
                if let Some(reach) = &st.grab_reach {
                    n += dispatch(pass, reach, None);
                }
            }
        });
        pass(TimedStage::SelfBroadPhase, &mut |pass| {
            if let Some(contact) = &st.self_contact {
                n += contact.record_broad_phase(pass, particles);
            }
        });
        pass(TimedStage::SelfNarrowPhase, &mut |pass| {
            if let Some(contact) = &st.self_contact {
                n += contact.record_narrow_phase(pass, particles);
            }
        });
        pass(TimedStage::SelfSolve, &mut |pass| {
            if let Some(contact) = &st.self_contact {
                n += contact.record_solve(pass, particles);
            }
        });
        pass(TimedStage::Collisions, &mut |pass| {
            if let Some(collide) = &st.collide {
                n += dispatch(pass, collide, Some(particles));
            }
            if let (true, Some(limits)) = (self.limits_after_contacts, &st.strain_limit) {
                n += limits.record(pass);
            }
            n += over_particles(pass, &st.update_velocities, particles);
        });
        n
    }
}

/// A pass of the held limits, with the state bound with the frame's first
/// parameters.
fn held_pass<'e>(
    encoder: &'e mut wgpu::CommandEncoder,
    state: &wgpu::BindGroup,
) -> wgpu::ComputePass<'e> {
    let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
        label: Some("held fold limits"),
        timestamp_writes: None,
    });
    pass.set_bind_group(0, state, &[0]);
    pass
}

/// Dispatches `pipeline` over `particles` invocations (one dispatch).
fn over_particles(
    pass: &mut wgpu::ComputePass<'_>,
    pipeline: &wgpu::ComputePipeline,
    particles: u32,
) -> u32 {
    pass.set_pipeline(pipeline);
    let (x, y) = workgroups(particles);
    pass.dispatch_workgroups(x, y, 1);
    1
}

/// Dispatches `stage` over each of its slices, or over `count` invocations;
/// returns how many dispatches that took.
pub(super) fn dispatch(pass: &mut wgpu::ComputePass<'_>, stage: &Stage, count: Option<u32>) -> u32 {
    pass.set_pipeline(&stage.pipeline);
    match count {
        Some(count) => {
            if let Some(&(offset, _)) = stage.dispatches.first() {
                pass.set_bind_group(1, &stage.bind_group, &[offset]);
            }
            let (x, y) = workgroups(count);
            pass.dispatch_workgroups(x, y, 1);
            1
        }
        None => {
            for &(offset, count) in &stage.dispatches {
                pass.set_bind_group(1, &stage.bind_group, &[offset]);
                let (x, y) = workgroups(count);
                pass.dispatch_workgroups(x, y, 1);
            }
            stage.dispatches.len() as u32
        }
    }
}
