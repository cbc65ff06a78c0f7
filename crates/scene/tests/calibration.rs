//! The twin calibration of [`Film`] predicts the error of every sampler: each pixel of a film
//! estimates `∫₀¹ √(1−x²) dx = π/4` (1D) or `∫∫ √(1−x²) √(1−y²) = (π/4)²` (2D) from N samples
//! of its own randomization, its twin from the independent replica 1; the mean of the film's
//! calibrated variances is within 1.5× of the measured mean squared error. The per-sample
//! variance passes for the independent sampler only (for stratified and Sobol samples it
//! overstates the error tens of times) and the same check must reject it; so must it reject a
//! biased estimate (the tests of the test).

use std::f64::consts::FRAC_PI_4;
use stratapt_sampling::{replica, Sampler, SamplerKind};
use stratapt_scene::Film;

/// Film side (pixels = independent randomizations) and samples per pixel.
const SIDE: u32 = 64;
const N: u32 = 64;
/// Largest predicted/measured ratio (either way) allowed.
const FACTOR: f64 = 1.5;

type Integrand = fn(&Sampler, [u32; 2], u32) -> f32;

fn circle(x: f32) -> f32 {
    (1.0 - x * x).max(0.0).sqrt()
}

fn one_d(s: &Sampler, pixel: [u32; 2], i: u32) -> f32 {
    circle(s.sample_1d(pixel, i, 3))
}

fn two_d(s: &Sampler, pixel: [u32; 2], i: u32) -> f32 {
    let p = s.sample_2d(pixel, i, 5);
    circle(p.x) * circle(p.y)
}

/// A film of estimates of `f`, its twins sampled from replica 1.
fn film(kind: SamplerKind, f: Integrand) -> Film {
    let seed = 0xca1b;
    let (render, twin) = (
        Sampler::new(kind, N, seed),
        Sampler::new(kind, N, replica::seed(seed, 1)),
    );
    let mut film = Film::with_twins(SIDE, SIDE, true);
    for y in 0..SIDE {
        for x in 0..SIDE {
            for i in 0..N {
                film.add_sample(x, y, [f(&render, [x, y], i); 3]);
            }
        }
    }
    let layout = film.twin_layout();
    for k in 0..layout.count {
        let pixel = layout.pixel(k);
        for i in 0..N {
            film.add_twin_sample(k as usize, [f(&twin, pixel, i); 3]);
        }
    }
    film
}

/// (measured MSE against `truth`, mean calibrated variance, mean per-sample variance).
fn errors(film: &Film, truth: f64) -> [f64; 3] {
    let n = film.sum.len() as f64;
    let variances = film.variances();
    let mut e = [0.0; 3];
    for (i, variance) in variances.iter().enumerate() {
        e[0] += (film.mean(i)[0] - truth).powi(2) / n;
        e[1] += variance[0] / n;
        e[2] += film.sample_variance_of_mean(i)[0] / n;
    }
    e
}

fn within(ratio: f64) -> bool {
    (1.0 / FACTOR..=FACTOR).contains(&ratio)
}

#[test]
fn twin_calibrated_variance_predicts_the_error_of_every_sampler() {
    let cases: [(&str, Integrand, f64); 2] = [
        ("1D", one_d, FRAC_PI_4),
        ("2D", two_d, FRAC_PI_4 * FRAC_PI_4),
    ];
    for (name, f, truth) in cases {
        for kind in SamplerKind::ALL {
            let film = film(kind, f);
            let [mse, calibrated, per_sample] = errors(&film, truth);
            eprintln!(
                "{name} {kind:<11}: MSE {mse:.3e}, calibrated {:.3}x, per-sample {:.3}x",
                calibrated / mse,
                per_sample / mse
            );
            assert!(
                within(calibrated / mse),
                "{name} {kind}: calibrated {:.3}x the MSE",
                calibrated / mse
            );
            let independent = kind == SamplerKind::Independent;
            assert_eq!(
                within(per_sample / mse),
                independent,
                "{name} {kind}: per-sample {:.3}x",
                per_sample / mse
            );
        }
    }
}

#[test]
fn calibration_check_rejects_a_biased_estimate() {
    // A bias of one RMS error doubles the true MSE; the twins cannot see it, so the prediction
    // must fail the check.
    let film = film(SamplerKind::Sobol, one_d);
    let [mse, ..] = errors(&film, FRAC_PI_4);
    let [biased, calibrated, _] = errors(&film, FRAC_PI_4 + mse.sqrt());
    assert!(within(calibrated / mse));
    assert!(
        !within(calibrated / biased),
        "{:.3}x passed",
        calibrated / biased
    );
}

#[test]
fn identical_twins_mean_no_error() {
    // A twin that repeats its pixel's samples exactly: κ = 0, so no variance is predicted. The
    // calibration reads the twins, not the per-sample variance alone.
    let mut film = Film::with_twins(16, 16, true);
    let layout = film.twin_layout();
    let value = |x: u32, y: u32, i: u32| [(x * 7 + y * 3 + i) as f32 * 0.1; 3];
    for y in 0..16 {
        for x in 0..16 {
            for i in 0..8 {
                film.add_sample(x, y, value(x, y, i));
            }
        }
    }
    for k in 0..layout.count {
        let [x, y] = layout.pixel(k);
        for i in 0..8 {
            film.add_twin_sample(k as usize, value(x, y, i));
        }
    }
    assert_eq!(film.calibration().film, [0.0; 3]);
    assert!(film.variances().iter().all(|v| *v == [0.0; 3]));
    assert!(film.sample_variance_of_mean(0)[0] > 0.0);
}
