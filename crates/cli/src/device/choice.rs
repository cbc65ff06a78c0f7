//! Which renderer `--device auto` picks, as a pure function of the adapters found (and, for a
//! software Vulkan adapter, a measured speed ratio), so it is tested on lists of adapters
//! without a device.
//!
//! The order: a hardware GPU (discrete > integrated > virtual > other, Vulkan/Metal before GL);
//! else Mesa's software Vulkan (lavapipe) only where it renders at least as fast as the CPU
//! reference; else the CPU reference. Mesa's GL llvmpipe never by default: it renders strata's
//! kernel far slower than the CPU reference (measured:
//! docs/measurements/performance.md#what---device-auto-picks).

/// What kind of adapter, for the choice.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Kind {
    Discrete,
    Integrated,
    Virtual,
    Other,
    /// A CPU-type adapter: lavapipe (Vulkan) or llvmpipe (GL).
    Software,
}

/// What one adapter is, as the choice sees it.
#[derive(Clone, Debug, PartialEq)]
pub struct AdapterFacts {
    pub name: String,
    pub kind: Kind,
    /// GL (Mesa's llvmpipe, or a GL-only driver) rather than Vulkan / Metal / DX12.
    pub gl: bool,
    /// The driver's own description, e.g. `Mesa 25.0.7-2~bpo12+1 (LLVM 15.0.6)`.
    pub driver: String,
}

impl AdapterFacts {
    pub fn of(info: &wgpu::AdapterInfo) -> Self {
        Self {
            name: info.name.clone(),
            kind: match info.device_type {
                wgpu::DeviceType::DiscreteGpu => Kind::Discrete,
                wgpu::DeviceType::IntegratedGpu => Kind::Integrated,
                wgpu::DeviceType::VirtualGpu => Kind::Virtual,
                wgpu::DeviceType::Other => Kind::Other,
                wgpu::DeviceType::Cpu => Kind::Software,
            },
            gl: info.backend == wgpu::Backend::Gl,
            driver: info.driver_info.clone(),
        }
    }
}

/// The lavapipe speed measured against the CPU renderer `auto` would use on this machine (see
/// `probe`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Probe {
    /// lavapipe's samples per second over the CPU renderer's.
    pub ratio: f64,
}

/// The CPU renderer `auto` weighs lavapipe against, and renders on when the CPU wins: the
/// eight-lane renderer where it covers the scene (the same image, about twice as fast), else
/// the reference.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CpuKind {
    Reference,
    EightLanes,
}

impl CpuKind {
    /// How the reasons name it.
    pub fn name(self) -> &'static str {
        match self {
            CpuKind::Reference => "the CPU reference",
            CpuKind::EightLanes => "the eight-lane CPU renderer",
        }
    }
}

/// What `auto` renders on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Pick {
    /// The adapter at this index of the list.
    Gpu(usize),
    Cpu,
}

/// A pick and the reason printed with it.
#[derive(Clone, Debug, PartialEq)]
pub struct Choice {
    pub pick: Pick,
    pub reason: String,
}

/// From this Mesa release on, lavapipe runs strata's kernel about as fast as the CPU reference,
/// where Mesa 22.3 ran it well behind, so `auto` takes it without a probe figure (measured:
/// docs/measurements/performance.md#what---device-auto-picks).
pub const FAST_LAVAPIPE_MESA: u32 = 25;

/// The Mesa major and minor version in a driver description (`Mesa 25.0.7-2~bpo12+1`).
pub fn mesa_version(driver: &str) -> Option<(u32, u32)> {
    let rest = &driver[driver.find("Mesa ")? + 5..];
    let mut parts = rest.split(|c: char| !c.is_ascii_digit());
    let major = parts.next()?.parse().ok()?;
    let minor = parts.next().and_then(|p| p.parse().ok()).unwrap_or(0);
    Some((major, minor))
}

