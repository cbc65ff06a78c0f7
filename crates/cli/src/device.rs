//! Which renderer runs a render.

use clap::ValueEnum;

/// `--device`: where to render.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum DeviceChoice {
    /// The best renderer available: a GPU adapter when the GPU renderer is built, else the CPU.
    Auto,
    /// A GPU adapter (fails if none can be used).
    Gpu,
    /// The CPU reference renderer.
    Cpu,
}

/// The renderer a render will run on, resolved from a [`DeviceChoice`].
pub enum Device {
    Cpu { threads: usize },
}

impl Device {
    /// Resolve the choice. This build carries only the CPU reference renderer, so `auto` falls
    /// back to it (and says so) and `gpu` is refused with the reason.
    pub fn choose(choice: DeviceChoice) -> anyhow::Result<(Device, Option<&'static str>)> {
        let cpu = Device::Cpu {
            threads: rayon::current_num_threads(),
        };
        match choice {
            DeviceChoice::Cpu => Ok((cpu, None)),
            DeviceChoice::Auto => Ok((cpu, Some("no GPU renderer in this build; using the CPU"))),
            DeviceChoice::Gpu => anyhow::bail!(
                "--device gpu: this build has no GPU renderer yet; use --device cpu or auto"
            ),
        }
    }

    pub fn describe(&self) -> String {
        match self {
            Device::Cpu { threads } => format!("CPU reference renderer ({threads} threads)"),
        }
    }
}
