//! [`GpuBackend`]: the XPBD substep of the core as a sequence of compute
//! dispatches, one frame per queue submission. Constraints are projected
//! colour by colour (one dispatch per colour, the slice chosen by a dynamic
//! uniform offset), in the core's order, so the result follows the CPU
//! backend's to round-off. Pin targets and collider poses of every substep
//! of a frame are computed on the CPU from their scripts and uploaded once
//! per frame (a few bytes per pin and collider), with the colliders'
//! friction when the world's has changed.
//!
//! This file holds the backend's state and the [`Backend`] impl; the work
//! is split by job: `resources` checks and uploads the model and owns the
//! buffers, `projection` builds the constraint kinds' buffers by solver,
//! `bindings` binds the kernels to them, `record` writes each frame's
//! uniforms and records its passes, `persistent` runs a small sheet's
//! whole frame in one workgroup, and `readback` copies the state back.

use crate::context::GpuContext;
use crate::data::Counts;
use crate::health::HealthWatch;
use crate::kernels::Kernels;
use crate::momentum::Momentum;
use crate::readback::Readback;
use crate::timing::Timestamps;
use pleat::constraint::{Compliances, DistanceConstraint};
use pleat::control::Control;
use pleat::solver::xpbd::FoldLimits;
use pleat::solver::{SolverSettings, StageTimes};
use pleat::{Backend, Particles, World};

mod bindings;
mod kernel_buffers;
pub(crate) mod persistent;
mod projection;
mod ranges;
mod readback;
mod record;
mod resources;

use bindings::Stages;
use kernel_buffers::{FrameData, KernelBuffers, PerSubstep};

/// Bytes of one particle in the state buffers (`vec4<f32>`).
const PARTICLE_BYTES: u64 = 16;

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
    /// The hinges as the items buffer holds them, less their tracked
    /// angles, which live on the GPU alone: a fold's step rewrites only
    /// their start and end angles ([`GpuBackend::set_hinge_targets`]).
    hinges: Vec<pleat::constraint::OrigamiHinge>,
    /// A small sheet's frame in one dispatch, where the model allows it.
    persistent: Option<persistent::Persistent>,
    /// Whether frames may take the persistent kernel (the default).
    persistent_allowed: bool,
    /// Dispatches the last frame recorded.
    dispatches: u32,
    /// Whether the strain limits are swept again after the contacts, as
    /// the CPU backend does where something touches cloth with limits
    /// (`pleat::solver::xpbd::XpbdConstraints::limits_after_contacts`).
    limits_after_contacts: bool,
}

impl GpuBackend {
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

    /// Lets frames of a small sheet run as one dispatch of one workgroup
    /// (the default), or keeps them to a dispatch per colour, kind and
    /// substep (to compare the two).
    pub fn allow_persistent(&mut self, allowed: bool) {
        self.persistent_allowed = allowed;
    }

    /// Whether the model is one the persistent kernel runs (a small sheet
    /// of hinges and distances alone).
    pub fn has_persistent(&self) -> bool {
        self.persistent.is_some()
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
        self.record_frame(world, (settings, compliances), control, stages);
    }

    fn finish(&mut self, stages: &mut StageTimes) {
        // The health's map callback may only run on a later poll than the
        // one that saw the frame finish (parallel tests polling one
        // device), as the state's read back may: poll again a few times.
        for _ in 0..readback::READBACK_POLLS {
            let _ = self
                .context
                .device
                .poll(wgpu::PollType::wait_indefinitely());
            if !self.health.pending() {
                break;
            }
            std::thread::yield_now();
        }
        if let Some(t) = &mut self.timestamps {
            t.collect(stages);
        }
    }

    fn steps_in_place(&self) -> bool {
        false
    }

    fn download(&mut self, particles: &mut Particles) {
        self.read_into(particles);
    }

    fn request_download(&mut self) {
        self.request_read();
    }

    fn try_download(&mut self, particles: &mut Particles) -> bool {
        self.try_read_into(particles)
    }

    fn as_any(&self) -> &dyn std::any::Any {
        self
    }

    fn dispatches_per_frame(&self) -> Option<u32> {
        Some(self.dispatches)
    }

    fn health(&mut self) -> Option<pleat::stability::Health> {
        let _ = self.context.device.poll(wgpu::PollType::Poll);
        self.health.collect()
    }

    fn upload(&mut self, particles: &Particles) {
        self.upload_state(particles);
    }

    fn set_hinge_targets(&mut self, targets: &pleat::fold_steps::HingeTargets) {
        self.write_hinge_targets(targets);
    }
}
