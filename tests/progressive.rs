//! Progressive renders (`render_progressive`): to a target error on an analytic scene (a white
//! furnace), they stop with a true error within the target at the stated confidence, no later
//! than one batch after the estimate first meets it; to a time limit, within one batch of it.

mod common;

use common::{furnace_exact, furnace_toml, scene};
use std::time::Duration;
use stratapt::cpu::CpuRenderer;
use stratapt::scene::render::progressive::{
    render_progressive, settings_for, ErrorMetric, Progressive, StopRule, Stopped,
};
use stratapt::scene::{Film, FlatScene, Render, RenderSettings, SamplerKind};

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
            // No overshoot: the same samples without the last batch had not reached it.
            let spp = done.film.spp();
            let before = spp - done.last_batch;
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
            // Batches at most double the film.
            assert!(
                done.last_batch <= before,
                "{label}: last batch {}",
                done.last_batch
            );
        }
        // Calibrated: the RMS true error over the seeds is about the target, not far beyond.
        let rms = (sum_sq / SEEDS as f64).sqrt();
        eprintln!("{sampler}: RMS true relative error {rms:.2e} at target {TARGET}");
        assert!(rms <= 1.5 * TARGET, "{sampler}: RMS true error {rms:.2e}");
    }
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
    assert_eq!(done.film.spp(), 24);
}

#[test]
fn time_limit_stops_within_one_batch_of_it() {
    let mut furnace = scene("furnace", &furnace_toml(16, 8));
    (furnace.camera.width, furnace.camera.height) = (64, 64);
    let limit = Duration::from_millis(1500);
    let stop = StopRule {
        max_spp: 1 << 20,
        target_error: None,
        time_limit: Some(limit),
    };
    let done = on_cpu(&furnace, &furnace.settings, &stop);
    assert_eq!(done.stopped, Stopped::TimeLimit);
    let limit = limit.as_secs_f64();
    eprintln!(
        "time limit {limit} s: stopped at {:.3} s, {} spp, last batch {} spp in {:.3} s",
        done.seconds,
        done.film.spp(),
        done.last_batch,
        done.last_batch_seconds
    );
    // Never past the limit by more than a batch, never short of it by more than two (the next
    // batch, sized from the time per sample so far, did not fit).
    let batch = done.last_batch_seconds;
    assert!(done.seconds <= limit + batch, "{} s", done.seconds);
    assert!(
        done.seconds >= limit - 2.0 * batch - 0.05,
        "{} s",
        done.seconds
    );
}
