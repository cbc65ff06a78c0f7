//! Integration error against known integrals, per sampler: every estimate within 5 standard
//! errors (estimated from independent replicas = pixels), and the RMS error falling with N at
//! the sampler's rate (log-log slope).

use std::f64::consts::FRAC_PI_4;

use stratapt_sampling::{Sampler, SamplerKind};

/// Independent replicas: one per pixel.
const REPLICAS: u32 = 256;
/// Sample counts N = 2^k, k = 4..=12.
const LOG2_N: std::ops::RangeInclusive<u32> = 4..=12;

struct Study {
    /// (N, RMS error) per sample count.
    rms: Vec<(f64, f64)>,
}

/// Estimate `truth` with `estimate(sampler, pixel, n)` over all replicas and sample counts,
/// asserting each replica-mean within 5 standard errors.
fn study(
    kind: SamplerKind,
    name: &str,
    truth: f64,
    estimate: &dyn Fn(&Sampler, [u32; 2], u32) -> f64,
) -> Study {
    let mut rms = Vec::new();
    for k in LOG2_N {
        let n = 1u32 << k;
        let sampler = Sampler::new(kind, n, 0x5eed);
        let estimates: Vec<f64> = (0..REPLICAS)
            .map(|r| estimate(&sampler, [r % 16, r / 16], n))
            .collect();
        let count = f64::from(REPLICAS);
        let mean = estimates.iter().sum::<f64>() / count;
        let var = estimates
            .iter()
            .map(|e| (e - mean) * (e - mean))
            .sum::<f64>()
            / (count - 1.0);
        let se = (var / count).sqrt();
        assert!(
            (mean - truth).abs() <= 5.0 * se,
            "{kind} {name} N={n}: mean {mean} vs {truth}, |error| {:e} > 5 SE ({se:e})",
            (mean - truth).abs()
        );
        let mse = estimates
            .iter()
            .map(|e| (e - truth) * (e - truth))
            .sum::<f64>()
            / count;
        rms.push((f64::from(n), mse.sqrt()));
    }
    Study { rms }
}

/// Least-squares slope of log(RMS) against log(N).
fn slope(points: &[(f64, f64)]) -> f64 {
    let pts: Vec<(f64, f64)> = points.iter().map(|&(n, e)| (n.ln(), e.ln())).collect();
    let m = pts.len() as f64;
    let (mx, my) = (
        pts.iter().map(|p| p.0).sum::<f64>() / m,
        pts.iter().map(|p| p.1).sum::<f64>() / m,
    );
    let sxy: f64 = pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    let sxx: f64 = pts.iter().map(|p| (p.0 - mx) * (p.0 - mx)).sum();
    sxy / sxx
}

/// Slope bounds: independent ~ N^-1/2 everywhere. In 1D, jittered strata and Owen-scrambled
/// van der Corput both reach ≈ N^-1.4 on this integrand (its √ edge costs a little of the smooth
/// N^-1.5): bound −0.9. In 2D Sobol measures ≈ N^-1.4 (bound −0.9); correlated multi-jitter
/// measures ≈ N^-0.77 here, because all samples of a row share their x sub-stratum (Kensler's
/// correlation), which leaves a row-level error on non-periodic smooth integrands: bound −0.65.
fn slope_bounds(kind: SamplerKind, dims: u32) -> (f64, f64) {
    match (kind, dims) {
        (SamplerKind::Independent, _) => (-0.6, -0.4),
        (SamplerKind::Stratified, 2) => (-2.0, -0.65),
        _ => (-2.0, -0.9),
    }
}

fn check(kind: SamplerKind, name: &str, dims: u32, s: &Study) {
    let measured = slope(&s.rms);
    let table: Vec<String> = s.rms.iter().map(|(n, e)| format!("{n}:{e:.2e}")).collect();
    eprintln!(
        "convergence {kind:<11} {name}: slope {measured:+.3}  RMS {}",
        table.join(" ")
    );
    let (lo, hi) = slope_bounds(kind, dims);
    assert!(
        measured > lo && measured < hi,
        "{kind} {name}: slope {measured} outside ({lo}, {hi})"
    );
}

