//! Progressive renders (`render_progressive`): to a target error on an analytic scene (a white
//! furnace), they stop with a true error within the target at the stated confidence, no later
//! than one batch after the estimate first meets it; to a time limit, on a simulated clock,
//! exactly where the time per sample says the next sample would not fit, and past the limit by
//! at most one batch when the renderer slows down.

mod common;

use common::{furnace_exact, furnace_toml, rare_light_exact, rare_light_toml, scene};
use std::cell::{Cell, RefCell};
use std::sync::atomic::AtomicBool;
use std::time::Duration;
use stratapt::cpu::CpuRenderer;
use stratapt::film::render::progressive::{
    render_progressive, render_progressive_with_clock, settings_for, Clock, ErrorMetric,
    Progressive, StopRule, Stopped, MIN_SPP_FOR_TARGET,
};
use stratapt::film::render::Progress;
use stratapt::film::{Film, Render, RenderError, RenderStats};
use stratapt::scene::{FlatScene, RenderSettings, SamplerKind};

fn exact() -> f64 {
    furnace_exact(0.5, 8)
}

fn relative_error(film: &Film) -> f64 {
    let (mean, _) = film.image_mean();
    (mean.iter().sum::<f64>() / 3.0 - exact()).abs() / exact()
}

/// `scene` rendered on the CPU reference until `stop` says so.
fn on_cpu(scene: &FlatScene, settings: &RenderSettings, stop: &StopRule) -> Progressive {
    render_progressive(&CpuRenderer, scene, settings, stop, &|_| {}, None).unwrap()
}

const TARGET: f64 = 0.002;
const SEEDS: u32 = 8;

#[test]
fn target_error_stops_within_the_target_and_no_later_than_one_batch() {
    let furnace = scene("furnace", &furnace_toml(16, 8));
    let stop = StopRule {
        max_spp: 1 << 14,
        target_error: Some((TARGET, ErrorMetric::ImageMean)),
        time_limit: None,
    };
    for sampler in SamplerKind::ALL {
        let mut sum_sq = 0.0;
        for seed in 0..SEEDS {
            let settings = RenderSettings {
                sampler,
                seed,
                ..furnace.settings
            };
            let done = on_cpu(&furnace, &settings, &stop);
            let label = format!("{sampler} seed {seed}");
            assert_eq!(done.stopped, Stopped::TargetError, "{label}");
            let estimated = ErrorMetric::ImageMean.of(&done.film);
            assert!(estimated <= TARGET, "{label}: estimate {estimated}");
            // True error: within 3.3 targets (99.9 % for a normal estimate at the target).
            let truth = relative_error(&done.film);
            assert!(
                truth <= 3.3 * TARGET,
                "{label}: true relative error {truth:.2e}"
            );
            sum_sq += truth * truth;
            // No overshoot: the same samples without the last batch had not reached it, or
            // were fewer than the minimum a target stop needs.
            let spp = done.film.held_spp();
            let before = spp - done.last_batch;
            // Batches at most double the film.
            assert!(
                done.last_batch <= before,
                "{label}: last batch {}",
                done.last_batch
            );
            assert!(spp >= MIN_SPP_FOR_TARGET, "{label}: stopped at {spp} spp");
            if before < MIN_SPP_FOR_TARGET {
                assert_eq!(spp, MIN_SPP_FOR_TARGET, "{label}");
                continue;
            }
            let mut film = Film::with_twins(16, 16, settings.twins());
            let render_settings = settings_for(&settings, &stop);
            CpuRenderer
                .render_into(&furnace, &render_settings, &mut film, before, &|_| {}, None)
                .unwrap();
            let earlier = ErrorMetric::ImageMean.of(&film);
            assert!(
                earlier > TARGET,
                "{label}: {before} spp already had {earlier:.2e} ≤ {TARGET} (stopped at {spp})"
            );
        }
        // Calibrated: the RMS true error over the seeds is about the target, not far beyond.
        let rms = (sum_sq / SEEDS as f64).sqrt();
        eprintln!("{sampler}: RMS true relative error {rms:.2e} at target {TARGET}");
        assert!(rms <= 1.5 * TARGET, "{sampler}: RMS true error {rms:.2e}");
    }
}

/// Seeds per sampler of the rare-light target test.
const RARE_SEEDS: u32 = 64;
/// The 99.9 % quantile of χ² with 64 degrees of freedom over 64 (Wilson–Hilferty): a mean of
/// 64 squared normal errors of RMS σ exceeds σ² times this in one case in 1000.
const CHI2_64_999: f64 = 1.637;

