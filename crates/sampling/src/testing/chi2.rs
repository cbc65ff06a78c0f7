//! A chi-square goodness-of-fit test for sampling routines, in the manner of Mitsuba 3's
//! `ChiSquareTest`: map samples into `[0,1]²`, histogram them, integrate the claimed density
//! over the same bins (adaptive Simpson), and compare by Pearson's statistic. With planted
//! errors ([`Plant`]) a test shows that it rejects what it exists to catch.
//!
//! Behind the `chi2` feature (it needs `statrs`): for the workspace's tests, not for renderers.

use statrs::distribution::{ChiSquared, ContinuousCDF, Normal};

/// A family of chi-square tests run together: each test's significance is Šidák-corrected so
/// that the whole family wrongly rejects a correct routine with probability `alpha`.
#[derive(Clone, Copy, Debug)]
pub struct Family {
    /// Family-wise significance.
    pub alpha: f64,
    /// Upper bound on the number of tests in the family (fits with a planted error, which must
    /// be rejected, are not counted).
    pub tests: u32,
}

impl Family {
    /// Per-test significance level after the Šidák correction.
    pub fn significance(&self) -> f64 {
        1.0 - (1.0 - self.alpha).powf(1.0 / f64::from(self.tests))
    }
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
    /// Samples the routine refused ([`Refusals::Allowed`]).
    pub refused: u64,
    /// Samples in all (in the bins, outside, refused).
    pub samples: u64,
    /// Total expected probability of the bins (1, or at most 1 when refusals are allowed).
    pub total_probability: f64,
}

/// What a sample that is `None` means to [`chi2`] and [`fit`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Refusals {
    /// The routine always samples: `None` is a sample outside the domain (an error).
    Never,
    /// The routine may refuse (a BSDF whose sampled direction leaves the hemisphere): `None` is
    /// a refusal, expected with the probability the bins leave, `1 − Σ probs`, counted in a
    /// cell of its own.
    Allowed,
}

/// Histogram `samples` (coordinates in `[0,1]²`, `None` = outside the domain or a refusal, as
/// `refusals` says) over an `nx × ny` grid and compare with the bin probabilities `probs` by
/// Pearson's chi-square, pooling bins whose expected count is below 5.
pub fn chi2(
    samples: impl Iterator<Item = Option<[f64; 2]>>,
    probs: &[f64],
    nx: usize,
    ny: usize,
    refusals: Refusals,
) -> Chi2 {
    let mut counts = vec![0u64; nx * ny];
    let (mut n, mut outside, mut refused) = (0u64, 0u64, 0u64);
    for s in samples {
        n += 1;
        match s {
            Some([x, y]) if (0.0..=1.0).contains(&x) && (0.0..=1.0).contains(&y) => {
                let i = ((x * nx as f64) as usize).min(nx - 1);
                let j = ((y * ny as f64) as usize).min(ny - 1);
                counts[j * nx + i] += 1;
            }
            None if refusals == Refusals::Allowed => refused += 1,
            _ => outside += 1,
        }
    }
    let total_probability: f64 = probs.iter().sum();
    let mut probs = probs.to_vec();
    if refusals == Refusals::Allowed {
        probs.push((1.0 - total_probability).max(0.0));
        counts.push(refused);
    }
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
        refused,
        samples: n,
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
    /// The same bend with a given δ: for densities with steep slopes, where the first-order
    /// estimate of [`detectable_bend`] (the Jacobian term alone) overstates what a fit sees.
    Bend(f64),
}

/// A fit's outcome: the statistics, the bend planted (0 unless [`Plant::WarpBend`] or
/// [`Plant::Bend`]), and `Err`
/// naming every check that rejected it.
#[derive(Debug)]
pub struct Fit {
    pub name: String,
    pub chi2: Chi2,
    pub bend: f64,
    pub verdict: Result<(), String>,
}

/// Histogram `samples` against `probs` with `plant` planted, as [`chi2`] does, and check the fit:
/// nothing outside the support, bin probabilities summing to one (at most one when `refusals`
/// are allowed: the refusal cell holds the rest), and a p-value above the family's
/// Šidák-corrected significance.
#[allow(clippy::too_many_arguments)]
pub fn fit(
    family: &Family,
    name: &str,
    samples: impl Iterator<Item = Option<[f64; 2]>>,
    probs: &[f64],
    nx: usize,
    ny: usize,
    refusals: Refusals,
    plant: Plant,
) -> Fit {
    let mut samples: Vec<Option<[f64; 2]>> = samples.collect();
    let mut probs = probs.to_vec();
    let mut bend = 0.0;
    match plant {
        Plant::None => {}
        Plant::PdfScale(factor) => probs.iter_mut().for_each(|p| *p *= factor),
        Plant::WarpBend | Plant::Bend(_) => {
            bend = match plant {
                Plant::Bend(delta) => delta,
                _ => detectable_bend(family, &probs, samples.len(), nx, ny),
            };
            for [_, y] in samples.iter_mut().flatten() {
                *y += bend * *y * (1.0 - *y);
            }
        }
    }
    let r = chi2(samples.into_iter(), &probs, nx, ny, refusals);
    let mut failed = Vec::new();
    if r.outside != 0 {
        failed.push(format!("{} samples outside the support", r.outside));
    }
    let normalized = match refusals {
        Refusals::Never => (r.total_probability - 1.0).abs() < 2e-3,
        Refusals::Allowed => r.total_probability < 1.0 + 2e-3,
    };
    if !normalized {
        failed.push(format!("Σp = {}", r.total_probability));
    }
    // The refusal count alone, as a binomial: Pearson's statistic over hundreds of cells dilutes
    // a wrong normalization that this one cell shows plainly.
    if refusals == Refusals::Allowed && normalized {
        let q = (1.0 - r.total_probability).max(0.0);
        let n = r.samples as f64;
        let sd = (n * q * (1.0 - q)).sqrt();
        let z = (r.refused as f64 - n * q) / sd.max(1e-300);
        let critical = Normal::new(0.0, 1.0)
            .unwrap()
            .inverse_cdf(1.0 - 0.5 * family.significance());
        if z.abs() > critical && (r.refused as f64 - n * q).abs() >= 1.0 {
            failed.push(format!(
                "refused {} of {n}, expected {:.1} (z = {z:.2}, |z| > {critical:.2})",
                r.refused,
                n * q
            ));
        }
    }
    let significance = family.significance();
    if r.p_value <= significance {
        failed.push(format!("p = {:.3e} ≤ {significance:.3e}", r.p_value));
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
pub fn detectable_bend(family: &Family, probs: &[f64], n: usize, nx: usize, ny: usize) -> f64 {
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
        .inverse_cdf(1.0 - family.significance());
    // dof + λ − z √(2 dof + 4λ) = critical, solved for s = √(2 dof + 4λ).
    let z = 4.0;
    let s = 2.0 * z + 2.0 * (z * z + critical - 0.5 * dof).sqrt();
    let lambda = (s * s - 2.0 * dof) / 4.0;
    (lambda / (n * sensitivity)).sqrt()
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

/// Print a fit's statistics and verdict on one line (stderr).
pub fn print_fit(f: &Fit) {
    let r = &f.chi2;
    eprintln!(
        "chi2 {}: statistic {:.1}, dof {}, p = {:.4e}, outside {}, refused {}, Σp = {:.6}{}: {}",
        f.name,
        r.statistic,
        r.dof,
        r.p_value,
        r.outside,
        r.refused,
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
