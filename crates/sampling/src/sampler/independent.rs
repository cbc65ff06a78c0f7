//! Independent sampler: every `(pixel, index, dim, seed)` is hashed on its own, so values are
//! independent uniform draws with no stratification at all (the `N^-1/2` baseline).
//!
//! ```text
//! value(pixel, index, dim, seed) = to_unit_float(hash_combine(pattern_seed(seed, pixel, dim), index))
//! ```
//! Every function takes the pixel's [`pixel_seed`](crate::hash::pixel_seed) `key` (render seed
//! and pixel, hashed once per path); `hash_combine(key, dim)` is the domain's pattern seed.

use glam::Vec2;

use super::to_unit_float;
use crate::hash::hash_combine;

/// 32 random bits for dimension `dim` of sample `index`.
#[inline]
pub fn bits(key: u32, index: u32, dim: u32) -> u32 {
    hash_combine(hash_combine(key, dim), index)
}

/// Value in `[0, 1)` for dimension `dim` of sample `index`.
#[inline]
pub fn sample_1d(key: u32, index: u32, dim: u32) -> f32 {
    to_unit_float(bits(key, index, dim))
}

/// Point in `[0, 1)²`: dimensions `dim` and `dim + 1`, each drawn independently.
#[inline]
pub fn sample_2d(key: u32, index: u32, dim: u32) -> Vec2 {
    Vec2::new(
        sample_1d(key, index, dim),
        sample_1d(key, index, dim.wrapping_add(1)),
    )
}
