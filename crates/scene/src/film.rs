//! The film both renderers produce: per-pixel sums of sample values and of their squares, in
//! f64, from which the mean and the variance of the mean follow.

mod write;

use std::path::Path;

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
}

impl Film {
    pub fn new(width: u32, height: u32) -> Self {
        let n = width as usize * height as usize;
        Self {
            width,
            height,
            sum: vec![[0.0; 3]; n],
            sum_sq: vec![[0.0; 3]; n],
            count: vec![0; n],
        }
    }

    pub fn index(&self, x: u32, y: u32) -> usize {
        y as usize * self.width as usize + x as usize
    }

    /// Add one sample value to pixel `(x, y)`.
    pub fn add_sample(&mut self, x: u32, y: u32, value: [f32; 3]) {
        let i = self.index(x, y);
        for (c, &v) in value.iter().enumerate() {
            let v = v as f64;
            self.sum[i][c] += v;
            self.sum_sq[i][c] += v * v;
        }
        self.count[i] += 1;
    }

    /// Add another film's samples (same size) to this one.
    pub fn merge(&mut self, other: &Film) {
        assert_eq!((self.width, self.height), (other.width, other.height));
        for i in 0..self.sum.len() {
            for c in 0..3 {
                self.sum[i][c] += other.sum[i][c];
                self.sum_sq[i][c] += other.sum_sq[i][c];
            }
            self.count[i] += other.count[i];
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

    /// Unbiased estimate of the variance of pixel `i`'s mean: s² / n (0 with fewer than 2 samples).
    pub fn variance_of_mean(&self, i: usize) -> [f64; 3] {
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

    /// Mean over all pixels of the per-pixel means, and its standard error.
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

    /// OpenEXR: linear f32 `R, G, B` (the mean) and `var.R, var.G, var.B` (variance of each
    /// pixel's mean); the sample count is in the header attribute `spp`.
    pub fn write_exr(&self, path: &Path) -> Result<(), FilmError> {
        write::atomically(path, |tmp| write::exr(self, tmp))
    }

    /// PNG: the mean, clamped to [0, 1] and encoded with the sRGB transfer curve.
    pub fn write_png(&self, path: &Path) -> Result<(), FilmError> {
        write::atomically(path, |tmp| write::png(self, tmp))
    }
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
