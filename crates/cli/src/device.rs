//! Which renderer runs a render: a GPU adapter through wgpu, or the CPU reference.

use clap::ValueEnum;
use stratapt_cpu::CpuRenderer;
use stratapt_gpu::adapter::{self, AdapterChoice, Gpu};
use stratapt_scene::Render;

/// `--device`: where to render.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum DeviceChoice {
    /// The best GPU adapter (hardware, else Mesa's lavapipe, else GL llvmpipe); the CPU
    /// reference when there is none or it cannot run the renderer.
    Auto,
    /// A GPU adapter (fails if none can be used).
    Gpu,
    /// The CPU reference renderer.
    Cpu,
}

/// The renderer a render will run on, resolved from a [`DeviceChoice`].
pub enum Device {
    Gpu {
        gpu: Gpu,
        renderer: stratapt_gpu::Renderer,
    },
    Cpu {
        threads: usize,
    },
}

impl Device {
    /// Resolve the choice (`adapter`: `--adapter NAME`, implies a GPU). `auto` falls back to
    /// the CPU with a note saying why.
    pub fn choose(
        choice: DeviceChoice,
        adapter: Option<&str>,
    ) -> anyhow::Result<(Device, Option<String>)> {
        let cpu = Device::Cpu {
            threads: rayon::current_num_threads(),
        };
        if choice == DeviceChoice::Cpu {
            if adapter.is_some() {
                anyhow::bail!("--adapter picks a GPU adapter; it cannot be used with --device cpu");
            }
            return Ok((cpu, None));
        }
        let wanted = match adapter {
            Some(name) => AdapterChoice::Named(name.to_string()),
            None => AdapterChoice::Best,
        };
        let opened = adapter::open(&wanted)
            .map_err(anyhow::Error::from)
            .and_then(|gpu| {
                let renderer = stratapt_gpu::Renderer::new(&gpu.device, &gpu.queue)
                    .map_err(|e| anyhow::anyhow!("{}: {e}", gpu.describe()))?;
                Ok(Device::Gpu { gpu, renderer })
            });
        match (opened, choice) {
            (Ok(device), _) => Ok((device, None)),
            (Err(e), DeviceChoice::Auto) if adapter.is_none() => Ok((
                cpu,
                Some(format!(
                    "no usable GPU adapter ({e:#}); using the CPU reference renderer"
                )),
            )),
            (Err(e), _) => Err(e.context("cannot render on a GPU (use --device cpu for the CPU)")),
        }
    }

    /// The renderer itself, behind the interface both devices share.
    pub fn renderer(&self) -> &dyn Render {
        match self {
            Device::Gpu { renderer, .. } => renderer,
            Device::Cpu { .. } => &CpuRenderer,
        }
    }

    pub fn describe(&self) -> String {
        match self {
            Device::Gpu { gpu, .. } => format!("GPU {}", gpu.describe()),
            Device::Cpu { threads } => match cpu_model() {
                Some(model) => format!("CPU reference renderer ({threads} threads, {model})"),
                None => format!("CPU reference renderer ({threads} threads)"),
            },
        }
    }
}

/// The processor's model name, where the OS says it (Linux: /proc/cpuinfo).
fn cpu_model() -> Option<String> {
    let info = std::fs::read_to_string("/proc/cpuinfo").ok()?;
    info.lines()
        .find(|l| l.starts_with("model name"))
        .and_then(|l| l.split_once(':'))
        .map(|(_, name)| name.trim().to_string())
        .filter(|name| !name.is_empty())
}

/// `strata adapters`: every adapter, best first, with its backend, type and the limit that
/// most often decides whether a scene fits.
pub fn list_adapters() -> anyhow::Result<()> {
    let adapters = adapter::ranked();
    if adapters.is_empty() {
        anyhow::bail!(
            "no GPU adapter found (for a software one: apt-get install mesa-vulkan-drivers); \
             `strata render --device cpu` uses the CPU reference renderer"
        );
    }
    for (i, a) in adapters.iter().enumerate() {
        let info = a.get_info();
        let limits = a.limits();
        out!(
            "{}. {}  storage buffers: {} per stage, {} MiB each{}",
            i + 1,
            adapter::describe(&info),
            limits.max_storage_buffers_per_shader_stage,
            limits.max_storage_buffer_binding_size >> 20,
            if a.features().contains(wgpu::Features::TIMESTAMP_QUERY) {
                ", timestamps"
            } else {
                ""
            }
        );
    }
    Ok(())
}
