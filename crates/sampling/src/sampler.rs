//! The sampler contract.
//!
//! A sampler is stateless: the value of dimension `dim` of sample `index` in pixel `pixel` under
//! `seed` is a pure function of those integers. 2D domains (pixel, lens, light point, direction)
//! take two consecutive dimensions `dim, dim + 1` through [`Sampler::sample_2d`]; 1D domains
//! (time, light selection, lobe choice, roulette) take one through [`Sampler::sample_1d`].
//! The renderer's dimension layout decides which is which; samplers only see what they're asked.
//! The light domain (which light, then the point on it: a 1D and a 2D dimension) is asked for
//! as one through [`PathSampler::sample_light`], so a sampler may stratify it jointly (Sobol
//! does; the others draw the two domains as apart).

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

    /// The light domain: the choice (1D at `select_dim`) and the point on the light (2D at
    /// `point_dim`), see [`PathSampler::sample_light`].
    pub fn sample_light(
        &self,
        pixel: [u32; 2],
        index: u32,
        select_dim: u32,
        point_dim: u32,
    ) -> (f32, Vec2) {
        self.path(pixel, index).sample_light(select_dim, point_dim)
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
    /// The light domain: the value that chooses a light (the 1D domain at `select_dim`) and the
    /// point on it (the 2D domain at `point_dim`). Sobol draws both from one 3D pattern (keyed
    /// by `point_dim`; [`sobol::bits_light`]), so the samples that choose a light are stratified
    /// on it; its point equals [`PathSampler::sample_2d`] at `point_dim`. The other samplers
    /// return `(sample_1d(select_dim), sample_2d(point_dim))`.
    #[inline]
    pub fn sample_light(&self, select_dim: u32, point_dim: u32) -> (f32, Vec2) {
        match self.kind {
            SamplerKind::Sobol => {
                let (c, [x, y]) = sobol::bits_light(self.key, self.index, point_dim);
                (
                    to_unit_float(c),
                    Vec2::new(to_unit_float(x), to_unit_float(y)),
                )
            }
            _ => (self.sample_1d(select_dim), self.sample_2d(point_dim)),
        }
    }
}

/// Map 32 random bits to a float in `[0, 1)`: the top 24 bits times 2⁻²⁴ (exact in f32, and
/// identical in WGSL).
#[inline]
pub fn to_unit_float(bits: u32) -> f32 {
    (bits >> 8) as f32 * (1.0 / 16_777_216.0)
}
