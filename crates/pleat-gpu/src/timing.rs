//! Per-stage GPU times from timestamp queries, where the adapter has them:
//! each substep runs as six compute passes (prediction with wind and pins,
//! constraints, the self-contacts' broad phase, narrow phase (their
//! Jacobi iterations but the last application of corrections) and solve,
//! collider contacts with the velocity update),
//! each stamped at its start and end. The stamps of a frame are resolved
//! into a buffer and copied to a mappable one of a small pool, read back
//! without blocking: every frame is timed while the stamps of up to
//! [`IN_FLIGHT`] earlier ones are on their way (a frame past that, or of
//! more substeps than a query set holds, is not). The query set grows with
//! the substeps.

use pleat::solver::StageTimes;
use std::sync::atomic::{AtomicU8, Ordering};
use std::sync::Arc;
use std::time::Duration;

/// The timed stages of a substep, in the order they run.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TimedStage {
    Predict = 0,
    Constraints = 1,
    SelfBroadPhase = 2,
    SelfNarrowPhase = 3,
    SelfSolve = 4,
    Collisions = 5,
}

impl TimedStage {
    /// Every stage, in the order they run.
    pub const ALL: [TimedStage; STAGES as usize] = [
        TimedStage::Predict,
        TimedStage::Constraints,
        TimedStage::SelfBroadPhase,
        TimedStage::SelfNarrowPhase,
        TimedStage::SelfSolve,
        TimedStage::Collisions,
    ];
}

const STAGES: u32 = 6;
/// Frames whose stamps may be on their way back at once.
const IN_FLIGHT: usize = 8;
const PENDING: u8 = 0;
const ARRIVED: u8 = 1;
const FAILED: u8 = 2;

/// The stamps of a frame of `substeps` substeps.
fn stamps(substeps: u32) -> u32 {
    substeps * STAGES * 2
}

/// A mappable copy of one frame's stamps.
struct Slot {
    buffer: wgpu::Buffer,
    /// Stamps of the frame read back through it, and how that goes;
    /// `None`: free.
    in_flight: Option<(u32, Arc<AtomicU8>)>,
}

impl Slot {
    fn new(device: &wgpu::Device, bytes: u64) -> Self {
        Slot {
            buffer: buffer(
                device,
                "stage times readback",
                bytes,
                wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            ),
            in_flight: None,
        }
    }

    /// Adds its stamps to `stages` if they have arrived, and frees it then
    /// (or when the read failed).
    fn collect(&mut self, period: f32, stages: &mut StageTimes) {
        let Some((count, state)) = &self.in_flight else {
            return;
        };
        match state.load(Ordering::Acquire) {
            PENDING => return,
            ARRIVED => {
                if let Ok(data) = self.buffer.get_mapped_range(..) {
                    let ticks: &[u64] = bytemuck::cast_slice(&data[..*count as usize * 8]);
                    add_ticks(ticks, period, stages);
                }
                self.buffer.unmap();
            }
            _ => {}
        }
        self.in_flight = None;
    }
}

/// Adds the begin and end stamps of each pass, in substep and stage order,
/// to their stages.
fn add_ticks(ticks: &[u64], period: f32, stages: &mut StageTimes) {
    for (k, pair) in ticks.chunks_exact(2).enumerate() {
        let ns = pair[1].saturating_sub(pair[0]) as f64 * period as f64;
        let d = Duration::from_nanos(ns as u64);
        let self_part = match k as u32 % STAGES {
            0 => &mut stages.predict,
            1 => &mut stages.constraints,
            2 => &mut stages.self_broad_phase,
            3 => &mut stages.self_narrow_phase,
            4 => &mut stages.self_solve,
            _ => &mut stages.collisions,
        };
        *self_part += d;
        if (2..5).contains(&(k as u32 % STAGES)) {
            stages.self_collision += d;
        }
    }
}

fn buffer(
    device: &wgpu::Device,
    label: &str,
    bytes: u64,
    usage: wgpu::BufferUsages,
) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size: bytes,
        usage,
        mapped_at_creation: false,
    })
}

/// A query set for frames of up to `substeps` substeps (as many as one
/// query set holds), its resolve buffer, and the substeps it has room for.
fn query_set(device: &wgpu::Device, substeps: u32) -> (wgpu::QuerySet, wgpu::Buffer, u32) {
    let count = stamps(substeps).min(wgpu::QUERY_SET_MAX_QUERIES);
    let set = device.create_query_set(&wgpu::QuerySetDescriptor {
        label: Some("stage times"),
        ty: wgpu::QueryType::Timestamp,
        count,
    });
    let resolve = buffer(
        device,
        "stage times",
        count as u64 * 8,
        wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
    );
    (set, resolve, count / (STAGES * 2))
}

/// Timestamp queries of a frame and their way back.
pub struct Timestamps {
    query_set: wgpu::QuerySet,
    /// Substeps the query set has room for.
    capacity: u32,
    resolve: wgpu::Buffer,
    /// At most [`IN_FLIGHT`], made as frames need them.
    slots: Vec<Slot>,
    /// Nanoseconds per tick.
    period: f32,
    /// The slot of the frame being recorded, if it is timed.
    current: Option<usize>,
}

