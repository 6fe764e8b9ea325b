//! Angular momentum kept through a substep's own constraints on the GPU
//! (`shaders/momentum.wgsl`): after the strain limits' sweeps, each cloth
//! nothing outside holds is turned back by the angle its projection turned
//! it without cause, as the core's [`pleat::solver::momentum`] does. Three
//! dispatches a free cloth and substep: the sums per workgroup, their sum
//! and the turn, the turn applied.

use crate::buffers::{entry, sized_entry, zeroed};
use crate::kernels::{workgroups, Kernels, WORKGROUP};

/// Bytes of one workgroup's sums (`Sums` in momentum.wgsl: seven vec4).
const SUMS_BYTES: u64 = 7 * 16;

/// The free cloths' kernels, their buffers and their slices.
pub struct Momentum {
    bind_group: wgpu::BindGroup,
    /// What the last turn could not move each particle by.
    left: wgpu::Buffer,
    pipelines: [wgpu::ComputePipeline; 3],
    /// Per free cloth: the dynamic offset of its range and its particle count.
    parts: Vec<(u32, u32)>,
}

impl Momentum {
    /// The stage for the free cloths whose ranges are at `parts` (dynamic
    /// offset, particle count) in `ranges`, of `particles` particles in
    /// all; `None` when there is none.
    pub fn new(
        device: &wgpu::Device,
        kernels: &Kernels,
        (ranges, parts): (&wgpu::Buffer, Vec<(u32, u32)>),
        particles: u32,
    ) -> Option<Self> {
        let largest = parts.iter().map(|&(_, count)| count).max()?;
        let blocks = largest.div_ceil(WORKGROUP) as u64;
        let left = zeroed(device, "turn round-off", particles as u64 * 16);
        let partials = zeroed(device, "momentum partials", blocks * SUMS_BYTES);
        let turn = zeroed(device, "turn", 32);
        let spare = zeroed(device, "unused slot", 16);
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("momentum"),
            layout: &kernels.kernel_layout,
            entries: &[
                entry(0, &left),
                entry(1, &partials),
                entry(2, &turn),
                entry(3, &spare),
                sized_entry(4, ranges, size_of::<crate::data::Range>()),
            ],
        });
        Some(Momentum {
            bind_group,
            left,
            pipelines: kernels.momentum.clone(),
            parts,
        })
    }

    /// What the last turn could not move each particle by (round-off),
    /// which a persistent kernel carries on.
    pub fn left(&self) -> &wgpu::Buffer {
        &self.left
    }

    /// Records the turn of every free cloth, cloth after cloth; returns
    /// the dispatches that took.
    pub fn record(&self, pass: &mut wgpu::ComputePass<'_>) -> u32 {
        let [sum_blocks, solve, apply] = &self.pipelines;
        for &(offset, count) in &self.parts {
            pass.set_bind_group(1, &self.bind_group, &[offset]);
            let (x, y) = workgroups(count);
            pass.set_pipeline(sum_blocks);
            pass.dispatch_workgroups(x, y, 1);
            pass.set_pipeline(solve);
            pass.dispatch_workgroups(1, 1, 1);
            pass.set_pipeline(apply);
            pass.dispatch_workgroups(x, y, 1);
        }
        3 * self.parts.len() as u32
    }
}