/// `--target-error` where the error comes from rare bright samples (the rare-light floor, the
/// image mean to 4 %): over 64 seeds per sampler, the true error where the render stopped is at
/// most the target in RMS, tested at 99.9 %: the mean squared error may exceed target² only by
/// the χ² quantile, RMS 1.28× (16 seeds would allow 1.57×). Measured: RMS 0.96–1.08× the target
/// (see the output). Its planted companion stops at twice the target, as an estimate half as
/// large as it should be would, and must be rejected.
#[test]
fn target_error_holds_in_rms_where_rare_bright_samples_dominate() {
    let floor = scene("rare-light", &rare_light_toml(16));
    let exact = rare_light_exact(&floor);
    let target = 0.04;
    let bound = target * CHI2_64_999.sqrt();
    let rms_at = |asked: f64, sampler: SamplerKind| {
        let stop = StopRule {
            max_spp: 1 << 16,
            target_error: Some((asked, ErrorMetric::ImageMean)),
            time_limit: None,
        };
        let mut sum_sq = 0.0;
        let mut spp = Vec::new();
        for seed in 0..RARE_SEEDS {
            let settings = RenderSettings {
                sampler,
                seed,
                ..floor.settings
            };
            let done = on_cpu(&floor, &settings, &stop);
            assert_eq!(done.stopped, Stopped::TargetError, "{sampler} seed {seed}");
            let (mean, _) = done.film.image_mean();
            let truth = (mean.iter().sum::<f64>() / 3.0 - exact) / exact;
            sum_sq += truth * truth;
            spp.push(done.film.held_spp());
        }
        let rms = (sum_sq / RARE_SEEDS as f64).sqrt();
        spp.sort();
        eprintln!(
            "{sampler}, stopped at {asked}: RMS true error {:.2}× the target {target} \
             (spp {}–{})",
            rms / target,
            spp[0],
            spp[spp.len() - 1]
        );
        rms
    };
    for sampler in SamplerKind::ALL {
        let rms = rms_at(target, sampler);
        assert!(
            rms <= bound,
            "{sampler}: RMS true error {rms:.4} > {bound:.4}"
        );
        let planted = rms_at(2.0 * target, sampler);
        assert!(
            planted > bound,
            "{sampler}: stopping at twice the target passed ({planted:.4} ≤ {bound:.4})"
        );
    }
}

/// A render to a target error never stops before [`MIN_SPP_FOR_TARGET`] samples per pixel,
/// even where its estimate meets the target at once; below that cap it stops at the cap.
#[test]
fn target_error_stops_no_earlier_than_its_minimum_samples() {
    let furnace = scene("furnace", &furnace_toml(16, 8));
    let loose = |max_spp| StopRule {
        max_spp,
        target_error: Some((0.5, ErrorMetric::ImageMean)),
        time_limit: None,
    };
    let done = on_cpu(&furnace, &furnace.settings, &loose(1 << 14));
    assert_eq!(done.stopped, Stopped::TargetError);
    assert_eq!(done.film.held_spp(), MIN_SPP_FOR_TARGET);
    let capped = on_cpu(&furnace, &furnace.settings, &loose(12));
    assert_eq!(capped.stopped, Stopped::MaxSpp);
    assert_eq!(capped.film.held_spp(), 12);
}

#[test]
fn pixel_metric_target_is_met_per_pixel() {
    let furnace = scene("furnace", &furnace_toml(16, 8));
    let stop = StopRule {
        max_spp: 1 << 14,
        target_error: Some((0.02, ErrorMetric::PixelP95)),
        time_limit: None,
    };
    let done = on_cpu(&furnace, &furnace.settings, &stop);
    assert_eq!(done.stopped, Stopped::TargetError);
    assert!(done.film.relative_error().pixel_p95 <= 0.02);
    // The image mean is then far better than 2 %.
    assert!(relative_error(&done.film) < 0.01);
}

#[test]
fn spp_cap_wins_over_an_unreachable_target() {
    let furnace = scene("furnace", &furnace_toml(16, 8));
    let stop = StopRule {
        max_spp: 24,
        target_error: Some((1e-6, ErrorMetric::ImageMean)),
        time_limit: None,
    };
    let done = on_cpu(&furnace, &furnace.settings, &stop);
    assert_eq!(done.stopped, Stopped::MaxSpp);
    assert_eq!(done.film.held_spp(), 24);
}

// ---------------------------------------------------------------------------------------------
// To a time limit, on a simulated clock: where the render stops is exactly predictable
// ---------------------------------------------------------------------------------------------

/// A clock that moves only when [`Timed`] says a batch took time.
#[derive(Default)]
struct FakeClock(Cell<Duration>);

impl Clock for FakeClock {
    fn now(&self) -> Duration {
        self.0.get()
    }
}

