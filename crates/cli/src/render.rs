//! `strata render`.

// The options' doc comments are clap's help text, plain text: `[render]` and `[film]` there name
// the scene's TOML tables, not items to link.
#![allow(rustdoc::broken_intra_doc_links)]

use crate::device::{Device, DeviceChoice};
use crate::part::{Part, PartArgs};
use crate::progress::Meter;
use anyhow::Context;
use clap::Args;
use indicatif::{ProgressBar, ProgressStyle};
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};
use stratapt_cpu::CpuRenderer;
use stratapt_film::part::PartInfo;
use stratapt_film::render::progressive::{
    render_progressive, ErrorMetric, Progressive, StopRule, Stopped,
};
use stratapt_film::render::{Progress, RenderError};
use stratapt_film::RelativeError;
use stratapt_film::{Film, Render, RenderStats};
use stratapt_gpu::{Kernel, KernelChecks, SampleSplit};
use stratapt_import::load::MAX_RESOLUTION;
use stratapt_scene::{Effects, FlatScene, RenderSettings, SamplerKind, Strategy};

#[derive(Args)]
pub struct RenderArgs {
    /// Scene file: strata's TOML, or pbrt-v4 (.pbrt, .pbrt.gz).
    scene: PathBuf,
    #[command(flatten)]
    import: crate::scene::ImportArgs,
    /// Output image(s): .exr (linear RGB + variance) or .png (sRGB); repeatable.
    /// Default: SCENE-NAME.exr and SCENE-NAME.png in the current folder.
    #[arg(short, long = "output")]
    output: Vec<PathBuf>,
    /// Samples per pixel (overrides the scene's [render] spp).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..))]
    spp: Option<u32>,
    /// Sample sequence (overrides the scene).
    #[arg(long, value_parser = parse_sampler)]
    sampler: Option<SamplerKind>,
    /// Importance-sampling strategy (overrides the scene).
    #[arg(long, value_parser = parse_strategy)]
    strategy: Option<Strategy>,
    /// Maximum path vertices after the camera (overrides the scene).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=1024))]
    max_depth: Option<u32>,
    /// Film size in pixels, e.g. 512x512 (overrides the scene's [film] width and height; the
    /// vertical field of view is kept).
    #[arg(long, value_parser = parse_size, value_name = "WxH")]
    size: Option<(u32, u32)>,
    /// Seed of the sample sequences (overrides the scene).
    #[arg(long)]
    seed: Option<u32>,
    /// Skip the twin pixels that calibrate the error estimate of the stratified and Sobol
    /// samplers (6 % of the samples): the reported error is then the per-sample variance,
    /// which overstates theirs.
    #[arg(long)]
    no_calibration: bool,
    /// Render until the estimated relative standard error reaches this (e.g. 0.01 for 1 %), and
    /// at least 64 spp; `--spp` then caps the samples (default 65536).
    #[arg(long, value_parser = parse_target_error, value_name = "E")]
    target_error: Option<f64>,
    /// What `--target-error` applies to: the image mean, or the 95th-percentile pixel.
    #[arg(long, value_parser = parse_metric, default_value = "image-mean")]
    target_error_metric: ErrorMetric,
    /// Stop before a batch would end past this wall time, e.g. 30s, 2m, 1h30m.
    #[arg(long, value_parser = parse_duration, value_name = "DURATION")]
    time_limit: Option<Duration>,
    /// Where to render.
    #[arg(long, value_enum, default_value_t = DeviceChoice::Auto)]
    device: DeviceChoice,
    /// GPU adapter to use, by (part of) its name, e.g. llvmpipe or "RTX 4090" (see
    /// `strata adapters`).
    #[arg(long, value_name = "NAME")]
    adapter: Option<String>,
    /// The GPU kernel: compiled for the scene's effects, or the generic one with every effect
    /// compiled in and chosen at run time (the same image; to compare).
    #[arg(long, value_enum, default_value_t = KernelChoice::Specialized)]
    kernel: KernelChoice,
    /// wgpu's runtime checks the GPU kernel is compiled with: `default` (bounds and loops),
    /// `audited` (the bounds checks alone: the kernel provably needs no other), `all` (wgpu's
    /// fully checked kernel), `none`, or a list of bounds, loops, int-division. Leaving out
    /// the bounds checks is for measuring what they cost.
    #[arg(long, value_parser = KernelChecks::parse, value_name = "CHECKS", default_value = "default")]
    kernel_checks: KernelChecks,
    /// Split each pixel's samples over this many GPU invocations per batch (1 to 64), or `auto`:
    /// as many as bring a dispatch to about 2^18 invocations on a discrete GPU (2^16 on an
    /// integrated one), none on a CPU adapter such as lavapipe. The same image either way.
    #[arg(long, value_parser = SampleSplit::parse, value_name = "auto|N", default_value = "auto")]
    sample_split: SampleSplit,
    /// How the GPU finds hits: `auto` (the renderer's choice for the adapter: its own BVH
    /// traversal), `bvh`, or `ray-query`: the adapter's ray queries (scenes of static triangles
    /// without alpha, on devices that have them; an image of the same estimate whose hit
    /// distances differ in their last bits).
    #[arg(long, value_enum, default_value_t = TraversalArg::Auto)]
    traversal: TraversalArg,
    #[command(flatten)]
    part: PartArgs,
}

