//! The sampler contract.
//!
//! A sampler is stateless: the value of dimension `dim` of sample `index` in pixel `pixel` under
//! `seed` is a pure function of those integers. 2D domains (pixel, lens, light point, direction)
//! take two consecutive dimensions `dim, dim + 1` through [`Sampler::sample_2d`]; 1D domains
//! (time, light selection, lobe choice, roulette) take one through [`Sampler::sample_1d`].
//! The renderer's dimension layout decides which is which; samplers only see what they're asked.
//! A 1D domain whose effect depends on a 2D one (which light, with the point on it; the shutter
//! instant, with the position in the pixel) is asked for together with it through
//! [`PathSampler::sample_1d_2d`], so a sampler may stratify the three dimensions jointly (Sobol
//! does; the others draw the two domains apart).

pub mod independent;
pub mod sobol;
pub mod stratified;

use glam::Vec2;

use crate::hash::pixel_seed;

/// Which sample sequence to draw from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub enum SamplerKind {
    /// Independent uniform values from an integer hash.
    Independent,
    /// Jittered strata per domain for any `spp` (correlated multi-jittered, Kensler 2013),
    /// decorrelated across dimensions by per-dimension permutation.
    Stratified,
    /// Owen-scrambled Sobol (Burley 2020), per-pixel decorrelated.
    #[default]
    Sobol,
}

impl SamplerKind {
    /// All kinds, in the order tests and studies sweep them.
    pub const ALL: [SamplerKind; 3] = [Self::Independent, Self::Stratified, Self::Sobol];

    /// The name used in scene files and on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Self::Independent => "independent",
            Self::Stratified => "stratified",
            Self::Sobol => "sobol",
        }
    }

    /// Parse a name as written by [`SamplerKind::name`].
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|k| k.name() == name)
    }

    /// The WGSL `override` constant value for this kind (its index in [`SamplerKind::ALL`]).
    pub fn id(self) -> u32 {
        self as u32
    }
}

impl std::fmt::Display for SamplerKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// A configured sampler: kind, samples per pixel (the stratified sampler needs it to size its
/// strata; the others ignore it) and seed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Sampler {
    pub kind: SamplerKind,
    pub spp: u32,
    pub seed: u32,
}

impl Sampler {
    pub fn new(kind: SamplerKind, spp: u32, seed: u32) -> Self {
        Self {
            kind,
            spp: spp.max(1),
            seed,
        }
    }

    /// The samples of path `index` of `pixel`: the pixel's part of every pattern seed hashed
    /// once, for a renderer that draws many domains of one path.
    #[inline]
    pub fn path(&self, pixel: [u32; 2], index: u32) -> PathSampler {
        PathSampler {
            kind: self.kind,
            spp: self.spp,
            key: pixel_seed(self.seed, pixel),
            index,
        }
    }

    /// Value in `[0, 1)` for the 1D domain at `dim`.
    pub fn sample_1d(&self, pixel: [u32; 2], index: u32, dim: u32) -> f32 {
        self.path(pixel, index).sample_1d(dim)
    }

    /// Point in `[0, 1)²` for the 2D domain occupying `dim` and `dim + 1`.
    pub fn sample_2d(&self, pixel: [u32; 2], index: u32, dim: u32) -> Vec2 {
        self.path(pixel, index).sample_2d(dim)
    }

    /// The 1D domain at `dim_1d` and the 2D domain at `dim_2d` drawn together, see
    /// [`PathSampler::sample_1d_2d`].
    pub fn sample_1d_2d(
        &self,
        pixel: [u32; 2],
        index: u32,
        dim_1d: u32,
        dim_2d: u32,
    ) -> (f32, Vec2) {
        self.path(pixel, index).sample_1d_2d(dim_1d, dim_2d)
    }
}

/// One path's samples ([`Sampler::path`]): the same values as [`Sampler::sample_1d`] and
/// [`Sampler::sample_2d`] for its pixel and index.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PathSampler {
    kind: SamplerKind,
    spp: u32,
    /// [`pixel_seed`] of the render seed and the pixel.
    key: u32,
    index: u32,
}

impl PathSampler {
    /// The pixel's key: [`pixel_seed`] of the render seed and the pixel.
    pub fn key(&self) -> u32 {
        self.key
    }

    /// The sample's index in the pixel.
    pub fn index(&self) -> u32 {
        self.index
    }

    /// Value in `[0, 1)` for the 1D domain at `dim`.
    #[inline]
    pub fn sample_1d(&self, dim: u32) -> f32 {
        let (key, index) = (self.key, self.index);
        match self.kind {
            SamplerKind::Independent => independent::sample_1d(key, index, dim),
            SamplerKind::Stratified => stratified::sample_1d(key, index, dim, self.spp),
            SamplerKind::Sobol => sobol::sample_1d(key, index, dim),
        }
    }

    /// Point in `[0, 1)²` for the 2D domain occupying `dim` and `dim + 1`.
    #[inline]
    pub fn sample_2d(&self, dim: u32) -> Vec2 {
        let (key, index) = (self.key, self.index);
        match self.kind {
            SamplerKind::Independent => independent::sample_2d(key, index, dim),
            SamplerKind::Stratified => stratified::sample_2d(key, index, dim, self.spp),
            SamplerKind::Sobol => sobol::sample_2d(key, index, dim),
        }
    }
}

impl PathSampler {
    /// The 1D domain at `dim_1d` (the value that chooses a light; the shutter instant) and the
    /// 2D domain at `dim_2d` (the point on that light; the position in the pixel) drawn
    /// together. Sobol draws them from one 3D pattern (keyed by `dim_2d`;
    /// [`sobol::bits_1d_2d`]), so the samples that choose one light, or one stretch of the
    /// shutter, are stratified over the 2D domain; its 2D point equals
    /// [`PathSampler::sample_2d`] at `dim_2d`. The other samplers return
    /// `(sample_1d(dim_1d), sample_2d(dim_2d))`.
    #[inline]
    pub fn sample_1d_2d(&self, dim_1d: u32, dim_2d: u32) -> (f32, Vec2) {
        match self.kind {
            SamplerKind::Sobol => {
                let (c, [x, y]) = sobol::bits_1d_2d(self.key, self.index, dim_2d);
                (
                    to_unit_float(c),
                    Vec2::new(to_unit_float(x), to_unit_float(y)),
                )
            }
            _ => (self.sample_1d(dim_1d), self.sample_2d(dim_2d)),
        }
    }
}

/// Map 32 random bits to a float in `[0, 1)`: the top 24 bits times 2⁻²⁴ (exact in f32, and
/// identical in WGSL).
#[inline]
pub fn to_unit_float(bits: u32) -> f32 {
    (bits >> 8) as f32 * (1.0 / 16_777_216.0)
}
