//! The film both renderers produce: per-pixel sums in f64 of the sample values and of their
//! squares, and the same for the film's twin pixels ([`twin`]), from which the mean and a
//! calibrated variance of the mean follow.
//!
//! # The calibrated error estimate
//! The per-sample variance `s²/n` is the variance of the mean of independent samples only;
//! stratified and Sobol samples are negatively correlated and it overstates their error many
//! times over (measured:
//! docs/measurements/error-estimate.md#predicted-against-true-error-cornell-box). A twin pixel
//! is sampled twice, by the render's randomization and by an independent one with the same
//! sample indices, so the two means `m`, `m'` of a twin pair are independent estimates of one
//! integral and `(m − m')²/2` is an unbiased estimate of the variance of either. Over the pairs
//! of a class of pixels (or the film), the ratio `κ = Σ (m − m')²/2 / Σ (s² + s'²)/(2n)` says
//! how far the per-sample variance overstates the error there, and every pixel's calibrated
//! variance is `κ · s²/n`, with the κ of the pixels whose per-sample variance is like its own
//! ([`Calibration`]). For the independent sampler `κ = 1` exactly and no twins are rendered.

//!
//! Owns: the [`Film`] and its calibrated error, render parts and their merge ([`part`]), EXR and
//! PNG output, and the interface both renderers offer ([`Render`]) with the progressive driver
//! built on it ([`render::progressive`]): above both renderers, so that neither knows the other.
//! Must not know: scene files, and how anything is rendered.

pub mod part;
pub mod render;
pub mod twin;
mod write;

pub use render::{Render, RenderError, RenderStats};

pub use write::atomically as write_atomically;

use std::path::Path;
use stratapt_scene::{FlatScene, RenderSettings};
pub use twin::TwinLayout;

/// Per-pixel Monte Carlo estimates. Pixel `(x, y)` is at index `y * width + x`, `y = 0` on top.
#[derive(Clone, Debug, PartialEq)]
pub struct Film {
    pub width: u32,
    pub height: u32,
    /// Σ f(Xᵢ)/pdf(Xᵢ) per pixel and channel.
    pub sum: Vec<[f64; 3]>,
    /// Σ (f(Xᵢ)/pdf(Xᵢ))² per pixel and channel.
    pub sum_sq: Vec<[f64; 3]>,
    /// Number of samples per pixel.
    pub count: Vec<u32>,
    /// Index of the first sample the film holds: a render adds samples `first_sample +
    /// spp() ..` of every pixel (0 for a whole render; a part of one starts further on, see
    /// [`part`]).
    pub first_sample: u32,
    /// Σ f/pdf of each twin ([`TwinLayout`]; empty when the render has none). A twin holds as
    /// many samples as its pixel (the film's renders add samples to every pixel at once).
    pub twin_sum: Vec<[f64; 3]>,
    /// Σ (f/pdf)² of each twin.
    pub twin_sum_sq: Vec<[f64; 3]>,
    /// Twins of the pixels whose error the uniform twins cannot calibrate: [`PEAK_REPLICAS`]
    /// at each of the pixels of largest per-sample variance ([`Film::peak_pixels`]), rendered
    /// after the film's samples and for all of them, pixel by pixel in replica order. Empty
    /// when the film has none; merging films empties them (they no longer hold the film's
    /// samples).
    pub peaks: Vec<PeakTwin>,
}

/// A twin at a pixel chosen from the film ([`Film::peaks`]): the same samples of the pixel as
/// the film holds, from an independent randomization.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PeakTwin {
    /// Its pixel, `[x, y]`.
    pub pixel: [u32; 2],
    /// Its randomization: replica `1 ..= PEAK_REPLICAS` of the render's seed
    /// (`stratapt_sampling::replica::seed`; replica 1 is also the uniform twins').
    pub replica: u32,
    /// Σ f/pdf.
    pub sum: [f64; 3],
    /// Σ (f/pdf)².
    pub sum_sq: [f64; 3],
}

impl Film {
    /// An empty film without twins (its error estimate is the per-sample variance).
    pub fn new(width: u32, height: u32) -> Self {
        Self::with_twins(width, height, false)
    }

    /// An empty film for rendering `scene` with `settings`: its size, and twins when the
    /// settings call for them ([`RenderSettings::twins`]).
    pub fn for_render(scene: &FlatScene, settings: &RenderSettings) -> Self {
        Self::with_twins(scene.camera.width, scene.camera.height, settings.twins())
    }