/// `--traversal` of render.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub(crate) enum TraversalArg {
    /// The renderer's choice for the adapter.
    Auto,
    /// The kernel's own BVH traversal.
    Bvh,
    /// The adapter's ray queries.
    RayQuery,
}

/// Set `renderer`'s traversal to `--traversal`; ray queries the device lacks or the scene
/// cannot use are an error that says which.
pub(crate) fn set_traversal(
    renderer: &mut stratapt_gpu::Renderer,
    traversal: TraversalArg,
    scene: &FlatScene,
) -> anyhow::Result<()> {
    use stratapt_gpu::Traversal;
    match traversal {
        TraversalArg::Auto => {}
        TraversalArg::Bvh => renderer.set_traversal(Traversal::Bvh),
        TraversalArg::RayQuery => {
            if !renderer.has_ray_queries() {
                anyhow::bail!("--traversal ray-query: this device has no ray queries");
            }
            if !Traversal::serves(scene) {
                anyhow::bail!(
                    "--traversal ray-query serves scenes of static triangles without alpha; \
                     this one has spheres, disks, moving primitives or cut-outs"
                );
            }
            renderer.set_traversal(Traversal::RayQuery);
        }
    }
    Ok(())
}

/// `--kernel` of render and bench.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub(crate) enum KernelChoice {
    /// Compiled for the scene: only the effects it calls for.
    Specialized,
    /// Every effect compiled in, each chosen at run time from the scene.
    Generic,
}

impl KernelChoice {
    pub(crate) fn kernel(self) -> Kernel {
        match self {
            KernelChoice::Specialized => Kernel::Specialized,
            KernelChoice::Generic => Kernel::Generic,
        }
    }
}

/// Compile `renderer`'s kernel with `checks` (`--kernel-checks` of render and bench), saying so
/// when they leave out a check the kernel is not proven to do without.
pub(crate) fn set_kernel_checks(
    renderer: &mut stratapt_gpu::Renderer,
    checks: KernelChecks,
) -> anyhow::Result<()> {
    if checks.covers(KernelChecks::AUDITED) {
        renderer.set_checks(checks)?;
    } else {
        eprintln!(
            "warning: --kernel-checks {checks} leaves out checks the kernel is not proven to do \
             without (audited: {}); for measuring what they cost",
            KernelChecks::AUDITED
        );
        // SAFETY: none proven: the user asked for these checks on the command line, to measure
        // what they cost, and was warned above.
        unsafe { renderer.set_checks_unaudited(checks)? };
    }
    Ok(())
}

/// Samples per pixel a render to an error or a time may take without `--spp`.
const OPEN_ENDED_MAX_SPP: u32 = 1 << 16;

