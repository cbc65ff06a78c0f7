//! The calibrated error estimate (twin pixels, `stratapt::film`) predicts the true error
//! of a render for every sampler: the mean of the film's variance channel is within 1.5× of the
//! measured mean squared error, averaged over seeds, on an analytic scene (a white furnace,
//! whose every pixel is known) and on the Cornell box against an independent-sampler reference
//! whose own (exactly estimated) variance is subtracted. The per-sample variance, the estimate
//! before calibration, fails the same check for the stratified and Sobol samplers.

mod common;

use common::{furnace_exact, furnace_toml, scene};
use std::path::Path;
use stratapt::cpu::render;
use stratapt::film::Film;
use stratapt::film::PEAK_REPLICAS;
use stratapt::import::scene_file::load;
use stratapt::scene::{FlatScene, RenderSettings, SamplerKind};

const FACTOR: f64 = 1.5;
const SEEDS: u32 = 4;

fn within(ratio: f64) -> bool {
    (1.0 / FACTOR..=FACTOR).contains(&ratio)
}

/// Mean over pixels and channels of the calibrated and of the per-sample variance.
fn predicted(film: &Film) -> (f64, f64) {
    let n = 3.0 * film.sum.len() as f64;
    let calibrated: f64 = film.variances().iter().flatten().sum::<f64>() / n;
    let per_sample: f64 = (0..film.sum.len())
        .map(|i| film.sample_variance_of_mean(i).iter().sum::<f64>())
        .sum::<f64>()
        / n;
    (calibrated, per_sample)
}

/// For every sampler: (measured MSE, calibrated prediction, per-sample prediction), each the
/// mean over seeds; `truth(i)` is pixel i's (value, variance of that value).
fn check(name: &str, scene: &FlatScene, spp: u32, truth: &dyn Fn(usize) -> ([f64; 3], [f64; 3])) {
    for sampler in SamplerKind::ALL {
        let (mut mse, mut calibrated, mut per_sample) = (0.0, 0.0, 0.0);
        for seed in 0..SEEDS {
            let settings = RenderSettings {
                pattern_spp: spp,
                sampler,
                seed,
                ..scene.settings
            };
            let (film, _) = render(scene, &settings, &|_| {}, None);
            let n = 3.0 * film.sum.len() as f64;
            for i in 0..film.sum.len() {
                let (value, variance) = truth(i);
                let m = film.mean(i);
                for c in 0..3 {
                    mse += ((m[c] - value[c]).powi(2) - variance[c]) / n / SEEDS as f64;
                }
            }
            let (c, p) = predicted(&film);
            calibrated += c / SEEDS as f64;
            per_sample += p / SEEDS as f64;
        }
        eprintln!(
            "{name} {sampler:<11}: MSE {mse:.3e}, calibrated {:.3}x, per-sample {:.3}x",
            calibrated / mse,
            per_sample / mse
        );
        assert!(
            within(calibrated / mse),
            "{name} {sampler}: calibrated {:.3}x",
            calibrated / mse
        );
        if sampler != SamplerKind::Independent {
            assert!(
                !within(per_sample / mse),
                "{name} {sampler}: per-sample {:.3}x passed",
                per_sample / mse
            );
        }
    }
}

#[test]
fn calibrated_on_an_analytic_furnace() {
    let furnace = scene("furnace", &furnace_toml(48, 8));
    let exact = furnace_exact(0.5, 8);
    check("furnace", &furnace, 32, &|_| ([exact; 3], [0.0; 3]));
}

#[test]
fn calibrated_on_the_cornell_box() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/cornell-box.toml");
    let mut cornell = load(&path).unwrap_or_else(|e| panic!("{e}"));
    (cornell.camera.width, cornell.camera.height) = (128, 128);
    // The reference: independent samples, whose per-sample variance is their error.
    let settings = RenderSettings {
        pattern_spp: 1024,
        sampler: SamplerKind::Independent,
        seed: 0xfeed,
        ..cornell.settings
    };
    let (reference, _) = render(&cornell, &settings, &|_| {}, None);
    check("cornell", &cornell, 16, &|i| {
        (reference.mean(i), reference.sample_variance_of_mean(i))
    });
}

