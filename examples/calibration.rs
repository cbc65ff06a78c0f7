//! Measures what the replica error estimate costs and how well it predicts the error, on a
//! scene against a high-spp reference, on the CPU reference renderer:
//!
//! ```text
//! cargo run --release --example calibration -- [SCENE.toml] [SIZE] [SPP] [SEEDS] [REF_SPP]
//! ```
//!
//! For every sampler and replica count R ∈ {1, 2, 4, 8}: the true MSE of an SPP-sample render
//! (mean over pixels and channels of (x − ref)², less the reference's own variance), its ratio
//! to the R = 1 render's (the cost of splitting), and the predicted MSE (mean of the film's
//! variance channel) over the measured one, each averaged over SEEDS seeds. The reference is an
//! independent-sampler render (whose per-sample variance is exact) at REF_SPP.

use std::path::PathBuf;
use stratapt::cpu::render_with_stats;
use stratapt::scene::{load::load, Film, RenderSettings, SamplerKind};

fn mean_variance(film: &Film) -> f64 {
    (0..film.sum.len())
        .map(|i| film.variance_of_mean(i).iter().sum::<f64>() / 3.0)
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
        spp: ref_spp,
        sampler: SamplerKind::Independent,
        seed: 0xfeed,
        replicas: 1,
        ..scene.settings
    };
    let (reference, _) = render_with_stats(&scene, &reference_settings, &|_| {}, None);
    let ref_var = mean_variance(&reference);
    eprintln!(
        "reference: {} at {size}², {ref_spp} spp independent in {:.1} s; its own MSE {ref_var:.3e}",
        path.display(),
        start.elapsed().as_secs_f64()
    );
    println!("| sampler | R | true MSE | MSE / MSE(R=1) | predicted / true |");
    println!("|---|---|---|---|---|");
    for sampler in SamplerKind::ALL {
        let mut base = None;
        for replicas in [1, 2, 4, 8] {
            let (mut mse, mut predicted) = (0.0, 0.0);
            for seed in 0..seeds {
                let settings = RenderSettings {
                    spp,
                    sampler,
                    seed,
                    replicas,
                    ..scene.settings
                };
                let (film, _) = render_with_stats(&scene, &settings, &|_| {}, None);
                mse += (squared_error(&film, &reference) - ref_var) / seeds as f64;
                predicted += mean_variance(&film) / seeds as f64;
            }
            let base_mse = *base.get_or_insert(mse);
            println!(
                "| {sampler} | {replicas} | {mse:.3e} | {:.3} | {:.3} |",
                mse / base_mse,
                predicted / mse
            );
        }
    }
    Ok(())
}
