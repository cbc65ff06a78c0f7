//! `strata bench`: paths/s, rays/s and ms per spp of the GPU renderer and the CPU reference,
//! scene by scene, at a fixed film size and depth.

mod choice;

use crate::device::{Device, DeviceChoice};
use crate::render::parse_size;
use choice::{BindingChoice, BvhChoice, KernelsChoice, Renderers, TraversalChoice};
use clap::Args;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::time::Instant;
use stratapt_film::Render;
use stratapt_gpu::adapter::Gpu;
use stratapt_gpu::{
    BvhLayout, Kernel, KernelChecks, Renderer, SampleSplit, SceneBinding, Traversal,
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
    /// How the GPU finds hits: the renderer's choice for the adapter, its own BVH traversal,
    /// the adapter's ray queries (scenes of static triangles on devices that have them), or
    /// both, rows each.
    #[arg(long, value_enum, default_value_t = TraversalChoice::Auto)]
    traversal: TraversalChoice,
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
    let scenes = scene_files(&args.scenes)?;
    // Load everything first: a bad scene fails before minutes of benchmarking.
    let mut loaded = load_scenes(&scenes, args.import, args.size)?;
    let mut gpu = open_gpu(&args)?;
    let renderer = gpu.as_ref().map(|(_, renderer)| renderer);
    let plan = Plan {
        spp: args.spp,
        max_depth: args.max_depth,
        kernel: args.kernel,
        layouts: args.bvh.layouts(renderer),
        bindings: args.binding.bindings(renderer),
        traversals: args.traversal.traversals(renderer),
        cpu: args.device != Renderers::Gpu,
        cpu8: args.device == Renderers::Cpu8,
    };
    print_setup(&args, &gpu, plan.cpu)?;
    print_columns()?;
    for (path, scene) in &mut loaded {
        let renderer = gpu.as_mut().map(|(_, renderer)| renderer);
        plan.scene_rows(renderer, path, scene)?;
    }
    Ok(())
}

/// The scene files named, else every .toml in ./scenes.
fn scene_files(named: &[PathBuf]) -> anyhow::Result<Vec<PathBuf>> {
    if !named.is_empty() {
        return Ok(named.to_vec());
    }
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
    Ok(files)
}

/// Load every scene at the benchmark's film size.
fn load_scenes(
    paths: &[PathBuf],
    import: crate::scene::ImportArgs,
    size: (u32, u32),
) -> anyhow::Result<Vec<(&PathBuf, FlatScene)>> {
    paths
        .iter()
        .map(|path| {
            let mut scene = crate::scene::load(path, import, true)?;
            (scene.camera.width, scene.camera.height) = size;
            Ok((path, scene))
        })
        .collect()
}

/// Open the GPU renderer with the kernel checks and sample split asked for, unless only the
/// CPU is timed.
fn open_gpu(args: &BenchArgs) -> anyhow::Result<Option<(Gpu, Renderer)>> {
    if matches!(args.device, Renderers::Cpu | Renderers::Cpu8) {
        return Ok(None);
    }
    match Device::choose(DeviceChoice::Gpu, args.adapter.as_deref(), None)?.0 {
        Device::Gpu { gpu, mut renderer } => {
            crate::render::set_kernel_checks(&mut renderer, args.kernel_checks)?;
            renderer.set_sample_split(args.sample_split);
            Ok(Some((gpu, renderer)))
        }
        Device::Cpu { .. } | Device::Cpu8 { .. } => {
            unreachable!("DeviceChoice::Gpu never falls back")
        }
    }
}

