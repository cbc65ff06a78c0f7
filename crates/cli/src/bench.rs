//! `strata bench`: paths/s, rays/s and ms per spp of the GPU renderer and the CPU reference,
//! scene by scene, at a fixed film size and depth.

use crate::device::{Device, DeviceChoice};
use crate::render::parse_size;
use clap::{Args, ValueEnum};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::time::Instant;
use stratapt_gpu::{
    BvhLayout, Kernel, KernelChecks, Runtime, SampleSplit, SceneBinding, Specialization,
};
use stratapt_scene::{FlatScene, RenderSettings};

#[derive(Args)]
pub struct BenchArgs {
    /// Scene files: strata's TOML or pbrt-v4 (.pbrt, .pbrt.gz). Default: every .toml in
    /// ./scenes.
    scenes: Vec<PathBuf>,
    #[command(flatten)]
    import: crate::scene::ImportArgs,
    /// Samples per pixel of each timed render.
    #[arg(long, default_value_t = 4, value_parser = clap::value_parser!(u32).range(1..))]
    spp: u32,
    /// Film size, e.g. 512x512 (the vertical field of view is kept).
    #[arg(long, value_parser = parse_size, value_name = "WxH", default_value = "512x512")]
    size: (u32, u32),
    /// Maximum path vertices after the camera.
    #[arg(long, default_value_t = 8, value_parser = clap::value_parser!(u32).range(1..=1024))]
    max_depth: u32,
    /// Which renderers to time.
    #[arg(long, value_enum, default_value_t = Renderers::Both)]
    device: Renderers,
    /// GPU adapter, by (part of) its name (see `strata adapters`); default: the best one.
    #[arg(long, value_name = "NAME")]
    adapter: Option<String>,
    /// BVH layout(s) the GPU traverses: the renderer's choice for the adapter, one, or both.
    #[arg(long, value_enum, default_value_t = BvhChoice::Auto)]
    bvh: BvhChoice,
    /// Where the GPU reads the scene's arrays from: the renderer's choice for the adapter, their
    /// storage buffers, their uniform copy (scenes that fit it: 16–64 KiB, as the device binds),
    /// or both.
    #[arg(long, value_enum, default_value_t = BindingChoice::Auto)]
    binding: BindingChoice,
    /// GPU kernel(s) to time: specialized, generic, both side by side, or `effects`: the
    /// specialized kernel, then carrying each effect the scene does not use, one at a time,
    /// then the generic kernel (what each unused effect costs).
    #[arg(long, value_enum, default_value_t = KernelsChoice::Specialized)]
    kernel: KernelsChoice,
    /// wgpu's runtime checks the GPU kernel is compiled with, as `strata render
    /// --kernel-checks` takes them (`default`, `audited`, `all`, `none`, or a list of bounds,
    /// loops, int-division).
    #[arg(long, value_parser = KernelChecks::parse, value_name = "CHECKS", default_value = "default")]
    kernel_checks: KernelChecks,
    /// Slices each pixel's samples are split into on the GPU, as `strata render --sample-split`
    /// takes them (`auto` or 1 to 64).
    #[arg(long, value_parser = SampleSplit::parse, value_name = "auto|N", default_value = "auto")]
    sample_split: SampleSplit,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum KernelsChoice {
    /// The kernel compiled for each scene.
    Specialized,
    /// The one kernel with every effect, chosen at run time.
    Generic,
    /// Specialized, then generic, a row each.
    Both,
    /// Specialized, each unused effect carried alone, generic.
    Effects,
}

impl KernelsChoice {
    /// The kernels to time on a scene whose specialization is `spec`.
    fn kernels(self, spec: &Specialization) -> Vec<Kernel> {
        match self {
            KernelsChoice::Specialized => vec![Kernel::Specialized],
            KernelsChoice::Generic => vec![Kernel::Generic],
            KernelsChoice::Both => vec![Kernel::Specialized, Kernel::Generic],
            KernelsChoice::Effects => {
                // Each effect, light kind and material kind the scene does not use, alone.
                let unused = |all: u32, used: u32| {
                    (0..32)
                        .map(|k| 1u32 << k)
                        .filter(move |bit| all & bit != 0 && used & bit == 0)
                };
                let (all, none) = (Runtime::ALL, Runtime::NONE);
                let e = &spec.effects;
                let carried = unused(all.effects, spec.effect_bits())
                    .map(|effects| Runtime { effects, ..none })
                    .chain(
                        unused(all.light_kinds, e.light_kinds).map(|light_kinds| Runtime {
                            light_kinds,
                            ..none
                        }),
                    )
                    .chain(
                        unused(all.material_kinds, e.material_kinds).map(|material_kinds| {
                            Runtime {
                                material_kinds,
                                ..none
                            }
                        }),
                    )
                    .chain([Runtime { dims: true, ..none }]);
                std::iter::once(Kernel::Specialized)
                    .chain(carried.map(Kernel::Carrying))
                    .chain([Kernel::Generic])
                    .collect()
            }
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum BvhChoice {
    /// The layout the renderer picks for the adapter.
    Auto,
    /// The binary BVH (obvhs BVH2).
    Bvh2,
    /// The compressed 8-wide BVH.
    Cwbvh,
    /// Each layout in turn, a row each.
    Both,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum BindingChoice {
    /// The binding the renderer picks for the adapter.
    Auto,
    /// The storage buffers.
    Storage,
    /// The uniform copy, where the scene fits it.
    Uniform,
    /// Storage, then uniform, a row each.
    Both,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum Renderers {
    /// The GPU renderer and the CPU reference.
    Both,
    /// The GPU renderer only.
    Gpu,
    /// The CPU reference only.
    Cpu,
}

/// One timed render.
struct Timing {
    seconds: f64,
    paths: u64,
    rays: u64,
}

impl Timing {
    fn row(&self, scene: &str, renderer: &str, spp: u32, note: &str) -> String {
        format!(
            "{scene:<22} {renderer:<9} {spp:>4} {:>8.3} {:>9.1} {:>10.3} {:>9.3} {:>9.2}  {note}",
            self.seconds,
            self.seconds * 1e3 / spp as f64,
            self.paths as f64 / self.seconds / 1e6,
            self.rays as f64 / self.seconds / 1e6,
            self.rays as f64 / self.paths.max(1) as f64,
        )
    }
}

pub fn run(args: BenchArgs) -> anyhow::Result<()> {
    let scenes = if args.scenes.is_empty() {
        let dir = Path::new("scenes");
        let files = stratapt_import::load::scene_files(dir).map_err(|e| {
            anyhow::anyhow!(
                "{}: {e} (name scene files, or run from the strata folder)",
                dir.display()
            )
        })?;
        if files.is_empty() {
            anyhow::bail!("{}: no .toml scene files", dir.display());
        }
        files
    } else {
        args.scenes.clone()
    };
    // Load everything first: a bad scene fails before minutes of benchmarking.
    let mut loaded = scenes
        .iter()
        .map(|path| {
            let mut scene = crate::scene::load(path, args.import, true)?;
            (scene.camera.width, scene.camera.height) = args.size;
            Ok((path, scene))
        })
        .collect::<anyhow::Result<Vec<_>>>()?;

    let mut gpu = match args.device {
        Renderers::Cpu => None,
        _ => match Device::choose(DeviceChoice::Gpu, args.adapter.as_deref(), None)?.0 {
            Device::Gpu { gpu, mut renderer } => {
                crate::render::set_kernel_checks(&mut renderer, args.kernel_checks)?;
                renderer.set_sample_split(args.sample_split);
                Some((gpu, renderer))
            }
            Device::Cpu { .. } => unreachable!("DeviceChoice::Gpu never falls back"),
        },
    };
    let cpu = args.device != Renderers::Gpu;
    let (w, h) = args.size;
    out!(
        "strata bench: {w}×{h}, {} spp, max depth {}, each scene's sampler and strategy",
        args.spp,
        args.max_depth
    );
    let layouts = match (args.bvh, &gpu) {
        (_, None) => Vec::new(),
        (BvhChoice::Auto, Some((_, renderer))) => vec![renderer.bvh_layout()],
        (BvhChoice::Bvh2, _) => vec![BvhLayout::Bvh2],
        (BvhChoice::Cwbvh, _) => vec![BvhLayout::Cwbvh],
        (BvhChoice::Both, _) => BvhLayout::ALL.to_vec(),
    };
    let bindings = match (args.binding, &gpu) {
        (_, None) => Vec::new(),
        (BindingChoice::Auto, Some((_, renderer))) => vec![(renderer.scene_binding(), "")],
        (BindingChoice::Storage, _) => vec![(SceneBinding::Storage, "/storage")],
        (BindingChoice::Uniform, _) => vec![(SceneBinding::Uniform, "/uniform")],
        (BindingChoice::Both, _) => vec![
            (SceneBinding::Storage, "/storage"),
            (SceneBinding::Uniform, "/uniform"),
        ],
    };
    if let Some((gpu, renderer)) = &gpu {
        out!(
            "gpu: {} (its default BVH: {}; kernel checks: {}; sample split: {}; scene arrays \
             from {})",
            gpu.describe(),
            renderer.bvh_layout(),
            renderer.checks(),
            renderer.sample_split(),
            match renderer.scene_binding() {
                SceneBinding::Uniform => format!(
                    "a {} KiB uniform copy where they fit",
                    renderer.uniform_scene_words() / 64
                ),
                SceneBinding::Storage => "storage buffers".into(),
            }
        );
    }
    if cpu {
        let threads = rayon::current_num_threads();
        out!("cpu: {}", Device::Cpu { threads }.describe());
    }
    out!(
        "{:<22} {:<9} {:>4} {:>8} {:>9} {:>10} {:>9} {:>9}",
        "scene",
        "on",
        "spp",
        "seconds",
        "ms/spp",
        "M paths/s",
        "M rays/s",
        "rays/path"
    );
    for (path, scene) in &mut loaded {
        let name = path.file_stem().unwrap_or_default().to_string_lossy();
        let settings = RenderSettings {
            spp: args.spp,
            max_depth: args.max_depth,
            ..scene.settings
        };
        let mut gpu_rate = None;
        if let Some((_, renderer)) = &mut gpu {
            let kernels = args
                .kernel
                .kernels(&stratapt_gpu::Renderer::specialization(scene, &settings));
            for (&layout, &(binding, label)) in layouts
                .iter()
                .flat_map(|l| bindings.iter().map(move |b| (l, b)))
            {
                renderer.set_bvh_layout(layout);
                renderer.set_scene_binding(binding);
                let mut specialized_rate = None;
                for &kernel in &kernels {
                    renderer.set_kernel(kernel);
                    let (timing, mut note) = time_gpu(renderer, scene, &settings)?;
                    let rate = timing.paths as f64 / timing.seconds;
                    let on = match kernel {
                        Kernel::Specialized => format!("gpu/{layout}{label}"),
                        Kernel::Generic => format!("gpu/{layout}{label}/generic"),
                        Kernel::Carrying(_) => format!("gpu/{layout}{label}/+"),
                    };
                    match (kernel, specialized_rate) {
                        (Kernel::Specialized, _) => specialized_rate = Some(rate),
                        (_, Some(s)) => note = format!("specialized/this {:.3}×, {note}", s / rate),
                        _ => {}
                    }
                    if let Kernel::Carrying(r) = kernel {
                        note = format!("carries {}; {note}", r.describe());
                    }
                    out!("{}", timing.row(&name, &on, args.spp, &note));
                    if kernel == Kernel::Specialized || gpu_rate.is_none() {
                        gpu_rate = Some(rate);
                    }
                }
            }
        }
        if cpu {
            let timing = time_cpu(scene, &settings);
            let note = gpu_rate
                .map(|g| format!("gpu/cpu {:.2}×", g / (timing.paths as f64 / timing.seconds)))
                .unwrap_or_default();
            out!("{}", timing.row(&name, "cpu", args.spp, &note));
        }
        std::io::stdout().flush()?;
    }
    Ok(())
}

/// The kernel is compiled (the pipeline, then the driver's compile at its first dispatch, in a
/// tiny render) before the clock starts; the note says what each took.
fn time_gpu(
    renderer: &stratapt_gpu::Renderer,
    scene: &mut FlatScene,
    settings: &RenderSettings,
) -> anyhow::Result<(Timing, String)> {
    let spec = renderer.specialize(scene, settings);
    let compile = renderer.prepare(&spec)?;
    let size = (scene.camera.width, scene.camera.height);
    (scene.camera.width, scene.camera.height) = (8, 8);
    let warm = RenderSettings {
        spp: 1,
        ..*settings
    };
    let warmed = renderer.render_with_stats(scene, &warm, &|_| {}, None);
    (scene.camera.width, scene.camera.height) = size;
    let first_dispatch = warmed?.1.first_dispatch_seconds;

    let start = Instant::now();
    let (film, stats) = renderer.render_with_stats(scene, settings, &|_| {}, None)?;
    let seconds = start.elapsed().as_secs_f64();
    let mut note = format!(
        "compile {compile:.2} + {first_dispatch:.2} s at first dispatch, {} dispatches",
        stats.dispatches
    );
    if stats.uniform_scene {
        note.push_str(", scene from its uniform copy");
    }
    if let Some(t) = stats.gpu_seconds {
        note.push_str(&format!(", {:.0}% GPU busy", 100.0 * t / seconds));
    }
    if stats.non_finite > 0 {
        note.push_str(&format!(", {} non-finite samples", stats.non_finite));
    }
    debug_assert_eq!(film.spp(), settings.spp);
    Ok((
        Timing {
            seconds,
            paths: stats.samples,
            rays: stats.rays,
        },
        note,
    ))
}

fn time_cpu(scene: &FlatScene, settings: &RenderSettings) -> Timing {
    let start = Instant::now();
    let (_, stats) = stratapt_cpu::render_with_stats(scene, settings, &|_| {}, None);
    Timing {
        seconds: start.elapsed().as_secs_f64(),
        paths: stats.samples,
        rays: stats.rays,
    }
}