pub fn parse_target_error(s: &str) -> Result<f64, String> {
    match s.trim().parse::<f64>() {
        Ok(e) if e > 0.0 && e < 1.0 => Ok(e),
        _ => Err("expected a relative error between 0 and 1, e.g. 0.01 for 1 %".into()),
    }
}

pub fn parse_metric(s: &str) -> Result<ErrorMetric, String> {
    ErrorMetric::from_name(s).ok_or_else(|| format!("expected one of {}", names(ErrorMetric::ALL)))
}

pub fn parse_duration(s: &str) -> Result<Duration, String> {
    match humantime::parse_duration(s.trim()) {
        Ok(d) if !d.is_zero() => Ok(d),
        Ok(_) => Err("the time limit must be positive".into()),
        Err(e) => Err(format!("{e} (expected e.g. 30s, 2m, 1h30m)")),
    }
}

/// Ctrl-C sets the returned flag (the work in flight finishes and what was done is written,
/// saying `doing`); a second Ctrl-C exits at once with 130.
pub fn cancel_on_ctrl_c(doing: &'static str) -> anyhow::Result<Arc<AtomicBool>> {
    let cancel = Arc::new(AtomicBool::new(false));
    let flag = cancel.clone();
    ctrlc::set_handler(move || {
        if flag.swap(true, Ordering::SeqCst) {
            std::process::exit(130);
        }
        eprintln!("\ninterrupted: {doing} (Ctrl-C again to quit)");
    })
    .context("cannot install the Ctrl-C handler")?;
    Ok(cancel)
}

pub fn parse_sampler(s: &str) -> Result<SamplerKind, String> {
    SamplerKind::from_name(s).ok_or_else(|| format!("expected one of {}", names(SamplerKind::ALL)))
}

pub fn parse_strategy(s: &str) -> Result<Strategy, String> {
    Strategy::from_name(s).ok_or_else(|| format!("expected one of {}", names(Strategy::ALL)))
}

pub fn parse_size(s: &str) -> Result<(u32, u32), String> {
    let bad = || format!("expected WIDTHxHEIGHT, each 1 to {MAX_RESOLUTION}, e.g. 512x512");
    let (w, h) = s.split_once(['x', 'X', '×']).ok_or_else(bad)?;
    let side = |t: &str| {
        t.trim()
            .parse::<u32>()
            .ok()
            .filter(|v| (1..=MAX_RESOLUTION).contains(v))
            .ok_or_else(bad)
    };
    Ok((side(w)?, side(h)?))
}

fn names<T: std::fmt::Display>(all: impl IntoIterator<Item = T>) -> String {
    all.into_iter()
        .map(|t| t.to_string())
        .collect::<Vec<_>>()
        .join(", ")
}

