//! Progressive rendering: keep adding batches of samples to one [`Film`] until its calibrated
//! error reaches a target, a time limit runs out, or a sample cap is met. Time is read from a
//! [`Clock`]: wall time unless the caller passes another (tests pass a simulated one).

use super::{Progress, Render, RenderError, RenderStats};
use crate::Film;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};
use stratapt_scene::{FlatScene, RenderSettings};

/// Which estimated relative standard error a target applies to ([`Film::relative_error`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum ErrorMetric {
    /// The image mean's.
    #[default]
    ImageMean,
    /// The 95th percentile of the pixels'.
    PixelP95,
}

impl ErrorMetric {
    pub const ALL: [ErrorMetric; 2] = [Self::ImageMean, Self::PixelP95];

    /// The name on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Self::ImageMean => "image-mean",
            Self::PixelP95 => "pixel-p95",
        }
    }

    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|m| m.name() == name)
    }

    /// This metric's value for `film`.
    pub fn of(self, film: &Film) -> f64 {
        let e = film.relative_error();
        match self {
            Self::ImageMean => e.image_mean,
            Self::PixelP95 => e.pixel_p95,
        }
    }
}

impl std::fmt::Display for ErrorMetric {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// When a progressive render stops: at the first of these that is met.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StopRule {
    /// Most samples per pixel.
    pub max_spp: u32,
    /// Stop once this relative standard error is reached.
    pub target_error: Option<(f64, ErrorMetric)>,
    /// Stop before a batch would end past this much time (by the render's [`Clock`]: wall time
    /// unless the caller passes another), as far as the time per sample so far predicts.
    pub time_limit: Option<Duration>,
}

impl StopRule {
    /// Whether the render's length is not known in advance: it stops at an error or a time, not
    /// only at the sample cap.
    pub fn open_ended(&self) -> bool {
        self.target_error.is_some() || self.time_limit.is_some()
    }
}

/// Why a progressive render stopped.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stopped {
    /// The sample cap was reached.
    MaxSpp,
    /// The target error was reached.
    TargetError,
    /// Another batch would not fit in the time left.
    TimeLimit,
    /// The cancel flag was set.
    Cancelled,
}

/// What [`render_progressive`] produced.
pub struct Progressive {
    pub film: Film,
    pub stats: RenderStats,
    pub stopped: Stopped,
    /// Samples per pixel of the last batch: the granularity of the stop.
    pub last_batch: u32,
    /// Seconds of the whole render and of its last batch, by the render's [`Clock`].
    pub seconds: f64,
    pub last_batch_seconds: f64,
}

/// The time a progressive render goes by: time since an origin of the clock's choosing, never
/// decreasing. [`WallClock`] is the real one; a test passes a clock it advances itself, so that
/// where a render to a time limit stops is exactly predictable.
pub trait Clock {
    /// The time now, since the clock's origin.
    fn now(&self) -> Duration;
}

/// Wall time since the clock was made (monotonic: [`Instant`]).
#[derive(Clone, Copy, Debug)]
pub struct WallClock(Instant);

impl WallClock {
    pub fn new() -> Self {
        Self(Instant::now())
    }
}

impl Default for WallClock {
    fn default() -> Self {
        Self::new()
    }
}

impl Clock for WallClock {
    fn now(&self) -> Duration {
        self.0.elapsed()
    }
}

/// Samples per pixel of the first batch of a render to an error or a time.
const FIRST_BATCH: u32 = 4;
/// The fewest samples per pixel a render may stop at for reaching a target error (short of
/// the cap): one whole pattern of the stratified sampler's open-ended strata and of Sobol's
/// first points. Before it the estimate rests on too few samples of a pixel to have seen its
/// rare bright paths, and renders that stopped sooner erred by several times their estimate
/// (docs/measurements/error-estimate-honesty.md, "--target-error where rare bright samples
/// dominate").
pub const MIN_SPP_FOR_TARGET: u32 = 64;
/// The stratified sampler's strata in a render to an error or a time (the total is not known in
/// advance; every pass of that many samples is one stratified pattern).
pub const OPEN_ENDED_STRATA: u32 = 64;

