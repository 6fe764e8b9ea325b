//! The wgpu device the backend runs on: found headless here, or handed in by
//! a caller (the app, the renderer) that already has one.

use std::fmt;

/// Why the GPU backend cannot run a simulation. The text says what
/// happened; what a user can do about it (another backend, a software
/// driver) is the caller's to say, as only it knows its options.
#[derive(Debug, thiserror::Error)]
pub enum GpuError {
    /// No adapter at all: no GPU and no software driver.
    #[error("no GPU adapter found ({0})")]
    NoAdapter(String),
    /// The adapter would not give a device.
    #[error("the GPU adapter {adapter} gave no device: {reason}")]
    NoDevice {
        /// Adapter name.
        adapter: String,
        /// wgpu's reason.
        reason: String,
    },
    /// The scene uses a feature the GPU backend does not have yet.
    #[error("{field}: {reason}")]
    Unsupported {
        /// JSON path of the scene field.
        field: String,
        /// What is missing.
        reason: String,
    },
    /// A buffer would pass the device's limits.
    #[error("{0}")]
    TooLarge(String),
    /// Reading the state back failed.
    #[error("reading the state back from the GPU failed: {0}")]
    Readback(String),
}

/// A device and its queue, with what reports say about the adapter.
#[derive(Clone)]
pub struct GpuContext {
    /// The device every buffer and pipeline lives on.
    pub device: wgpu::Device,
    /// Its queue.
    pub queue: wgpu::Queue,
    /// The adapter's name and wgpu backend, e.g. "llvmpipe (LLVM 15.0.6, 256 bits) (Vulkan)".
    pub adapter: String,
    /// What the adapter is: a CPU (lavapipe) runs a workgroup on one core.
    pub device_type: wgpu::DeviceType,
}

impl fmt::Debug for GpuContext {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("GpuContext")
            .field("adapter", &self.adapter)
            .finish()
    }
}

impl GpuContext {
    /// A headless device on the best adapter found, blocking until it is ready.
    pub fn new() -> Result<Self, GpuError> {
        pollster::block_on(Self::request())
    }

    /// A headless device on the best adapter found (high performance first).
    pub async fn request() -> Result<Self, GpuError> {
        let instance =
            wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle_from_env());
        let adapter = instance
            .request_adapter(&wgpu::RequestAdapterOptions {
                power_preference: wgpu::PowerPreference::HighPerformance,
                force_fallback_adapter: false,
                compatible_surface: None,
                ..Default::default()
            })
            .await
            .map_err(|e| GpuError::NoAdapter(e.to_string()))?;
        let info = adapter.get_info();
        let name = format!("{} ({:?})", info.name, info.backend);
        let (device, queue) = adapter
            .request_device(&wgpu::DeviceDescriptor {
                label: Some("pleat-gpu"),
                // Per-stage times where the adapter can stamp passes.
                required_features: adapter.features() & wgpu::Features::TIMESTAMP_QUERY,
                required_limits: Self::limits(&adapter.limits()),
                ..Default::default()
            })
            .await
            .map_err(|e| GpuError::NoDevice {
                adapter: name.clone(),
                reason: e.to_string(),
            })?;
        Ok(GpuContext {
            device,
            queue,
            adapter: name,
            device_type: info.device_type,
        })
    }

    /// WebGPU's default limits, with buffers as large as the adapter allows
    /// (large cloths on native GPUs), as many storage buffers a kernel as
    /// it binds (the persistent kernel with self-contacts binds nine) and
    /// as much workgroup memory (the persistent kernel keeps a sheet's
    /// positions there where they fit).
    pub fn limits(adapter: &wgpu::Limits) -> wgpu::Limits {
        wgpu::Limits {
            max_storage_buffer_binding_size: adapter.max_storage_buffer_binding_size,
            max_buffer_size: adapter.max_buffer_size,
            max_storage_buffers_per_shader_stage: adapter.max_storage_buffers_per_shader_stage,
            max_compute_workgroup_storage_size: adapter.max_compute_workgroup_storage_size,
            ..wgpu::Limits::default()
        }
    }
}