impl Timestamps {
    /// Timestamps for frames of up to `substeps` substeps, if the device has them.
    pub fn new(device: &wgpu::Device, queue: &wgpu::Queue, substeps: u32) -> Option<Self> {
        if !device.features().contains(wgpu::Features::TIMESTAMP_QUERY) {
            return None;
        }
        let (query_set, resolve, capacity) = query_set(device, substeps);
        Some(Timestamps {
            query_set,
            capacity,
            resolve,
            slots: Vec::new(),
            period: queue.get_timestamp_period(),
            current: None,
        })
    }

    /// Grows the query set to frames of `substeps` substeps; the stamps of
    /// earlier frames still come back.
    pub fn reserve(&mut self, device: &wgpu::Device, substeps: u32) {
        if substeps > self.capacity {
            (self.query_set, self.resolve, self.capacity) = query_set(device, substeps);
        }
    }

    /// Starts a frame of `substeps` substeps: timed unless it has more than
    /// the query set holds or [`IN_FLIGHT`] frames' stamps are on their way.
    pub fn begin_frame(&mut self, device: &wgpu::Device, substeps: u32) {
        self.current = None;
        if substeps > self.capacity {
            return;
        }
        let bytes = stamps(substeps) as u64 * 8;
        let k = match self.slots.iter().position(|s| s.in_flight.is_none()) {
            Some(k) => k,
            None if self.slots.len() < IN_FLIGHT => {
                self.slots.push(Slot::new(device, bytes));
                self.slots.len() - 1
            }
            None => return,
        };
        if self.slots[k].buffer.size() < bytes {
            self.slots[k] = Slot::new(device, bytes);
        }
        self.current = Some(k);
    }

    /// The stamps of `stage` of substep `s`, if this frame is timed.
    pub fn writes(
        &self,
        s: u32,
        stage: TimedStage,
    ) -> Option<wgpu::ComputePassTimestampWrites<'_>> {
        let first = (s * STAGES + stage as u32) * 2;
        self.current.map(|_| wgpu::ComputePassTimestampWrites {
            query_set: &self.query_set,
            beginning_of_pass_write_index: Some(first),
            end_of_pass_write_index: Some(first + 1),
        })
    }

    /// Resolves the frame's stamps and copies them to its slot.
    pub fn resolve(&self, encoder: &mut wgpu::CommandEncoder, substeps: u32) {
        if let Some(k) = self.current {
            let count = stamps(substeps);
            encoder.resolve_query_set(&self.query_set, 0..count, &self.resolve, 0);
            let slot = &self.slots[k].buffer;
            encoder.copy_buffer_to_buffer(&self.resolve, 0, slot, 0, count as u64 * 8);
        }
    }

    /// After the frame's submission: asks for its stamps.
    pub fn request(&mut self, substeps: u32) {
        let Some(k) = self.current.take() else {
            return;
        };
        let state = Arc::new(AtomicU8::new(PENDING));
        let callback_state = state.clone();
        let slot = &mut self.slots[k];
        slot.buffer.map_async(wgpu::MapMode::Read, .., move |r| {
            callback_state.store(if r.is_ok() { ARRIVED } else { FAILED }, Ordering::Release);
        });
        slot.in_flight = Some((stamps(substeps), state));
    }

    /// Adds the stamps that have arrived to `stages`.
    pub fn collect(&mut self, stages: &mut StageTimes) {
        for slot in &mut self.slots {
            slot.collect(self.period, stages);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::GpuContext;

    /// Submits a frame of `substeps` substeps of empty stamped passes, not
    /// waiting for it; whether it was timed.
    fn frame(context: &GpuContext, t: &mut Timestamps, substeps: u32) -> bool {
        t.reserve(&context.device, substeps);
        t.begin_frame(&context.device, substeps);
        let timed = t.writes(0, TimedStage::Predict).is_some();
        let mut encoder = context
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor::default());
        for s in 0..substeps {
            for stage in TimedStage::ALL {
                encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                    label: None,
                    timestamp_writes: t.writes(s, stage),
                });
            }
        }
        t.resolve(&mut encoder, substeps);
        context.queue.submit([encoder.finish()]);
        t.request(substeps);
        timed
    }

    #[test]
    fn every_frame_is_timed_while_earlier_stamps_are_on_their_way() {
        let context = GpuContext::new().expect("a GPU adapter (in CI: Mesa lavapipe)");
        let mut t = Timestamps::new(&context.device, &context.queue, 2)
            .expect("timestamp queries (lavapipe has them)");
        for (round, substeps) in [2, 2, 5].into_iter().enumerate() {
            for k in 0..IN_FLIGHT {
                assert!(
                    frame(&context, &mut t, substeps),
                    "frame {k} of round {round} ({substeps} substeps) is timed"
                );
            }
            assert!(
                !frame(&context, &mut t, substeps),
                "a frame past the pool is not"
            );
            context
                .device
                .poll(wgpu::PollType::wait_indefinitely())
                .unwrap();
            t.collect(&mut StageTimes::default());
            assert!(
                t.slots.iter().all(|s| s.in_flight.is_none()),
                "round {round}: every frame's stamps are taken"
            );
        }
        assert_eq!(t.slots.len(), IN_FLIGHT);
    }
}
