//! The Vulkan adapter the wgpu renderer runs on, found on its own and once per process:
//! finding it is cheap next to opening a device, uploading a scene and compiling the shaders
//! (about 0.1 s on turtlebot3_house and 0.4 s on aws_small_house with Mesa's llvmpipe). So
//! [`super::Renderer::auto`] looks at the adapter first and builds the GPU renderer only on
//! a real GPU.

use super::gpu::{block, GpuError};
use std::sync::OnceLock;

/// A Vulkan adapter: a GPU first (discrete, integrated, virtual, other), else a software one
/// such as llvmpipe; the environment variable `XHAB_GPU_ADAPTER` keeps only the adapters
/// whose name contains it (case-insensitive).
#[derive(Clone)]
pub struct GpuAdapter {
    /// The adapter, for [`super::GpuRenderer`] to open its device on.
    pub(super) adapter: wgpu::Adapter,
    /// Its name, backend, device type and driver.
    info: wgpu::AdapterInfo,
}

impl std::fmt::Debug for GpuAdapter {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "GpuAdapter({})", self.describe())
    }
}

impl GpuAdapter {
    /// Finds the adapter (no device is opened); [`GpuError::NoAdapter`] when there is none.
    /// The adapters are enumerated once per process (creating the Vulkan instance takes tens
    /// of milliseconds, even for llvmpipe), so `XHAB_GPU_ADAPTER` is read then.
    pub fn find() -> Result<GpuAdapter, GpuError> {
        static FOUND: OnceLock<Option<GpuAdapter>> = OnceLock::new();
        FOUND.get_or_init(GpuAdapter::enumerate).clone().ok_or(GpuError::NoAdapter)
    }

    /// The adapter as [`GpuAdapter::find`] ranks them, enumerated now.
    fn enumerate() -> Option<GpuAdapter> {
        let instance = wgpu::Instance::new(wgpu::InstanceDescriptor {
            backends: wgpu::Backends::VULKAN,
            ..wgpu::InstanceDescriptor::new_without_display_handle()
        });
        let mut adapters = block(instance.enumerate_adapters(wgpu::Backends::VULKAN));
        if let Ok(want) = std::env::var("XHAB_GPU_ADAPTER") {
            let want = want.to_lowercase();
            adapters.retain(|a| a.get_info().name.to_lowercase().contains(&want));
        }
        let rank = |t: wgpu::DeviceType| match t {
            wgpu::DeviceType::DiscreteGpu => 0,
            wgpu::DeviceType::IntegratedGpu => 1,
            wgpu::DeviceType::VirtualGpu => 2,
            wgpu::DeviceType::Other => 3,
            wgpu::DeviceType::Cpu => 4,
        };
        adapters.sort_by_key(|a| rank(a.get_info().device_type));
        let adapter = adapters.into_iter().next()?;
        let info = adapter.get_info();
        Some(GpuAdapter { adapter, info })
    }

    /// The adapter's description: name, backend, device type (and driver).
    pub fn describe(&self) -> String {
        let info = &self.info;
        let driver = if info.driver.is_empty() { String::new() } else { format!(", driver {} {}", info.driver, info.driver_info) };
        format!("{} ({:?}, {:?}{driver})", info.name, info.backend, info.device_type)
    }

    /// True when the adapter renders on the CPU (device type `Cpu`, e.g. Mesa's llvmpipe).
    pub fn is_software(&self) -> bool {
        self.info.device_type == wgpu::DeviceType::Cpu
    }
}
