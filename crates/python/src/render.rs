//! `strata.render`: a scene rendered as `strata render` renders it, into a `Film`.

use crate::error;
use crate::film::{About, Film};
use crate::scene::Scene;
use crate::session;
use pyo3::prelude::*;
use std::sync::Arc;
use std::time::Duration;
use stratapt_cli::device::{Device, DeviceChoice};
use stratapt_cli::render::{
    parse_metric, parse_sampler, parse_size, parse_strategy, parse_target_error, stop_rule_for,
};
use stratapt_cpu::CpuRenderer;
use stratapt_film::render::progressive::{render_progressive, Progressive, Stopped};
use stratapt_film::render::RenderError;
use stratapt_scene::{FlatScene, RenderSettings};

/// Render `scene` (see the `strata` package's `render` for the arguments); `progress` is called
/// with the samples done so far, from this thread, every tenth of a second.
#[pyfunction]
#[pyo3(signature = (
    scene, *, spp = None, size = None, sampler = None, strategy = None, max_depth = None,
    seed = None, device = "auto", adapter = None, target_error = None,
    target_error_metric = "image-mean", time_limit = None, calibrate = true, progress = None
))]
#[allow(clippy::too_many_arguments)]
pub fn render(
    py: Python<'_>,
    scene: &Scene,
    spp: Option<i64>,
    size: Option<(i64, i64)>,
    sampler: Option<&str>,
    strategy: Option<&str>,
    max_depth: Option<i64>,
    seed: Option<i64>,
    device: &str,
    adapter: Option<String>,
    target_error: Option<f64>,
    target_error_metric: &str,
    time_limit: Option<f64>,
    calibrate: bool,
    progress: Option<Bound<'_, PyAny>>,
) -> PyResult<Film> {
    // ---- the options, checked as the command line checks them ----------------------------
    let defaults = &scene.scene.settings;
    let settings = RenderSettings {
        pattern_spp: spp
            .map(|n| in_range("spp", n, 1, u32::MAX as i64))
            .transpose()?
            .unwrap_or(defaults.pattern_spp),
        max_depth: max_depth
            .map(|n| in_range("max_depth", n, 1, 1024))
            .transpose()?
            .unwrap_or(defaults.max_depth),
        sampler: named("sampler", sampler, parse_sampler)?.unwrap_or(defaults.sampler),
        strategy: named("strategy", strategy, parse_strategy)?.unwrap_or(defaults.strategy),
        seed: seed
            .map(|n| in_range("seed", n, 0, u32::MAX as i64))
            .transpose()?
            .unwrap_or(defaults.seed),
        calibrate: defaults.calibrate && calibrate,
    };
    let metric =
        parse_metric(target_error_metric).map_err(|e| error::argument("target_error_metric", e))?;
    let target = target_error
        .map(|e| parse_target_error(&e.to_string()).map_err(|m| error::argument("target_error", m)))
        .transpose()?;
    let limit = time_limit
        .map(|t| match t.is_finite() && t > 0.0 {
            true => Ok(Duration::from_secs_f64(t)),
            false => Err(error::argument(
                "time_limit",
                "must be a positive number of seconds",
            )),
        })
        .transpose()?;
    let stop = stop_rule_for(
        &settings,
        spp.map(|n| n as u32),
        target.map(|e| (e, metric)),
        limit,
    );
    let choice = match device {
        "auto" => DeviceChoice::Auto,
        "gpu" => DeviceChoice::Gpu,
        "cpu" => DeviceChoice::Cpu,
        "cpu8" => DeviceChoice::Cpu8,
        other => {
            return Err(error::argument(
                "device",
                format!("expected auto, gpu, cpu or cpu8, got {other:?}"),
            ))
        }
    };
    let scene = sized(&scene.scene, size)?;

    // ---- the device, kept for the process ----------------------------------------------
    let (device, reason) = py
        .detach(|| session::device(choice, adapter.as_deref(), &scene, &settings))
        .map_err(|e| error::runtime(format!("{e:#}")))?;

    // ---- the render, off the interpreter's lock ----------------------------------------
    let falls_back = |e: &RenderError| Device::falls_back(choice, adapter.as_deref(), e);
    let rendered = session::interruptible(py, progress.as_ref(), |watch| {
        let progress = |n| watch.add(n);
        let cancel = Some(&watch.cancel);
        match render_progressive(
            device.renderer(),
            &scene,
            &settings,
            &stop,
            &progress,
            cancel,
        ) {
            // A scene the GPU cannot hold renders on the CPU reference under `auto`.
            Err(e) if falls_back(&e) => {
                let why = format!("CPU reference instead ({}: {e})", device.describe());
                render_progressive(&CpuRenderer, &scene, &settings, &stop, &progress, cancel)
                    .map(|done| (done, Some(why)))
                    .map_err(|e| format!("CPU reference: {e}"))
            }
            Err(e) => Err(format!("{}: {e}", device.describe())),
            Ok(done) => Ok((done, None)),
        }
    })?;
    let (done, fell_back) = rendered.map_err(error::runtime)?;
    Ok(film(done, &device, reason, fell_back, settings))
}

/// The scene at `size` (a copy) or as it is; `size` keeps the vertical field of view, as
/// `--size` does.
fn sized(scene: &Arc<FlatScene>, size: Option<(i64, i64)>) -> PyResult<Arc<FlatScene>> {
    let Some((w, h)) = size else {
        return Ok(scene.clone());
    };
    let (w, h) = parse_size(&format!("{w}x{h}")).map_err(|e| error::argument("size", e))?;
    if (w, h) == (scene.camera.width, scene.camera.height) {
        return Ok(scene.clone());
    }
    let mut resized = FlatScene::clone(scene);
    (resized.camera.width, resized.camera.height) = (w, h);
    Ok(Arc::new(resized))
}

fn film(
    done: Progressive,
    device: &Device,
    reason: Option<String>,
    fell_back: Option<String>,
    settings: RenderSettings,
) -> Film {
    let (device, device_reason) = match fell_back {
        Some(why) => (Device::cpu().describe(), Some(why)),
        None => (device.describe(), reason),
    };
    let about = About {
        seconds: done.seconds,
        device,
        device_reason,
        stopped: match done.stopped {
            Stopped::MaxSpp | Stopped::Cancelled => "spp",
            Stopped::TargetError => "target-error",
            Stopped::TimeLimit => "time-limit",
        },
        settings,
        stats: Some(done.stats),
    };
    Film::new(done.film, about)
}

/// `value` as a u32 within `min..=max`, or a `ValueError` naming the argument.
fn in_range(name: &str, value: i64, min: i64, max: i64) -> PyResult<u32> {
    if (min..=max).contains(&value) {
        Ok(value as u32)
    } else {
        Err(error::argument(
            name,
            format!("{value} is not in {min}..={max}"),
        ))
    }
}

/// A sampler's or strategy's name parsed as the command line parses it.
fn named<T>(
    name: &str,
    value: Option<&str>,
    parse: fn(&str) -> Result<T, String>,
) -> PyResult<Option<T>> {
    value
        .map(|v| parse(v).map_err(|e| error::argument(name, e)))
        .transpose()
}
