//! `strata study`: what accuracy costs in time. Renders the scene with every chosen sampler ×
//! strategy at 1, 2, 4, … spp and several seeds, times each render, measures its error against a
//! reference, and writes `study.csv`, error-vs-time and error-vs-spp plots and a ranked
//! `report.md`.

mod measure;
mod plot;
mod reference;
mod report;

use crate::device::{Device, DeviceChoice};
use crate::render::{cancel_on_ctrl_c, parse_sampler, parse_size, parse_strategy};
use anyhow::Context;
use clap::Args;
use measure::{Measured, Plan, Timed};
use reference::Reference;
use report::Summary;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;
use stratapt_film::Render;
use stratapt_scene::{FlatScene, SamplerKind, Strategy};

#[derive(Args)]
pub struct StudyArgs {
    /// Scene file: strata's TOML, or pbrt-v4 (.pbrt, .pbrt.gz).
    scene: PathBuf,
    #[command(flatten)]
    import: crate::scene::ImportArgs,
    /// Output folder (created if missing). Default: study-SCENE-NAME.
    #[arg(long)]
    out: Option<PathBuf>,
    /// Samplers to compare, comma-separated (default: all).
    #[arg(long, value_delimiter = ',', value_parser = parse_sampler)]
    samplers: Vec<SamplerKind>,
    /// Strategies to compare, comma-separated (default: all).
    #[arg(long, value_delimiter = ',', value_parser = parse_strategy)]
    strategies: Vec<Strategy>,
    /// Largest spp: renders at 1, 2, 4, … up to it.
    #[arg(long, default_value_t = 64, value_parser = clap::value_parser!(u32).range(1..=1 << 20))]
    max_spp: u32,
    /// Stop adding spp levels when the next one would end past this time (e.g. 60s, 5m).
    #[arg(long, value_parser = parse_duration)]
    budget: Option<Duration>,
    /// Seeds per point (for the bands and the confidence of the fits).
    #[arg(long, default_value_t = 4, value_parser = clap::value_parser!(u32).range(1..=1024))]
    seeds: u32,
    /// Reference image (an RGB EXR of the film's size, e.g. from another renderer). Default: the
    /// scene's `[render] exact` value, else a high-spp render cached in the output folder.
    #[arg(long)]
    reference: Option<PathBuf>,
    /// Samples per pixel of a rendered reference (default: 16 × --max-spp, at least 1024).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..))]
    reference_spp: Option<u32>,
    /// relMSE threshold for the report's "time to reach it".
    #[arg(long, default_value_t = 1e-3)]
    threshold: f64,
    /// Film size, e.g. 256x256 (overrides the scene; the vertical field of view is kept).
    #[arg(long, value_parser = parse_size, value_name = "WxH")]
    size: Option<(u32, u32)>,
    /// Maximum path vertices after the camera (overrides the scene).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=1024))]
    max_depth: Option<u32>,
    /// Where to render.
    #[arg(long, value_enum, default_value_t = DeviceChoice::Auto)]
    device: DeviceChoice,
    /// GPU adapter, by (part of) its name.
    #[arg(long, value_name = "NAME")]
    adapter: Option<String>,
    /// How the report names the command that made it (the bindings' call); the process's
    /// command line when unset.
    #[arg(skip)]
    pub command: Option<String>,
}

fn parse_duration(s: &str) -> Result<Duration, String> {
    humantime::parse_duration(s.trim()).map_err(|e| format!("{e} (expected e.g. 60s, 5m)"))
}

pub fn run(args: StudyArgs) -> anyhow::Result<ExitCode> {
    let cancel = cancel_on_ctrl_c("writing what was measured")?;
    Ok(match study(&args, &cancel)? {
        Studied::Measured {
            cancelled: false, ..
        } => ExitCode::SUCCESS,
        Studied::Measured {
            cancelled: true, ..
        }
        | Studied::NothingMeasured => ExitCode::from(130),
    })
}

/// How a study ended.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Studied {
    /// Its files were written in `out`; `cancelled` when `cancel` cut the measurements short
    /// (the files then hold what was measured).
    Measured { out: PathBuf, cancelled: bool },
    /// `cancel` was set while the reference was being rendered: nothing was measured.
    NothingMeasured,
}

/// The study `args` asks for, stopping early once `cancel` is set (Ctrl-C).
pub fn study(args: &StudyArgs, cancel: &AtomicBool) -> anyhow::Result<Studied> {
    study_with(args, cancel, &mut |a| Device::open(a).map(Box::new))
}

