//! The multi-threaded render loop: the image is rendered in passes of a few samples per pixel
//! over every pixel (rows in parallel with rayon), so that a cancelled render still returns
//! an image with the same number of samples in every pixel.

use crate::{accel, Integrator};
use rayon::prelude::*;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use stratapt_scene::{Film, FlatScene, RenderSettings};

/// Samples per pixel rendered between two checks of the cancel flag.
const PASS_SPP: u32 = 4;

/// What happened during a render besides the film.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RenderStats {
    /// Samples added to the film.
    pub samples: u64,
    /// Samples whose estimate was NaN or infinite (a bug: they panic in debug builds and are
    /// recorded as zero in release builds).
    pub non_finite: u64,
    /// Whether the render stopped early.
    pub cancelled: bool,
    /// Rays traced (path and shadow rays; a cancelled pass's partial rows included).
    pub rays: u64,
}

/// Render `scene` with `settings`; `progress` is called with the number of newly finished
/// samples (once per row and pass).
pub fn render(
    scene: &FlatScene,
    settings: &RenderSettings,
    progress: &(dyn Fn(u64) + Sync),
) -> Film {
    render_with_stats(scene, settings, progress, None).0
}

/// [`render`] that stops when `cancel` becomes true, returning the passes completed so far
/// (every pixel with the same sample count).
pub fn render_with_cancel(
    scene: &FlatScene,
    settings: &RenderSettings,
    progress: &(dyn Fn(u64) + Sync),
    cancel: &AtomicBool,
) -> Film {
    render_with_stats(scene, settings, progress, Some(cancel)).0
}

/// [`render_with_cancel`] that also returns the [`RenderStats`].
pub fn render_with_stats(
    scene: &FlatScene,
    settings: &RenderSettings,
    progress: &(dyn Fn(u64) + Sync),
    cancel: Option<&AtomicBool>,
) -> (Film, RenderStats) {
    let integrator = Integrator::new(scene, settings);
    let (width, height) = (scene.camera.width, scene.camera.height);
    let mut film = Film::new(width, height);
    let mut stats = RenderStats::default();
    let counts = Counts::default();
    let cancelled = || cancel.is_some_and(|c| c.load(Ordering::Relaxed));
    let mut start = 0;
    while start < settings.spp && width > 0 && height > 0 {
        if cancelled() {
            stats.cancelled = true;
            break;
        }
        let end = (start + PASS_SPP).min(settings.spp);
        let pass = render_pass(
            &integrator,
            width,
            height,
            start..end,
            progress,
            &cancelled,
            &counts,
        );
        let Some(pass) = pass else {
            stats.cancelled = true;
            break;
        };
        film.merge(&pass);
        stats.samples += (end - start) as u64 * width as u64 * height as u64;
        start = end;
    }
    stats.non_finite = counts.non_finite.into_inner();
    stats.rays = counts.rays.into_inner();
    (film, stats)
}

/// What the threads of a render count as they go.
#[derive(Default)]
struct Counts {
    non_finite: AtomicU64,
    rays: AtomicU64,
}

/// Samples `indices` of every pixel into a fresh film; `None` if cancelled midway.
fn render_pass(
    integrator: &Integrator,
    width: u32,
    height: u32,
    indices: std::ops::Range<u32>,
    progress: &(dyn Fn(u64) + Sync),
    cancelled: &(dyn Fn() -> bool + Sync),
    counts: &Counts,
) -> Option<Film> {
    let mut pass = Film::new(width, height);
    let w = width as usize;
    let complete = AtomicBool::new(true);
    pass.sum
        .par_chunks_mut(w)
        .zip(pass.sum_sq.par_chunks_mut(w))
        .zip(pass.count.par_chunks_mut(w))
        .enumerate()
        .for_each(|(y, ((sum, sum_sq), count))| {
            if cancelled() {
                complete.store(false, Ordering::Relaxed);
                return;
            }
            let rays_before = accel::rays_traced();
            for x in 0..w {
                for index in indices.clone() {
                    let value = integrator.sample_pixel([x as u32, y as u32], index);
                    let value = if value.is_finite() {
                        value
                    } else {
                        debug_assert!(
                            false,
                            "non-finite sample {value} at pixel ({x}, {y}), index {index}"
                        );
                        counts.non_finite.fetch_add(1, Ordering::Relaxed);
                        glam::Vec3::ZERO
                    };
                    // Film::add_sample, on this row's slices.
                    for c in 0..3 {
                        let v = value[c] as f64;
                        sum[x][c] += v;
                        sum_sq[x][c] += v * v;
                    }
                    count[x] += 1;
                }
            }
            let row_rays = accel::rays_traced() - rays_before;
            counts.rays.fetch_add(row_rays, Ordering::Relaxed);
            progress(w as u64 * indices.len() as u64);
        });
    complete.into_inner().then_some(pass)
}
