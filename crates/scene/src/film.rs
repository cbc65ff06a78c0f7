//! The film both renderers produce: per-pixel sums in f64 of the sample values, of their
//! squares, and of each independent randomization's ("replica's", see
//! [`stratapt_sampling::replica`]) values, from which the mean and a calibrated variance of the
//! mean follow.

mod write;

use std::path::Path;
use stratapt_sampling::replica;

/// Per-pixel Monte Carlo estimates. Pixel `(x, y)` is at index `y * width + x`, `y = 0` on top.
/// A pixel with `count` samples holds its sample indices `0 .. count`.
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
    /// Independent randomizations the samples are split into (sample `i` is in replica
    /// `i % replicas`).
    pub replicas: u32,
    /// Σ f/pdf over each replica's samples: pixel `p`, replica `r` at `p * replicas + r`.
    pub replica_sum: Vec<[f64; 3]>,
}

impl Film {
    /// An empty film whose samples are not split into replicas.
    pub fn new(width: u32, height: u32) -> Self {
        Self::with_replicas(width, height, 1)
    }

    /// An empty film for samples split into `replicas` randomizations.
    pub fn with_replicas(width: u32, height: u32, replicas: u32) -> Self {
        let n = width as usize * height as usize;
        let replicas = replicas.max(1);
        Self {
            width,
            height,
            sum: vec![[0.0; 3]; n],
            sum_sq: vec![[0.0; 3]; n],
            count: vec![0; n],
            replicas,
            replica_sum: vec![[0.0; 3]; n * replicas as usize],
        }
    }

    pub fn index(&self, x: u32, y: u32) -> usize {
        y as usize * self.width as usize + x as usize
    }

    /// Add the value of pixel `(x, y)`'s next sample (index `count`).
    pub fn add_sample(&mut self, x: u32, y: u32, value: [f32; 3]) {
        let i = self.index(x, y);
        let r = (self.count[i] % self.replicas) as usize;
        for (c, &v) in value.iter().enumerate() {
            let v = v as f64;
            self.sum[i][c] += v;
            self.sum_sq[i][c] += v * v;
            self.replica_sum[i * self.replicas as usize + r][c] += v;
        }
        self.count[i] += 1;
    }

    /// Add another film's samples (same size and replicas; its samples follow this film's, so
    /// the replica sums add up).
    pub fn merge(&mut self, other: &Film) {
        assert_eq!((self.width, self.height), (other.width, other.height));
        assert_eq!(self.replicas, other.replicas);
        for i in 0..self.sum.len() {
            for c in 0..3 {
                self.sum[i][c] += other.sum[i][c];
                self.sum_sq[i][c] += other.sum_sq[i][c];
            }
            self.count[i] += other.count[i];
        }
        for (a, b) in self.replica_sum.iter_mut().zip(&other.replica_sum) {
            for c in 0..3 {
                a[c] += b[c];
            }
        }
    }

    /// Samples per pixel (the smallest count over the film).
    pub fn spp(&self) -> u32 {
        self.count.iter().copied().min().unwrap_or(0)
    }

    /// Mean of pixel `i` (0 where no sample was taken).
    pub fn mean(&self, i: usize) -> [f64; 3] {
        let n = self.count[i].max(1) as f64;
        self.sum[i].map(|s| s / n)
    }

