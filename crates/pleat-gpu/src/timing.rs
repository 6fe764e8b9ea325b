//! Per-stage GPU times from timestamp queries, where the adapter has them:
//! each substep runs as four compute passes (prediction with wind and pins,
//! constraints, self-contacts, collider contacts with the velocity update),
//! each stamped at its start and end. The stamps of a frame are resolved
//! into a buffer and read back without blocking the next frame: a frame
//! whose predecessor's stamps have not arrived yet is not timed.

use pleat::solver::StageTimes;
use std::sync::atomic::{AtomicU8, Ordering};
use std::sync::Arc;
use std::time::Duration;

/// The timed stages of a substep, in the order they run.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TimedStage {
    Predict = 0,
    Constraints = 1,
    SelfContacts = 2,
    Collisions = 3,
}

const STAGES: u32 = 4;
const PENDING: u8 = 0;
const ARRIVED: u8 = 1;
const FAILED: u8 = 2;

/// Timestamp queries of one frame and their way back.
pub struct Timestamps {
    query_set: wgpu::QuerySet,
    /// Substeps the query set has room for.
    capacity: u32,
    resolve: wgpu::Buffer,
    readback: wgpu::Buffer,
    /// Nanoseconds per tick.
    period: f32,
    /// Queries of the frame being read back, and how that goes.
    in_flight: Option<(u32, Arc<AtomicU8>)>,
    /// Whether the frame being recorded is timed.
    timing: bool,
}

impl Timestamps {
    /// Timestamps for frames of up to `substeps` substeps, if the device has them.
    pub fn new(device: &wgpu::Device, queue: &wgpu::Queue, substeps: u32) -> Option<Self> {
        if !device.features().contains(wgpu::Features::TIMESTAMP_QUERY) {
            return None;
        }
        let count = (substeps * STAGES * 2).min(wgpu::QUERY_SET_MAX_QUERIES);
        let bytes = count as u64 * 8;
        let buffer = |label, usage| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: bytes,
                usage,
                mapped_at_creation: false,
            })
        };
        Some(Timestamps {
            query_set: device.create_query_set(&wgpu::QuerySetDescriptor {
                label: Some("stage times"),
                ty: wgpu::QueryType::Timestamp,
                count,
            }),
            capacity: count / (STAGES * 2),
            resolve: buffer(
                "stage times",
                wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
            ),
            readback: buffer(
                "stage times readback",
                wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            ),
            period: queue.get_timestamp_period(),
            in_flight: None,
            timing: false,
        })
    }

    /// Starts a frame of `substeps` substeps: timed unless the last frame's
    /// times are still on their way or the frame has too many substeps.
    pub fn begin_frame(&mut self, substeps: u32) {
        self.timing = self.in_flight.is_none() && substeps <= self.capacity;
    }

    /// The stamps of `stage` of substep `s`, if this frame is timed.
    pub fn writes(
        &self,
        s: u32,
        stage: TimedStage,
    ) -> Option<wgpu::ComputePassTimestampWrites<'_>> {
        let first = (s * STAGES + stage as u32) * 2;
        self.timing.then_some(wgpu::ComputePassTimestampWrites {
            query_set: &self.query_set,
            beginning_of_pass_write_index: Some(first),
            end_of_pass_write_index: Some(first + 1),
        })
    }

    /// Resolves the frame's stamps and copies them to the readback buffer.
    pub fn resolve(&self, encoder: &mut wgpu::CommandEncoder, substeps: u32) {
        if self.timing {
            let count = substeps * STAGES * 2;
            encoder.resolve_query_set(&self.query_set, 0..count, &self.resolve, 0);
            encoder.copy_buffer_to_buffer(&self.resolve, 0, &self.readback, 0, count as u64 * 8);
        }
    }

    /// After the frame's submission: asks for its stamps.
    pub fn request(&mut self, substeps: u32) {
        if !self.timing {
            return;
        }
        let state = Arc::new(AtomicU8::new(PENDING));
        let callback_state = state.clone();
        self.readback.map_async(wgpu::MapMode::Read, .., move |r| {
            callback_state.store(if r.is_ok() { ARRIVED } else { FAILED }, Ordering::Release);
        });
        self.in_flight = Some((substeps * STAGES * 2, state));
    }

    /// Adds the stamps that have arrived to `stages`.
    pub fn collect(&mut self, stages: &mut StageTimes) {
        let Some((count, state)) = &self.in_flight else {
            return;
        };
        match state.load(Ordering::Acquire) {
            PENDING => return,
            ARRIVED => {
                if let Ok(data) = self.readback.get_mapped_range(..) {
                    let ticks: &[u64] = bytemuck::cast_slice(&data[..*count as usize * 8]);
                    for (k, pair) in ticks.chunks_exact(2).enumerate() {
                        let ns = pair[1].saturating_sub(pair[0]) as f64 * self.period as f64;
                        let d = Duration::from_nanos(ns as u64);
                        match k as u32 % STAGES {
                            0 => stages.predict += d,
                            1 => stages.constraints += d,
                            2 => stages.self_collision += d,
                            _ => stages.collisions += d,
                        }
                    }
                }
                self.readback.unmap();
            }
            _ => {}
        }
        self.in_flight = None;
    }
}
