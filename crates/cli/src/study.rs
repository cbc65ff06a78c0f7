//! `strata study`: what accuracy costs in time. Renders the scene with every chosen sampler ×
//! strategy at 1, 2, 4, … spp and several seeds, times each render, measures its error against a
//! reference, and writes `study.csv`, error-vs-time and error-vs-spp plots and a ranked
//! `report.md`.

mod plot;
mod reference;
mod report;

use crate::device::{Device, DeviceChoice};
use crate::render::{cancel_on_ctrl_c, parse_sampler, parse_size, parse_strategy};
use anyhow::Context;
use clap::Args;
use indicatif::{ProgressBar, ProgressStyle};
use reference::Reference;
use report::Row;
use std::path::{Path, PathBuf};
use std::sync::atomic::Ordering;
use std::time::{Duration, Instant};
use stratapt_scene::{RenderSettings, SamplerKind, Strategy};

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
}

fn parse_duration(s: &str) -> Result<Duration, String> {
    humantime::parse_duration(s.trim()).map_err(|e| format!("{e} (expected e.g. 60s, 5m)"))
}

pub fn run(args: StudyArgs) -> anyhow::Result<std::process::ExitCode> {
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
    let (w, h) = (scene.camera.width, scene.camera.height);
    let pixels = (w * h) as usize;
    // Check the reference before rendering anything.
    let supplied = match &args.reference {
        Some(path) => Some(Reference::read_exr(path, w, h)?),
        None => scene.exact.map(|v| Reference::exact(v, pixels)),
    };
    let out = args.out.clone().unwrap_or_else(|| {
        let stem = args.scene.file_stem().unwrap_or(args.scene.as_os_str());
        PathBuf::from(format!("study-{}", stem.to_string_lossy()))
    });
    std::fs::create_dir_all(&out)
        .with_context(|| format!("{}: cannot create the folder", out.display()))?;

    let probe_settings = scene.settings;
    let (device, why) = Device::choose(
        args.device,
        args.adapter.as_deref(),
        Some((&mut scene, &probe_settings)),
    )?;
    eprintln!("{}", device.line(why.as_deref()));
    let renderer = device.renderer();
    let cancel = cancel_on_ctrl_c("writing what was measured")?;

    let reference = match supplied {
        Some(r) => r,
        None => {
            let spp = args.reference_spp.unwrap_or((16 * args.max_spp).max(1024));
            let settings = reference::reference_settings(&scene, spp);
            let path = reference::cache_path(&out, &scene, &settings);
            match reference::cached(renderer, &scene, &settings, &path, &cancel)? {
                Some(r) => r,
                None => {
                    eprintln!("interrupted while rendering the reference: nothing measured");
                    return Ok(std::process::ExitCode::from(130));
                }
            }
        }
    };

    let samplers = if args.samplers.is_empty() {
        SamplerKind::ALL.to_vec()
    } else {
        args.samplers.clone()
    };
    let strategies = if args.strategies.is_empty() {
        Strategy::ALL.to_vec()
    } else {
        args.strategies.clone()
    };
    let configs: Vec<(SamplerKind, Strategy)> = samplers
        .iter()
        .flat_map(|&s| strategies.iter().map(move |&t| (s, t)))
        .collect();
    let levels: Vec<u32> = std::iter::successors(Some(1u32), |&s| {
        (s < args.max_spp).then(|| (s * 2).min(args.max_spp))
    })
    .collect();
    let samples_per_level =
        |spp: u32| configs.len() as u64 * args.seeds as u64 * pixels as u64 * spp as u64;
    let bar = ProgressBar::new(levels.iter().map(|&s| samples_per_level(s)).sum());
    bar.set_style(
        ProgressStyle::with_template(
            "{bar:40.cyan/blue} {percent:>3}% study: {msg} {elapsed} (eta {eta})",
        )
        .expect("valid progress template"),
    );

    // ---- Warm up: compile each configuration's kernel (and lavapipe's JIT) off the clock ----
    (scene.camera.width, scene.camera.height) = (8, 8);
    for &(sampler, strategy) in &configs {
        let settings = RenderSettings {
            spp: 1,
            sampler,
            strategy,
            ..scene.settings
        };
        renderer
            .render(&scene, &settings, &|_| {}, Some(&cancel))
            .map_err(|e| anyhow::anyhow!("{}: {e}", renderer.describe()))?;
    }
    (scene.camera.width, scene.camera.height) = (w, h);

    // ---- Render: level by level, so a budget or Ctrl-C leaves every configuration comparable --
    let start = Instant::now();
    let mut rows: Vec<Row> = Vec::new();
    let mut stopped = None;
    let mut last_level_seconds = 0.0;
    let mut time_source = "wall";
    'levels: for &spp in &levels {
        if let Some(budget) = args.budget {
            // Each level takes about twice the one before.
            let expect = start.elapsed().as_secs_f64() + 2.0 * last_level_seconds;
            if expect > budget.as_secs_f64() && !rows.is_empty() {
                stopped = Some(format!(
                    "the next level ({spp} spp) would end past the {}-s budget",
                    budget.as_secs()
                ));
                break;
            }
        }
        let level_start = Instant::now();
        for &(sampler, strategy) in &configs {
            for seed in 0..args.seeds {
                bar.set_message(format!("{sampler} / {strategy}, {spp} spp, seed {seed}"));
                let settings = RenderSettings {
                    spp,
                    sampler,
                    strategy,
                    seed,
                    ..scene.settings
                };
                let t = Instant::now();
                let (film, stats) = renderer
                    .render(&scene, &settings, &|n| bar.inc(n), Some(&cancel))
                    .map_err(|e| anyhow::anyhow!("{}: {e}", renderer.describe()))?;
                let wall = t.elapsed().as_secs_f64()
                    - stats.compile_seconds
                    - stats.first_dispatch_seconds;
                if stats.cancelled {
                    stopped = Some("interrupted by Ctrl-C".to_string());
                    break 'levels;
                }
                let seconds = match stats.gpu_seconds {
                    Some(gpu) => {
                        time_source = "GPU timestamps";
                        gpu
                    }
                    None => wall,
                };
                rows.push(Row {
                    sampler,
                    strategy,
                    spp,
                    seed,
                    seconds,
                    time_source: if stats.gpu_seconds.is_some() {
                        "gpu-timestamps"
                    } else {
                        "wall"
                    },
                    errors: report::measure(&film, &reference),
                });
            }
        }
        last_level_seconds = level_start.elapsed().as_secs_f64();
    }
    bar.finish_and_clear();

    // ---- Write everything measured --------------------------------------------------------------
    write_atomically(&out.join("study.csv"), report::csv(&rows).as_bytes())?;
    let (summaries, common) = report::summarize(&rows, args.threshold);
    let name = args.scene.display().to_string();
    plot::write(
        &out,
        "error-vs-time",
        &format!("{name}: error against render time"),
        plot::Axis::Seconds,
        &summaries,
    )?;
    plot::write(
        &out,
        "error-vs-spp",
        &format!("{name}: error against samples per pixel"),
        plot::Axis::Spp,
        &summaries,
    )?;
    // The command as a user types it: `strata` and the arguments given.
    let command: Vec<String> = std::iter::once("strata".to_string())
        .chain(std::env::args().skip(1))
        .collect();
    let meta = report::Meta {
        scene: &args.scene,
        size: (w, h),
        max_depth: scene.settings.max_depth,
        device: &device.describe(),
        time_source,
        reference: &reference.source,
        threshold: args.threshold,
        seeds: args.seeds,
        command: &command.join(" "),
        stopped: stopped.as_deref(),
    };
    write_atomically(
        &out.join("report.md"),
        report::markdown(&meta, &summaries, common).as_bytes(),
    )?;
    eprintln!(
        "studied {} configurations × {} seeds, {} renders in {:.1} s{}; wrote {}/{{study.csv, error-vs-time.svg/.png, error-vs-spp.svg/.png, report.md}}",
        configs.len(),
        args.seeds,
        rows.len(),
        start.elapsed().as_secs_f64(),
        stopped.as_ref().map_or(String::new(), |s| format!(" (stopped: {s})")),
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
    Ok(if cancel.load(Ordering::Relaxed) {
        std::process::ExitCode::from(130)
    } else {
        std::process::ExitCode::SUCCESS
    })
}

/// Write `bytes` to a temporary sibling of `path`, then rename it into place (the film's
/// atomic writer).
pub(crate) fn write_atomically(path: &Path, bytes: &[u8]) -> anyhow::Result<()> {
    stratapt_film::write_atomically(path, |tmp| {
        std::fs::write(tmp, bytes).map_err(|e| format!("cannot write: {e}"))
    })?;
    Ok(())
}
