//! Owen-scrambled Sobol sampler: Burley 2020, "Practical Hash-based Owen Scrambling" (JCGT 9(4)),
//! with Vegdahl's LK-hash constants (see [`crate::hash::lk_hash`]).
//!
//! Every domain is its own low-dimensional Sobol pattern, decorrelated from the others by seeds:
//! ```text
//! base = pattern_seed(seed, pixel, dim)              // hash_combine(key, dim), key = pixel_seed
//! i    = owen_scramble(index, base)                       // nested uniform index shuffle
//! 1D:  x = owen_scramble(reverse_bits(i), hash_combine(base, 1))
//! 2D:  x = owen_scramble(reverse_bits(i), hash_combine(base, 1))
//!      y = owen_scramble(sobol_dim1(i),   hash_combine(base, 2))
//! value = to_unit_float(x), to_unit_float(y)
//! ```
//! The index shuffle maps every aligned block `[k·2^m, (k+1)·2^m)` onto an aligned block of the
//! same size, and every such block of the Sobol (0,2)-sequence is a (0,m,2)-net; Owen scrambling
//! preserves nets. So every power-of-two prefix of every pixel's pattern is a (0,m,2)-net.

use glam::Vec2;

use super::to_unit_float;
use crate::hash::{hash_combine, owen_scramble};

/// Sobol dimension 0: the base-2 van der Corput radical inverse, as 32-bit fixed point.
#[inline]
pub fn sobol_dim0(i: u32) -> u32 {
    i.reverse_bits()
}

/// Sobol dimension 1 (with dimension 0, a (0,2)-sequence), as 32-bit fixed point. Its
/// generator matrix is Pascal's triangle mod 2: output bit `31 − p` is the parity of the index
/// bits `j` with `C(j, p)` odd, i.e. (Lucas) with `p ⊆ j` bitwise. That superset-parity
/// transform of the 32 index bits takes five shift-xor steps, one per bit of `j`, then a bit
/// reversal: no loop over the index bits (which costs a masked 32-step loop per lane on SIMD
/// GPUs). [`sobol_dim1_columns`] builds the same matrix column by column, for the tests.
#[inline]
pub fn sobol_dim1(i: u32) -> u32 {
    let mut a = i;
    a ^= (a >> 1) & 0x5555_5555;
    a ^= (a >> 2) & 0x3333_3333;
    a ^= (a >> 4) & 0x0f0f_0f0f;
    a ^= (a >> 8) & 0x00ff_00ff;
    a ^= (a >> 16) & 0x0000_ffff;
    a.reverse_bits()
}

/// [`sobol_dim1`] the textbook way: column `j` of the generator matrix is `v_j`, with
/// `v_0 = 2³¹` and `v_{j+1} = v_j ^ (v_j >> 1)`.
pub fn sobol_dim1_columns(mut i: u32) -> u32 {
    let mut r = 0;
    let mut v = 1u32 << 31;
    while i != 0 {
        if i & 1 != 0 {
            r ^= v;
        }
        i >>= 1;
        v ^= v >> 1;
    }
    r
}

/// The scrambled index and the pattern's base seed (`key`: the pixel's
/// [`pixel_seed`](crate::hash::pixel_seed)).
#[inline]
fn shuffled(key: u32, index: u32, dim: u32) -> (u32, u32) {
    let base = hash_combine(key, dim);
    (owen_scramble(index, base), base)
}

/// 32-bit fixed-point value of the 1D domain at `dim`.
#[inline]
pub fn bits_1d(key: u32, index: u32, dim: u32) -> u32 {
    let (i, base) = shuffled(key, index, dim);
    owen_scramble(sobol_dim0(i), hash_combine(base, 1))
}

/// 32-bit fixed-point point of the 2D domain at `dim`, `dim + 1`.
#[inline]
pub fn bits_2d(key: u32, index: u32, dim: u32) -> [u32; 2] {
    let (i, base) = shuffled(key, index, dim);
    [
        owen_scramble(sobol_dim0(i), hash_combine(base, 1)),
        owen_scramble(sobol_dim1(i), hash_combine(base, 2)),
    ]
}

/// Value in `[0, 1)` of the 1D domain at `dim`.
#[inline]
pub fn sample_1d(key: u32, index: u32, dim: u32) -> f32 {
    to_unit_float(bits_1d(key, index, dim))
}

/// Point in `[0, 1)²` of the 2D domain at `dim`, `dim + 1`.
#[inline]
pub fn sample_2d(key: u32, index: u32, dim: u32) -> Vec2 {
    let [x, y] = bits_2d(key, index, dim);
    Vec2::new(to_unit_float(x), to_unit_float(y))
}