pub fn run(args: RenderArgs) -> anyhow::Result<ExitCode> {
    let started = std::time::Instant::now();
    let mut scene = crate::scene::load(&args.scene, args.import, true)?;
    let loaded = started.elapsed();
    if let Some((w, h)) = args.size {
        (scene.camera.width, scene.camera.height) = (w, h);
    }
    let settings = settings(&scene.settings, &args);
    let stop = stop_rule(&settings, &args);
    let part = args
        .part
        .resolve(settings.pattern_spp, |k| std::env::var(k).ok())?;
    if part.is_some() && stop.open_ended() {
        anyhow::bail!(
            "a part renders a fixed range of samples: --part, --samples and --part-from-env \
             do not combine with --target-error or --time-limit"
        );
    }
    let outputs = match &part {
        Some(part) => crate::part::outputs(&args.output, &args.scene, part)?,
        None => default_outputs(&args),
    };
    check_outputs(&outputs)?;
    let (mut device, why) = Device::choose(
        args.device,
        args.adapter.as_deref(),
        Some((&mut scene, &settings)),
    )?;
    if args.traversal == TraversalArg::RayQuery && !matches!(device, Device::Gpu { .. }) {
        anyhow::bail!("--traversal ray-query needs a GPU (--device gpu)");
    }
    if let Device::Gpu { renderer, .. } = &mut device {
        renderer.set_kernel(args.kernel.kernel());
        set_kernel_checks(renderer, args.kernel_checks)?;
        renderer.set_sample_split(args.sample_split);
        set_traversal(renderer, args.traversal, &scene)?;
    }
    eprintln!("{}", device.line(why.as_deref()));
    eprintln!(
        "scene: {} primitives, {} points, loaded with its BVH in {:.2} s",
        scene.geometry.len(),
        scene.geometry.points.len(),
        loaded.as_secs_f64()
    );
    eprintln!("effects: {}", Effects::of(&scene, &settings).summary());

    let cancel = cancel_on_ctrl_c("writing the samples taken so far")?;

    let (w, h) = (scene.camera.width, scene.camera.height);
    // The samples this process takes: all of them, or its part's.
    let spp = part
        .as_ref()
        .map_or(stop.max_spp, |p| p.samples.end - p.samples.start);
    let total = (!stop.open_ended()).then(|| w as u64 * h as u64 * spp as u64);
    let bar = Meter::new(progress_bar(total));
    let start = Instant::now();
    let progress = |n| bar.inc(n);
    let render = |renderer: &dyn Render| match &part {
        Some(part) => render_part(renderer, &scene, &settings, part, &progress, &cancel),
        None => render_progressive(renderer, &scene, &settings, &stop, &progress, Some(&cancel)),
    };
    let mut on_gpu = matches!(device, Device::Gpu { .. });
    let done = match render(device.renderer()) {
        Ok(done) => done,
        // A scene the GPU cannot hold renders on the CPU reference under `auto`.
        Err(e) if Device::falls_back(args.device, args.adapter.as_deref(), &e) => {
            bar.reset();
            on_gpu = false;
            eprintln!("device: CPU reference instead ({}: {e})", device.describe());
            render(&CpuRenderer).map_err(|e| anyhow::anyhow!("CPU reference: {e}"))?
        }
        Err(e) => return Err(anyhow::anyhow!("{}: {e}", device.describe())),
    };
    let seconds = start.elapsed().as_secs_f64();
    bar.bar().finish_and_clear();
    let film = &done.film;

    // A part's header (the scene's content hash walks every primitive: once).
    let info = part.as_ref().map(|_| part_info(&scene, &settings, film));
    for path in &outputs {
        match &info {
            Some(info) => stratapt_film::part::write(film, info, path)?,
            None => film.write(path)?,
        }
    }
    let samples = w as f64 * h as f64 * film.held_spp() as f64;
    let partial = if done.stopped == Stopped::Cancelled {
        " (interrupted)"
    } else {
        ""
    };
    let error = film.relative_error();
    let non_finite = match done.stats.non_finite {
        0 => "no non-finite samples".to_string(),
        n => format!("warning: {n} non-finite samples replaced by zero"),
    };
    let held = match &part {
        Some(_) => format!(
            " (samples {}..{} of {})",
            film.first_sample,
            film.first_sample + film.held_spp(),
            settings.pattern_spp
        ),
        None => String::new(),
    };
    eprintln!(
        "rendered {} at {w}×{h}, {} spp{held}{partial}, {} / {}, depth {} in {} s: \
         {:.3} M samples/s, {non_finite}; wrote {}",
        args.scene.display(),
        film.held_spp(),
        settings.sampler,
        settings.strategy,
        settings.max_depth,
        significant(seconds),
        samples / seconds.max(1e-9) / 1e6,
        joined(&outputs)
    );
    eprintln!(
        "{}{}{}",
        error_line(film, &error),
        calibration_note(film, &settings),
        stop_note(&done, &stop)
    );
    eprintln!("{}", mean_line(film));
    if let (Device::Gpu { renderer, .. }, true) = (&device, on_gpu) {
        eprintln!("{}", gpu_summary(&done.stats, renderer, &scene));
    }
    // A render cut short by Ctrl-C says so to scripts: 130, the shell's code for SIGINT.
    Ok(if done.stopped == Stopped::Cancelled {
        ExitCode::from(130)
    } else {
        ExitCode::SUCCESS
    })
}