/// The renderer `--device auto` uses, given the adapters found, the CPU renderer the scene
/// allows (`cpu`) and, when there is a software Vulkan adapter and no hardware one, the probe's
/// measured speed ratio against that CPU renderer (if any).
pub fn choose(adapters: &[AdapterFacts], probe: Option<Probe>, cpu: CpuKind) -> Choice {
    let name = cpu.name();
    // ---- A hardware GPU ----------------------------------------------------------------------
    let hardware = adapters
        .iter()
        .enumerate()
        .filter(|(_, a)| a.kind != Kind::Software)
        .min_by_key(|(_, a)| (a.kind, a.gl));
    if let Some((i, a)) = hardware {
        return Choice {
            pick: Pick::Gpu(i),
            reason: format!("hardware GPU {}", a.name),
        };
    }
    // ---- Software Vulkan, where it is at least as fast as the CPU ----------------------------
    let lavapipe = adapters
        .iter()
        .position(|a| a.kind == Kind::Software && !a.gl);
    if let Some(i) = lavapipe {
        let a = &adapters[i];
        let mesa = mesa_version(&a.driver);
        let version = mesa.map_or("unknown Mesa".to_string(), |(m, n)| format!("Mesa {m}.{n}"));
        return match probe {
            Some(p) => Choice {
                pick: if p.ratio >= 1.0 {
                    Pick::Gpu(i)
                } else {
                    Pick::Cpu
                },
                reason: format!(
                    "no hardware GPU; lavapipe ({version}) measured {:.2}× {name} here",
                    p.ratio
                ),
            },
            // The eight-lane renderer renders the Cornell boxes 2.2× the reference's speed,
            // lavapipe about 0.8× (docs/measurements/eight-lanes.md).
            None if cpu == CpuKind::EightLanes => Choice {
                pick: Pick::Cpu,
                reason: format!(
                    "no hardware GPU; {name} covers this scene, about twice the speed of the CPU \
                     reference, which lavapipe ({version}) about matches"
                ),
            },
            None if mesa.is_some_and(|(m, _)| m >= FAST_LAVAPIPE_MESA) => Choice {
                pick: Pick::Gpu(i),
                reason: format!(
                    "no hardware GPU; lavapipe ({version}) is about as fast as the CPU reference"
                ),
            },
            None => Choice {
                pick: Pick::Cpu,
                reason: format!(
                    "no hardware GPU; lavapipe ({version}) runs about 0.3–0.7× the CPU reference \
                     (Mesa {FAST_LAVAPIPE_MESA}+ is about 2× faster)"
                ),
            },
        };
    }
    // ---- GL llvmpipe only, or nothing ---------------------------------------------------------
    let mut reason = if adapters.iter().any(|a| a.kind == Kind::Software) {
        "only Mesa's GL llvmpipe, about 0.1× the CPU reference (--device gpu uses it anyway)"
            .to_string()
    } else {
        "no GPU adapter".to_string()
    };
    if cpu == CpuKind::EightLanes {
        reason.push_str(&format!("; {name} covers this scene"));
    }
    Choice {
        pick: Pick::Cpu,
        reason,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn adapter(name: &str, kind: Kind, gl: bool, driver: &str) -> AdapterFacts {
        AdapterFacts {
            name: name.into(),
            kind,
            gl,
            driver: driver.into(),
        }
    }

    fn lavapipe(mesa: &str) -> AdapterFacts {
        adapter(
            "llvmpipe (LLVM 15.0.6, 256 bits)",
            Kind::Software,
            false,
            &format!("Mesa {mesa} (LLVM 15.0.6)"),
        )
    }

    fn llvmpipe_gl() -> AdapterFacts {
        adapter(
            "llvmpipe (LLVM 15.0.6, 256 bits)",
            Kind::Software,
            true,
            "4.5 (Core Profile) Mesa 22.3.6",
        )
    }

    #[test]
    fn hardware_first_discrete_before_integrated() {
        let list = [
            lavapipe("25.0.7"),
            adapter("Intel UHD 770", Kind::Integrated, false, "Mesa 25.0.7"),
            adapter("NVIDIA H200", Kind::Discrete, false, "570.86"),
        ];
        let c = choose(&list, Some(Probe { ratio: 9.0 }), CpuKind::Reference);
        assert_eq!(c.pick, Pick::Gpu(2));
        assert!(
            c.reason.contains("hardware GPU NVIDIA H200"),
            "{}",
            c.reason
        );
        // A GL-only hardware GPU still beats any software renderer.
        let list = [
            lavapipe("25.0.7"),
            adapter("Radeon", Kind::Integrated, true, "4.6 Mesa"),
        ];
        assert_eq!(choose(&list, None, CpuKind::Reference).pick, Pick::Gpu(1));
    }

    #[test]
    fn software_vulkan_by_mesa_version_without_a_probe() {
        let fast = choose(
            &[lavapipe("25.0.7-2~bpo12+1"), llvmpipe_gl()],
            None,
            CpuKind::Reference,
        );
        assert_eq!(fast.pick, Pick::Gpu(0));
        assert!(fast.reason.contains("Mesa 25.0"), "{}", fast.reason);
        let slow = choose(&[lavapipe("22.3.6")], None, CpuKind::Reference);
        assert_eq!(slow.pick, Pick::Cpu);
        assert!(
            slow.reason.contains("Mesa 22.3") && slow.reason.contains("0.3–0.7×"),
            "{}",
            slow.reason
        );
        assert_eq!(
            choose(&[lavapipe("26.1.0")], None, CpuKind::Reference).pick,
            Pick::Gpu(0)
        );
    }

    #[test]
    fn a_probe_overrides_the_version_rule() {
        let c = choose(
            &[lavapipe("25.0.7")],
            Some(Probe { ratio: 0.64 }),
            CpuKind::Reference,
        );
        assert_eq!(c.pick, Pick::Cpu);
        assert!(c.reason.contains("0.64×"), "{}", c.reason);
        let c = choose(
            &[lavapipe("22.3.6")],
            Some(Probe { ratio: 1.2 }),
            CpuKind::Reference,
        );
        assert_eq!(c.pick, Pick::Gpu(0));
    }

    /// Where the eight-lane CPU renderer covers the scene, lavapipe is weighed against it, and
    /// without a probe figure the CPU wins; the reasons name it.
    #[test]
    fn the_eight_lane_renderer_where_it_covers_the_scene() {
        let eight = CpuKind::EightLanes;
        let c = choose(&[lavapipe("25.0.7")], None, eight);
        assert_eq!(c.pick, Pick::Cpu);
        assert!(c.reason.contains("eight-lane CPU renderer"), "{}", c.reason);
        let c = choose(&[lavapipe("25.0.7")], Some(Probe { ratio: 0.35 }), eight);
        assert_eq!(c.pick, Pick::Cpu);
        assert!(
            c.reason.contains("0.35× the eight-lane CPU renderer"),
            "{}",
            c.reason
        );
        let c = choose(&[lavapipe("25.0.7")], Some(Probe { ratio: 1.3 }), eight);
        assert_eq!(c.pick, Pick::Gpu(0));
        let hardware = [adapter("NVIDIA H200", Kind::Discrete, false, "570.86")];
        assert_eq!(choose(&hardware, None, eight).pick, Pick::Gpu(0));
        let c = choose(&[], None, eight);
        assert_eq!((c.pick, c.reason.contains("eight-lane")), (Pick::Cpu, true));
    }

    #[test]
    fn gl_llvmpipe_never_by_default() {
        let c = choose(&[llvmpipe_gl()], None, CpuKind::Reference);
        assert_eq!(c.pick, Pick::Cpu);
        assert!(c.reason.contains("GL llvmpipe"), "{}", c.reason);
        let c = choose(&[], None, CpuKind::Reference);
        assert_eq!(c.pick, Pick::Cpu);
        assert_eq!(c.reason, "no GPU adapter");
    }

    #[test]
    fn mesa_versions_parse() {
        assert_eq!(
            mesa_version("Mesa 25.0.7-2~bpo12+1 (LLVM 15.0.6)"),
            Some((25, 0))
        );
        assert_eq!(
            mesa_version("4.5 (Core Profile) Mesa 22.3.6"),
            Some((22, 3))
        );
        assert_eq!(mesa_version("570.86.15"), None);
    }
}
