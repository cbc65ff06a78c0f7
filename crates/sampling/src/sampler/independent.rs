//! Independent sampler: every `(pixel, index, dim, seed)` is hashed on its own, so values are
//! independent uniform draws with no stratification at all (the `N^-1/2` baseline).
//!
//! ```text
//! value(pixel, index, dim, seed) = to_unit_float(hash_combine(pattern_seed(seed, pixel, dim), index))
//! ```

use glam::Vec2;

use super::to_unit_float;
use crate::hash::{hash_combine, pattern_seed};

/// 32 random bits for dimension `dim` of sample `index`.
#[inline]
pub fn bits(pixel: [u32; 2], index: u32, dim: u32, seed: u32) -> u32 {
    hash_combine(pattern_seed(seed, pixel, dim), index)
}

/// Value in `[0, 1)` for dimension `dim` of sample `index`.
#[inline]
pub fn sample_1d(pixel: [u32; 2], index: u32, dim: u32, seed: u32) -> f32 {
    to_unit_float(bits(pixel, index, dim, seed))
}

/// Point in `[0, 1)²`: dimensions `dim` and `dim + 1`, each drawn independently.
#[inline]
pub fn sample_2d(pixel: [u32; 2], index: u32, dim: u32, seed: u32) -> Vec2 {
    Vec2::new(
        sample_1d(pixel, index, dim, seed),
        sample_1d(pixel, index, dim.wrapping_add(1), seed),
    )
}
