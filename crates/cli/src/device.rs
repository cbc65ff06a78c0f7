//! Which renderer runs a render: a GPU adapter through wgpu, or the CPU reference.

pub mod choice;
mod probe;

use choice::{AdapterFacts, CpuKind, Kind, Pick, Probe};
use clap::ValueEnum;
use stratapt_cpu::{Cpu8Renderer, CpuRenderer};
use stratapt_film::{Render, RenderError};
use stratapt_gpu::adapter::{self, AdapterChoice, Gpu};
use stratapt_gpu::GpuError;
use stratapt_scene::{FlatScene, RenderSettings};

/// `--device`: where to render.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum DeviceChoice {
    /// The fastest renderer here: a hardware GPU, else Mesa's lavapipe where it is measured at
    /// least as fast as the CPU reference on the scene, else the CPU reference (never Mesa's GL
    /// llvmpipe, about 10× slower); it says which and why.
    Auto,
    /// A GPU adapter (fails if none can be used).
    Gpu,
    /// The CPU reference renderer.
    Cpu,
    /// The eight-lane CPU renderer, a prototype: it covers what Mitsuba's Cornell box calls for
    /// (static triangles, plain diffuse materials, one one-sided rectangle light, a pinhole
    /// camera with the box filter, the Sobol sampler, MIS) and refuses any other scene.
    Cpu8,
}

/// The renderer a render will run on, resolved from a [`DeviceChoice`]. (A process holds one
/// or a few, so the GPU variant's size does not matter.)
#[allow(clippy::large_enum_variant)]
pub enum Device {
    Gpu {
        gpu: Gpu,
        renderer: stratapt_gpu::Renderer,
    },
    Cpu {
        threads: usize,
    },
    /// The eight-lane CPU prototype ([`DeviceChoice::Cpu8`]).
    Cpu8 {
        threads: usize,
    },
}

impl Device {
    /// Resolve the choice (`adapter`: `--adapter NAME`, implies a GPU). `auto` follows
    /// [`choice::choose`]: a hardware GPU, else lavapipe where it renders `probe` (the scene
    /// about to be rendered) at least as fast as the CPU reference (measured once per machine,
    /// adapter and scene, and cached), else the CPU. Returns the device and why it was chosen.
    pub fn choose(
        choice: DeviceChoice,
        adapter: Option<&str>,
        probe: Option<(&mut FlatScene, &RenderSettings)>,
    ) -> anyhow::Result<(Device, Option<String>)> {
        let (device, why) = Device::choose_with(choice, adapter, probe, &mut |a| {
            Device::open(a).map(Box::new)
        })?;
        Ok((*device, why))
    }

    /// [`Device::choose`] with the devices opened by `open` (e.g. from a cache of the devices a
    /// process has opened, so that their compiled kernels serve every render) and handed out
    /// as `D`.
    pub fn choose_with<D: std::ops::Deref<Target = Device> + From<Device>>(
        choice: DeviceChoice,
        adapter: Option<&str>,
        probe: Option<(&mut FlatScene, &RenderSettings)>,
        open: &mut dyn FnMut(wgpu::Adapter) -> anyhow::Result<D>,
    ) -> anyhow::Result<(D, Option<String>)> {
        let cpu = || D::from(Device::cpu());
        if choice == DeviceChoice::Cpu {
            if adapter.is_some() {
                anyhow::bail!("--adapter picks a GPU adapter; it cannot be used with --device cpu");
            }
            return Ok((cpu(), None));
        }
        if choice == DeviceChoice::Cpu8 {
            if adapter.is_some() {
                anyhow::bail!(
                    "--adapter picks a GPU adapter; it cannot be used with --device cpu8"
                );
            }
            let threads = rayon::current_num_threads();
            return Ok((D::from(Device::Cpu8 { threads }), None));
        }
        if choice == DeviceChoice::Gpu || adapter.is_some() {
            let wanted = match adapter {
                Some(name) => AdapterChoice::Named(name.to_string()),
                None => AdapterChoice::Best,
            };
            let device = adapter::find(&wanted)
                .map_err(anyhow::Error::from)
                .and_then(&mut *open)
                .map_err(|e| e.context("cannot render on a GPU (use --device cpu for the CPU)"))?;
            return Ok((device, None));
        }
        // ---- auto ------------------------------------------------------------------------------
        // The CPU renderer to weigh lavapipe against: the eight-lane one where it covers the
        // scene (the same image, faster), else the reference.
        let cpu_kind = match &probe {
            Some((scene, settings)) if stratapt_cpu::eight::supports(scene, settings).is_ok() => {
                CpuKind::EightLanes
            }
            _ => CpuKind::Reference,
        };
        let cpu = || match cpu_kind {
            CpuKind::EightLanes => D::from(Device::Cpu8 {
                threads: rayon::current_num_threads(),
            }),
            CpuKind::Reference => D::from(Device::cpu()),
        };
        let adapters = adapter::ranked();
        let facts: Vec<AdapterFacts> = adapters
            .iter()
            .map(|a| AdapterFacts::of(&a.get_info()))
            .collect();
        let first = choice::choose(&facts, None, cpu_kind);
        let lavapipe_at = facts.iter().position(|a| a.kind == Kind::Software && !a.gl);
        let has_hardware = facts.iter().any(|a| a.kind != Kind::Software);
        // Only lavapipe could beat the CPU: measure it on this scene (or take the cached figure).
        let mut opened: Option<D> = None;
        let mut measured = None;
        if let (false, Some(i), Some((scene, settings))) = (has_hardware, lavapipe_at, probe) {
            match open(adapters[i].clone()) {
                Ok(device) => {
                    measured = probe::ratio(&device, scene, settings, cpu_kind);
                    opened = Some(device);
                }
                Err(e) => {
                    return Ok((
                        cpu(),
                        Some(format!("lavapipe cannot run the kernel ({e:#})")),
                    ))
                }
            }
        }
        let decided = match measured {
            Some(ratio) => choice::choose(&facts, Some(Probe { ratio }), cpu_kind),
            None => first,
        };
        match decided.pick {
            Pick::Cpu => Ok((cpu(), Some(decided.reason))),
            Pick::Gpu(i) => {
                let device = match opened {
                    Some(device) => Ok(device),
                    None => open(adapters[i].clone()),
                };
                match device {
                    Ok(device) => Ok((device, Some(decided.reason))),
                    Err(e) => Ok((
                        cpu(),
                        Some(format!("{} cannot run the kernel ({e:#})", facts[i].name)),
                    )),
                }
            }
        }
    }

