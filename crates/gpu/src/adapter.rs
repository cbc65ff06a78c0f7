//! Adapter choice for the `strata` binary and the tests (a library user brings their own
//! device): the best hardware adapter, one by name, or the software rasterizers Mesa ships —
//! lavapipe (Vulkan) first, then llvmpipe (GL).

use crate::GpuError;

/// Which adapter to open.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum AdapterChoice {
    /// Discrete > integrated > virtual > CPU-type (software), Vulkan before GL.
    Best,
    /// The first adapter whose name contains this text (case-insensitive).
    Named(String),
    /// A software adapter: lavapipe (Vulkan), else llvmpipe (GL).
    Software,
}

/// An opened device and what it runs on.
pub struct Gpu {
    pub adapter: wgpu::Adapter,
    pub device: wgpu::Device,
    pub queue: wgpu::Queue,
}

impl Gpu {
    /// "NAME (BACKEND, TYPE)".
    pub fn describe(&self) -> String {
        describe(&self.adapter.get_info())
    }
}

/// "NAME (BACKEND, TYPE)" of an adapter.
pub fn describe(info: &wgpu::AdapterInfo) -> String {
    let kind = match info.device_type {
        wgpu::DeviceType::DiscreteGpu => "discrete GPU",
        wgpu::DeviceType::IntegratedGpu => "integrated GPU",
        wgpu::DeviceType::VirtualGpu => "virtual GPU",
        wgpu::DeviceType::Cpu => "software",
        wgpu::DeviceType::Other => "other",
    };
    format!("{} ({:?}, {kind})", info.name, info.backend)
}

/// Every adapter of the native backends (Vulkan, and Metal on macOS); GL adapters (Mesa's
/// llvmpipe, found headless through EGL) only when there is none, since probing EGL is slow
/// and noisy on machines without a display.
pub fn adapters() -> Vec<wgpu::Adapter> {
    let native = enumerate(wgpu::Backends::VULKAN | wgpu::Backends::METAL);
    if native.is_empty() {
        enumerate(wgpu::Backends::GL)
    } else {
        native
    }
}

/// [`adapters`], best first (the order [`AdapterChoice::Best`] picks from).
pub fn ranked() -> Vec<wgpu::Adapter> {
    let mut all = adapters();
    all.sort_by_key(|a| rank(&a.get_info()));
    all
}

fn enumerate(backends: wgpu::Backends) -> Vec<wgpu::Adapter> {
    let mut desc = wgpu::InstanceDescriptor::new_without_display_handle();
    desc.backends = backends;
    let instance = wgpu::Instance::new(desc);
    pollster::block_on(instance.enumerate_adapters(backends))
}

/// Rank for [`AdapterChoice::Best`]: lower is better.
fn rank(info: &wgpu::AdapterInfo) -> (u32, u32) {
    let kind = match info.device_type {
        wgpu::DeviceType::DiscreteGpu => 0,
        wgpu::DeviceType::IntegratedGpu => 1,
        wgpu::DeviceType::VirtualGpu => 2,
        wgpu::DeviceType::Other => 3,
        wgpu::DeviceType::Cpu => 4,
    };
    let backend = match info.backend {
        wgpu::Backend::Vulkan | wgpu::Backend::Metal => 0,
        _ => 1,
    };
    (kind, backend)
}

/// Open the adapter `choice` asks for, with the adapter's own limits (the renderer needs more
/// storage buffers and bigger ones than the WebGPU defaults).
pub fn open(choice: &AdapterChoice) -> Result<Gpu, GpuError> {
    open_adapter(find(choice)?)
}

/// The adapter `choice` asks for, not yet opened (an error lists the adapters there are).
pub fn find(choice: &AdapterChoice) -> Result<wgpu::Adapter, GpuError> {
    let all = ranked();
    if all.is_empty() {
        return Err(GpuError::NoAdapter(
            "no Vulkan or GL adapter found (for a software one: apt-get install \
             mesa-vulkan-drivers)"
                .into(),
        ));
    }
    let names = || {
        all.iter()
            .map(|a| describe(&a.get_info()))
            .collect::<Vec<_>>()
            .join("; ")
    };
    let adapter = match choice {
        AdapterChoice::Best => all.first(),
        AdapterChoice::Named(name) => {
            let needle = name.to_lowercase();
            all.iter()
                .find(|a| a.get_info().name.to_lowercase().contains(&needle))
        }
        AdapterChoice::Software => all
            .iter()
            .find(|a| a.get_info().device_type == wgpu::DeviceType::Cpu),
    };
    let Some(adapter) = adapter.cloned() else {
        return Err(GpuError::NoAdapter(match choice {
            AdapterChoice::Named(name) => {
                format!("no adapter named like `{name}`; adapters: {}", names())
            }
            _ => format!(
                "no software adapter (install lavapipe: apt-get install mesa-vulkan-drivers); \
                 adapters: {}",
                names()
            ),
        }));
    };
    Ok(adapter)
}

/// Open `adapter` (one of [`ranked`]) with its own limits.
pub fn open_adapter(adapter: wgpu::Adapter) -> Result<Gpu, GpuError> {
    let (device, queue) = request_device(&adapter)?;
    Ok(Gpu {
        adapter,
        device,
        queue,
    })
}

/// A device with the adapter's limits and, when offered, timestamp queries and ray queries
/// (wgpu's `EXPERIMENTAL_RAY_QUERY`: the renderer's ray-query kernel, [`crate::Traversal`]);
/// a device that refuses the ray queries is opened without them.
pub fn request_device(adapter: &wgpu::Adapter) -> Result<(wgpu::Device, wgpu::Queue), GpuError> {
    let features = adapter.features() & wgpu::Features::TIMESTAMP_QUERY;
    let open = |features: wgpu::Features, experimental: wgpu::ExperimentalFeatures| {
        let desc = wgpu::DeviceDescriptor {
            label: Some("strata"),
            required_features: features,
            required_limits: adapter.limits(),
            experimental_features: experimental,
            ..Default::default()
        };
        pollster::block_on(adapter.request_device(&desc))
    };
    if adapter
        .features()
        .contains(wgpu::Features::EXPERIMENTAL_RAY_QUERY)
    {
        // SAFETY: wgpu's experimental features may have bugs; the renderer uses ray queries
        // only in the ray-query kernel, which is tested against the CPU reference on every
        // scene it serves (crates/gpu/tests/ray_query.rs).
        let experimental = unsafe { wgpu::ExperimentalFeatures::enabled() };
        if let Ok(device) = open(
            features | wgpu::Features::EXPERIMENTAL_RAY_QUERY,
            experimental,
        ) {
            return Ok(device);
        }
    }
    open(features, wgpu::ExperimentalFeatures::disabled())
        .map_err(|e| GpuError::Device(format!("{}: {e}", describe(&adapter.get_info()))))
}
