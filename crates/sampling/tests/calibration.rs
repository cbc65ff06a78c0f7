//! The replica error estimate is calibrated for every sampler: on `∫₀¹ √(1−x²) dx = π/4` (1D)
//! and `∫∫ √(1−x²) √(1−y²) = (π/4)²` (2D), the mean over many independently scrambled pixels
//! of the predicted variance of an N-sample estimate (the spread of its replica means) is within
//! 1.5× of its measured mean squared error. The per-sample variance `s²/N` passes for the
//! independent sampler only: for stratified and Sobol samples it overstates the error many
//! times, and the same check must reject it (the test of the test).

use std::f64::consts::FRAC_PI_4;
use stratapt_sampling::replica::split;
use stratapt_sampling::{ReplicatedSampler, SamplerKind};

/// Pixels (independent randomizations of the whole estimate).
const PIXELS: u32 = 4096;
/// Samples per estimate, and the replicas they are split into.
const N: u32 = 64;
const REPLICAS: u32 = 4;
/// Largest predicted/measured ratio (either way) the calibration allows.
const FACTOR: f64 = 1.5;

/// For every pixel, one N-sample estimate of `f`: (squared error, replica-predicted variance,
/// per-sample-predicted variance), averaged over the pixels.
fn calibration(kind: SamplerKind, f: &dyn Fn(&ReplicatedSampler, [u32; 2], u32) -> f64, truth: f64) -> [f64; 3] {
    let sampler = ReplicatedSampler::new(kind, N, 0xca1b, REPLICAS);
    let mut totals = [0.0; 3];
    for p in 0..PIXELS {
        let pixel = [p % 64, p / 64];
        let mut replica_sum = [0.0; REPLICAS as usize];
        let (mut sum, mut sum_sq) = (0.0, 0.0);
        for i in 0..N {
            let v = f(&sampler, pixel, i);
            replica_sum[split(i, REPLICAS).0 as usize] += v;
            sum += v;
            sum_sq += v * v;
        }
        let n = N as f64;
        let mean = sum / n;
        let per_replica = n / REPLICAS as f64;
        let means = replica_sum.map(|s| s / per_replica);
        let avg = means.iter().sum::<f64>() / REPLICAS as f64;
        let spread = means.iter().map(|m| (m - avg).powi(2)).sum::<f64>();
        let replica_var = spread / (REPLICAS * (REPLICAS - 1)) as f64;
        let sample_var = (sum_sq - n * mean * mean) / (n - 1.0) / n;
        totals[0] += (mean - truth).powi(2);
        totals[1] += replica_var;
        totals[2] += sample_var;
    }
    totals.map(|t| t / PIXELS as f64)
}

fn circle(x: f32) -> f64 {
    (1.0 - (x as f64).powi(2)).max(0.0).sqrt()
}

fn one_d(s: &ReplicatedSampler, pixel: [u32; 2], i: u32) -> f64 {
    circle(s.sample_1d(pixel, i, 3))
}

fn two_d(s: &ReplicatedSampler, pixel: [u32; 2], i: u32) -> f64 {
    let p = s.sample_2d(pixel, i, 5);
    circle(p.x) * circle(p.y)
}

fn within(ratio: f64) -> bool {
    (1.0 / FACTOR..=FACTOR).contains(&ratio)
}

#[test]
fn replica_variance_is_calibrated_for_every_sampler() {
    let cases: [(&str, &dyn Fn(&ReplicatedSampler, [u32; 2], u32) -> f64, f64); 2] =
        [("1D", &one_d, FRAC_PI_4), ("2D", &two_d, FRAC_PI_4 * FRAC_PI_4)];
    for (name, f, truth) in cases {
        for kind in SamplerKind::ALL {
            let [mse, replica, sample] = calibration(kind, f, truth);
            eprintln!(
                "{name} {kind:<11}: measured MSE {mse:.3e}, replica-predicted {:.3} x, per-sample {:.3} x",
                replica / mse,
                sample / mse
            );
            assert!(within(replica / mse), "{name} {kind}: replica prediction {:.3}x the MSE", replica / mse);
            // The per-sample variance is right for independent samples only.
            let independent = kind == SamplerKind::Independent;
            assert_eq!(within(sample / mse), independent, "{name} {kind}: per-sample {:.3}x", sample / mse);
        }
    }
}

#[test]
fn calibration_check_rejects_a_biased_estimate() {
    // Plant a bias of one RMS error (the estimate of π/4 shifted): the true MSE doubles while
    // the replica spread does not see it, and the check must reject the prediction.
    let [mse, ..] = calibration(SamplerKind::Sobol, &one_d, FRAC_PI_4);
    let shift = mse.sqrt();
    let [biased_mse, replica, _] = calibration(SamplerKind::Sobol, &one_d, FRAC_PI_4 + shift);
    assert!(
        !within(replica / biased_mse),
        "a bias of one RMS error passed: predicted {:.3}x the MSE",
        replica / biased_mse
    );
}
