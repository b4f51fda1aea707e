//! The GPU device Drape draws with when there is no window: headless
//! rendering, the CLI and the tests.
//!
//! Machines without a GPU render through Mesa: lavapipe (Vulkan, Debian's
//! `mesa-vulkan-drivers`) and llvmpipe (OpenGL ES through EGL, `libegl-mesa0`
//! with `libgl1-mesa-dri`). `WGPU_BACKEND=vulkan` or `=gl` picks one; otherwise
//! Vulkan is tried first, then GL. A missing adapter is an error that names
//! what was tried and what to install, never a silent fallback.

use std::fmt::Write as _;

/// A device and its queue, with a description of the adapter behind them.
#[derive(Clone)]
pub struct GpuContext {
    pub device: wgpu::Device,
    pub queue: wgpu::Queue,
    pub adapter_info: wgpu::AdapterInfo,
}

#[derive(Debug, thiserror::Error)]
pub enum ContextError {
    #[error(
        "no GPU adapter found. Tried: {tried}. On a machine without a GPU install Mesa's software drivers: \
         `apt-get install mesa-vulkan-drivers` (lavapipe, Vulkan) or `apt-get install libegl-mesa0 libgl1-mesa-dri` \
         (llvmpipe, OpenGL); WGPU_BACKEND=vulkan or =gl picks one"
    )]
    NoAdapter { tried: String },
    #[error("the {adapter} adapter would not open a device: {reason}")]
    NoDevice { adapter: String, reason: String },
}

/// The backends tried, in order, when `WGPU_BACKEND` does not choose.
const BACKEND_ORDER: [(wgpu::Backends, &str); 2] = [
    (wgpu::Backends::VULKAN, "Vulkan (lavapipe on Mesa)"),
    (wgpu::Backends::GL, "OpenGL ES via EGL (llvmpipe on Mesa)"),
];

impl GpuContext {
    /// Opens a device with no window, honouring `WGPU_BACKEND`.
    pub fn headless() -> Result<GpuContext, ContextError> {
        let allowed = wgpu::Backends::from_env().unwrap_or(wgpu::Backends::VULKAN | wgpu::Backends::GL);
        let mut tried = String::new();
        for (backend, name) in BACKEND_ORDER {
            if !allowed.contains(backend) {
                continue;
            }
            let mut descriptor = wgpu::InstanceDescriptor::new_without_display_handle();
            descriptor.backends = backend;
            descriptor.flags = wgpu::InstanceFlags::default().with_env();
            let instance = wgpu::Instance::new(descriptor);
            let options = wgpu::RequestAdapterOptions {
                power_preference: wgpu::PowerPreference::HighPerformance,
                force_fallback_adapter: false,
                compatible_surface: None,
                apply_limit_buckets: false,
            };
            match pollster::block_on(instance.request_adapter(&options)) {
                Ok(adapter) => return open_device(&adapter),
                Err(error) => {
                    if !tried.is_empty() {
                        tried.push_str("; ");
                    }
                    let _ = write!(tried, "{name}: {error}");
                }
            }
        }
        if tried.is_empty() {
            tried = format!("nothing (WGPU_BACKEND={:?} names no Vulkan or GL backend)", std::env::var("WGPU_BACKEND"));
        }
        Err(ContextError::NoAdapter { tried })
    }

    /// "llvmpipe (LLVM 15.0.6, 256 bits) on Gl", for logs and reports.
    pub fn describe(&self) -> String {
        format!("{} on {:?}", self.adapter_info.name, self.adapter_info.backend)
    }
}

/// A device with the adapter's own limits (software drivers allow large
/// textures, which big `--size` renders need) and no optional features.
pub fn open_device(adapter: &wgpu::Adapter) -> Result<GpuContext, ContextError> {
    let adapter_info = adapter.get_info();
    let descriptor = wgpu::DeviceDescriptor {
        label: Some("drape"),
        required_features: wgpu::Features::empty(),
        required_limits: wgpu::Limits::downlevel_defaults().using_resolution(adapter.limits()),
        experimental_features: wgpu::ExperimentalFeatures::disabled(),
        memory_hints: wgpu::MemoryHints::MemoryUsage,
        trace: wgpu::Trace::Off,
    };
    let (device, queue) = pollster::block_on(adapter.request_device(&descriptor))
        .map_err(|error| ContextError::NoDevice { adapter: adapter_info.name.clone(), reason: error.to_string() })?;
    Ok(GpuContext { device, queue, adapter_info })
}