    /// The CPU reference on every thread of rayon's pool.
    pub fn cpu() -> Device {
        Device::Cpu {
            threads: rayon::current_num_threads(),
        }
    }

    /// A renderer on `adapter`, opened with its own limits.
    pub fn open(adapter: wgpu::Adapter) -> anyhow::Result<Device> {
        let gpu = adapter::open_adapter(adapter)?;
        // The kernel places its twins by a hash; the error estimate's peak twins come from the
        // CPU reference.
        let renderer = stratapt_gpu::Renderer::new(&gpu.device, &gpu.queue)
            .map_err(|e| anyhow::anyhow!("{}: {e}", gpu.describe()))?
            .with_peak_twins(std::sync::Arc::new(stratapt_cpu::render_peak_twins));
        Ok(Device::Gpu { gpu, renderer })
    }

    /// Whether a render that failed with `error` on this device should be redone on the CPU
    /// reference: under `auto`, when the scene does not fit on the GPU.
    pub fn falls_back(choice: DeviceChoice, adapter: Option<&str>, error: &RenderError) -> bool {
        choice == DeviceChoice::Auto
            && adapter.is_none()
            && matches!(
                error.downcast_ref::<GpuError>(),
                Some(GpuError::TooLarge(_))
            )
    }

    /// The renderer itself, behind the interface both devices share.
    pub fn renderer(&self) -> &(dyn Render + Sync) {
        match self {
            Device::Gpu { renderer, .. } => renderer,
            Device::Cpu { .. } => &CpuRenderer,
            Device::Cpu8 { .. } => &Cpu8Renderer,
        }
    }

    /// `device: WHAT (WHY)`, the line every render starts with.
    pub fn line(&self, why: Option<&str>) -> String {
        match why {
            Some(why) => format!("device: {} ({why})", self.describe()),
            None => format!("device: {}", self.describe()),
        }
    }

    pub fn describe(&self) -> String {
        match self {
            Device::Gpu { gpu, .. } => format!("GPU {}", gpu.describe()),
            Device::Cpu { threads } => match cpu_model() {
                Some(model) => format!("CPU reference renderer ({threads} threads, {model})"),
                None => format!("CPU reference renderer ({threads} threads)"),
            },
            Device::Cpu8 { threads } => match cpu_model() {
                Some(model) => {
                    format!("CPU, eight lanes per thread (prototype; {threads} threads, {model})")
                }
                None => format!("CPU, eight lanes per thread (prototype; {threads} threads)"),
            },
        }
    }
}

/// The processor's model name, where the OS says it (Linux: /proc/cpuinfo).
pub(crate) fn cpu_model() -> Option<String> {
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_auto_falls_back_and_only_for_a_scene_too_large() {
        let too_large: RenderError = Box::new(GpuError::TooLarge("244 MiB > 128 MiB".into()));
        let lost: RenderError = Box::new(GpuError::Device("device lost".into()));
        assert!(Device::falls_back(DeviceChoice::Auto, None, &too_large));
        assert!(!Device::falls_back(DeviceChoice::Gpu, None, &too_large));
        assert!(!Device::falls_back(
            DeviceChoice::Auto,
            Some("llvmpipe"),
            &too_large
        ));
        assert!(!Device::falls_back(DeviceChoice::Auto, None, &lost));
    }
}
