//! Shared test harness: input uniforms, adaptive Simpson integration, and a chi-square
//! goodness-of-fit test in the manner of mitsuba3's `ChiSquareTest`.
#![allow(dead_code)]

use glam::Vec2;
use statrs::distribution::{ChiSquared, ContinuousCDF};
use stratapt_sampling::{Sampler, SamplerKind};

/// Family-wise significance of all chi-square tests in this crate.
pub const FAMILY_ALPHA: f64 = 0.01;
/// Upper bound on the number of chi-square tests run by the crate (Šidák correction); the fits
/// with a planted error, which must be rejected, are not in the family.
pub const CHI2_TESTS: u32 = 48;

/// Per-test significance level after the Šidák correction.
pub fn significance() -> f64 {
    1.0 - (1.0 - FAMILY_ALPHA).powf(1.0 / f64::from(CHI2_TESTS))
}

/// `n` uniform points from the independent sampler (deterministic for a given `seed`).
pub fn uniforms(n: u32, seed: u32) -> impl Iterator<Item = Vec2> {
    let sampler = Sampler::new(SamplerKind::Independent, 1, seed);
    (0..n).map(move |i| sampler.sample_2d([i & 0xff, i >> 8], 0, 0))
}

/// The corners and middle of `[0,1)²`, including the largest sampler value `1 − 2⁻²⁴`.
pub fn edge_uniforms() -> Vec<Vec2> {
    let edges = [0.0, 2f32.powi(-24), 0.25, 0.5, 1.0 - 2f32.powi(-24)];
    edges
        .iter()
        .flat_map(|&x| edges.iter().map(move |&y| Vec2::new(x, y)))
        .collect()
}

/// Adaptive Simpson quadrature of `f` over `[a, b]` to absolute tolerance `eps`.
pub fn simpson(f: &dyn Fn(f64) -> f64, a: f64, b: f64, eps: f64) -> f64 {
    let (fa, fm, fb) = (f(a), f(0.5 * (a + b)), f(b));
    let whole = (b - a) / 6.0 * (fa + 4.0 * fm + fb);
    simpson_step(f, a, b, fa, fm, fb, whole, eps, 0)
}

const MIN_DEPTH: u32 = 2;
const MAX_DEPTH: u32 = 12;

#[allow(clippy::too_many_arguments)]
fn simpson_step(
    f: &dyn Fn(f64) -> f64,
    a: f64,
    b: f64,
    fa: f64,
    fm: f64,
    fb: f64,
    whole: f64,
    eps: f64,
    depth: u32,
) -> f64 {
    let m = 0.5 * (a + b);
    let (lm, rm) = (0.5 * (a + m), 0.5 * (m + b));
    let (flm, frm) = (f(lm), f(rm));
    let left = (m - a) / 6.0 * (fa + 4.0 * flm + fm);
    let right = (b - m) / 6.0 * (fm + 4.0 * frm + fb);
    let delta = left + right - whole;
    if depth >= MAX_DEPTH || (depth >= MIN_DEPTH && delta.abs() <= 15.0 * eps) {
        return left + right + delta / 15.0;
    }
    simpson_step(f, a, m, fa, flm, fm, left, 0.5 * eps, depth + 1)
        + simpson_step(f, m, b, fm, frm, fb, right, 0.5 * eps, depth + 1)
}

/// Nested adaptive Simpson over the rectangle `[x0, x1] × [y0, y1]`.
pub fn simpson_2d(f: &dyn Fn(f64, f64) -> f64, x: [f64; 2], y: [f64; 2], eps: f64) -> f64 {
    let inner = |yy: f64| simpson(&|xx| f(xx, yy), x[0], x[1], eps / (y[1] - y[0]).max(1e-300));
    simpson(&inner, y[0], y[1], eps)
}

/// Probability of each bin of an `nx × ny` grid over `[0,1]²` for a density over `[0,1]²`.
pub fn density_bins(density: &dyn Fn(f64, f64) -> f64, nx: usize, ny: usize) -> Vec<f64> {
    let eps = 1e-5 / (nx * ny) as f64;
    let mut probs = Vec::with_capacity(nx * ny);
    for j in 0..ny {
        for i in 0..nx {
            let x = [i as f64 / nx as f64, (i + 1) as f64 / nx as f64];
            let y = [j as f64 / ny as f64, (j + 1) as f64 / ny as f64];
            probs.push(simpson_2d(density, x, y, eps));
        }
    }
    probs
}

