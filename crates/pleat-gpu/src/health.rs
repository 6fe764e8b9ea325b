//! The health watch of the GPU backend: after the last substep of a frame
//! a reduction (`shaders/health.wgsl`) sums the state up as the core's
//! instability criteria read it ([`pleat::stability::Health`]), and its 32
//! bytes come back without blocking. A frame that ends while the last
//! result is still on its way is not measured.

use crate::buffers::{entry, sized_entry, storage, zeroed};
use crate::kernels::{workgroups, Kernels};
use bytemuck::{Pod, Zeroable};
use pleat::stability::{tear_edges, Health};
use pleat::Model;
use std::sync::atomic::{AtomicU8, Ordering};
use std::sync::Arc;

const PENDING: u8 = 0;
const ARRIVED: u8 = 1;
const FAILED: u8 = 2;
const NONE: u32 = u32::MAX;

/// The reduction's result (`Summary` in structs.wgsl).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub(crate) struct Summary {
    pub(crate) non_finite: u32,
    pub(crate) first_bad: u32,
    pub(crate) fastest: u32,
    pub(crate) speed2: f32,
    pub(crate) kinetic: f32,
    pub(crate) potential: f32,
    pub(crate) tear: f32,
    pub(crate) pad: u32,
}

impl Summary {
    /// The summary as the core's monitor reads it, at simulated time `time`.
    fn health(&self, time: f32) -> Health {
        let culprit = [self.first_bad, self.fastest]
            .into_iter()
            .find(|&i| i != NONE);
        Health {
            time,
            non_finite: self.non_finite > 0,
            mechanical_energy: self.kinetic + self.potential,
            tear: self.tear,
            culprit,
        }
    }
}

/// A paper edge whose stretch beyond its tear length is a tear
/// (`TearEdge` in structs.wgsl, [`pleat::stability::TearEdge`]).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub(crate) struct TearEdge {
    pub(crate) a: u32,
    pub(crate) b: u32,
    pub(crate) tear_length: f32,
    pub(crate) pad: u32,
}

/// The edges of `model` the reduction watches for a tear: paper's. A
/// cloth's tear is found when its state is read back
/// ([`pleat::Simulation::sync`]): a list of every cloth edge would more
/// than double a large cloth's memory (a 2048 x 2048 cloth's would pass
/// WebGPU's 128 MiB binding limit).
pub struct TearEdges(Vec<TearEdge>);

impl TearEdges {
    pub fn of(model: &Model) -> Self {
        TearEdges(
            tear_edges(model)
                .filter(|e| e.paper)
                .map(|e| TearEdge {
                    a: e.v[0],
                    b: e.v[1],
                    tear_length: e.tear_length,
                    pad: 0,
                })
                .collect(),
        )
    }

    pub fn len(&self) -> u32 {
        self.0.len() as u32
    }
}

/// The reduction's buffers and kernels, and its result on the way back.
pub struct HealthWatch {
    bind_group: wgpu::BindGroup,
    pipelines: [wgpu::ComputePipeline; 2],
    /// Dynamic offset of the range that holds the tear edge count.
    range_offset: u32,
    /// Invocations of the first kernel: particles or tear edges, the more.
    items: u32,
    result: wgpu::Buffer,
    readback: wgpu::Buffer,
    /// Simulated time of the frame being recorded, when it is measured.
    measuring: Option<f32>,
    /// Time of the frame whose result is being mapped, and how that goes.
    in_flight: Option<(f32, Arc<AtomicU8>)>,
    /// The self-contacts' candidates, whose header's counters come back
    /// with the result and are cleared then.
    contact_counts: Option<wgpu::Buffer>,
    /// The persistent kernel's self-contact counters (solved, acted,
    /// builds) and their offset in its buffer: they come back and are
    /// cleared likewise, and are added to the candidates' ones.
    persistent_counts: Option<(wgpu::Buffer, u64)>,
    /// The counters that came back and have not been taken yet.
    arrived_counts: Option<ContactCounts>,
}

/// The self-contacts' counters read back, summed over substeps since the
/// last read.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ContactCounts {
    /// Candidate pairs solved.
    pub candidates: u64,
    /// Contacts that acted.
    pub acted: u64,
    /// Builds of the candidates.
    pub builds: u64,
    /// The most pairs a build found that the buffer could not all hold
    /// (0: every build's fit).
    pub overflowed: u64,
}

/// Bytes of the result read back: the summary, then the counters' words
/// of the candidates' header (lib/contact.wgsl: solved, acted, builds,
/// the most found by a build that overflowed).
const SUMMARY_BYTES: u64 = size_of::<Summary>() as u64;
const COUNTERS: std::ops::Range<u64> = 8..24;
/// Bytes of the persistent kernel's counters read back after those
/// (shaders/persistent.wgsl: pairs solved, contacts that acted, builds;
/// zero where it has none).
const PERSISTENT_COUNTERS: u64 = 12;

/// What [`HealthWatch::new`] binds besides its own buffers.
pub struct HealthInputs<'a> {
    pub model: &'a Model,
    pub tears: &'a TearEdges,
    /// The range table and the offset of the tear edges' range in it.
    pub ranges: (&'a wgpu::Buffer, u32),
    /// The self-contacts' candidates, if any: their counters come back too.
    pub contact_counts: Option<&'a wgpu::Buffer>,
}

