//! `strata render`.

use crate::device::{Device, DeviceChoice};
use anyhow::Context;
use clap::Args;
use indicatif::{ProgressBar, ProgressStyle};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::Instant;
use stratapt_scene::load::MAX_RESOLUTION;
use stratapt_scene::{RenderSettings, SamplerKind, Strategy};

#[derive(Args)]
pub struct RenderArgs {
    /// Scene file (TOML).
    scene: PathBuf,
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
    /// Where to render.
    #[arg(long, value_enum, default_value_t = DeviceChoice::Auto)]
    device: DeviceChoice,
    /// GPU adapter to use, by (part of) its name, e.g. llvmpipe or "RTX 4090" (see
    /// `strata adapters`).
    #[arg(long, value_name = "NAME")]
    adapter: Option<String>,
}

fn parse_sampler(s: &str) -> Result<SamplerKind, String> {
    SamplerKind::from_name(s).ok_or_else(|| format!("expected one of {}", names(SamplerKind::ALL)))
}

fn parse_strategy(s: &str) -> Result<Strategy, String> {
    Strategy::from_name(s).ok_or_else(|| format!("expected one of {}", names(Strategy::ALL)))
}

pub(crate) fn parse_size(s: &str) -> Result<(u32, u32), String> {
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

pub fn run(args: RenderArgs) -> anyhow::Result<()> {
    let mut scene = stratapt_scene::load::load(&args.scene)?;
    if let Some((w, h)) = args.size {
        (scene.camera.width, scene.camera.height) = (w, h);
    }
    let settings = settings(&scene.settings, &args);
    let outputs = outputs(&args)?;
    let (device, note) = Device::choose(args.device, args.adapter.as_deref())?;
    if let Some(note) = note {
        eprintln!("note: {note}");
    }
    eprintln!("device: {}", device.describe());

    // Ctrl-C: finish the pass in flight and write what was rendered; a second one quits.
    let cancel = Arc::new(AtomicBool::new(false));
    let flag = cancel.clone();
    ctrlc::set_handler(move || {
        if flag.swap(true, Ordering::SeqCst) {
            std::process::exit(130);
        }
        eprintln!("\ninterrupted: writing the samples taken so far (Ctrl-C again to quit)");
    })
    .context("cannot install the Ctrl-C handler")?;

    let (w, h) = (scene.camera.width, scene.camera.height);
    let total = w as u64 * h as u64 * settings.spp as u64;
    let bar = progress_bar(total);
    let start = Instant::now();
    let mut gpu_note = None;
    let film = match &device {
        Device::Cpu { .. } => {
            stratapt_cpu::render_with_cancel(&scene, &settings, &|n| bar.inc(n), &cancel)
        }
        Device::Gpu { renderer, .. } => {
            let (film, stats) =
                renderer.render_with_stats(&scene, &settings, &|n| bar.inc(n), Some(&cancel))?;
            gpu_note = Some(gpu_summary(&stats, renderer.bvh_layout()));
            film
        }
    };
    let seconds = start.elapsed().as_secs_f64();
    bar.finish_and_clear();

    for path in &outputs {
        film.write(path)?;
    }
    let samples = w as f64 * h as f64 * film.spp() as f64;
    let partial = if film.spp() < settings.spp {
        " (interrupted)"
    } else {
        ""
    };
    eprintln!(
        "rendered {} at {w}×{h}, {} spp{partial}, {} / {}, depth {} in {seconds:.2} s: \
         {:.3} M samples/s; wrote {}",
        args.scene.display(),
        film.spp(),
        settings.sampler,
        settings.strategy,
        settings.max_depth,
        samples / seconds.max(1e-9) / 1e6,
        outputs
            .iter()
            .map(|p| p.display().to_string())
            .collect::<Vec<_>>()
            .join(", ")
    );
    if let Some(note) = gpu_note {
        eprintln!("{note}");
    }
    Ok(())
}

/// One line on the GPU render: BVH layout, compile time, batches, GPU time, non-finite samples.
fn gpu_summary(stats: &stratapt_gpu::RenderStats, bvh: stratapt_gpu::BvhLayout) -> String {
    let mut line = format!(
        "gpu: {bvh} BVH, kernel compiled in {:.2} s, {} dispatches",
        stats.compile_seconds, stats.dispatches
    );
    if let Some(t) = stats.gpu_seconds {
        line.push_str(&format!(", {t:.2} s of GPU time"));
    }
    if stats.non_finite > 0 {
        line.push_str(&format!(
            "; warning: {} non-finite samples replaced by zero",
            stats.non_finite
        ));
    }
    line
}

/// The scene's `[render]` defaults with the command line's overrides.
fn settings(defaults: &RenderSettings, args: &RenderArgs) -> RenderSettings {
    RenderSettings {
        spp: args.spp.unwrap_or(defaults.spp),
        max_depth: args.max_depth.unwrap_or(defaults.max_depth),
        sampler: args.sampler.unwrap_or(defaults.sampler),
        strategy: args.strategy.unwrap_or(defaults.strategy),
        seed: args.seed.unwrap_or(defaults.seed),
    }
}

/// The output paths, checked before rendering so a typo doesn't cost a render.
fn outputs(args: &RenderArgs) -> anyhow::Result<Vec<PathBuf>> {
    let outputs = if args.output.is_empty() {
        let stem = args.scene.file_stem().unwrap_or(args.scene.as_os_str());
        vec![
            Path::new(stem).with_extension("exr"),
            Path::new(stem).with_extension("png"),
        ]
    } else {
        args.output.clone()
    };
    for path in &outputs {
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
    }
    Ok(outputs)
}

fn progress_bar(total: u64) -> ProgressBar {
    let bar = ProgressBar::new(total);
    bar.set_style(
        ProgressStyle::with_template(
            "{bar:40.cyan/blue} {percent:>3}% {human_pos}/{human_len} samples, {per_sec}, eta {eta}",
        )
        .expect("valid progress template"),
    );
    bar
}
