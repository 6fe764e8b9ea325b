//! Buffers and bind group entries as every kernel's set-up makes them.

use crate::context::{GpuContext, GpuError};
use bytemuck::Pod;
use wgpu::util::DeviceExt;

/// Binding `binding` to the whole of `buffer`.
pub fn entry(binding: u32, buffer: &wgpu::Buffer) -> wgpu::BindGroupEntry<'_> {
    wgpu::BindGroupEntry {
        binding,
        resource: buffer.as_entire_binding(),
    }
}

/// Binding `binding` to the first `size` bytes of `buffer` (a dynamic
/// uniform's window).
pub fn sized_entry(binding: u32, buffer: &wgpu::Buffer, size: usize) -> wgpu::BindGroupEntry<'_> {
    wgpu::BindGroupEntry {
        binding,
        resource: wgpu::BindingResource::Buffer(wgpu::BufferBinding {
            buffer,
            offset: 0,
            size: wgpu::BufferSize::new(size as u64),
        }),
    }
}

/// A storage buffer holding `items` (16 bytes at least: empty bindings are invalid).
pub fn storage<T: Pod>(device: &wgpu::Device, label: &str, items: &[T]) -> wgpu::Buffer {
    let mut bytes = bytemuck::cast_slice::<T, u8>(items).to_vec();
    bytes.resize(bytes.len().max(16).next_multiple_of(4), 0);
    device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some(label),
        contents: &bytes,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
    })
}

/// A zeroed storage buffer of `size` bytes (16 at least).
pub fn zeroed(device: &wgpu::Device, label: &str, size: u64) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size: size.max(16).next_multiple_of(4),
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}

/// Refuses a buffer larger than one binding may be.
pub fn check_size(context: &GpuContext, bytes: u64, what: &str) -> Result<(), GpuError> {
    let limit = context.device.limits().max_storage_buffer_binding_size;
    if bytes > limit {
        return Err(GpuError::TooLarge(format!(
            "the {what} take {} MiB, more than the {} MiB one buffer may hold on {}",
            bytes >> 20,
            limit >> 20,
            context.adapter
        )));
    }
    Ok(())
}