/// [`study`] on a device opened by `open` (see [`Device::choose_with`]: the Python bindings
/// pass their process's devices, whose compiled kernels then serve the study too).
pub fn study_with<D: std::ops::Deref<Target = Device> + From<Device>>(
    args: &StudyArgs,
    cancel: &AtomicBool,
    open: &mut dyn FnMut(wgpu::Adapter) -> anyhow::Result<D>,
) -> anyhow::Result<Studied> {
    let mut scene = load_scene(args)?;
    let pixels = (scene.camera.width * scene.camera.height) as usize;
    // Check the reference before rendering anything.
    let supplied = supplied_reference(args, &scene, pixels)?;
    let out = create_out_folder(args)?;
    let plan = Plan::new(
        &args.samplers,
        &args.strategies,
        args.max_spp,
        args.seeds,
        args.budget,
    );
    let device = choose_device(args, &mut scene, &plan.configs, open)?;
    let renderer = device.renderer();
    let Some(reference) = resolve_reference(supplied, args, &scene, &out, renderer, cancel)? else {
        eprintln!("interrupted while rendering the reference: nothing measured");
        return Ok(Studied::NothingMeasured);
    };
    let bar = plan.progress_bar(pixels);
    measure::warm_up(renderer, &mut scene, &plan.configs, cancel)?;
    let timed = Timed {
        renderer,
        scene: &scene,
        reference: &reference,
        cancel,
        bar: &bar,
    };
    let measured = timed.measure(&plan)?;
    let (summaries, common) = write_files(args, &out, &scene, &device, &reference, &measured)?;
    print_summary(&plan, &measured, &out, &summaries, common);
    Ok(Studied::Measured {
        out,
        cancelled: cancel.load(Ordering::Relaxed),
    })
}

/// Load the scene with the film size and depth asked for, and check the threshold.
fn load_scene(args: &StudyArgs) -> anyhow::Result<FlatScene> {
    let mut scene = crate::scene::load(&args.scene, args.import, true)?;
    if let Some((w, h)) = args.size {
        (scene.camera.width, scene.camera.height) = (w, h);
    }
    if let Some(depth) = args.max_depth {
        scene.settings.max_depth = depth;
    }
    if args.threshold.is_nan() || args.threshold <= 0.0 {
        anyhow::bail!("--threshold must be positive, got {}", args.threshold);
    }
    Ok(scene)
}

/// The reference given without rendering: `--reference`'s EXR, else the scene's exact value.
fn supplied_reference(
    args: &StudyArgs,
    scene: &FlatScene,
    pixels: usize,
) -> anyhow::Result<Option<Reference>> {
    let (w, h) = (scene.camera.width, scene.camera.height);
    Ok(match &args.reference {
        Some(path) => Some(Reference::read_exr(path, w, h)?),
        None => scene.exact.map(|v| Reference::exact(v, pixels)),
    })
}

/// Create the output folder: `--out`, else `study-SCENE-NAME`.
fn create_out_folder(args: &StudyArgs) -> anyhow::Result<PathBuf> {
    let out = args.out.clone().unwrap_or_else(|| {
        let stem = args.scene.file_stem().unwrap_or(args.scene.as_os_str());
        PathBuf::from(format!("study-{}", stem.to_string_lossy()))
    });
    std::fs::create_dir_all(&out)
        .with_context(|| format!("{}: cannot create the folder", out.display()))?;
    Ok(out)
}

/// Choose the device (`auto` probes it on the scene) and say which.
fn choose_device<D: std::ops::Deref<Target = Device> + From<Device>>(
    args: &StudyArgs,
    scene: &mut FlatScene,
    configs: &[(SamplerKind, Strategy)],
    open: &mut dyn FnMut(wgpu::Adapter) -> anyhow::Result<D>,
) -> anyhow::Result<D> {
    // The probe renders a configuration the study renders that the eight-lane CPU renderer does
    // not cover, if there is one: `auto` then weighs lavapipe against the CPU reference and
    // picks a CPU renderer that renders every configuration of the study.
    let base = scene.settings;
    let probe_settings = {
        let scene: &FlatScene = scene;
        configs
            .iter()
            .map(|&(sampler, strategy)| stratapt_scene::RenderSettings {
                sampler,
                strategy,
                ..base
            })
            .find(|settings| stratapt_cpu::eight::supports(scene, settings).is_err())
            .unwrap_or(base)
    };
    let (device, why) = Device::choose_with(
        args.device,
        args.adapter.as_deref(),
        Some((scene, &probe_settings)),
        open,
    )?;
    eprintln!("{}", device.line(why.as_deref()));
    Ok(device)
}