    /// An empty film, with the twins of [`TwinLayout::new`] when `twins`.
    pub fn with_twins(width: u32, height: u32, twins: bool) -> Self {
        let n = width as usize * height as usize;
        let k = if twins && n > 0 {
            TwinLayout::new(width, height).count as usize
        } else {
            0
        };
        Self {
            width,
            height,
            sum: vec![[0.0; 3]; n],
            sum_sq: vec![[0.0; 3]; n],
            count: vec![0; n],
            first_sample: 0,
            twin_sum: vec![[0.0; 3]; k],
            twin_sum_sq: vec![[0.0; 3]; k],
            peaks: Vec::new(),
        }
    }

    /// Whether the film has twins.
    pub fn has_twins(&self) -> bool {
        !self.twin_sum.is_empty()
    }

    /// Where the twins are.
    pub fn twin_layout(&self) -> TwinLayout {
        TwinLayout::new(self.width, self.height)
    }

    pub fn index(&self, x: u32, y: u32) -> usize {
        y as usize * self.width as usize + x as usize
    }

    /// Add one sample value to pixel `(x, y)`.
    pub fn add_sample(&mut self, x: u32, y: u32, value: [f32; 3]) {
        let i = self.index(x, y);
        accumulate(&mut self.sum[i], &mut self.sum_sq[i], value);
        self.count[i] += 1;
    }

    /// Add one sample value to twin `k` (its count follows its pixel's).
    pub fn add_twin_sample(&mut self, k: usize, value: [f32; 3]) {
        accumulate(&mut self.twin_sum[k], &mut self.twin_sum_sq[k], value);
    }

    /// Add another film's samples (same size and twins) to this one: the caller keeps track of
    /// which sample indices each holds ([`part::merge`] checks them).
    pub fn merge(&mut self, other: &Film) {
        assert_eq!((self.width, self.height), (other.width, other.height));
        assert_eq!(self.twin_sum.len(), other.twin_sum.len());
        for i in 0..self.sum.len() {
            for c in 0..3 {
                self.sum[i][c] += other.sum[i][c];
                self.sum_sq[i][c] += other.sum_sq[i][c];
            }
            self.count[i] += other.count[i];
        }
        for k in 0..self.twin_sum.len() {
            for c in 0..3 {
                self.twin_sum[k][c] += other.twin_sum[k][c];
                self.twin_sum_sq[k][c] += other.twin_sum_sq[k][c];
            }
        }
        self.peaks.clear();
    }

    /// The pixels that deserve a peak twin: the [`peak_count`] pixels of largest per-sample
    /// variance (channel-averaged, ties to the lower index) that have none of the uniform
    /// twins and some variance. Empty without twins or with fewer than 2 samples.
    ///
    /// Where a few bright pixels carry most of a render's error (the edges of small lights),
    /// the uniform twins, one pixel in 16, put only a few twins there, and those few set their
    /// class's κ, so single renders' predictions scattered widely (measured on Veach's scene:
    /// docs/measurements/error-estimate-honesty.md, "Where the error lives, and where the twins
    /// must be").
    pub fn peak_pixels(&self) -> Vec<[u32; 2]> {
        if !self.has_twins() || self.held_spp() < 2 {
            return Vec::new();
        }
        let layout = self.twin_layout();
        let mut is_twin = vec![false; self.sum.len()];
        for k in 0..layout.count {
            let [x, y] = layout.pixel(k);
            is_twin[self.index(x, y)] = true;
        }
        let mut candidates: Vec<(f64, usize)> = (0..self.sum.len())
            .filter(|&i| !is_twin[i])
            .map(|i| (class_key(self.sample_variance_of_mean(i)), i))
            .filter(|(key, _)| *key > 0.0)
            .collect();
        let k = peak_count(self.width, self.height).min(candidates.len());
        if k == 0 {
            return Vec::new();
        }
        let largest_first =
            |a: &(f64, usize), b: &(f64, usize)| b.0.total_cmp(&a.0).then(a.1.cmp(&b.1));
        if k < candidates.len() {
            candidates.select_nth_unstable_by(k - 1, largest_first);
            candidates.truncate(k);
        }
        candidates.sort_by(largest_first);
        let w = self.width as usize;
        candidates
            .into_iter()
            .map(|(_, i)| [(i % w) as u32, (i / w) as u32])
            .collect()
    }