impl HealthWatch {
    pub fn new(device: &wgpu::Device, kernels: &Kernels, inputs: HealthInputs<'_>) -> Self {
        let HealthInputs {
            model,
            tears,
            ranges: (ranges, range_offset),
            contact_counts,
        } = inputs;
        let rest: Vec<[f32; 4]> = model
            .rest
            .iter()
            .map(|p| p.extend(0.0).to_array())
            .collect();
        let items = (model.particle_count() as u32).max(tears.len());
        let (x, y) = workgroups(items);
        let size = size_of::<Summary>() as u64;
        let rest = storage(device, "rest positions", &rest);
        let edges = storage(device, "tear edges", &tears.0);
        let partials = zeroed(device, "health partials", x as u64 * y as u64 * size);
        let result = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("health"),
            size,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("health"),
            layout: &kernels.kernel_layout,
            entries: &[
                entry(0, &rest),
                entry(1, &edges),
                entry(2, &partials),
                entry(3, &result),
                sized_entry(4, ranges, size_of::<crate::data::Range>()),
            ],
        });
        HealthWatch {
            bind_group,
            pipelines: kernels.health.clone(),
            range_offset,
            items,
            readback: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("health readback"),
                size: size + (COUNTERS.end - COUNTERS.start) + PERSISTENT_COUNTERS,
                usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }),
            result,
            measuring: None,
            in_flight: None,
            contact_counts: contact_counts.cloned(),
            persistent_counts: None,
            arrived_counts: None,
        }
    }

    /// Records the reduction of the state at the end of a frame (simulated
    /// time `time`), the state bound with the frame's last parameters at
    /// `params_offset`, unless the last result is still on its way;
    /// returns the dispatches it recorded.
    pub fn record(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        (state, params_offset): (&wgpu::BindGroup, u32),
        time: f32,
    ) -> u32 {
        if self.in_flight.is_some() {
            return 0;
        }
        {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("health"),
                timestamp_writes: None,
            });
            pass.set_bind_group(0, state, &[params_offset]);
            pass.set_bind_group(1, &self.bind_group, &[self.range_offset]);
            let [blocks, sums] = &self.pipelines;
            pass.set_pipeline(blocks);
            let (x, y) = workgroups(self.items);
            pass.dispatch_workgroups(x, y, 1);
            pass.set_pipeline(sums);
            pass.dispatch_workgroups(1, 1, 1);
        }
        encoder.copy_buffer_to_buffer(&self.result, 0, &self.readback, 0, SUMMARY_BYTES);
        if let Some(counts) = &self.contact_counts {
            let len = COUNTERS.end - COUNTERS.start;
            encoder.copy_buffer_to_buffer(
                counts,
                COUNTERS.start,
                &self.readback,
                SUMMARY_BYTES,
                len,
            );
            encoder.clear_buffer(counts, COUNTERS.start, Some(len));
        }
        if let Some((counts, offset)) = &self.persistent_counts {
            let at = SUMMARY_BYTES + COUNTERS.end - COUNTERS.start;
            encoder.copy_buffer_to_buffer(counts, *offset, &self.readback, at, PERSISTENT_COUNTERS);
            encoder.clear_buffer(counts, *offset, Some(PERSISTENT_COUNTERS));
        }
        self.measuring = Some(time);
        2
    }

    /// Reads the persistent kernel's self-contact counters too, the three
    /// words at byte `offset` of `buffer`.
    pub fn set_persistent_counts(&mut self, buffer: &wgpu::Buffer, offset: u64) {
        self.persistent_counts = Some((buffer.clone(), offset));
    }

    /// Reads the self-contacts' counters from `candidates` from now on
    /// (a larger buffer replaced the last).
    pub fn set_contact_counts(&mut self, candidates: &wgpu::Buffer) {
        self.contact_counts = Some(candidates.clone());
    }

    /// The self-contacts' counters that came back since the last call, if any did.
    pub fn take_contact_counts(&mut self) -> Option<ContactCounts> {
        self.arrived_counts.take()
    }

    /// After the frame's submission: asks for its result, if it was measured.
    pub fn request(&mut self) {
        let Some(time) = self.measuring.take() else {
            return;
        };
        let state = Arc::new(AtomicU8::new(PENDING));
        let callback_state = state.clone();
        self.readback.map_async(wgpu::MapMode::Read, .., move |r| {
            callback_state.store(if r.is_ok() { ARRIVED } else { FAILED }, Ordering::Release);
        });
        self.in_flight = Some((time, state));
    }

    /// Whether a result asked for has not arrived yet.
    pub fn pending(&self) -> bool {
        self.in_flight
            .as_ref()
            .is_some_and(|(_, state)| state.load(Ordering::Acquire) == PENDING)
    }

    /// The result on its way, if it has arrived.
    pub fn collect(&mut self) -> Option<Health> {
        let (time, state) = self.in_flight.as_ref()?;
        let health = match state.load(Ordering::Acquire) {
            PENDING => return None,
            ARRIVED => {
                let summary = self.readback.get_mapped_range(..).ok().map(|data| {
                    let (summary, counters) = data.split_at(SUMMARY_BYTES as usize);
                    let [candidates, acted, builds, overflowed, solved, touched, kept]: [u32; 7] =
                        bytemuck::pod_read_unaligned(counters);
                    let arrived = self.arrived_counts.get_or_insert_default();
                    arrived.candidates += u64::from(candidates) + u64::from(solved);
                    arrived.acted += u64::from(acted) + u64::from(touched);
                    arrived.builds += u64::from(builds) + u64::from(kept);
                    arrived.overflowed = arrived.overflowed.max(u64::from(overflowed));
                    *bytemuck::from_bytes::<Summary>(summary)
                });
                self.readback.unmap();
                summary.map(|s| s.health(*time))
            }
            _ => None,
        };
        self.in_flight = None;
        health
    }
}
