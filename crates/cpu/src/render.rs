//! The multi-threaded render loop: the image is rendered in passes of a few samples per pixel
//! over every pixel (rows in parallel with rayon), so that a cancelled render still returns
//! an image with the same number of samples in every pixel.

use crate::accel::{self, Accel};
use crate::Integrator;
use glam::Vec3;
use rayon::prelude::*;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use stratapt_film::render::Progress;
use stratapt_film::{accumulate, PeakTwin, TwinLayout, PEAK_REPLICAS};
use stratapt_film::{Film, Render, RenderError, RenderStats};
use stratapt_sampling::replica;
use stratapt_scene::{FlatScene, RenderSettings};

/// Samples per pixel rendered between two checks of the cancel flag.
const PASS_SPP: u32 = 4;

/// The CPU reference as a [`Render`]: renders on rayon's global thread pool.
#[derive(Clone, Copy, Debug, Default)]
pub struct CpuRenderer;

impl Render for CpuRenderer {
    fn render_into(
        &self,
        scene: &FlatScene,
        settings: &RenderSettings,
        film: &mut Film,
        added_spp: u32,
        progress: Progress,
        cancel: Option<&AtomicBool>,
    ) -> Result<RenderStats, RenderError> {
        Ok(render_into(
            scene,
            settings,
            film,
            added_spp,
            progress,
            cancel,
            Lanes::One,
        ))
    }

    fn describe(&self) -> String {
        format!("CPU reference ({} threads)", rayon::current_num_threads())
    }
}

/// The eight-lane prototype as a [`Render`]: renders on rayon's global thread pool, and fails
/// with [`RenderError`] on a scene it does not cover ([`supports`]).
#[derive(Clone, Copy, Debug, Default)]
pub struct Cpu8Renderer;

impl Render for Cpu8Renderer {
    fn render_into(
        &self,
        scene: &FlatScene,
        settings: &RenderSettings,
        film: &mut Film,
        added_spp: u32,
        progress: Progress,
        cancel: Option<&AtomicBool>,
    ) -> Result<RenderStats, RenderError> {
        crate::eight::supports(scene, settings)?;
        Ok(render_into(
            scene,
            settings,
            film,
            added_spp,
            progress,
            cancel,
            Lanes::Eight,
        ))
    }

    fn describe(&self) -> String {
        format!(
            "CPU, eight lanes per thread (prototype; {} threads)",
            rayon::current_num_threads()
        )
    }
}

/// Render `settings.pattern_spp` samples per pixel of `scene` into a new film: the CPU
/// reference's one entry besides [`CpuRenderer`] (which cannot fail, so this returns no
/// `Result`). `progress` is called with the number of newly finished samples (once per row and
/// pass); once `cancel` is set it stops after the pass in flight, every pixel with the same
/// sample count.
pub fn render(
    scene: &FlatScene,
    settings: &RenderSettings,
    progress: Progress,
    cancel: Option<&AtomicBool>,
) -> (Film, RenderStats) {
    let mut film = Film::for_render(scene, settings);
    let stats = render_into(
        scene,
        settings,
        &mut film,
        settings.pattern_spp,
        progress,
        cancel,
        Lanes::One,
    );
    (film, stats)
}

/// How a render traces its paths.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Lanes {
    /// One path at a time: the reference ([`Integrator`]).
    One,
    /// Eight paths at a time ([`crate::eight`]; the scene must be one it supports).
    Eight,
}