/// When the render stops: the `--spp` cap (default: the scene's, or [`OPEN_ENDED_MAX_SPP`] for a
/// render to an error or a time), the target error, the time limit.
fn stop_rule(settings: &RenderSettings, args: &RenderArgs) -> StopRule {
    let target = args.target_error.map(|e| (e, args.target_error_metric));
    stop_rule_for(settings, args.spp, target, args.time_limit)
}

/// [`StopRule`] of a render with `settings` and these options (`spp`: the cap asked for).
pub fn stop_rule_for(
    settings: &RenderSettings,
    spp: Option<u32>,
    target_error: Option<(f64, ErrorMetric)>,
    time_limit: Option<Duration>,
) -> StopRule {
    let mut stop = StopRule {
        max_spp: settings.pattern_spp,
        target_error,
        time_limit,
    };
    stop.max_spp = match spp {
        Some(spp) => spp,
        None if stop.open_ended() => OPEN_ENDED_MAX_SPP,
        None => settings.pattern_spp,
    };
    stop
}

/// `a.exr, a.png`: the files written, for closing lines.
pub fn joined(paths: &[PathBuf]) -> String {
    let names: Vec<String> = paths.iter().map(|p| p.display().to_string()).collect();
    names.join(", ")
}

/// `error: 0.075 % relative standard error of the image mean, 6.35 % at the 95th-percentile
/// pixel`: the film's calibrated error, for closing lines. A film with a pixel of fewer than two
/// samples has no variance estimate there (its EXR `var.*` is 0): the line says so instead of
/// printing a zero error.
pub fn error_line(film: &Film, error: &RelativeError) -> String {
    if film.held_spp() < 2 {
        return format!(
            "error: not estimated: a pixel's variance needs at least 2 samples, this film has {} \
             spp (its EXR's var.* channels are 0 there)",
            film.held_spp()
        );
    }
    format!(
        "error: {:.3} % relative standard error of the image mean, {:.2} % at the \
         95th-percentile pixel",
        100.0 * error.image_mean,
        100.0 * error.pixel_p95
    )
}

/// `mean: 0.18731 0.17102 0.12233 (± 0.00004 0.00004 0.00003)`: the image mean per channel and
/// its calibrated standard error, for closing lines: what an analytic scene's closed form is
/// checked against.
pub fn mean_line(film: &Film) -> String {
    let (m, se) = film.image_mean();
    format!(
        "mean: {:.5} {:.5} {:.5} (± {:.5} {:.5} {:.5})",
        m[0], m[1], m[2], se[0], se[1], se[2]
    )
}

/// " (calibrated on 4096 twin pixels: …)": how the error estimate was calibrated, in a few
/// words, for closing lines (nothing without an estimate).
fn calibration_note(film: &Film, settings: &RenderSettings) -> String {
    if film.held_spp() < 2 {
        return String::new();
    }
    let note = if film.has_twins() {
        // How far the per-sample variance overstates the calibrated one, over the whole film.
        let calibrated: f64 = film.variances().iter().flatten().sum();
        let per_sample: f64 = (0..film.sum.len())
            .map(|i| film.sample_variance_of_mean(i).iter().sum::<f64>())
            .sum();
        let peak_pixels = film.peaks.chunk_by(|a, b| a.pixel == b.pixel).count();
        let peaks = match peak_pixels {
            0 => String::new(),
            n => format!(
                " and {} twins at each of {n} peak pixels",
                film.peaks.len() / n
            ),
        };
        format!(
            "calibrated on {} twin pixels{peaks}: the per-sample variance overstates it {:.1}×",
            film.twin_layout().count,
            per_sample / calibrated.max(1e-300)
        )
    } else if settings.sampler == SamplerKind::Independent {
        "independent samples: their per-sample variance".to_string()
    } else {
        "uncalibrated per-sample variance: overstates the error".to_string()
    };
    format!(" ({note})")
}