/// ∫₀¹ √(1 − x²) dx = π/4 with 1D samples (dimension 3).
#[test]
fn quarter_circle_1d_converges_at_each_samplers_rate() {
    let f = |x: f64| (1.0 - x * x).max(0.0).sqrt();
    for kind in SamplerKind::ALL {
        let estimate = |s: &Sampler, pixel: [u32; 2], n: u32| {
            (0..n)
                .map(|i| f(f64::from(s.sample_1d(pixel, i, 3))))
                .sum::<f64>()
                / f64::from(n)
        };
        check(
            kind,
            "1D ∫√(1−x²)",
            1,
            &study(kind, "1D", FRAC_PI_4, &estimate),
        );
    }
}

/// ∫∫ √(1 − x²) √(1 − y²) dx dy = (π/4)² with 2D samples (dimensions 5, 6).
#[test]
fn quarter_circle_2d_converges_at_each_samplers_rate() {
    let f = |x: f64| (1.0 - x * x).max(0.0).sqrt();
    for kind in SamplerKind::ALL {
        let estimate = |s: &Sampler, pixel: [u32; 2], n: u32| {
            let sum: f64 = (0..n)
                .map(|i| {
                    let p = s.sample_2d(pixel, i, 5);
                    f(f64::from(p.x)) * f(f64::from(p.y))
                })
                .sum();
            sum / f64::from(n)
        };
        check(
            kind,
            "2D ∫∫√(1−x²)√(1−y²)",
            2,
            &study(kind, "2D", FRAC_PI_4 * FRAC_PI_4, &estimate),
        );
    }
}

/// The light domain: four "lights" chosen uniformly by the choice `c`, light `j` contributing
/// `(j + 1) √(1 − x²) √(1 − y²)` at its point: `∫ = 2.5 (π/4)²`. Sobol draws (c, x, y) as one
/// (1,m,3)-net, so the points that choose each light are stratified on it: ≈ N^-1.3 here (bound
/// −0.9). Drawn apart, as the choice and the point were before (each stratified on its own, their
/// pairing random), the same Sobol values reach only ≈ N^-0.5 (asserted above −0.7): the test
/// tells the two apart.
#[test]
fn light_domain_converges_jointly_with_sobol() {
    use stratapt_sampling::hash::pixel_seed;
    use stratapt_sampling::sampler::{sobol, to_unit_float};
    let f = |x: f64| (1.0 - x * x).max(0.0).sqrt();
    let light = |c: f32, x: f32, y: f32| {
        let j = (f64::from(c) * 4.0).floor();
        (j + 1.0) * f(f64::from(x)) * f(f64::from(y))
    };
    let truth = 2.5 * FRAC_PI_4 * FRAC_PI_4;
    let joint = |s: &Sampler, pixel: [u32; 2], n: u32| {
        let sum: f64 = (0..n)
            .map(|i| {
                let (c, p) = s.sample_1d_2d(pixel, i, 7, 8);
                light(c, p.x, p.y)
            })
            .sum();
        sum / f64::from(n)
    };
    let measured = study(SamplerKind::Sobol, "light", truth, &joint);
    check(SamplerKind::Sobol, "light domain (c, x, y)", 3, &measured);

    let apart = |s: &Sampler, pixel: [u32; 2], n: u32| {
        let key = pixel_seed(s.seed, pixel);
        let sum: f64 = (0..n)
            .map(|i| {
                let c = to_unit_float(sobol::bits_1d(key, i, 7));
                let [x, y] = sobol::bits_2d(key, i, 8).map(to_unit_float);
                light(c, x, y)
            })
            .sum();
        sum / f64::from(n)
    };
    let measured = slope(&study(SamplerKind::Sobol, "light apart", truth, &apart).rms);
    eprintln!("convergence sobol       light domain drawn apart: slope {measured:+.3}");
    assert!(
        measured > -0.7,
        "drawn apart, slope {measured}: the test cannot tell"
    );
}