/// A render's path tracer, one lane or eight.
enum Tracer<'a> {
    One(Integrator<'a>),
    Eight(Box<crate::eight::Paths<'a>>),
}

impl<'a> Tracer<'a> {
    fn new(lanes: Lanes, accel: &'a Accel<'a>, settings: &RenderSettings) -> Self {
        match lanes {
            Lanes::One => Self::One(Integrator::new(accel, settings)),
            Lanes::Eight => {
                let support = crate::eight::supports(accel.scene(), settings)
                    .expect("the eight-lane renderer checks the scene first");
                Self::Eight(Box::new(crate::eight::Paths::new(
                    accel, settings, &support,
                )))
            }
        }
    }

    /// Samples `indices` of the pixels `pixel(0 .. count)`, each value (non-finite ones
    /// counted and replaced by zero) to `add(j, value)`.
    fn trace_row(
        &self,
        count: usize,
        pixel: &dyn Fn(usize) -> [u32; 2],
        indices: std::ops::Range<u32>,
        counts: &Counts,
        add: &mut dyn FnMut(usize, Vec3),
    ) {
        match self {
            Self::One(integrator) => {
                for j in 0..count {
                    for index in indices.clone() {
                        add(j, sample(integrator, pixel(j), index, counts));
                    }
                }
            }
            Self::Eight(paths) => {
                paths.trace_row(count, pixel, indices, &mut |j, value| {
                    add(j, finite(value, counts))
                });
            }
        }
    }
}

/// Add `added_spp` samples of every pixel to `film`, from index
/// `film.first_sample + film.held_spp()` (what [`CpuRenderer`]'s `render_into` does)
/// ([`Render::render_into`]), tracing `lanes` paths at a time.
pub(crate) fn render_into(
    scene: &FlatScene,
    settings: &RenderSettings,
    film: &mut Film,
    added_spp: u32,
    progress: Progress,
    cancel: Option<&AtomicBool>,
    lanes: Lanes,
) -> RenderStats {
    let accel = Accel::new(scene);
    let integrator = Tracer::new(lanes, &accel, settings);
    // The uniform twins' independent randomization: replica 1 of the render's seed.
    let twin_settings = replica_settings(settings, 1);
    let twins = film.has_twins().then(|| {
        (
            Tracer::new(lanes, &accel, &twin_settings),
            film.twin_layout(),
        )
    });
    let (width, height) = (scene.camera.width, scene.camera.height);
    let mut stats = RenderStats::default();
    let counts = Counts::default();
    let cancelled = || cancel.is_some_and(|c| c.load(Ordering::Relaxed));
    // One pass film for the render, cleared before each pass (a fresh one per pass faulted its
    // pages in every time, and unmapping it shot down the other threads' TLBs).
    let mut pass_film = Film::with_twins(width, height, twins.is_some());
    let mut start = film.first_sample.saturating_add(film.held_spp());
    let stop = start.saturating_add(added_spp);
    while start < stop && width > 0 && height > 0 {
        if cancelled() {
            stats.cancelled = true;
            break;
        }
        let end = start.saturating_add(PASS_SPP).min(stop);
        let completed = render_pass(
            &mut pass_film,
            &integrator,
            twins.as_ref(),
            width,
            start..end,
            progress,
            &cancelled,
            &counts,
        );
        if !completed {
            stats.cancelled = true;
            break;
        }
        film.merge(&pass_film);
        stats.samples += (end - start) as u64 * width as u64 * height as u64;
        start = end;
    }
    // The peak twins, for all the film's samples (merging the passes emptied them).
    if twins.is_some() && !stats.cancelled {
        add_peak_twins(film, film.peak_pixels(), &accel, settings, &counts);
    }
    stats.non_finite = counts.non_finite.into_inner();
    stats.rays = counts.rays.into_inner();
    stats
}

/// Render the peak twins of `film` ([`Film::peak_pixels`]) for all its samples, into
/// `film.peaks`: what [`render_into`] does after its samples, for a film another renderer
/// filled (the GPU renderer's; both compute the same samples). Returns the non-finite samples
/// met (counted and replaced by zero, as in a render). Nothing without twins.
pub fn render_peak_twins(scene: &FlatScene, settings: &RenderSettings, film: &mut Film) -> u64 {
    let pixels = film.peak_pixels();
    if pixels.is_empty() {
        film.peaks.clear();
        return 0;
    }
    let accel = Accel::new(scene);
    let counts = Counts::default();
    add_peak_twins(film, pixels, &accel, settings, &counts);
    counts.non_finite.into_inner()
}

/// `settings` with replica `replica`'s randomization of the render's seed.
fn replica_settings(settings: &RenderSettings, replica: u32) -> RenderSettings {
    RenderSettings {
        seed: replica::seed(settings.seed, replica),
        ..*settings
    }
}

/// Sample the [`PEAK_REPLICAS`] twins of each of `film`'s peak `pixels`
/// ([`Film::peak_pixels`]), replicas `1 ..= PEAK_REPLICAS` of the render's seed, for its
/// samples `film.first_sample ..` `+ film.held_spp()`, into `film.peaks`.
fn add_peak_twins<'a>(
    film: &mut Film,
    pixels: Vec<[u32; 2]>,
    accel: &'a Accel<'a>,
    settings: &RenderSettings,
    counts: &Counts,
) {
    let replicas: Vec<Integrator> = (1..=PEAK_REPLICAS)
        .map(|r| Integrator::new(accel, &replica_settings(settings, r)))
        .collect();
    let indices = film.first_sample..film.first_sample.saturating_add(film.held_spp());
    let twins: Vec<(usize, [u32; 2])> = pixels
        .iter()
        .flat_map(|&pixel| (0..replicas.len()).map(move |r| (r, pixel)))
        .collect();
    film.peaks = twins
        .into_par_iter()
        .map(|(r, pixel)| {
            let (mut sum, mut sum_sq) = ([0.0; 3], [0.0; 3]);
            for index in indices.clone() {
                let value = sample(&replicas[r], pixel, index, counts);
                accumulate(&mut sum, &mut sum_sq, value.to_array());
            }
            PeakTwin {
                pixel,
                replica: r as u32 + 1,
                sum,
                sum_sq,
            }
        })
        .collect();
}