/// "; stopped at the target error (batches of 8 spp)" and the like, for open-ended renders.
fn stop_note(done: &Progressive, stop: &StopRule) -> String {
    if stop.target_error.is_none() && stop.time_limit.is_none() {
        return String::new();
    }
    let why = match done.stopped {
        Stopped::MaxSpp => "at the spp cap".to_string(),
        Stopped::TargetError => {
            let (target, metric) = stop.target_error.unwrap_or_default();
            format!("at the target ({metric} ≤ {:.3} %)", 100.0 * target)
        }
        Stopped::TimeLimit => "before the time limit".to_string(),
        Stopped::Cancelled => "by Ctrl-C".to_string(),
    };
    format!("; stopped {why}, last batch {} spp", done.last_batch)
}

/// One line on the GPU render: kernel, BVH layout, where the scene's arrays were read from
/// (their uniform copy or storage buffers), compile time (pipeline and the driver's compile at
/// first dispatch), batches, GPU time.
fn gpu_summary(
    stats: &RenderStats,
    renderer: &stratapt_gpu::Renderer,
    scene: &FlatScene,
) -> String {
    let compile = stats.compile_seconds + stats.first_dispatch_seconds;
    let compiled = if compile > 0.0 {
        format!(
            "compiled in {compile:.2} s (pipeline {:.2} s + first dispatch {:.2} s)",
            stats.compile_seconds, stats.first_dispatch_seconds
        )
    } else {
        "already compiled".to_string()
    };
    let slices = match stats.slices {
        0 | 1 => String::new(),
        k => format!(", each pixel's samples in up to {k} slices"),
    };
    let traversal = match renderer.uses_ray_queries(scene) {
        true => "the adapter's ray queries".to_string(),
        false => format!("{} BVH", renderer.bvh_layout()),
    };
    let mut line = format!(
        "gpu: {} kernel (checks: {}), {traversal}, scene from {}, {compiled}, {} dispatches{slices}",
        renderer.kernel().name(),
        renderer.checks(),
        if stats.uniform_scene {
            "its uniform copy"
        } else {
            "storage buffers"
        },
        stats.dispatches
    );
    if let Some(t) = stats.gpu_seconds {
        line.push_str(&format!(", {} s of GPU time", significant(t)));
    }
    // The host's own part of the wall time, where it could be large next to a fast GPU's.
    line.push_str(&format!(
        "; host: setup {} s, peak twins {} s",
        significant(stats.setup_seconds.max(0.0)),
        significant(stats.peak_twin_seconds)
    ));
    line
}

/// Seconds to at least three significant digits and at least two decimals: "3.87", "0.0412"
/// (a render on a large GPU can take hundredths of a second, which "0.04" would blur).
fn significant(t: f64) -> String {
    let decimals = if t > 0.0 && t < 1.0 {
        (2.0 - t.log10().floor()).clamp(2.0, 9.0) as usize
    } else {
        2
    };
    format!("{t:.decimals$}")
}

/// The scene's `[render]` defaults with the command line's overrides.
fn settings(defaults: &RenderSettings, args: &RenderArgs) -> RenderSettings {
    RenderSettings {
        pattern_spp: args.spp.unwrap_or(defaults.pattern_spp),
        max_depth: args.max_depth.unwrap_or(defaults.max_depth),
        sampler: args.sampler.unwrap_or(defaults.sampler),
        strategy: args.strategy.unwrap_or(defaults.strategy),
        seed: args.seed.unwrap_or(defaults.seed),
        calibrate: defaults.calibrate && !args.no_calibration,
    }
}