    /// Every pixel's calibration class key ([`Calibration`]): the mean channel-averaged
    /// per-sample variance of its up to 8 neighbours, not its own (a 1×1 film: its own).
    ///
    /// Keyed by its own samples, a pixel whose samples happened to hit a rare bright path lands
    /// in a bright class, and its twin, drawn independently, usually misses: with about one hit
    /// per pixel such a pair measures κ ≈ ½ of the truth, so the bright classes were calibrated
    /// low (a floor lit through a rare bounce, stratified and Sobol samples). The neighbours are
    /// independent randomizations of nearly the same integrand, so they class a pixel by its
    /// kind without selecting on its own noise (measured:
    /// docs/measurements/error-estimate-honesty.md#classes-keyed-by-the-neighbours-2026-12-04).
    /// An isolated bright pixel gets its neighbours' class; where it holds a twin it pulls that
    /// class's κ (a ratio of sums) towards its own, which then errs high for its dim
    /// neighbours, not low for it.
    pub fn class_keys(&self) -> Vec<f64> {
        let own: Vec<f64> = (0..self.sum.len())
            .map(|i| class_key(self.sample_variance_of_mean(i)))
            .collect();
        let (w, h) = (self.width as i64, self.height as i64);
        (0..self.sum.len())
            .map(|i| {
                let (x, y) = ((i as i64) % w, (i as i64) / w);
                let (mut sum, mut n) = (0.0, 0u32);
                for (dx, dy) in NEIGHBOURS {
                    let (nx, ny) = (x + dx, y + dy);
                    if (0..w).contains(&nx) && (0..h).contains(&ny) {
                        sum += own[(ny * w + nx) as usize];
                        n += 1;
                    }
                }
                if n == 0 {
                    own[i]
                } else {
                    sum / n as f64
                }
            })
            .collect()
    }

    /// Samples each pixel holds (the smallest count over the film): what the film's estimate
    /// rests on, whatever pattern it was rendered in (`RenderSettings::pattern_spp`).
    pub fn held_spp(&self) -> u32 {
        self.count.iter().copied().min().unwrap_or(0)
    }

    /// Mean of pixel `i` (0 where no sample was taken).
    pub fn mean(&self, i: usize) -> [f64; 3] {
        let n = self.count[i].max(1) as f64;
        self.sum[i].map(|s| s / n)
    }

    /// The per-sample estimate of the variance of pixel `i`'s mean, s² / n (0 with fewer than 2
    /// samples): right for independent samples only; it overstates the error of stratified and
    /// Sobol samples, which are negatively correlated.
    pub fn sample_variance_of_mean(&self, i: usize) -> [f64; 3] {
        variance_of_mean(self.sum[i], self.sum_sq[i], self.count[i])
    }

    /// The calibration ratios κ (see the module docs) per channel: of the whole film, and of
    /// each class of pixels by its neighbours' per-sample variance ([`Calibration`]). All 1
    /// without twins.
    pub fn calibration(&self) -> Calibration {
        if !self.has_twins() {
            return Calibration::uncalibrated();
        }
        self.calibration_with(&self.class_keys())
    }