/// What every row shares, then the GPU and the CPU timed.
fn print_setup(args: &BenchArgs, gpu: &Option<(Gpu, Renderer)>, cpu: bool) -> anyhow::Result<()> {
    let (w, h) = args.size;
    out!(
        "strata bench: {w}×{h}, {} spp, max depth {}, each scene's sampler and strategy",
        args.spp,
        args.max_depth
    );
    if let Some((gpu, renderer)) = gpu {
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
    Ok(())
}

/// The table's column headings.
fn print_columns() -> anyhow::Result<()> {
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
    Ok(())
}

/// What each scene is timed with: the GPU's layouts × bindings × kernels, and the CPU.
struct Plan {
    spp: u32,
    max_depth: u32,
    kernel: KernelsChoice,
    layouts: Vec<BvhLayout>,
    /// Each binding with its label in the rows (none for the renderer's own choice).
    bindings: Vec<(SceneBinding, &'static str)>,
    traversals: Vec<Traversal>,
    cpu: bool,
    /// The eight-lane prototype after the reference.
    cpu8: bool,
}

/// One scene as it is timed: its name in the rows and the settings of every timed render.
struct Subject<'a> {
    name: &'a str,
    scene: &'a mut FlatScene,
    settings: RenderSettings,
}

impl Plan {
    /// Time one scene: its GPU rows, then the CPU's row with the GPU's speed against it.
    fn scene_rows(
        &self,
        renderer: Option<&mut Renderer>,
        path: &Path,
        scene: &mut FlatScene,
    ) -> anyhow::Result<()> {
        let name = path.file_stem().unwrap_or_default().to_string_lossy();
        let settings = RenderSettings {
            pattern_spp: self.spp,
            max_depth: self.max_depth,
            ..scene.settings
        };
        let mut subject = Subject {
            name: &name,
            scene,
            settings,
        };
        let gpu_rate = match renderer {
            Some(renderer) => self.gpu_rows(renderer, &mut subject)?,
            None => None,
        };
        if self.cpu {
            let timing = time_cpu(subject.scene, &settings);
            let note = gpu_rate
                .map(|g| format!("gpu/cpu {:.2}×", g / (timing.paths as f64 / timing.seconds)))
                .unwrap_or_default();
            out!("{}", timing.row(&name, "cpu", self.spp, &note));
            if self.cpu8 {
                let reference = timing.paths as f64 / timing.seconds;
                out!(
                    "{}",
                    cpu8_row(subject.scene, &settings, &name, self.spp, reference)
                );
            }
        }
        std::io::stdout().flush()?;
        Ok(())
    }

    /// Time the scene on the GPU in each BVH layout × binding, every kernel; returns the rate
    /// the CPU is compared with (the last specialized kernel's, else the first kernel's).
    fn gpu_rows(
        &self,
        renderer: &mut Renderer,
        subject: &mut Subject,
    ) -> anyhow::Result<Option<f64>> {
        let kernels = self
            .kernel
            .kernels(&Renderer::specialization(subject.scene, &subject.settings));
        let mut gpu_rate = None;
        for &traversal in &self.traversals {
            renderer.set_traversal(traversal);
            if traversal == Traversal::RayQuery {
                // ---- The adapter's ray queries: no BVH layout of ours --------------------------
                let why_not = if !renderer.has_ray_queries() {
                    Some("the device has no ray queries")
                } else if !Traversal::serves(subject.scene) {
                    Some("the ray-query kernel serves scenes of static triangles only")
                } else {
                    None
                };
                if let Some(why) = why_not {
                    out!("{:<22} {:<9} {why}", subject.name, "gpu/rq");
                    continue;
                }
                for &(binding, label) in &self.bindings {
                    renderer.set_scene_binding(binding);
                    let on = format!("gpu/rq{label}");
                    self.kernel_rows(renderer, subject, &kernels, &on, &mut gpu_rate)?;
                }
                continue;
            }
            for (&layout, &(binding, label)) in self
                .layouts
                .iter()
                .flat_map(|l| self.bindings.iter().map(move |b| (l, b)))
            {
                renderer.set_bvh_layout(layout);
                renderer.set_scene_binding(binding);
                let on = format!("gpu/{layout}{label}");
                self.kernel_rows(renderer, subject, &kernels, &on, &mut gpu_rate)?;
            }
        }
        Ok(gpu_rate)
    }

    /// Time each kernel in the renderer's layout and binding (`on`), a row each, the
    /// specialized kernel's speed noted against the others; `gpu_rate` takes the specialized
    /// kernel's rate, else the first one's.
    fn kernel_rows(
        &self,
        renderer: &mut Renderer,
        subject: &mut Subject,
        kernels: &[Kernel],
        on: &str,
        gpu_rate: &mut Option<f64>,
    ) -> anyhow::Result<()> {
        let mut specialized_rate = None;
        for &kernel in kernels {
            renderer.set_kernel(kernel);
            let (timing, mut note) = time_gpu(renderer, subject.scene, &subject.settings)?;
            let rate = timing.paths as f64 / timing.seconds;
            let on = match kernel {
                Kernel::Specialized => on.to_string(),
                Kernel::Generic => format!("{on}/generic"),
                Kernel::Carrying(_) => format!("{on}/+"),
            };
            match (kernel, specialized_rate) {
                (Kernel::Specialized, _) => specialized_rate = Some(rate),
                (_, Some(s)) => note = format!("specialized/this {:.3}×, {note}", s / rate),
                _ => {}
            }
            if let Kernel::Carrying(r) = kernel {
                note = format!("carries {}; {note}", r.describe());
            }
            out!("{}", timing.row(subject.name, &on, self.spp, &note));
            if kernel == Kernel::Specialized || gpu_rate.is_none() {
                *gpu_rate = Some(rate);
            }
        }
        Ok(())
    }
}

/// The kernel is compiled (the pipeline, then the driver's compile at its first dispatch, in a
/// tiny render) before the clock starts; the note says what each took.
fn time_gpu(
    renderer: &Renderer,
    scene: &mut FlatScene,
    settings: &RenderSettings,
) -> anyhow::Result<(Timing, String)> {
    let spec = renderer.specialize(scene, settings);
    let compile = renderer.prepare(&spec)?;
    let size = (scene.camera.width, scene.camera.height);
    (scene.camera.width, scene.camera.height) = (8, 8);
    let warm = RenderSettings {
        pattern_spp: 1,
        ..*settings
    };
    let warmed = renderer.render(scene, &warm, &|_| {}, None);
    (scene.camera.width, scene.camera.height) = size;
    let first_dispatch = warmed
        .map_err(|e| anyhow::anyhow!(e))?
        .1
        .first_dispatch_seconds;

    let start = Instant::now();
    let (film, stats) = renderer
        .render(scene, settings, &|_| {}, None)
        .map_err(|e| anyhow::anyhow!(e))?;
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
    debug_assert_eq!(film.held_spp(), settings.pattern_spp);
    Ok((
        Timing {
            seconds,
            paths: stats.samples,
            rays: stats.rays,
        },
        note,
    ))
}

/// Time the CPU reference on the scene.
/// The eight-lane prototype's row, its speed against the reference's `reference` paths/s; a
/// scene it does not cover gets a row that says why.
fn cpu8_row(
    scene: &FlatScene,
    settings: &RenderSettings,
    name: &str,
    spp: u32,
    reference: f64,
) -> String {
    use stratapt_film::Render;
    let start = Instant::now();
    match stratapt_cpu::Cpu8Renderer.render(scene, settings, &|_| {}, None) {
        Ok((_, stats)) => {
            let timing = Timing {
                seconds: start.elapsed().as_secs_f64(),
                paths: stats.samples,
                rays: stats.rays,
            };
            let note = format!(
                "cpu8/cpu {:.2}×",
                timing.paths as f64 / timing.seconds / reference
            );
            timing.row(name, "cpu8", spp, &note)
        }
        Err(e) => format!("{name:<22} {:<9} {e}", "cpu8"),
    }
}

fn time_cpu(scene: &FlatScene, settings: &RenderSettings) -> Timing {
    let start = Instant::now();
    let (_, stats) = stratapt_cpu::render(scene, settings, &|_| {}, None);
    Timing {
        seconds: start.elapsed().as_secs_f64(),
        paths: stats.samples,
        rays: stats.rays,
    }
}
