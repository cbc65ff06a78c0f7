//! Measures how well strata's error estimate predicts the true error, and what its twin pixels
//! cost, on a scene against a high-spp reference, on the CPU reference renderer:
//!
//! ```text
//! cargo run --release --example calibration -- [SCENE.toml] [SIZE] [SPP] [SEEDS] [REF_SPP]
//! ```
//!
//! For every sampler: the true MSE of an SPP-sample render (mean over pixels and channels of
//! (x − ref)², less the reference's own variance), the predicted MSE (mean of the film's
//! variance channel) over the measured one, with the twin calibration and without it (the
//! per-sample variance), and the render time with and without twins; averaged over SEEDS seeds.
//! The reference is an independent-sampler render (whose per-sample variance is exact) at
//! REF_SPP.

use std::path::PathBuf;
use stratapt::cpu::render;
use stratapt::film::Film;
use stratapt::import::scene_file::load;
use stratapt::scene::{RenderSettings, SamplerKind};

fn mean_variance(film: &Film) -> f64 {
    (0..film.sum.len())
        .map(|i| film.sample_variance_of_mean(i).iter().sum::<f64>() / 3.0)
        .sum::<f64>()
        / film.sum.len() as f64
}

fn mean_calibrated_variance(film: &Film) -> f64 {
    film.variances()
        .iter()
        .map(|v| v.iter().sum::<f64>() / 3.0)
        .sum::<f64>()
        / film.sum.len() as f64
}

fn squared_error(film: &Film, reference: &Film) -> f64 {
    (0..film.sum.len())
        .map(|i| {
            let (a, b) = (film.mean(i), reference.mean(i));
            (0..3).map(|c| (a[c] - b[c]).powi(2)).sum::<f64>() / 3.0
        })
        .sum::<f64>()
        / film.sum.len() as f64
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let path = PathBuf::from(args.first().map_or("scenes/cornell-box.toml", |s| s));
    let size: u32 = args.get(1).map_or(Ok(64), |s| s.parse())?;
    let spp: u32 = args.get(2).map_or(Ok(64), |s| s.parse())?;
    let seeds: u32 = args.get(3).map_or(Ok(4), |s| s.parse())?;
    let ref_spp: u32 = args.get(4).map_or(Ok(4096), |s| s.parse())?;
    let mut scene = load(&path)?;
    (scene.camera.width, scene.camera.height) = (size, size);

    let start = std::time::Instant::now();
    let reference_settings = RenderSettings {
        pattern_spp: ref_spp,
        sampler: SamplerKind::Independent,
        seed: 0xfeed,
        calibrate: false,
        ..scene.settings
    };
    let (reference, _) = render(&scene, &reference_settings, &|_| {}, None);
    let ref_var = mean_variance(&reference);
    eprintln!(
        "reference: {} at {size}², {ref_spp} spp independent in {:.1} s; its own MSE {ref_var:.3e}",
        path.display(),
        start.elapsed().as_secs_f64()
    );
    println!(
        "| sampler | true MSE | predicted / true, calibrated | predicted / true, per-sample | time with twins / without |"
    );
    println!("|---|---|---|---|---|");
    for sampler in SamplerKind::ALL {
        let (mut mse, mut calibrated, mut per_sample) = (0.0, 0.0, 0.0);
        let (mut with, mut without) = (0.0, 0.0);
        for seed in 0..seeds {
            let mut films = Vec::new();
            for calibrate in [false, true] {
                let settings = RenderSettings {
                    pattern_spp: spp,
                    sampler,
                    seed,
                    calibrate,
                    ..scene.settings
                };
                let start = std::time::Instant::now();
                let (film, _) = render(&scene, &settings, &|_| {}, None);
                *(if calibrate { &mut with } else { &mut without }) +=
                    start.elapsed().as_secs_f64();
                films.push(film);
            }
            let (plain, twinned) = (&films[0], &films[1]);
            assert_eq!(plain.sum, twinned.sum, "twins must not change the image");
            mse += (squared_error(twinned, &reference) - ref_var) / seeds as f64;
            calibrated += mean_calibrated_variance(twinned) / seeds as f64;
            per_sample += mean_variance(twinned) / seeds as f64;
        }
        println!(
            "| {sampler} | {mse:.3e} | {:.3} | {:.3} | {:.3} |",
            calibrated / mse,
            per_sample / mse,
            with / without
        );
    }
    Ok(())
}