    /// [`Film::calibration`] of a film with twins, from its pixels' class keys.
    fn calibration_with(&self, keys: &[f64]) -> Calibration {
        // The twinned pixels with an estimate, keyed by their neighbours' per-sample variance:
        // each pixel's (key, num, den) from the means m₀ … m_R and per-sample variances
        // v₀ … v_R of the film and its R twins (sums `twins`): num = Σ (m_j − m̄)², the
        // sample variance of the R + 1 independent means times its R degrees of freedom, and
        // den = R · mean(v_j). With one twin that is ((m − m')²/2, (v + v')/2).
        let pixel = |i: usize, twins: &mut dyn Iterator<Item = ([f64; 3], [f64; 3])>| {
            let n = self.count[i];
            if n < 2 {
                return None;
            }
            let mut means = vec![self.mean(i)];
            let mut v_sum = self.sample_variance_of_mean(i);
            for (sum, sum_sq) in twins {
                means.push(sum.map(|s| s / n as f64));
                let v = variance_of_mean(sum, sum_sq, n);
                for c in 0..3 {
                    v_sum[c] += v[c];
                }
            }
            let r = (means.len() - 1) as f64;
            let num = std::array::from_fn(|c| {
                let mean = means.iter().map(|m| m[c]).sum::<f64>() / (r + 1.0);
                means.iter().map(|m| (m[c] - mean).powi(2)).sum()
            });
            let den = v_sum.map(|v| r * v / (r + 1.0));
            Some((keys[i], num, den))
        };
        let layout = self.twin_layout();
        let uniform = (0..layout.count).filter_map(|k| {
            let [x, y] = layout.pixel(k);
            let k = k as usize;
            let twin = (self.twin_sum[k], self.twin_sum_sq[k]);
            pixel(self.index(x, y), &mut std::iter::once(twin))
        });
        // Peak twins come pixel by pixel (`Film::peaks`).
        let peaks = self
            .peaks
            .chunk_by(|a, b| a.pixel == b.pixel)
            .filter_map(|twins| {
                let [x, y] = twins[0].pixel;
                pixel(
                    self.index(x, y),
                    &mut twins.iter().map(|t| (t.sum, t.sum_sq)),
                )
            });
        let mut pairs: Vec<(f64, [f64; 3], [f64; 3])> = uniform.chain(peaks).collect();
        if pairs.is_empty() {
            return Calibration::uncalibrated();
        }
        // Classes of equal twin count by key (edges at the twins' quantiles).
        pairs.sort_by(|a, b| a.0.total_cmp(&b.0));
        let classes = (pairs.len() / TWINS_PER_CLASS).max(1);
        let edges: Vec<f64> = (1..classes)
            .map(|c| pairs[c * pairs.len() / classes].0)
            .collect();
        let mut num = vec![[0.0; 3]; classes];
        let mut den = vec![[0.0; 3]; classes];
        for (key, n, d) in &pairs {
            let class = edges.partition_point(|e| e <= key);
            for c in 0..3 {
                num[class][c] += n[c];
                den[class][c] += d[c];
            }
        }
        let total = |parts: &[[f64; 3]]| -> [f64; 3] {
            std::array::from_fn(|c| parts.iter().map(|p| p[c]).sum())
        };
        let (num_all, den_all) = (total(&num), total(&den));
        let film: [f64; 3] = std::array::from_fn(|c| {
            if den_all[c] > 0.0 {
                num_all[c] / den_all[c]
            } else {
                1.0
            }
        });
        let kappa = num
            .iter()
            .zip(&den)
            .map(|(n, d)| std::array::from_fn(|c| if d[c] > 0.0 { n[c] / d[c] } else { film[c] }))
            .collect();
        Calibration { film, edges, kappa }
    }

    /// The calibrated variance of every pixel's mean, for every sampler: `κ · s²/n` with the κ
    /// of the pixel's class (see [`Calibration`]).
    pub fn variances(&self) -> Vec<[f64; 3]> {
        // Without twins every κ is 1 and no pixel needs a class.
        let keys = self.has_twins().then(|| self.class_keys());
        let calibration = match &keys {
            Some(keys) => self.calibration_with(keys),
            None => Calibration::uncalibrated(),
        };
        (0..self.sum.len())
            .map(|i| {
                let v = self.sample_variance_of_mean(i);
                let kappa = keys
                    .as_ref()
                    .map_or(calibration.film, |keys| calibration.kappa_for(keys[i]));
                std::array::from_fn(|c| kappa[c] * v[c])
            })
            .collect()
    }

    /// Mean over all pixels of the per-pixel means, and its calibrated standard error (pixels are
    /// independent randomizations, so their variances add).
    pub fn image_mean(&self) -> ([f64; 3], [f64; 3]) {
        self.image_mean_with(&self.variances())
    }

    /// [`Film::image_mean`] from the pixels' variances, already computed.
    fn image_mean_with(&self, variances: &[[f64; 3]]) -> ([f64; 3], [f64; 3]) {
        let n = self.sum.len().max(1) as f64;
        let mut mean = [0.0; 3];
        let mut var = [0.0; 3];
        for (i, v) in variances.iter().enumerate() {
            let m = self.mean(i);
            for c in 0..3 {
                mean[c] += m[c] / n;
                var[c] += v[c] / (n * n);
            }
        }
        (mean, var.map(f64::sqrt))
    }