/// Outcome of a chi-square test.
#[derive(Debug)]
pub struct Chi2 {
    pub statistic: f64,
    pub dof: usize,
    pub p_value: f64,
    /// Samples the warp mapped outside `[0,1]²` or where the expected density is zero.
    pub outside: u64,
    /// Total expected probability (should be 1).
    pub total_probability: f64,
}

/// Histogram `samples` (coordinates in `[0,1]²`, `None` = outside the domain) over an
/// `nx × ny` grid and compare with the bin probabilities `probs` by Pearson's chi-square,
/// pooling bins whose expected count is below 5.
pub fn chi2(
    samples: impl Iterator<Item = Option<[f64; 2]>>,
    probs: &[f64],
    nx: usize,
    ny: usize,
) -> Chi2 {
    let mut counts = vec![0u64; nx * ny];
    let (mut n, mut outside) = (0u64, 0u64);
    for s in samples {
        n += 1;
        match s {
            Some([x, y]) if (0.0..=1.0).contains(&x) && (0.0..=1.0).contains(&y) => {
                let i = ((x * nx as f64) as usize).min(nx - 1);
                let j = ((y * ny as f64) as usize).min(ny - 1);
                counts[j * nx + i] += 1;
            }
            _ => outside += 1,
        }
    }
    let total_probability: f64 = probs.iter().sum();
    let mut cells: Vec<(f64, f64)> = Vec::new();
    let (mut pooled_e, mut pooled_o) = (0.0, 0.0);
    for (&p, &c) in probs.iter().zip(&counts) {
        let e = p * n as f64;
        if p <= 0.0 && c > 0 {
            outside += c;
        } else if e < 5.0 {
            pooled_e += e;
            pooled_o += c as f64;
        } else {
            cells.push((e, c as f64));
        }
    }
    if pooled_e >= 5.0 {
        cells.push((pooled_e, pooled_o));
    } else if let Some(smallest) = cells.iter_mut().min_by(|a, b| a.0.total_cmp(&b.0)) {
        smallest.0 += pooled_e;
        smallest.1 += pooled_o;
    }
    let statistic: f64 = cells.iter().map(|(e, o)| (o - e) * (o - e) / e).sum();
    let dof = cells.len().saturating_sub(1).max(1);
    let p_value = 1.0 - ChiSquared::new(dof as f64).unwrap().cdf(statistic);
    Chi2 {
        statistic,
        dof,
        p_value,
        outside,
        total_probability,
    }
}

/// An error planted in a chi-square fit, to show that the fit rejects what it exists to catch.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Plant {
    /// Nothing planted: the fit as the tests run it.
    None,
    /// The pdf off by a constant factor: every bin probability times it.
    PdfScale(f64),
    /// The warp slightly wrong, or the sampler biased toward one side: every sample's y coordinate
    /// bent to `y + δ·y(1 − y)`, which moves a relative density `δ(1 − 2y)` from low to high y (a
    /// smooth error, the hardest kind for a chi-square test), with δ the smallest this fit surely
    /// rejects ([`detectable_bend`]).
    WarpBend,
}

/// A fit's outcome: the statistics, the bend planted (0 unless [`Plant::WarpBend`]), and `Err`
/// naming every check that rejected it.
#[derive(Debug)]
pub struct Fit {
    pub name: String,
    pub chi2: Chi2,
    pub bend: f64,
    pub verdict: Result<(), String>,
}