    /// The calibrated estimate of the variance of pixel `i`'s mean, for every sampler: from the
    /// spread of the replica means (randomized QMC, Owen 1997). With replica means `mᵣ` over
    /// `nᵣ` samples, weights `wᵣ = nᵣ/n` and their plain average `m̄`,
    /// `Var(mean) ≈ Σᵣ wᵣ² · Σᵣ (mᵣ − m̄)² / (R − 1)`, which with equal counts is
    /// `Σᵣ (mᵣ − m̄)² / (R (R − 1))`, unbiased. With fewer than two non-empty replicas it falls
    /// back to [`Film::sample_variance_of_mean`].
    pub fn variance_of_mean(&self, i: usize) -> [f64; 3] {
        let n = self.count[i];
        let replicas = self.replicas;
        let counts: Vec<u32> = (0..replicas)
            .map(|r| replica::count(0, n, r, replicas))
            .filter(|&c| c > 0)
            .collect();
        let k = counts.len();
        if k < 2 {
            return self.sample_variance_of_mean(i);
        }
        let sums = &self.replica_sum[i * replicas as usize..][..k];
        let weight_sq: f64 = counts.iter().map(|&c| (c as f64 / n as f64).powi(2)).sum();
        std::array::from_fn(|c| {
            let means: Vec<f64> = sums
                .iter()
                .zip(&counts)
                .map(|(s, &m)| s[c] / m as f64)
                .collect();
            let avg = means.iter().sum::<f64>() / k as f64;
            let spread = means.iter().map(|m| (m - avg).powi(2)).sum::<f64>() / (k - 1) as f64;
            weight_sq * spread
        })
    }

    /// The per-sample estimate of the variance of pixel `i`'s mean, s² / n (0 with fewer than 2
    /// samples): right for independent samples only; it overstates the error of stratified and
    /// Sobol samples, which are negatively correlated.
    pub fn sample_variance_of_mean(&self, i: usize) -> [f64; 3] {
        let n = self.count[i] as f64;
        if n < 2.0 {
            return [0.0; 3];
        }
        std::array::from_fn(|c| {
            let mean = self.sum[i][c] / n;
            let sample_var = ((self.sum_sq[i][c] - n * mean * mean) / (n - 1.0)).max(0.0);
            sample_var / n
        })
    }

    /// Mean over all pixels of the per-pixel means, and its standard error (calibrated:
    /// pixels are independent randomizations, so their variances add).
    pub fn image_mean(&self) -> ([f64; 3], [f64; 3]) {
        let n = self.sum.len().max(1) as f64;
        let mut mean = [0.0; 3];
        let mut var = [0.0; 3];
        for i in 0..self.sum.len() {
            let (m, v) = (self.mean(i), self.variance_of_mean(i));
            for c in 0..3 {
                mean[c] += m[c] / n;
                var[c] += v[c] / (n * n);
            }
        }
        (mean, var.map(f64::sqrt))
    }

    /// The calibrated error of the estimate, as relative standard errors: of the image mean
    /// (its luminance-free average over channels) and the 95th percentile over pixels of each
    /// pixel's relative standard error `√Var(mean) / max(mean, 0.01)` (channel-averaged),
    /// the floor keeping black pixels from dominating.
    pub fn relative_error(&self) -> RelativeError {
        let (mean, se) = self.image_mean();
        let m: f64 = mean.iter().sum::<f64>() / 3.0;
        let s: f64 = se.iter().sum::<f64>() / 3.0;
        let mut pixel: Vec<f64> = (0..self.sum.len())
            .map(|i| {
                let (m, v) = (self.mean(i), self.variance_of_mean(i));
                let mean = m.iter().sum::<f64>() / 3.0;
                let sd = v.iter().map(|v| v.sqrt()).sum::<f64>() / 3.0;
                sd / mean.max(PIXEL_ERROR_FLOOR)
            })
            .collect();
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
    /// variance of each pixel's mean, [`Film::variance_of_mean`]); the sample count is in the
    /// header attribute `spp`, the replica count in `replicas`.
    pub fn write_exr(&self, path: &Path) -> Result<(), FilmError> {
        write::atomically(path, |tmp| write::exr(self, tmp))
    }

    /// PNG: the mean, clamped to [0, 1] and encoded with the sRGB transfer curve.
    pub fn write_png(&self, path: &Path) -> Result<(), FilmError> {
        write::atomically(path, |tmp| write::png(self, tmp))
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