/// The CPU reference, each batch taking `cost_per_spp(start of the batch) × spp` of the fake
/// clock's time; it records the batch sizes.
struct Timed<'a> {
    clock: &'a FakeClock,
    cost_per_spp: fn(Duration) -> Duration,
    batches: RefCell<Vec<u32>>,
}

impl Render for Timed<'_> {
    fn render_into(
        &self,
        scene: &FlatScene,
        settings: &RenderSettings,
        film: &mut Film,
        spp: u32,
        progress: Progress,
        cancel: Option<&AtomicBool>,
    ) -> Result<RenderStats, RenderError> {
        let stats = CpuRenderer.render_into(scene, settings, film, spp, progress, cancel)?;
        let now = self.clock.now();
        self.clock.0.set(now + (self.cost_per_spp)(now) * spp);
        self.batches.borrow_mut().push(spp);
        Ok(stats)
    }

    fn describe(&self) -> String {
        "CPU reference on a simulated clock".into()
    }
}

/// The furnace rendered to `limit` by a renderer costing `cost_per_spp`; also the batch sizes.
fn to_time_limit(
    limit: Duration,
    cost_per_spp: fn(Duration) -> Duration,
) -> (Progressive, Vec<u32>) {
    let furnace = scene("furnace", &furnace_toml(16, 8));
    let stop = StopRule {
        max_spp: 1 << 20,
        target_error: None,
        time_limit: Some(limit),
    };
    let clock = FakeClock::default();
    let timed = Timed {
        clock: &clock,
        cost_per_spp,
        batches: RefCell::new(Vec::new()),
    };
    let done = render_progressive_with_clock(
        &timed,
        &furnace,
        &furnace.settings,
        &stop,
        &|_| {},
        None,
        &clock,
    )
    .unwrap();
    (done, timed.batches.into_inner())
}

/// 1/128 s per sample per pixel (exact in binary, so the arithmetic below is exact).
const SPP_COST: Duration = Duration::from_nanos(7_812_500);

/// At a steady time per sample, batches double from 4 until the time left holds fewer samples
/// than the film, then take exactly what fits: 190 spp of 1/128 s end at 1.484375 s, before a
/// limit of 1.49 s that a 191st would pass.
#[test]
fn time_limit_stops_where_the_time_per_sample_says_the_next_sample_would_not_fit() {
    let limit = Duration::from_millis(1490);
    let (done, batches) = to_time_limit(limit, |_| SPP_COST);
    assert_eq!(done.stopped, Stopped::TimeLimit);
    assert_eq!(batches, [4, 4, 8, 16, 32, 64, 62]);
    assert_eq!(done.film.held_spp(), 190);
    assert_eq!(done.last_batch, 62);
    assert_eq!(done.seconds, 190.0 / 128.0);
    assert_eq!(done.last_batch_seconds, 62.0 / 128.0);
    // Never past the limit, and short of it by less than one more sample.
    let (limit, cost) = (limit.as_secs_f64(), SPP_COST.as_secs_f64());
    assert!(done.seconds <= limit && done.seconds + cost > limit);
}

/// When the renderer slows down (4× after 1 s), the batch sized from the faster past runs past
/// the limit; the render then stops at once, past the limit by less than that one batch.
#[test]
fn time_limit_is_passed_by_at_most_the_batch_that_ran_slow() {
    let limit = Duration::from_millis(1490);
    let slows_down = |now: Duration| {
        if now < Duration::from_secs(1) {
            SPP_COST
        } else {
            SPP_COST * 4
        }
    };
    let (done, batches) = to_time_limit(limit, slows_down);
    assert_eq!(done.stopped, Stopped::TimeLimit);
    assert_eq!(batches, [4, 4, 8, 16, 32, 64, 62]);
    // 128 spp in 1 s, then 62 spp at 4/128 s: 1 + 248/128 s.
    assert_eq!(done.seconds, 1.0 + 248.0 / 128.0);
    let limit = limit.as_secs_f64();
    assert!(done.seconds > limit);
    assert!(done.seconds - done.last_batch_seconds <= limit);
}

/// On the wall clock (the default): the render stops at the time limit after at least its first
/// batch. Nothing here depends on how long anything takes.
#[test]
fn time_limit_on_the_wall_clock_stops_the_render() {
    let furnace = scene("furnace", &furnace_toml(16, 8));
    let stop = StopRule {
        max_spp: 1 << 20,
        target_error: None,
        time_limit: Some(Duration::from_millis(50)),
    };
    let done = on_cpu(&furnace, &furnace.settings, &stop);
    assert_eq!(done.stopped, Stopped::TimeLimit);
    assert!(done.film.held_spp() >= 4 && done.last_batch >= 1);
}
