//! Reading the particle state back from the GPU in two calls: one starts
//! the copy, the other takes the result once it has arrived, so that
//! WebGPU, which maps buffers only between turns of the event loop, is
//! never blocked on. A blocking read is the two with a wait between. Every
//! read goes through one mappable buffer, made once ([`staging`]).

use crate::GpuError;
use std::sync::atomic::{AtomicU8, Ordering};
use std::sync::Arc;

const PENDING: u8 = 0;
const ARRIVED: u8 = 1;
const FAILED: u8 = 2;

/// The mappable buffer every read of `bytes` bytes goes through.
pub fn staging(device: &wgpu::Device, bytes: u64) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("readback"),
        size: bytes.max(16),
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}

/// A copy of the state buffers on its way to the CPU.
pub struct Readback {
    staging: wgpu::Buffer,
    bytes: u64,
    state: Arc<AtomicU8>,
}

impl Readback {
    /// Copies `sources` (each `size` bytes) one after the other into
    /// `staging` (from [`staging`], large enough, with no read on its way)
    /// and asks for it to be mapped.
    pub fn start(
        (device, queue): (&wgpu::Device, &wgpu::Queue),
        staging: &wgpu::Buffer,
        sources: &[&wgpu::Buffer],
        size: u64,
    ) -> Self {
        let bytes = sources.len() as u64 * size;
        let mut encoder = device.create_command_encoder(&Default::default());
        for (k, buffer) in sources.iter().enumerate() {
            encoder.copy_buffer_to_buffer(buffer, 0, staging, k as u64 * size, size);
        }
        queue.submit([encoder.finish()]);
        let state = Arc::new(AtomicU8::new(PENDING));
        let callback_state = state.clone();
        staging.map_async(wgpu::MapMode::Read, .., move |r| {
            callback_state.store(if r.is_ok() { ARRIVED } else { FAILED }, Ordering::Release);
        });
        Readback {
            staging: staging.clone(),
            bytes,
            state,
        }
    }

    /// The copied vectors once they have arrived, `None` while on the way.
    pub fn try_take(&self) -> Option<Result<Vec<[f32; 4]>, GpuError>> {
        match self.state.load(Ordering::Acquire) {
            PENDING => None,
            ARRIVED => Some(self.take()),
            _ => Some(Err(GpuError::Readback(
                "the buffer could not be mapped".into(),
            ))),
        }
    }

    fn take(&self) -> Result<Vec<[f32; 4]>, GpuError> {
        let data = self
            .staging
            .get_mapped_range(..)
            .map_err(|e| GpuError::Readback(e.to_string()))?;
        let vectors = bytemuck::cast_slice::<u8, [f32; 4]>(&data[..self.bytes as usize]).to_vec();
        drop(data);
        self.staging.unmap();
        Ok(vectors)
    }
}