/// A CPU render's peak twins are its pixels' samples from independent randomizations: at each
/// peak pixel, replicas 1 to 4 of the render's seed, the same samples as renders seeded as
/// those replicas are, at that pixel. On Veach's scene they go to the pixels that carry its
/// error (the largest per-sample variances, none a uniform twin).
#[test]
fn peak_twins_are_the_replica_randomizations_at_the_brightest_pixels() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/veach-mis.toml");
    let mut veach = load(&path).unwrap_or_else(|e| panic!("{e}"));
    (veach.camera.width, veach.camera.height) = (96, 72);
    let settings = RenderSettings {
        pattern_spp: 8,
        sampler: SamplerKind::Sobol,
        ..veach.settings
    };
    let (film, _) = render(&veach, &settings, &|_| {}, None);
    // 96 × 72 / (64 × 4) pixels, four twins each, pixel by pixel.
    assert_eq!(PEAK_REPLICAS, 4);
    assert_eq!(film.peaks.len(), 27 * 4);
    let pixels = film.peak_pixels();
    for (k, peak) in film.peaks.iter().enumerate() {
        assert_eq!(
            (peak.pixel, peak.replica),
            (pixels[k / 4], k as u32 % 4 + 1)
        );
    }
    // The same samples, summed in another order (the render adds passes of 4).
    let same = |a: [f64; 3], b: [f64; 3]| (0..3).all(|c| (a[c] - b[c]).abs() <= 1e-12 * b[c].abs());
    for r in 1..=PEAK_REPLICAS {
        let replica_settings = RenderSettings {
            seed: stratapt::sampling::replica::seed(settings.seed, r),
            calibrate: false,
            ..settings
        };
        let (replica, _) = render(&veach, &replica_settings, &|_| {}, None);
        for peak in film.peaks.iter().filter(|p| p.replica == r) {
            let i = replica.index(peak.pixel[0], peak.pixel[1]);
            assert!(
                same(peak.sum, replica.sum[i]) && same(peak.sum_sq, replica.sum_sq[i]),
                "{:?}, replica {r}: {:?} against {:?}",
                peak.pixel,
                (peak.sum, peak.sum_sq),
                (replica.sum[i], replica.sum_sq[i])
            );
        }
    }
}

/// Where rare bright samples carry the error (the rare-light floor: 16×16 pixels lit through a
/// bounce that finds a sphere light in about 0.3 % of its samples, 320 spp, 64 seeds), the
/// calibrated variance predicts every pixel's error: Σ predicted / Σ expected over the pixels
/// within 0.83–1.2, the expected error of a pixel being its variance over the seeds (no
/// reference needed). Measured 1.00 for both; classes keyed by a pixel's own variance, the
/// estimate before, predicted 0.81 (stratified) and fail it. The planted companion, the
/// prediction scaled by 0.8, must fail too.
#[test]
fn calibrated_variance_predicts_each_pixel_where_rare_samples_dominate() {
    let floor = scene("rare-light", &common::rare_light_toml(16));
    const RARE_SEEDS: usize = 64;
    for sampler in [SamplerKind::Stratified, SamplerKind::Sobol] {
        let pixels = floor.camera.width as usize * floor.camera.height as usize;
        let mut means = vec![[0.0; RARE_SEEDS]; pixels];
        let mut predicted = 0.0;
        for seed in 0..RARE_SEEDS {
            let settings = RenderSettings {
                sampler,
                seed: seed as u32,
                pattern_spp: 320,
                ..floor.settings
            };
            let (film, _) = render(&floor, &settings, &|_| {}, None);
            let variances = film.variances();
            for (i, pixel_means) in means.iter_mut().enumerate() {
                pixel_means[seed] = film.sum[i][0] / film.count[i] as f64;
                predicted += variances[i][0] / RARE_SEEDS as f64;
            }
        }
        let expected: f64 = means
            .iter()
            .map(|m| {
                let mean = m.iter().sum::<f64>() / RARE_SEEDS as f64;
                m.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (RARE_SEEDS - 1) as f64
            })
            .sum();
        let ratio = predicted / expected;
        eprintln!("{sampler}: Σ predicted / Σ expected over the pixels {ratio:.3}");
        let holds = |r: f64| (0.83..=1.2).contains(&r);
        assert!(holds(ratio), "{sampler}: {ratio:.3}");
        assert!(!holds(0.8 * ratio), "{sampler}: the planted 0.8× passed");
    }
}