/// The reference to measure against: the one supplied, else a high-spp render cached in
/// `out`; `None` when Ctrl-C interrupted that render.
fn resolve_reference(
    supplied: Option<Reference>,
    args: &StudyArgs,
    scene: &FlatScene,
    out: &Path,
    renderer: &dyn Render,
    cancel: &AtomicBool,
) -> anyhow::Result<Option<Reference>> {
    if let Some(r) = supplied {
        return Ok(Some(r));
    }
    let spp = args.reference_spp.unwrap_or((16 * args.max_spp).max(1024));
    let settings = reference::reference_settings(scene, spp);
    let path = reference::cache_path(out, scene, &settings);
    reference::cached(renderer, scene, &settings, &path, cancel)
}

/// Write everything measured: `study.csv`, the two plots and `report.md`; returns the ranked
/// summaries and the spp level they are compared at.
fn write_files(
    args: &StudyArgs,
    out: &Path,
    scene: &FlatScene,
    device: &Device,
    reference: &Reference,
    measured: &Measured,
) -> anyhow::Result<(Vec<Summary>, Option<u32>)> {
    write_atomically(
        &out.join("study.csv"),
        report::csv(&measured.rows).as_bytes(),
    )?;
    let (summaries, common) = report::summarize(&measured.rows, args.threshold);
    write_plots(&args.scene, out, &summaries)?;
    // The command as a user types it: `strata` and the arguments given, or the caller's words.
    let command = args.command.clone().unwrap_or_else(|| {
        let words: Vec<String> = std::iter::once("strata".to_string())
            .chain(std::env::args().skip(1))
            .collect();
        words.join(" ")
    });
    let meta = report::Meta {
        scene: &args.scene,
        size: (scene.camera.width, scene.camera.height),
        max_depth: scene.settings.max_depth,
        device: &device.describe(),
        time_source: measured.time_source,
        reference: &reference.source,
        threshold: args.threshold,
        seeds: args.seeds,
        command: &command,
        stopped: measured.stopped.as_deref(),
    };
    write_atomically(
        &out.join("report.md"),
        report::markdown(&meta, &summaries, common).as_bytes(),
    )?;
    Ok((summaries, common))
}

/// Plot the error against render time and against spp.
fn write_plots(scene: &Path, out: &Path, summaries: &[Summary]) -> anyhow::Result<()> {
    let name = scene.display().to_string();
    plot::write(
        out,
        "error-vs-time",
        &format!("{name}: error against render time"),
        plot::Axis::Seconds,
        summaries,
    )?;
    plot::write(
        out,
        "error-vs-spp",
        &format!("{name}: error against samples per pixel"),
        plot::Axis::Spp,
        summaries,
    )
}

/// Say what was studied, where it was written, and which configuration was most efficient.
fn print_summary(
    plan: &Plan,
    measured: &Measured,
    out: &Path,
    summaries: &[Summary],
    common: Option<u32>,
) {
    eprintln!(
        "studied {} configurations × {} seeds, {} renders in {:.1} s{}; wrote {}/{{study.csv, error-vs-time.svg/.png, error-vs-spp.svg/.png, report.md}}",
        plan.configs.len(),
        plan.seeds,
        measured.rows.len(),
        measured.start.elapsed().as_secs_f64(),
        measured.stopped.as_ref().map_or(String::new(), |s| format!(" (stopped: {s})")),
        out.display()
    );
    if let Some(best) = summaries.first() {
        eprintln!(
            "most efficient: {} / {} (1/(MSE·s) = {:.3e} at {} spp)",
            best.sampler,
            best.strategy,
            best.efficiency,
            common.unwrap_or(0)
        );
    }
}

/// Write `bytes` to a temporary sibling of `path`, then rename it into place (the film's
/// atomic writer).
pub(crate) fn write_atomically(path: &Path, bytes: &[u8]) -> anyhow::Result<()> {
    stratapt_film::write_atomically(path, |tmp| {
        std::fs::write(tmp, bytes).map_err(|e| format!("cannot write: {e}"))
    })?;
    Ok(())
}