/// The render settings a progressive render under `stop` passes to the renderer: `pattern_spp`
/// (which sizes the stratified sampler's strata) is the cap for a render that only has one, else
/// [`OPEN_ENDED_STRATA`], at most the cap.
pub fn settings_for(settings: &RenderSettings, stop: &StopRule) -> RenderSettings {
    RenderSettings {
        pattern_spp: if stop.open_ended() {
            OPEN_ENDED_STRATA.min(stop.max_spp)
        } else {
            stop.max_spp
        },
        ..*settings
    }
}

/// Render `scene` in batches until `stop` says so. The first batch has `FIRST_BATCH`
/// samples per pixel; each next one at most doubles the film and aims at the target, from the
/// error measured so far and plain Monte Carlo's `1/√N` rate (conservative for stratified and
/// Sobol samples, whose error falls faster), or at the time left, from the time per sample so
/// far. A film without pixels is returned at once. Time is wall time
/// ([`render_progressive_with_clock`] takes another clock).
pub fn render_progressive(
    renderer: &dyn Render,
    scene: &FlatScene,
    settings: &RenderSettings,
    stop: &StopRule,
    progress: Progress,
    cancel: Option<&AtomicBool>,
) -> Result<Progressive, RenderError> {
    let clock = WallClock::new();
    render_progressive_with_clock(renderer, scene, settings, stop, progress, cancel, &clock)
}

/// [`render_progressive`] with time read from `clock`: the time limit, the time per sample that
/// sizes the batches, and the seconds reported.
pub fn render_progressive_with_clock(
    renderer: &dyn Render,
    scene: &FlatScene,
    settings: &RenderSettings,
    stop: &StopRule,
    progress: Progress,
    cancel: Option<&AtomicBool>,
    clock: &dyn Clock,
) -> Result<Progressive, RenderError> {
    let start = clock.now();
    let settings = settings_for(settings, stop);
    let (w, h) = (scene.camera.width, scene.camera.height);
    let mut film = Film::for_render(scene, &settings);
    let mut stats = RenderStats::default();
    // A render with only a cap is one batch (the renderer batches inside it).
    let mut next = if stop.open_ended() {
        FIRST_BATCH.min(stop.max_spp)
    } else {
        stop.max_spp
    };
    let mut last_batch = 0;
    let mut last_batch_seconds = 0.0;
    let stopped = loop {
        if w == 0 || h == 0 {
            break Stopped::MaxSpp;
        }
        let done = film.held_spp();
        if done >= stop.max_spp {
            break Stopped::MaxSpp;
        }
        if cancel.is_some_and(|c| c.load(Ordering::Relaxed)) {
            break Stopped::Cancelled;
        }
        let n = next.min(stop.max_spp - done).max(1);
        let batch_start = clock.now();
        let batch = renderer.render_into(scene, &settings, &mut film, n, progress, cancel)?;
        stats.add(&batch);
        if batch.cancelled {
            break Stopped::Cancelled;
        }
        let now = clock.now();
        last_batch = n;
        last_batch_seconds = now.saturating_sub(batch_start).as_secs_f64();
        let done = film.held_spp();
        let elapsed = now.saturating_sub(start);
        // ---- The target error, measured on the film so far -----------------------------------
        let mut want = done; // at most double
        if let Some((target, metric)) = stop.target_error {
            let error = metric.of(&film);
            if error <= target && done >= MIN_SPP_FOR_TARGET {
                break Stopped::TargetError;
            }
            let needed = (done as f64 * (error / target).powi(2)).max(MIN_SPP_FOR_TARGET as f64);
            want = want.min((needed.ceil() as u64).saturating_sub(done as u64) as u32);
        }
        // ---- The time left, at the time per sample so far --------------------------------------
        if let Some(limit) = stop.time_limit {
            let per_spp = elapsed.as_secs_f64() / done as f64;
            let left = limit.as_secs_f64() - elapsed.as_secs_f64();
            let fits = (left / per_spp.max(1e-12))
                .floor()
                .max(0.0)
                .min(u32::MAX as f64) as u32;
            if fits == 0 {
                break Stopped::TimeLimit;
            }
            want = want.min(fits);
        }
        next = want.max(1);
    };
    Ok(Progressive {
        film,
        stats,
        stopped,
        last_batch,
        seconds: clock.now().saturating_sub(start).as_secs_f64(),
        last_batch_seconds,
    })
}