    /// The calibrated error of the estimate, as relative standard errors: of the image mean
    /// (averaged over channels) and the 95th percentile over pixels of each pixel's relative
    /// standard error `√Var(mean) / max(mean, 0.01)` (channel-averaged; the floor keeps
    /// near-black pixels, whose relative error means nothing, from dominating).
    pub fn relative_error(&self) -> RelativeError {
        let variances = self.variances();
        let (mean, se) = self.image_mean_with(&variances);
        let m: f64 = mean.iter().sum::<f64>() / 3.0;
        let s: f64 = se.iter().sum::<f64>() / 3.0;
        let mut pixel = self.pixel_errors_with(&variances);
        let p95 = if pixel.is_empty() {
            0.0
        } else {
            let k = ((pixel.len() - 1) as f64 * 0.95).round() as usize;
            *pixel.select_nth_unstable_by(k, f64::total_cmp).1
        };
        RelativeError {
            image_mean: if m > 0.0 { s / m } else { 0.0 },
            pixel_p95: p95,
        }
    }

    /// Each pixel's calibrated relative standard error, `√Var(mean) / max(mean, 0.01)`
    /// (channel-averaged), row by row: what [`RelativeError::pixel_p95`] is the 95th
    /// percentile of.
    pub fn pixel_errors(&self) -> Vec<f64> {
        self.pixel_errors_with(&self.variances())
    }

    /// [`Film::pixel_errors`] from the pixels' variances, already computed.
    fn pixel_errors_with(&self, variances: &[[f64; 3]]) -> Vec<f64> {
        (0..self.sum.len())
            .map(|i| {
                let mean = self.mean(i).iter().sum::<f64>() / 3.0;
                let sd = variances[i].iter().map(|v| v.sqrt()).sum::<f64>() / 3.0;
                sd / mean.max(PIXEL_ERROR_FLOOR)
            })
            .collect()
    }

    /// Whether any pixel holds a NaN or infinite sum.
    pub fn has_non_finite(&self) -> bool {
        self.sum
            .iter()
            .chain(&self.sum_sq)
            .any(|p| p.iter().any(|v| !v.is_finite()))
    }

    /// Write by extension: `.exr` (linear RGB + variance of the mean) or `.png` (sRGB).
    pub fn write(&self, path: &Path) -> Result<(), FilmError> {
        match path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase)
            .as_deref()
        {
            Some("exr") => self.write_exr(path),
            Some("png") => self.write_png(path),
            _ => Err(FilmError::new(
                path,
                "unknown image extension (use .exr or .png)",
            )),
        }
    }

    /// OpenEXR: linear f32 `R, G, B` (the mean) and `var.R, var.G, var.B` (the calibrated
    /// variance of each pixel's mean, [`Film::variances`]); the sample count is in the header
    /// attribute `spp`, the film-wide calibration ratio in `kappa` (`[1, 1, 1]` when the
    /// per-sample variance is used as it is).
    pub fn write_exr(&self, path: &Path) -> Result<(), FilmError> {
        write::atomically(path, |tmp| write::exr(self, tmp))
    }

    /// PNG: the mean, clamped to [0, 1] and encoded with the sRGB transfer curve.
    pub fn write_png(&self, path: &Path) -> Result<(), FilmError> {
        write::atomically(path, |tmp| write::png(self, tmp))
    }
}

/// Add one sample `value` to a pixel's (or twin's) sum and sum of squares, in f64: what
/// [`Film::add_sample`] does, for renderers that fill a film's rows in place.
pub fn accumulate(sum: &mut [f64; 3], sum_sq: &mut [f64; 3], value: [f32; 3]) {
    for (c, &v) in value.iter().enumerate() {
        let v = v as f64;
        sum[c] += v;
        sum_sq[c] += v * v;
    }
}

/// s²/n from a sum, a sum of squares and a count (0 with fewer than 2 samples).
fn variance_of_mean(sum: [f64; 3], sum_sq: [f64; 3], count: u32) -> [f64; 3] {
    let n = count as f64;
    if n < 2.0 {
        return [0.0; 3];
    }
    std::array::from_fn(|c| {
        let mean = sum[c] / n;
        let sample_var = ((sum_sq[c] - n * mean * mean) / (n - 1.0)).max(0.0);
        sample_var / n
    })
}

/// Twins per calibration class: enough pairs for each class's κ to be within about a quarter.
pub const TWINS_PER_CLASS: usize = 32;