/// Histogram `samples` against `probs` with `plant` planted, as [`chi2`] does, and check the fit:
/// nothing outside the support, bin probabilities summing to one, and a p-value above the
/// Šidák-corrected significance.
pub fn fit(
    name: &str,
    samples: impl Iterator<Item = Option<[f64; 2]>>,
    probs: &[f64],
    nx: usize,
    ny: usize,
    plant: Plant,
) -> Fit {
    let mut samples: Vec<Option<[f64; 2]>> = samples.collect();
    let mut probs = probs.to_vec();
    let mut bend = 0.0;
    match plant {
        Plant::None => {}
        Plant::PdfScale(factor) => probs.iter_mut().for_each(|p| *p *= factor),
        Plant::WarpBend => {
            bend = detectable_bend(&probs, samples.len(), nx, ny);
            for [_, y] in samples.iter_mut().flatten() {
                *y += bend * *y * (1.0 - *y);
            }
        }
    }
    let r = chi2(samples.into_iter(), &probs, nx, ny);
    let mut failed = Vec::new();
    if r.outside != 0 {
        failed.push(format!("{} samples outside the support", r.outside));
    }
    if (r.total_probability - 1.0).abs() >= 2e-3 {
        failed.push(format!("Σp = {}", r.total_probability));
    }
    if r.p_value <= significance() {
        failed.push(format!("p = {:.3e} ≤ {:.3e}", r.p_value, significance()));
    }
    let verdict = if failed.is_empty() {
        Ok(())
    } else {
        Err(failed.join("; "))
    };
    Fit {
        name: name.to_string(),
        chi2: r,
        bend,
        verdict,
    }
}

/// The smallest bend δ ([`Plant::WarpBend`]) that a fit of `n` samples over these bins rejects
/// with a 4σ margin: its statistic, a non-central chi-square with `dof` degrees of freedom and
/// non-centrality `λ = n δ² Σ p (1 − 2y)²` (bins of expected count ≥ 5, `y` the row's centre),
/// has mean `dof + λ` and variance `2 (dof + 2λ)`; the mean less four deviations must reach the
/// critical value at the test's significance.
pub fn detectable_bend(probs: &[f64], n: usize, nx: usize, ny: usize) -> f64 {
    let n = n as f64;
    let (mut sensitivity, mut cells) = (0.0, 0);
    for (b, &p) in probs.iter().enumerate() {
        if p * n >= 5.0 {
            let y = ((b / nx) as f64 + 0.5) / ny as f64;
            sensitivity += p * (1.0 - 2.0 * y).powi(2);
            cells += 1;
        }
    }
    let dof = f64::from((cells.max(2) - 1) as u32);
    let critical = ChiSquared::new(dof)
        .unwrap()
        .inverse_cdf(1.0 - significance());
    // dof + λ − z √(2 dof + 4λ) = critical, solved for s = √(2 dof + 4λ).
    let z = 4.0;
    let s = 2.0 * z + 2.0 * (z * z + critical - 0.5 * dof).sqrt();
    let lambda = (s * s - 2.0 * dof) / 4.0;
    (lambda / (n * sensitivity)).sqrt()
}

/// Run [`fit`] with nothing planted and assert that it passes.
pub fn assert_chi2(
    name: &str,
    samples: impl Iterator<Item = Option<[f64; 2]>>,
    probs: &[f64],
    nx: usize,
    ny: usize,
) {
    accept(vec![fit(name, samples, probs, nx, ny, Plant::None)]);
}

/// Print each fit and assert that every one passed.
pub fn accept(fits: Vec<Fit>) {
    for f in fits {
        print_fit(&f);
        if let Err(why) = f.verdict {
            panic!("{}: rejected, {why}: {:?}", f.name, f.chi2);
        }
    }
}

/// Print each fit (planted) and assert that every one was rejected, by the check whose message
/// contains `check` ("p =" for the chi-square statistic, "Σp" for the normalization, "outside").
pub fn reject(fits: Vec<Fit>, check: &str) {
    for f in fits {
        print_fit(&f);
        match &f.verdict {
            Ok(()) => panic!("{}: planted error accepted: {:?}", f.name, f.chi2),
            Err(why) => assert!(why.contains(check), "{}: rejected for {why}", f.name),
        }
    }
}

fn print_fit(f: &Fit) {
    let r = &f.chi2;
    eprintln!(
        "chi2 {}: statistic {:.1}, dof {}, p = {:.4e}, outside {}, Σp = {:.6}{}: {}",
        f.name,
        r.statistic,
        r.dof,
        r.p_value,
        r.outside,
        r.total_probability,
        if f.bend > 0.0 {
            format!(", bent by δ = {:.4}", f.bend)
        } else {
            String::new()
        },
        match &f.verdict {
            Ok(()) => "accepted".to_string(),
            Err(why) => format!("rejected ({why})"),
        }
    );
}