/// Samples `part.samples` of every pixel into a film that starts there
/// (`settings.pattern_spp`, the whole render's, sizes the stratified sampler's strata).
fn render_part(
    renderer: &dyn Render,
    scene: &FlatScene,
    settings: &RenderSettings,
    part: &Part,
    progress: Progress,
    cancel: &AtomicBool,
) -> Result<Progressive, RenderError> {
    let start = Instant::now();
    let mut film = Film::for_render(scene, settings);
    film.first_sample = part.samples.start;
    let n = part.samples.end - part.samples.start;
    let stats = renderer.render_into(scene, settings, &mut film, n, progress, Some(cancel))?;
    let seconds = start.elapsed().as_secs_f64();
    Ok(Progressive {
        stopped: if stats.cancelled {
            Stopped::Cancelled
        } else {
            Stopped::MaxSpp
        },
        last_batch: film.held_spp(),
        film,
        stats,
        seconds,
        last_batch_seconds: seconds,
    })
}

/// What a part's file says it holds: the samples its film took (fewer than asked after a
/// Ctrl-C), the whole render's settings, the scene.
fn part_info(scene: &FlatScene, settings: &RenderSettings, film: &Film) -> PartInfo {
    let held = film.first_sample..film.first_sample + film.held_spp();
    PartInfo {
        samples: if held.is_empty() {
            Vec::new()
        } else {
            vec![held]
        },
        settings: *settings,
        scene_hash: scene.content_hash(),
        scene: scene.path.display().to_string(),
    }
}

/// The default outputs of a whole render: SCENE-NAME.exr and SCENE-NAME.png, or those given.
fn default_outputs(args: &RenderArgs) -> Vec<PathBuf> {
    if args.output.is_empty() {
        let stem = args.scene.file_stem().unwrap_or(args.scene.as_os_str());
        vec![
            Path::new(stem).with_extension("exr"),
            Path::new(stem).with_extension("png"),
        ]
    } else {
        args.output.clone()
    }
}

/// The output paths, checked before rendering so a typo doesn't cost a render.
pub fn check_outputs(outputs: &[PathBuf]) -> anyhow::Result<()> {
    for path in outputs {
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase);
        if !matches!(ext.as_deref(), Some("exr" | "png")) {
            anyhow::bail!("{}: output must end in .exr or .png", path.display());
        }
        let dir = path
            .parent()
            .filter(|d| !d.as_os_str().is_empty())
            .unwrap_or(Path::new("."));
        if !dir.is_dir() {
            anyhow::bail!(
                "{}: folder {} does not exist",
                path.display(),
                dir.display()
            );
        }
        if path.is_dir() {
            anyhow::bail!("{}: is a folder, not an image file", path.display());
        }
        // Whether the folder takes new files (the image is written next to it and renamed into
        // place), found out before rendering rather than after.
        let probe = dir.join(format!(".strata-probe-{}", std::process::id()));
        match std::fs::OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(&probe)
        {
            Ok(_) => {
                let _ = std::fs::remove_file(&probe);
            }
            Err(e) => anyhow::bail!(
                "{}: cannot write to folder {}: {e}",
                path.display(),
                dir.display()
            ),
        }
    }
    Ok(())
}

/// A bar over `total` samples, or a counter when the total is not known in advance.
fn progress_bar(total: Option<u64>) -> ProgressBar {
    let (bar, template) = match total {
        Some(total) => (
            ProgressBar::new(total),
            "{bar:40.cyan/blue} {percent:>3}% {human_pos}/{human_len} samples, {per_sec}, eta {eta}",
        ),
        None => (
            ProgressBar::no_length(),
            "{spinner} {human_pos} samples, {per_sec}, {elapsed}",
        ),
    };
    bar.set_style(ProgressStyle::with_template(template).expect("valid progress template"));
    bar
}

#[cfg(test)]
mod tests {
    use super::significant;

    #[test]
    fn seconds_keep_three_significant_digits() {
        assert_eq!(significant(3.874), "3.87");
        assert_eq!(significant(123.4), "123.40");
        assert_eq!(significant(0.5), "0.500");
        assert_eq!(significant(0.04123), "0.0412");
        assert_eq!(significant(0.000_812_3), "0.000812");
        assert_eq!(significant(0.0), "0.00");
    }
}