/// Pixels with peak twins ([`Film::peak_pixels`]): 64 (two classes' worth, enough for the few
/// pixels that carry most of the error on Veach's scene at 256×192, and 256 did no better:
/// docs/measurements/error-estimate-honesty.md#where-the-error-lives-and-where-the-twins-must-be),
/// but at most one in 64 × [`PEAK_REPLICAS`], so that their twins cost at most 1.6 % more
/// samples.
pub const PEAK_PIXELS: u32 = 64;

/// Twins at each peak pixel, each an independent randomization. With one, the κ of the
/// brightest class rested on a few pairs, each a single degree of freedom, and single renders
/// of Veach's scene still scattered far from the expected error. Four is where the gain
/// flattens, both simulated and rendered (measured:
/// docs/measurements/error-estimate-honesty.md#four-twins-at-each-peak-pixel-2026-12-04).
/// Four keep a peak pixel in films down to 16×16.
pub const PEAK_REPLICAS: u32 = 4;

/// How many pixels of a film of `width × height` get peak twins.
pub fn peak_count(width: u32, height: u32) -> usize {
    let pixels = width as u64 * height as u64;
    PEAK_PIXELS.min((pixels / (64 * PEAK_REPLICAS as u64)).min(u32::MAX as u64) as u32) as usize
}

/// The 8 neighbours of a pixel, as offsets.
const NEIGHBOURS: [(i64, i64); 8] = [
    (-1, -1),
    (0, -1),
    (1, -1),
    (-1, 0),
    (1, 0),
    (-1, 1),
    (0, 1),
    (1, 1),
];

/// A pixel's own key: its channel-averaged per-sample variance. Classes are keyed by its
/// neighbours' ([`Film::class_keys`]).
fn class_key(v: [f64; 3]) -> f64 {
    (v[0] + v[1] + v[2]) / 3.0
}

/// How far the per-sample variance overstates the error, per channel ([`Film::calibration`]).
///
/// How much stratification gains differs by orders of magnitude between pixels: on the edge of a
/// bright light the per-sample variance is huge and the error of a Sobol estimate tiny, on a
/// diffusely lit wall both are moderate. A single ratio applied to every pixel would give the
/// light's edge the wall's κ. So pixels are classed by the per-sample variance of their
/// neighbours ([`Film::class_keys`]; classes of [`TWINS_PER_CLASS`] twins each, edges at the
/// twins' quantiles) and each class has its own κ, the ratio over its twins (a separate ratio
/// estimator, post-stratified).
#[derive(Clone, Debug, PartialEq)]
pub struct Calibration {
    /// κ over all twins.
    pub film: [f64; 3],
    /// Upper class-key edges of the classes but the last (ascending; [`Film::class_keys`]).
    pub edges: Vec<f64>,
    /// κ of each class (`edges.len() + 1` of them; empty when uncalibrated).
    pub kappa: Vec<[f64; 3]>,
}

impl Calibration {
    /// κ = 1: the per-sample variance as it is.
    pub fn uncalibrated() -> Self {
        Self {
            film: [1.0; 3],
            edges: Vec::new(),
            kappa: Vec::new(),
        }
    }

    /// κ for a pixel of class key `key` ([`Film::class_keys`]).
    pub fn kappa_for(&self, key: f64) -> [f64; 3] {
        if self.kappa.is_empty() {
            return self.film;
        }
        self.kappa[self.edges.partition_point(|e| *e <= key)]
    }
}

/// Denominator floor of a pixel's relative error (radiance units): keeps near-black pixels,
/// whose relative error is meaningless, from dominating the percentile.
pub const PIXEL_ERROR_FLOOR: f64 = 0.01;

/// Estimated relative standard errors of a film ([`Film::relative_error`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RelativeError {
    /// Of the image mean.
    pub image_mean: f64,
    /// 95th percentile over pixels of the per-pixel relative standard error.
    pub pixel_p95: f64,
}

/// An image that could not be written.
#[derive(Debug, thiserror::Error)]
#[error("{}: {reason}", path.display())]
pub struct FilmError {
    pub path: std::path::PathBuf,
    pub reason: String,
}

impl FilmError {
    pub fn new(path: &Path, reason: impl Into<String>) -> Self {
        Self {
            path: path.to_path_buf(),
            reason: reason.into(),
        }
    }
}