/// What the threads of a render count as they go.
#[derive(Default)]
struct Counts {
    non_finite: AtomicU64,
    rays: AtomicU64,
}

/// Samples `indices` of every pixel (and of every twin, when there are) into `pass`, cleared
/// first; false if cancelled midway.
#[allow(clippy::too_many_arguments)]
fn render_pass(
    pass: &mut Film,
    integrator: &Tracer,
    twins: Option<&(Tracer, TwinLayout)>,
    width: u32,
    indices: std::ops::Range<u32>,
    progress: Progress,
    cancelled: &(dyn Fn() -> bool + Sync),
    counts: &Counts,
) -> bool {
    for v in [
        &mut pass.sum,
        &mut pass.sum_sq,
        &mut pass.twin_sum,
        &mut pass.twin_sum_sq,
    ] {
        v.fill([0.0; 3]);
    }
    pass.count.fill(0);
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
            let pixel = |x: usize| [x as u32, y as u32];
            integrator.trace_row(w, &pixel, indices.clone(), counts, &mut |x, value| {
                accumulate(&mut sum[x], &mut sum_sq[x], value.to_array());
                count[x] += 1;
            });
            let row_rays = accel::rays_traced() - rays_before;
            counts.rays.fetch_add(row_rays, Ordering::Relaxed);
            progress(w as u64 * indices.len() as u64);
        });
    // The twins: the same sample indices of their pixels, from the independent randomization.
    if let Some((twin_integrator, layout)) = twins {
        pass.twin_sum
            .par_chunks_mut(w)
            .zip(pass.twin_sum_sq.par_chunks_mut(w))
            .enumerate()
            .for_each(|(row, (sum, sum_sq))| {
                if cancelled() {
                    complete.store(false, Ordering::Relaxed);
                    return;
                }
                let rays_before = accel::rays_traced();
                let pixel = |j: usize| layout.pixel((row * w + j) as u32);
                let n = sum.len();
                twin_integrator.trace_row(n, &pixel, indices.clone(), counts, &mut |j, value| {
                    accumulate(&mut sum[j], &mut sum_sq[j], value.to_array());
                });
                let row_rays = accel::rays_traced() - rays_before;
                counts.rays.fetch_add(row_rays, Ordering::Relaxed);
            });
    }
    complete.into_inner()
}

/// Sample `index` of `pixel`, a non-finite value counted and replaced by zero.
fn sample(integrator: &Integrator, pixel: [u32; 2], index: u32, counts: &Counts) -> Vec3 {
    let value = integrator.sample_pixel(pixel, index);
    let _ = (pixel, index);
    finite(value, counts)
}

/// `value`, or zero (counted) where it is not finite.
fn finite(value: Vec3, counts: &Counts) -> Vec3 {
    if value.is_finite() {
        return value;
    }
    // Counted, not asserted: tests check the count is zero, and that it counts (tests/finite.rs).
    counts.non_finite.fetch_add(1, Ordering::Relaxed);
    Vec3::ZERO
}
